//! `stridekit pdr FILE`: its arguments and its run (the replays:
//! `stridekit_lab::replay::{pdr, map}`). The CSV goes to `--out FILE` (the SVG beside it) or, with `--out -`, to stdout (the
//! summary then goes to stderr).

use std::path::{Path, PathBuf};

use clap::Args;
use stridekit_lab::pdr::walks::Walk;
use stridekit_lab::replay::{map, pdr, pdr::PdrOptions};

use super::EXIT_CODES;
use crate::input::warn_truncated;
use crate::outcome::{check, Failure};
use crate::output::{say, write_to, Sink};

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
    /// Position on a floor plan instead: a floor folder (geojson_map.json,
    /// floor_info.json, floor_image.png) or a GeoJSON file in WGS84. The CSV then holds
    /// t_s,x_m,y_m (the live estimate, plan metres), σ, the smoothed path and flags.
    #[arg(long, value_name = "FLOORDIR|FILE", conflicts_with_all = ["calibration", "no_mag", "raw_gyro"])]
    pub map: Option<PathBuf>,
    /// With --map: where the walk starts, plan metres, and its σ (default: the log's
    /// first waypoint, σ 1 m).
    #[arg(long, value_name = "X,Y[,SIGMA]", value_parser = start_arg, requires = "map")]
    pub start: Option<(f64, f64, Option<f64>)>,
}

/// `X,Y` or `X,Y,SIGMA` (metres).
fn start_arg(s: &str) -> Result<(f64, f64, Option<f64>), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .map_err(|_| format!("{p:?} is not a number"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y] if x.is_finite() && y.is_finite() => Ok((x, y, None)),
        [x, y, s] if x.is_finite() && y.is_finite() && s.is_finite() && s >= 0.0 => {
            Ok((x, y, Some(s)))
        }
        _ => Err("expected X,Y or X,Y,SIGMA in metres (SIGMA ≥ 0)".into()),
    }
}

pub fn run(a: PdrArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    let walk = pdr::read(&a.file)?;
    if walk.rec.truncated {
        warn_truncated(&a.file);
    }
    match &a.map {
        Some(plan) => on_plan(&a, walk, plan, &sink)?,
        None => dead_reckoning(&a, walk, &sink)?,
    }
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
    }
    Ok(())
}

/// The walk through the phone navigator alone.
fn dead_reckoning(a: &PdrArgs, walk: Walk, sink: &Sink) -> Result<(), Failure> {
    let options = PdrOptions {
        calibration_file: a.calibration.clone(),
        no_mag: a.no_mag,
        raw_gyro: a.raw_gyro,
    };
    let r = pdr::replay(walk, options)?;
    write_to(sink, |w| r.write_csv(w))?;
    let svg = sink.beside("svg");
    if let Some(svg) = &svg {
        r.chart(svg)?;
    }
    say!("{}", r.summary(&sink.name(), svg.as_deref()));
    check(r.usable())
}

/// The walk on the floor plan `plan` (`--map`).
fn on_plan(a: &PdrArgs, walk: Walk, plan: &Path, sink: &Sink) -> Result<(), Failure> {
    let r = map::replay(walk, plan, a.start)?;
    write_to(sink, |w| r.write_csv(w))?;
    let svg = sink.beside("svg");
    if let Some(svg) = &svg {
        r.chart(svg)?;
    }
    say!("{}", r.summary(&sink.name(), svg.as_deref()));
    if r.walked() {
        Ok(())
    } else {
        Err(Failure::Failed("no step detected: no trajectory".into()))
    }
}
