//! Typed errors of the pace engine. A rejected sample leaves the tracker's state untouched.

use crate::snapshot::SnapshotError;

/// Which input stream a sample belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    Gnss,
    Steps,
    /// Raw accelerometer samples (steps detected by the tracker).
    Accelerometer,
}

impl std::fmt::Display for Stream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stream::Gnss => "GNSS",
            Stream::Steps => "step",
            Stream::Accelerometer => "accelerometer",
        })
    }
}

/// Why a sample, a configuration or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PaceError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A field is outside its physical range (latitude beyond ±90°, negative accuracy, ...).
    #[error("{field} = {value} is out of range ({expected})")]
    OutOfRange {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// A sample is not later than the previous sample of the same stream
    /// (timestamps going backwards or duplicated).
    #[error("{stream} sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing {
        stream: Stream,
        t_s: f64,
        last_t_s: f64,
    },
    /// Accelerometer samples average about 1 instead of about 9.8: they are in g.
    #[error(
        "acceleration magnitude averages {mean_magnitude:.2}: the samples look like g, \
         expected m/s² (about 9.8 at rest; multiply by 9.80665)"
    )]
    AccelerationNotInMps2 { mean_magnitude: f64 },
    /// The configuration is not usable.
    #[error("invalid configuration: {reason}")]
    InvalidConfig { reason: String },
    /// A snapshot could not be restored.
    #[error("cannot restore snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

impl From<crate::stepdetect::StepDetectError> for PaceError {
    fn from(e: crate::stepdetect::StepDetectError) -> Self {
        use crate::stepdetect::StepDetectError as D;
        match e {
            D::NonFinite { field } => Self::NonFinite { field },
            D::OutOfRange {
                field,
                value,
                expected,
            } => Self::OutOfRange {
                field,
                value,
                expected,
            },
            D::TimeNotIncreasing { t_s, last_t_s } => Self::TimeNotIncreasing {
                stream: Stream::Accelerometer,
                t_s,
                last_t_s,
            },
            D::LooksLikeG { mean_magnitude } => Self::AccelerationNotInMps2 { mean_magnitude },
            D::InvalidConfig { reason } => Self::InvalidConfig { reason },
            D::Snapshot(s) => Self::Snapshot(s),
        }
    }
}

pub(crate) fn finite(field: &'static str, v: f64) -> Result<f64, PaceError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(PaceError::NonFinite { field })
    }
}

pub(crate) fn in_range(
    field: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<f64, PaceError> {
    finite(field, v)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(PaceError::OutOfRange {
            field,
            value: v,
            expected,
        })
    }
}
