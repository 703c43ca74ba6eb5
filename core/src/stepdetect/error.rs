//! Typed errors of the step detector. A rejected sample leaves the detector untouched.

use crate::snapshot::SnapshotError;

/// Why a sample, a configuration or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepDetectError {
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
    /// The sample is not later than the previous one (timestamps going backwards or
    /// duplicated).
    #[error("sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The acceleration magnitude averages about 1 instead of about 9.8: the samples are
    /// in g, not m/s² (multiply by 9.80665).
    #[error(
        "acceleration magnitude averages {mean_magnitude:.2}: the samples look like g, \
         expected m/s² (about 9.8 at rest; multiply by 9.80665)"
    )]
    LooksLikeG { mean_magnitude: f64 },
    /// The configuration is not usable.
    #[error("invalid configuration: {reason}")]
    InvalidConfig { reason: String },
    /// A snapshot could not be restored.
    #[error("cannot restore snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}
