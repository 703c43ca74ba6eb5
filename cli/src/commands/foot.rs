//! `stridekit foot FILE`: its arguments and its run (the replay:
//! `stridekit_lab::replay::foot`).
//! The CSV goes to `--out FILE` (the SVGs beside it) or, with `--out -`, to stdout
//! (the summary then goes to stderr).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stridekit_core::foot::FootConfig;
use stridekit_lab::replay::foot::{self, svg_paths};
use stridekit_lab::replay::foot_config::{FootImu, FootOptions};

use super::EXIT_CODES;
use crate::input::warn_truncated;
use crate::outcome::Failure;
use crate::output::{say, write_to, Sink};

/// Replay a foot-mounted IMU recording through the foot navigator.
///
/// Replay a foot-mounted IMU recording (pyshoe / UofT CSV, or an x-io NGIMU CSV
/// export) through the foot navigator; write the trajectory CSV (t_s, east_m,
/// north_m, up_m, velocities, yaw, stance, strides, distance: a local level ENU frame
/// from where the walk started, east = where the foot's x axis pointed at the start
/// unless a heading is known) and, next to it, traj.svg (top view) and
/// traj_height.svg (height over time). Prints strides, distance and the loop closure;
/// with truth columns (gt_*), the aligned truth and the position RMSE.
#[derive(Clone, Debug, Default, Args)]
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
    #[arg(long = "gyro-range", value_name = "RAD_S", value_parser = positive_rads)]
    pub gyro_range_rads: Option<f64>,
    /// The accelerometer's range, m/s² (e.g. 39.23 for ±4 g): samples at 99 % of it
    /// are clipped, their velocity not trusted, from the first sample. Default: none
    /// until the navigator meets a ceiling while streaming (the ceiling the whole file
    /// shows is reported, not configured). The output says which.
    #[arg(long = "accel-range", value_name = "M_S2", value_parser = positive_mps2)]
    pub accel_range_mps2: Option<f64>,
}

impl FootArgs {
    /// The device flags, as the replay takes them.
    fn options(&self) -> FootOptions {
        FootOptions {
            axes: self.axes.clone(),
            imu: self.imu.map(FootImu::from),
            calibration: self.calibration.clone(),
            no_level_floor: self.no_level_floor,
            gyro_range_rads: self.gyro_range_rads,
            accel_range_mps2: self.accel_range_mps2,
            labels: self.labels.clone(),
        }
    }
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

/// `--accel-range`: a finite acceleration of at least 1.5 g, in m/s² (checked by clap:
/// exit 2; a range in g is refused with the reason).
fn positive_mps2(s: &str) -> Result<f64, String> {
    let min = stridekit_core::foot::MIN_ACCEL_CEILING_MPS2;
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= min => Ok(v),
        Ok(v) if v.is_finite() && v > 0.0 => Err(format!(
            "{s} m/s² is below 1.5 g ({min:.1} m/s²): gravity and a step exceed it; the range is in m/s² (±4 g = 39.23), not in g"
        )),
        _ => Err(format!("{s} is not an acceleration above 0 m/s²")),
    }
}

/// Which IMU the recording comes from (`--imu`; what each means: [`FootImu`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Imu {
    // FootConfig::default: consumer MEMS, gyro bias from the start rest.
    Consumer,
    // FootConfig::calibrated_imu: factory-calibrated IMU (the UofT MicroStrain).
    Calibrated,
}

impl From<Imu> for FootImu {
    fn from(imu: Imu) -> Self {
        match imu {
            Imu::Consumer => FootImu::Consumer,
            Imu::Calibrated => FootImu::Calibrated,
        }
    }
}

pub fn run(a: FootArgs) -> Result<(), Failure> {
    let sink = Sink::from_arg(&a.out, "csv")?;
    let rec = foot::read(&a.file)?;
    if rec.truncated {
        warn_truncated(&a.file);
    }
    let r = foot::replay(&a.file, rec, &a.options())?;
    say!("{}", r.head());
    r.check_aligned()?;
    write_to(&sink, |w| r.write_csv(w))?;
    let plots = sink.path().map(svg_paths);
    if let Some((top, height)) = &plots {
        r.plot(top, height)?;
    }
    let name = sink.name();
    let written = plots
        .as_ref()
        .map(|(top, height)| (name.as_str(), top.as_path(), height.as_path()));
    say!("{}", r.summary(written));
    if let Some(why) = r.unusable() {
        return Err(Failure::Failed(why));
    }
    if let Some(w) = sink.wrote() {
        say!("{w} (and the SVGs beside it)");
    }
    Ok(())
}
