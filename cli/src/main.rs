//! `stridekit`: the command-line tool of the stridekit SDK.

mod commands;
mod demo;
mod foot;
mod orientation;
mod output;
mod pdr;
mod pdr_map;
mod replay;
mod steps;

use std::process::ExitCode;

fn main() -> ExitCode {
    commands::main()
}
