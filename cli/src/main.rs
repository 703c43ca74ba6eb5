//! `stridekit`: the command-line tool of the stridekit SDK.

mod activity;
mod calibrate_pdr;
mod commands;
mod demo;
mod eval_foot;
mod eval_foot_diagnose;
mod eval_foot_sessions;
mod eval_foot_tune_shoe;
mod eval_orientation;
mod eval_pace;
mod eval_pace_device;
mod eval_pdr;
mod eval_pdr_odometry;
mod eval_pdr_real;
mod eval_steplength;
mod eval_steps;
mod foot;
mod odometry;
mod orientation;
mod orientation_metric;
mod output;
mod pdr;
mod pdr_diagnose;
mod pdr_metrics;
mod pdr_walks;
mod placement;
mod placement_mlp;
mod progress;
mod rejected;
mod replay;
mod report;
mod soak;
mod steps;
mod train_zupt;

use std::process::ExitCode;

fn main() -> ExitCode {
    commands::main()
}
