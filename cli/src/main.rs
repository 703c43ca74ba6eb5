//! `stridekit`: the command-line tool of the stridekit SDK.

mod commands;
mod input;
mod outcome;
mod output;

use std::process::ExitCode;

fn main() -> ExitCode {
    commands::main()
}
