//! `stridekit orientation FILE`: its arguments and its run (the replay:
//! `stridekit_lab::replay::orientation`). The CSV goes to `--out FILE` (the chart beside it) or, with
//! `--out -`, to stdout (the summary then goes to stderr).

use std::path::PathBuf;

use clap::Args;
use stridekit_lab::replay::orientation;

use super::EXIT_CODES;
use crate::input::warn_truncated;
use crate::outcome::{check, Failure};
use crate::output::{say, write_to, Sink};

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
    let rec = orientation::read(&a.file)?;
    if rec.truncated {
        warn_truncated(&a.file);
    }
    let r = orientation::replay(rec, a.imu_only)?;
    write_to(&sink, |w| r.write_csv(w))?;
    if let Some(svg) = sink.beside("svg") {
        r.chart(&svg)?;
    }
    say!("{}", r.summary(&sink.name()));
    check(r.usable())?;
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
    }
    Ok(())
}
