//! The foot navigator's configuration for a recording: the flags of `stridekit foot`
//! ([`FootOptions`]) and what the data say about the device ([`Evidence`]) give the
//! axes, the IMU profile, the gyroscope range and the accelerometer alignment, and a
//! text that says every device assumption made (printed by the replay).

use std::path::{Path, PathBuf};

use stridekit_core::foot::{FootConfig, GyroCeiling, ACCEL_LEVEL_SHARE, AT_RANGE, MIN_CLIP_HITS};
use stridekit_formats::FootFormat;

use crate::foot::device::Evidence;

/// The IMU profile: [`FootConfig::default`] for consumer MEMS (gyro bias from the
/// start rest), [`FootConfig::calibrated_imu`] for a factory-calibrated IMU (the UofT
/// MicroStrain).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FootImu {
    Consumer,
    Calibrated,
}

impl FootImu {
    fn name(self) -> &'static str {
        match self {
            Self::Consumer => "consumer",
            Self::Calibrated => "calibrated",
        }
    }

    fn config(self) -> FootConfig {
        match self {
            Self::Consumer => FootConfig::default(),
            Self::Calibrated => FootConfig::calibrated_imu(),
        }
    }
}

/// The device flags of `stridekit foot` and `calibrate foot`.
#[derive(Clone, Debug, Default)]
pub struct FootOptions {
    /// Sensor axes spec ([`FootConfig::axes_from_spec`]); default: the layout's.
    pub axes: Option<String>,
    /// The IMU profile; default: from the data.
    pub imu: Option<FootImu>,
    /// A device calibration file written by `stridekit calibrate foot`.
    pub calibration: Option<PathBuf>,
    /// Turn off the level-floor constraint.
    pub no_level_floor: bool,
    /// The gyroscope's range, rad/s; default: the ceiling the data show.
    pub gyro_range_rads: Option<f64>,
    /// The accelerometer's range, m/s²; default: the ceiling the data show.
    pub accel_range_mps2: Option<f64>,
    /// Drive the zero-velocity updates with this stance label column.
    pub labels: Option<String>,
}

impl FootOptions {
    /// The stance label column of `labels` without its `zv_` prefix (`zv_NAME` and
    /// `NAME` name the same column).
    pub fn label_column(&self) -> Option<&str> {
        self.labels
            .as_deref()
            .map(|l| l.strip_prefix("zv_").unwrap_or(l))
    }
}

/// The navigator configuration for a recording of `format` under `o`, given what the
/// data say about the device, and the device assumptions made, for the output.
///
/// Nothing about the device is taken from the file's layout alone, which any IMU's
/// export can have:
/// - axes: `--axes`, else the layout's usual axes (pyshoe: `frd`, x-io: `flu`);
/// - units: the ones the header names (the navigator refuses g and deg/s in SI columns);
/// - IMU profile: `--imu`, else `calibrated` only for a trial of the UofT VICON set (its
///   factory-calibrated MicroStrain, known by the set's label columns), `consumer` (the
///   SDK default, gyro bias measured at the start rest) for everything else;
/// - gyroscope range: `--gyro-range`, else the ceiling the data show (flat tops at a
///   constant rate, [`stridekit_core::foot::GyroCeilingDetector`]); without that
///   evidence, no range and nothing "repaired";
/// - accelerometer range: `--accel-range`, else none: the navigator finds a ceiling it
///   meets while streaming; the pre-scan of the data (the navigator's own rule over every
///   sample, [`stridekit_core::foot::AccelCeilingDetector`]) is reported, not configured
///   (configured from the first sample it made clipped copies worse on balance).
pub fn config_for(
    o: &FootOptions,
    format: FootFormat,
    device: &Evidence,
) -> Result<(FootConfig, String), String> {
    let default_axes = match format {
        FootFormat::Pyshoe => "frd",
        FootFormat::Xio => "flu",
    };
    let spec = o.axes.as_deref().unwrap_or(default_axes);
    let axis_remap = FootConfig::axes_from_spec(spec).map_err(|e| format!("--axes {spec}: {e}"))?;
    let (imu, imu_why) = imu_profile(o.imu, device);
    let units = match format {
        FootFormat::Pyshoe => "m/s² and rad/s, as the header names them",
        FootFormat::Xio => "g and deg/s in the file, converted to m/s² and rad/s",
    };
    let mut text = format!(
        "{}; device assumptions:\n  axes {spec} ({}); units {units}\n  IMU profile {} ({imu_why})",
        format.name(),
        if o.axes.is_some() {
            "given"
        } else {
            "default for this layout"
        },
        imu.name(),
    );
    let mut config = FootConfig {
        axis_remap,
        ..imu.config()
    };
    let (range, gyro_text) = gyro_range(o.gyro_range_rads, device);
    config.gyro_range_rads = range;
    text += &format!("\n  gyroscope: {gyro_text}");
    let accel_text = accel_range_text(o.accel_range_mps2, device);
    config.accel_range_mps2 = o.accel_range_mps2;
    text += &format!("\n  accelerometer: {accel_text}");
    if o.no_level_floor {
        config.level_stride_max_grade = None;
        text += "\n  level-floor constraint off";
    }
    if let Some(path) = &o.calibration {
        let a = read_calibration(path)?;
        config.accel_alignment_rad = a;
        text += &format!(
            "\n  accelerometer alignment ({:.2}°, {:.2}°, {:.2}°) from {}",
            a[0].to_degrees(),
            a[1].to_degrees(),
            a[2].to_degrees(),
            path.display()
        );
    }
    Ok((config, text))
}

