//! Typed errors of the step-length estimator. A rejected input leaves the state untouched.

use crate::snapshot::SnapshotError;

/// Why a step, a fix, a configuration or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepLengthError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A field is outside its physical range.
    #[error("{field} = {value} is out of range ({expected})")]
    OutOfRange {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// A step or fix is not later than the previous one of the same stream.
    #[error("{stream} at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing {
        stream: &'static str,
        t_s: f64,
        last_t_s: f64,
    },
    /// The configuration is not usable.
    #[error("invalid step-length configuration: {reason}")]
    InvalidConfig { reason: String },
    /// A snapshot could not be restored.
    #[error("cannot restore step-length snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

pub(crate) fn finite(field: &'static str, v: f64) -> Result<f64, StepLengthError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(StepLengthError::NonFinite { field })
    }
}

pub(crate) fn in_range(
    field: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<f64, StepLengthError> {
    finite(field, v)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(StepLengthError::OutOfRange {
            field,
            value: v,
            expected,
        })
    }
}
