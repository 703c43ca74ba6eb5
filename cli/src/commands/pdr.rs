//! `stridekit pdr FILE`: its arguments and its run (the replay: `crate::pdr`). The
//! CSV goes to `--out FILE` (the SVG beside it) or, with `--out -`, to stdout (the
//! summary then goes to stderr).

use std::path::PathBuf;

use clap::Args;

use super::EXIT_CODES;
use crate::outcome::Failure;
use crate::output::{say, Sink};

/// Replay an Android sensor log through the phone navigator (dead reckoning).
///
/// Replay a phone recording (Android sensor log, plain or gzip) through the phone
/// navigator without GNSS; write the trajectory (one row per step: t_s, east_m,
/// north_m, step_length_m, azimuth_deg, steps) and beside it an SVG of the track over
/// the aligned waypoints; with waypoints, print the four accuracy measures. The
/// summary says what the step length (model with population parameters, or a
/// calibration) and the heading (magnetometer or not) rest on.
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct PdrArgs {
    /// The sensor log.
    pub file: PathBuf,
    /// The trajectory CSV to write (the SVG goes beside it); `-`: the CSV on stdout
    /// (no plot), the summary on stderr.
    #[arg(long, value_name = "FILE", default_value = "pdr_trajectory.csv")]
    pub out: PathBuf,
    /// A personal calibration written by `stridekit calibrate pdr`.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
    /// Ignore the magnetometer.
    #[arg(long)]
    pub no_mag: bool,
    /// The gyroscope is raw (its bias not removed by the platform, e.g. Android's
    /// TYPE_GYROSCOPE_UNCALIBRATED alone): the magnetometer then corrects the heading
    /// fast (10 s instead of 120 s) to follow the gyroscope's drift.
    #[arg(long)]
    pub raw_gyro: bool,
}

pub fn run(a: PdrArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    crate::pdr::run(&a, &sink)?;
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
    }
    Ok(())
}
