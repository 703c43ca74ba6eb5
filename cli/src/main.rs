//! `stridekit`: the command-line tool of the stridekit SDK.

mod basis;
mod commands;
mod demo;
mod demo_facts;
mod foot;
mod input;
mod orientation;
mod outcome;
mod output;
mod pdr;
mod replay;
mod steps;

use std::process::ExitCode;

fn main() -> ExitCode {
    commands::main()
}
