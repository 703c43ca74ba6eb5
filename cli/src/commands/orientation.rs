//! `stridekit orientation FILE`: its arguments and its run (the replay:
//! `crate::orientation`). The CSV goes to `--out FILE` (the chart beside it) or, with
//! `--out -`, to stdout (the summary then goes to stderr).

use std::path::PathBuf;

use clap::Args;

use super::EXIT_CODES;
use crate::outcome::Failure;
use crate::output::{say, Sink};

/// Replay an IMU/magnetometer recording through the orientation filter.
///
/// Replay a recording with IMU and magnetometer samples (the BROAD CSV, .csv or
/// .csv.gz, or an Android sensor log) through the default orientation filter; write
/// one row per accepted sample, t_s,qw,qx,qy,qz (body → East-North-Up) and the
/// filter's flags, and a chart (SVG) beside it. With optical truth in the file, prints the BROAD errors; with
/// Android's rotation vector in a sensor log, the RMS difference to it (a second
/// opinion, not truth). The summary says whether the heading rests on the
/// magnetometer.
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct OrientationArgs {
    /// The recording.
    pub file: PathBuf,
    /// The orientation CSV to write (the chart goes beside it); `-`: the CSV on
    /// stdout (no chart), the summary on stderr.
    #[arg(long, value_name = "FILE", default_value = "orientation.csv")]
    pub out: PathBuf,
    /// Ignore the magnetometer.
    #[arg(long)]
    pub imu_only: bool,
}

pub fn run(a: OrientationArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    crate::orientation::run(&a, &sink)?;
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
    }
    Ok(())
}
