//! `stridekit steps FILE`: its arguments and its run (the replay:
//! `stridekit_lab::replay::steps`).
//! The CSV goes to `--out FILE` or, with `--out -`, to stdout (the summary then goes
//! to stderr).

use std::path::PathBuf;

use clap::Args;
use stridekit_lab::replay::steps;

use super::EXIT_CODES;
use crate::input::warn_truncated;
use crate::outcome::{check, Failure};
use crate::output::{say, write_to, Sink};

/// Replay a phone accelerometer recording through the step detector.
///
/// Replay a phone accelerometer recording (an Oxford Step Counter trace folder or an
/// Oxford-format accelerometer CSV, or an Android sensor log, plain or gzip; told by
/// the content) through the step detector; write one row per step (t_s on the
/// recording's clock, step number, cadence in steps/min, interval) and a cadence chart
/// (SVG, beside the CSV; with the trace's reference steps when it has them).
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct StepsArgs {
    /// The trace folder, accelerometer CSV or Android sensor log.
    pub file: PathBuf,
    /// The steps CSV to write (the chart goes beside it); `-`: the CSV on stdout (no
    /// chart), the summary on stderr.
    #[arg(long, value_name = "FILE", default_value = "steps.csv")]
    pub out: PathBuf,
}

pub fn run(a: StepsArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    let rec = steps::read(&a.file)?;
    if rec.truncated {
        warn_truncated(&a.file);
    }
    let r = steps::replay(rec)?;
    write_to(&sink, |w| r.write_csv(w))?;
    if let Some(svg) = sink.beside("svg") {
        r.chart(&svg)?;
    }
    say!("{}", r.summary(&sink.name()));
    check(r.usable())?;
    if let Some(w) = sink.wrote() {
        say!("{w}");
    }
    Ok(())
}
