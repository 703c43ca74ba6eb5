//! Replays of real recordings: `pace`, `steps`, `foot`, `pdr`, `orientation`,
//! `odometry`. Samples an engine rejects are skipped and counted by reason, never
//! fatal; a replay that produced nothing usable exits 1 (see `crate::outcome`). The
//! CSV goes to `--out FILE` (the terminal gets the summary) or, with `--out -`, to
//! stdout (the summary then goes to stderr).

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use stridekit_core::foot::FootConfig;
use stridekit_core::{PaceCalibration, PaceConfig};

use super::EXIT_CODES;
use crate::outcome::{usage, Failure};
use crate::output::{say, OutFile, Sink};

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

pub fn pace(a: PaceArgs) -> Result<(), Failure> {
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
    let sink = Sink::from_arg(&a.out, "csv")?;
    let options = crate::replay::Options {
        sink: &sink,
        no_gnss: a.no_gnss,
        calibration: a.calibration.as_deref(),
    };
    let tracker = crate::replay::run(&a.file, config, &options)?;
    if let Some(w) = sink.wrote() {
        say!("{w}");
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
        say!("calibration: {}", f.display());
    }
    Ok(())
}

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

pub fn steps(a: StepsArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    crate::steps::run(&crate::steps::StepsArgs {
        file: a.file,
        sink: sink.clone(),
    })?;
    if let Some(w) = sink.wrote() {
        say!("{w}");
    }
    Ok(())
}

/// Replay a foot-mounted IMU recording through the foot navigator.
///
/// Replay a foot-mounted IMU recording (pyshoe / UofT CSV, or an x-io NGIMU CSV
/// export) through the foot navigator; write the trajectory CSV (t_s, east_m,
/// north_m, up_m, velocities, yaw, stance, strides, distance: a local level ENU frame
/// from where the walk started, east = where the foot's x axis pointed at the start
/// unless a heading is known) and, next to it, traj.svg (top view) and
/// traj_height.svg (height over time). Prints strides, distance and the loop closure;
/// with truth columns (gt_*), the aligned truth and the position RMSE.
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct FootArgs {
    /// The recording.
    pub file: PathBuf,
    /// The trajectory CSV to write (the SVGs go beside it); `-`: the CSV on stdout
    /// (no plots), the summary on stderr.
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
    #[arg(long, value_name = "SPEC", value_parser = axes_spec)]
    pub axes: Option<String>,
    /// The IMU: calibrated (factory-calibrated; default for trials of the UofT VICON
    /// set, known by its label columns) or consumer (gyro bias measured at the start
    /// rest; default for every other file).
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
    /// above the ceiling is restored after each clipped run. Default: the ceiling the
    /// data show (flat tops at one rate, again and again, nothing above), else none and
    /// nothing repaired. The output says which.
    #[arg(long, value_name = "RAD_S", value_parser = positive_rads)]
    pub gyro_range: Option<f64>,
}

/// `--axes`: a spec [`FootConfig::axes_from_spec`] accepts (checked by clap: exit 2).
pub fn axes_spec(s: &str) -> Result<String, String> {
    FootConfig::axes_from_spec(s)
        .map(|_| s.to_string())
        .map_err(|e| e.to_string())
}

/// A finite angular rate above zero, rad/s.
fn positive_rads(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{s} is not a rate above 0 rad/s")),
    }
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

pub fn foot(a: FootArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    crate::foot::run(&crate::foot::FootArgs {
        file: a.file,
        sink: sink.clone(),
        labels: a
            .labels
            .map(|l| l.strip_prefix("zv_").map(str::to_string).unwrap_or(l)),
        axes: a.axes,
        imu: a.imu.map(Into::into),
        calibration: a.calibration,
        no_level_floor: a.no_level_floor,
        gyro_range_rads: a.gyro_range,
    })?;
    if let Some(w) = sink.wrote() {
        say!("{w} (and the SVGs beside it)");
    }
    Ok(())
}

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

pub fn pdr(a: PdrArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    crate::pdr::run(&crate::pdr::PdrArgs {
        file: a.file,
        sink: sink.clone(),
        calibration: a.calibration,
        no_mag: a.no_mag,
        raw_gyro: a.raw_gyro,
    })?;
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
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

pub fn orientation(a: OrientationArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    crate::orientation::run(&crate::orientation::OrientationArgs {
        file: a.file,
        sink: sink.clone(),
        imu_only: a.imu_only,
    })?;
    if let Sink::File(f) = &sink {
        if f.existed {
            say!("(replaced the previous {})", f.path.display());
        }
    }
    Ok(())
}

/// Replay a recording through the learned phone odometry.
///
/// Replay a recording (RIDI sequence, RIDI data.csv, RoNIN CSV export, or a simulator
/// walk `sim:SEED:PLACEMENT`) through the learned odometry and the baselines; print
/// ATE / RTE and write an SVG of the trajectories against the truth.
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct OdometryArgs {
    /// FILE, DIR or sim:SEED:PLACEMENT.
    #[arg(value_parser = odometry_input)]
    pub input: String,
    /// A model file (default: the shipped model).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// The SVG to write.
    #[arg(long, value_name = "FILE", default_value = "odometry.svg")]
    pub out: PathBuf,
}

/// `sim:SEED:PLACEMENT` is checked by clap (exit 2); a path is read later.
fn odometry_input(s: &str) -> Result<String, String> {
    if let Some(spec) = s.strip_prefix("sim:") {
        stridekit_lab::odometry::commands::parse_sim_spec(spec)?;
    }
    Ok(s.to_string())
}

pub fn odometry(a: OdometryArgs) -> Result<(), Failure> {
    if a.out == Path::new("-") {
        return Err(usage("--out", "odometry writes an SVG: give a file name"));
    }
    let out = OutFile::prepare(&a.out, "svg")?;
    if !a.input.starts_with("sim:") {
        stridekit_formats::check_file(Path::new(&a.input))
            .or_else(|e| match e {
                stridekit_formats::FormatError::Folder => Ok(()),
                other => Err(other),
            })
            .map_err(|e| crate::input::read_error(Path::new(&a.input), e, "a recording"))?;
    }
    let text = stridekit_lab::odometry::commands::replay(&a.input, a.model.as_deref(), &out.path)?;
    println!("{text}");
    Ok(())
}
