//! `stridekit pace FILE`: its arguments and its run. The CSV goes to `--out FILE`
//! (the terminal gets the summary) or, with `--out -`, to stdout (the summary then
//! goes to stderr); rejected samples are counted, never fatal (the replay:
//! `stridekit_lab::replay::pace`).

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use stridekit_core::{PaceCalibration, PaceConfig, PaceTracker};
use stridekit_lab::replay::pace::{self, PaceOptions};

use super::EXIT_CODES;
use crate::input::warn_truncated;
use crate::outcome::{check, usage, Failure};
use crate::output::{say, write_to, Sink};

/// Replay an activity file (.fit/.tcx/.gpx/.csv) through the pace tracker.
///
/// Replay a real activity file (FIT, TCX, GPX or CSV, told by its content; gzip
/// too) through the pace tracker; write one CSV row per GNSS epoch (pace as seconds
/// per km and as min:s per km) to --out and a speed chart (SVG) beside it. The
/// summary says the rejected samples, what the reader cleaned up (a file cut off
/// mid-write included) and what the distance rests on: GNSS, a learned or imported
/// step length, or the population prior with its typical error.
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct PaceArgs {
    /// The activity file.
    pub file: PathBuf,
    /// The CSV to write (FILE.svg, the speed over time, goes beside it); `-`: the
    /// CSV on stdout (no chart), the summary on stderr.
    #[arg(long, value_name = "FILE", default_value = "pace.csv")]
    pub out: PathBuf,
    /// The filter: the robust default or the method as published.
    #[arg(long, value_enum, default_value_t = PaceMode::Default)]
    pub mode: PaceMode,
    /// Start from a runner's calibration (a file written by --save-calibration):
    /// calibrated pedometer speed from the first steps.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
    /// After the replay, write what the tracker learned (the step-length line, and the
    /// accelerometer model when the file has raw acceleration) to FILE, for
    /// --calibration next time; fails when nothing was learned (no good GNSS).
    #[arg(long, value_name = "FILE")]
    pub save_calibration: Option<PathBuf>,
    /// Leave out every GNSS fix: replay the run as a treadmill or an indoor track
    /// would give it (steps only), e.g. to try a calibration learned on another run.
    #[arg(long)]
    pub no_gnss: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum PaceMode {
    Default,
    Published,
}

pub fn run(a: PaceArgs) -> Result<(), Failure> {
    let config = config(&a)?;
    let sink = Sink::from_arg(&a.out, "csv")?;
    let activity = pace::read(&a.file)?;
    if activity.cleanup.truncated {
        warn_truncated(&a.file);
    }
    let options = PaceOptions {
        no_gnss: a.no_gnss,
        calibration_file: a.calibration.clone(),
    };
    let r = pace::replay(activity, config, options)?;
    write_to(&sink, |w| r.write_csv(w))?;
    if let Some(svg) = sink.beside("svg") {
        r.chart(&svg)?;
        say!("speed chart: {}", svg.display());
    }
    say!("{}", r.summary());
    check(r.usable())?;
    if let Some(w) = sink.wrote() {
        say!("{w}");
    }
    if let Some(f) = &a.save_calibration {
        save_calibration(&a, &r.tracker, f)?;
    }
    Ok(())
}

/// The tracker's configuration: `--mode`, and the calibration of `--calibration`
/// (a file that cannot be read or parsed is a bad value: exit 2).
fn config(a: &PaceArgs) -> Result<PaceConfig, Failure> {
    let mut config = match a.mode {
        PaceMode::Default => PaceConfig::default(),
        PaceMode::Published => PaceConfig::as_published(),
    };
    if let Some(f) = &a.calibration {
        let text = std::fs::read_to_string(f)
            .map_err(|e| usage("--calibration", format!("cannot read {}: {e}", f.display())))?;
        config.calibration = Some(
            PaceCalibration::parse(&text)
                .map_err(|e| usage("--calibration", format!("{}: {e}", f.display())))?,
        );
    }
    Ok(config)
}

/// `--save-calibration FILE`: what the tracker learned; fails when it learned nothing.
fn save_calibration(a: &PaceArgs, tracker: &PaceTracker, f: &Path) -> Result<(), Failure> {
    let c = tracker.calibration().ok_or_else(|| {
        format!(
            "no calibration to save: the step length is learned from good GNSS with step data ({})",
            if a.no_gnss {
                "--no-gnss left every fix out"
            } else {
                "this file has too little of it: the line needs a few minutes of running with both"
            }
        )
    })?;
    let text = c.to_text(&[format!("learned by: stridekit pace {}", a.file.display())]);
    std::fs::write(f, text).map_err(|e| format!("cannot write {}: {e}", f.display()))?;
    say!("calibration: {}", f.display());
    Ok(())
}