/// The IMU profile and why: given, else the UofT set's calibrated MicroStrain when the
/// file has the set's label columns, else the consumer default.
fn imu_profile(given: Option<FootImu>, device: &Evidence) -> (FootImu, &'static str) {
    match given {
        Some(imu) => (imu, "given"),
        None if device.uoft_vicon_set => (
            FootImu::Calibrated,
            "the UofT VICON set's factory-calibrated MicroStrain: the file has the set's label columns",
        ),
        None => (
            FootImu::Consumer,
            "the SDK default for an IMU not known by name; --imu calibrated for a factory-calibrated one",
        ),
    }
}

/// The gyroscope range to configure and what it rests on: the range given, else the
/// ceiling the data show, else none (nothing is repaired without evidence). A given
/// range the data contradict gets a warning in the text.
fn gyro_range(given: Option<f64>, device: &Evidence) -> (Option<f64>, String) {
    match (given, device.ceiling) {
        (Some(r), found) => (Some(r), given_range(r, found, device.peak_rads)),
        (None, Some(c)) => (
            Some(c.range_rads()),
            format!(
                "clipping detected: {}; clipped swing peaks repaired above {:.2} rad/s (--gyro-range RAD_S to set the device's range instead)",
                ceiling_seen(&c),
                c.ceiling_rads
            ),
        ),
        (None, None) => (
            None,
            format!(
                "no clipping detected (peak {:.2} rad/s, no flat tops at a constant ceiling): nothing repaired (--gyro-range RAD_S if the device's range is known)",
                device.peak_rads
            ),
        ),
    }
}

/// What the accelerometer range rests on: the range given (questioned when the data
/// clip well below it), else none; what the pre-scan of the data found is said, not
/// configured.
fn accel_range_text(given: Option<f64>, device: &Evidence) -> String {
    let a = &device.accel;
    let g = |x: f64| x / crate::perturb::kinds::G0_MPS2;
    match (given, a.ceiling_mps2()) {
        (Some(r), found) => {
            let mut t = format!("range {r} m/s² ({:.1} g, given)", g(r));
            if let Some(c) = found.filter(|&c| c < 0.995 * AT_RANGE * r) {
                t += &format!(
                    "; warning: the data clip at {c:.2} m/s² — below 99 % of the given range: is --accel-range right?"
                );
            }
            if a.peak_mps2() > r * (1.0 + ACCEL_LEVEL_SHARE) {
                t += &format!(
                    "; warning: the data reach {:.2} m/s², above the given range: is --accel-range right?",
                    a.peak_mps2()
                );
            }
            t
        }
        (None, Some(c)) => format!(
            "the pre-scan of the file finds a ceiling of {c:.2} m/s² ({:.1} g) reached {MIN_CLIP_HITS} times or more with nothing above it; not configured from the first sample (on ±4 g copies of the UofT trials that made the clipping ones worse on balance, docs/lab/2026-12-06-foot-accel-clip.md round 2): the navigator takes it for clipped from its {MIN_CLIP_HITS}th clipped run (--accel-range M_S2 to set the device's range from the first sample)",
            g(c),
        ),
        (None, None) => format!(
            "no clipping detected (peak {:.2} m/s², no ceiling reached {MIN_CLIP_HITS} times): nothing taken for clipped (--accel-range M_S2 if the device's range is known)",
            a.peak_mps2()
        ),
    }
}

/// A given range `r`, questioned when the data clip below it or reach above it.
fn given_range(r: f64, found: Option<GyroCeiling>, peak_rads: f64) -> String {
    let mut t = format!("range {r} rad/s (given; clipped swing peaks repaired)");
    if let Some(c) = found.filter(|c| c.range_rads() < 0.995 * r) {
        t += &format!(
            "; warning: the data show {} — below 99 % of the given range: is --gyro-range right?",
            ceiling_seen(&c)
        );
    }
    if peak_rads > r {
        t += &format!("; warning: the data reach {peak_rads:.2} rad/s, above the given range");
    }
    t
}

/// What the data show of a clipped gyroscope.
fn ceiling_seen(c: &GyroCeiling) -> String {
    format!(
        "{} flat tops at a constant ceiling of {:.2} rad/s on sensor {} (peak {:.2} rad/s)",
        c.flat_tops,
        c.ceiling_rads,
        crate::foot::device::side_name(c),
        c.peak_rads
    )
}

/// The alignment of a foot calibration file (`stridekit calibrate foot`).
pub fn read_calibration(path: &Path) -> Result<[f64; 3], String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    crate::foot::alignment::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_axes_are_refused() {
        let o = FootOptions {
            axes: Some("x,y,-z".into()),
            ..Default::default()
        };
        let e = config_for(&o, FootFormat::Xio, &Evidence::default()).unwrap_err();
        assert!(e.contains("mirror"), "{e}");
    }
}
