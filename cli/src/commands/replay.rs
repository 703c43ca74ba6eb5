//! Replays of real recordings: `pace`, `steps`, `foot`, `pdr`, `orientation`,
//! `odometry`. Samples an engine rejects are skipped and counted by reason, never
//! fatal.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stridekit_core::{PaceCalibration, PaceConfig};

use crate::output::OutFile;

/// Replay an activity file (.fit/.tcx/.gpx/.csv) through the pace tracker.
///
/// Replay a real activity file (.fit, .tcx, .gpx or .csv) through the pace tracker;
/// print one CSV row per GNSS epoch on stdout (pace as seconds per km and as min:s per
/// km), or with --out write it to a file and a speed chart (SVG) beside it; rejected
/// samples and a summary go to stderr.
#[derive(Debug, Args)]
pub struct PaceArgs {
    /// The activity file.
    pub file: PathBuf,
    /// Write the CSV here (and FILE.svg, the speed over time, beside it) instead of
    /// printing it.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
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

pub fn pace(a: PaceArgs) -> Result<(), String> {
    let mut config = match a.mode {
        PaceMode::Default => PaceConfig::default(),
        PaceMode::Published => PaceConfig::as_published(),
    };
    if let Some(f) = &a.calibration {
        let text = std::fs::read_to_string(f)
            .map_err(|e| format!("cannot read the calibration {}: {e}", f.display()))?;
        config.calibration =
            Some(PaceCalibration::parse(&text).map_err(|e| format!("{}: {e}", f.display()))?);
    }
    let out = a
        .out
        .as_deref()
        .map(|p| OutFile::prepare(p, "csv"))
        .transpose()?;
    let options = crate::replay::Options {
        csv_out: out.as_ref().map(|o| o.path.as_path()),
        no_gnss: a.no_gnss,
    };
    let tracker = crate::replay::run(&a.file, config, &options)?;
    if let Some(o) = out {
        eprintln!("{}", o.wrote());
    }
    if let Some(f) = &a.save_calibration {
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
        eprintln!("calibration: {}", f.display());
    }
    Ok(())
}

/// Replay a phone accelerometer recording through the step detector.
///
/// Replay a phone accelerometer recording (an Oxford Step Counter trace folder or its
/// accelerometer.csv, or an Android sensor log .txt / .txt.gz) through the step detector; write one row per step (t_s on the
/// recording's clock, step number, cadence in steps/min, interval) and a cadence chart
/// (SVG, beside the CSV; with the trace's reference steps when it has them).
#[derive(Debug, Args)]
pub struct StepsArgs {
    /// The trace folder, accelerometer.csv or Android sensor log.
    pub file: PathBuf,
    /// The steps CSV to write.
    #[arg(long, value_name = "FILE", default_value = "steps.csv")]
    pub out: PathBuf,
}

pub fn steps(a: StepsArgs) -> Result<(), String> {
    let out = OutFile::prepare(&a.out, "csv")?;
    crate::steps::run(&crate::steps::StepsArgs {
        file: a.file,
        out: Some(out.path.clone()),
    })?;
    eprintln!("{}", out.wrote());
    Ok(())
}

/// Replay a foot-mounted IMU recording through the foot navigator.
///
/// Replay a foot-mounted IMU recording (pyshoe / UofT CSV, or an x-io NGIMU CSV
/// export) through the foot navigator; write the trajectory CSV and, next to it,
/// traj.svg (top view) and traj_height.svg (height over time). Prints strides,
/// distance and the loop closure; with truth columns (gt_*), the aligned truth and the
/// position RMSE.
#[derive(Debug, Args)]
pub struct FootArgs {
    /// The recording.
    pub file: PathBuf,
    /// The trajectory CSV to write (the SVGs go beside it).
    #[arg(long, value_name = "FILE", default_value = "foot_trajectory.csv")]
    pub out: PathBuf,
    /// Drive the zero-velocity updates with a stance label column of the file (e.g.
    /// vicon_opt or zv_vicon_opt) instead of the detector.
    #[arg(long, value_name = "NAME")]
    pub labels: Option<String>,
    /// Where the sensor axes point, in the order x, y, z, from f/b l/r u/d (frd = x
    /// forward, y right, z down, as in pyshoe; flu), or which signed sensor axis gives
    /// body forward, left, up (x,-y,-z = frd). Default: frd for pyshoe files, flu for
    /// x-io.
    #[arg(long, value_name = "SPEC")]
    pub axes: Option<String>,
    /// The IMU: calibrated (factory-calibrated; default for pyshoe/UofT files) or
    /// consumer (gyro bias measured at the start rest; default otherwise).
    #[arg(long, value_enum)]
    pub imu: Option<Imu>,
    /// A device calibration of this IMU written by `stridekit calibrate foot` (the
    /// accelerometer-to-gyroscope alignment learned from a level walk).
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
    /// Keep the filter's own height on level strides: turn off the level-floor
    /// constraint (on by default: a stride that rises or falls by at most 5 % of its
    /// length is taken as level; stairs and ramps keep their height).
    #[arg(long)]
    pub no_level_floor: bool,
    /// The gyroscope's range, rad/s: samples at 99 % of it are clipped, and the rotation
    /// above the ceiling is restored after each clipped run. Default: 9.2 for pyshoe /
    /// UofT files (their MicroStrain clips at about 9.13 rad/s), none for x-io.
    #[arg(long, value_name = "RAD_S")]
    pub gyro_range: Option<f64>,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Imu {
    Consumer,
    Calibrated,
}

impl From<Imu> for crate::foot::ImuProfile {
    fn from(i: Imu) -> Self {
        match i {
            Imu::Consumer => Self::Consumer,
            Imu::Calibrated => Self::Calibrated,
        }
    }
}

pub fn foot(a: FootArgs) -> Result<(), String> {
    let out = OutFile::prepare(&a.out, "csv")?;
    crate::foot::run(&crate::foot::FootArgs {
        file: a.file,
        out: out.path.clone(),
        labels: a
            .labels
            .map(|l| l.strip_prefix("zv_").map(str::to_string).unwrap_or(l)),
        axes: a.axes,
        imu: a.imu.map(Into::into),
        calibration: a.calibration,
        no_level_floor: a.no_level_floor,
        gyro_range_rads: a.gyro_range,
    })?;
    eprintln!("{} (and the SVGs beside it)", out.wrote());
    Ok(())
}

/// Replay an Android sensor log through the phone navigator (dead reckoning).
///
/// Replay a phone recording (Android sensor log .txt or .txt.gz) through the phone
/// navigator without GNSS; write the trajectory (one row per step: t_s, east_m,
/// north_m, step_length_m, azimuth_deg, steps) and beside it an SVG of the track over
/// the aligned waypoints; with waypoints, print the four accuracy measures.
#[derive(Debug, Args)]
pub struct PdrArgs {
    /// The sensor log.
    pub file: PathBuf,
    /// The trajectory CSV to write (the SVG goes beside it).
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

pub fn pdr(a: PdrArgs) -> Result<(), String> {
    let out = OutFile::prepare(&a.out, "csv")?;
    if let Some(map) = a.map {
        let text = crate::pdr_map::run(&crate::pdr_map::MapArgs {
            file: a.file,
            out: out.path.clone(),
            map,
            start: a.start,
        })?;
        print!("{text}");
        if out.existed {
            eprintln!("(replaced the previous {})", out.path.display());
        }
        return Ok(());
    }
    let text = crate::pdr::run(&crate::pdr::PdrArgs {
        file: a.file,
        out: Some(out.path.clone()),
        calibration: a.calibration,
        no_mag: a.no_mag,
        raw_gyro: a.raw_gyro,
    })?;
    print!("{text}");
    if out.existed {
        eprintln!("(replaced the previous {})", out.path.display());
    }
    Ok(())
}

/// Replay an IMU/magnetometer recording through the orientation filter.
///
/// Replay a recording with IMU and magnetometer samples (the BROAD CSV, .csv or
/// .csv.gz, or an Android sensor log) through the default orientation filter; write
/// one row per accepted sample, t_s,qw,qx,qy,qz (body → East-North-Up) and the
/// filter's flags, and a chart (SVG) beside it. With optical truth in the file, prints the BROAD errors; with
/// Android's rotation vector in a sensor log, the RMS difference to it (a second
/// opinion, not truth).
#[derive(Debug, Args)]
pub struct OrientationArgs {
    /// The recording.
    pub file: PathBuf,
    /// The orientation CSV to write.
    #[arg(long, value_name = "FILE", default_value = "orientation.csv")]
    pub out: PathBuf,
    /// Ignore the magnetometer.
    #[arg(long)]
    pub imu_only: bool,
}

pub fn orientation(a: OrientationArgs) -> Result<(), String> {
    let out = OutFile::prepare(&a.out, "csv")?;
    crate::orientation::run(&crate::orientation::OrientationArgs {
        file: a.file,
        out: out.path.clone(),
        imu_only: a.imu_only,
    })?;
    if out.existed {
        eprintln!("(replaced the previous {})", out.path.display());
    }
    Ok(())
}

/// Replay a recording through the learned phone odometry.
///
/// Replay a recording (RIDI sequence, RIDI data.csv, RoNIN CSV export, or a simulator
/// walk `sim:SEED:PLACEMENT`) through the learned odometry and the baselines; print
/// ATE / RTE and write an SVG of the trajectories against the truth.
#[derive(Debug, Args)]
pub struct OdometryArgs {
    /// FILE, DIR or sim:SEED:PLACEMENT.
    pub input: String,
    /// A model file (default: the shipped model).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// The SVG to write.
    #[arg(long, value_name = "FILE", default_value = "odometry.svg")]
    pub out: PathBuf,
}

pub fn odometry(a: OdometryArgs) -> Result<(), String> {
    let out = OutFile::prepare(&a.out, "svg")?;
    let text = stridekit_lab::odometry::commands::replay(&a.input, a.model.as_deref(), &out.path)?;
    println!("{text}");
    Ok(())
}
