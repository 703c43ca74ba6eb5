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
    match &a.map {
        Some(map) => crate::pdr_map::run(&a, map, &sink)?,
        None => crate::pdr::run(&a, &sink)?,
    }
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
    }
    Ok(())
}
