//! Typed errors of the foot-mounted navigator. A rejected sample leaves the state
//! untouched.

use crate::snapshot::SnapshotError;

/// Why a sample, the configuration, a detector model or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FootError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A value is outside what any foot-mounted IMU can report (|a| ≤ 2 000 m/s²,
    /// |ω| ≤ 200 rad/s per axis).
    #[error("{field} = {value} is out of range ({reason})")]
    OutOfRange {
        field: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// A sample is not later than the previous accepted one.
    #[error("IMU sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The accelerometer looks like it reports in g: the mean |a| over the alignment
    /// period is below 2.5 (m/s² expected: about 9.8 at rest).
    #[error(
        "acceleration magnitude {magnitude} at rest looks like units of g: accelerations \
         must be m/s² (multiply by 9.80665)"
    )]
    AccelerationNotInMps2 { magnitude: f64 },
    /// A configuration value is not usable.
    #[error("invalid foot navigator setting {field}: {reason}")]
    InvalidConfig {
        field: &'static str,
        reason: &'static str,
    },
    /// A zero-velocity SVM model could not be read.
    #[error("invalid zero-velocity model: {0}")]
    InvalidModel(String),
    /// A snapshot could not be restored.
    #[error("cannot restore foot navigator snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

pub(crate) fn finite3(field: &'static str, v: &[f64; 3]) -> Result<(), FootError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(FootError::NonFinite { field })
    }
}

pub(crate) fn positive(field: &'static str, v: f64) -> Result<(), FootError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(FootError::InvalidConfig {
            field,
            reason: "must be a finite number > 0",
        })
    }
}
