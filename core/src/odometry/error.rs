//! Typed errors of the phone odometry. A rejected sample leaves the state untouched.

use crate::ahrs::AhrsError;
use crate::snapshot::SnapshotError;

/// Why a sample, the configuration, a model file or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OdometryError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A value outside what a phone IMU reports (|a| ≤ 2 000 m/s², |ω| ≤ 200 rad/s,
    /// |m| ≤ 5 000 µT per axis).
    #[error("{field} = {value} is out of range")]
    OutOfRange { field: &'static str, value: f64 },
    /// A sample is not later than the previous accepted one.
    #[error("IMU sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The accelerometer looks like it reports in g (the AHRS heuristic).
    #[error(
        "acceleration magnitude {magnitude} looks like units of g: accelerations must be m/s² \
         (multiply by 9.80665)"
    )]
    AccelerationNotInMps2 { magnitude: f64 },
    /// A configuration value is not usable.
    #[error("invalid odometry setting {field}: {reason}")]
    InvalidConfig {
        field: &'static str,
        reason: &'static str,
    },
    /// A model file could not be read (line number, 1-based, and why).
    #[error("invalid odometry model (line {line}): {reason}")]
    InvalidModel { line: usize, reason: String },
    /// A model file of another format version (e.g. a version-1 file, which keyed
    /// the regressors by the simulator's placements): retrain it.
    #[error(
        "odometry model file version {found}, this build reads version {supported} \
         (retrain with `stridekit train odometry`)"
    )]
    ModelVersion { found: u32, supported: u32 },
    /// A snapshot could not be restored.
    #[error("cannot restore odometry snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

impl From<AhrsError> for OdometryError {
    fn from(e: AhrsError) -> Self {
        match e {
            AhrsError::NonFinite { field } => OdometryError::NonFinite { field },
            AhrsError::TimeNotIncreasing { t_s, last_t_s } => {
                OdometryError::TimeNotIncreasing { t_s, last_t_s }
            }
            AhrsError::AccelerationNotInMps2 { magnitude } => {
                OdometryError::AccelerationNotInMps2 { magnitude }
            }
            AhrsError::InvalidSettings { field, reason } => {
                OdometryError::InvalidConfig { field, reason }
            }
            AhrsError::Snapshot(s) => OdometryError::Snapshot(s),
        }
    }
}
