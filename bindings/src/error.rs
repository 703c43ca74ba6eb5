//! The one error type of the pace engine at the FFI: Kotlin `PaceException`
//! (a sealed class, one subclass per variant), Swift `PaceError`.
//!
//! Variants carry typed fields (Kotlin's `message` lists them); `toString()` in
//! Kotlin and `description` in Swift give the human sentence (Rust `Display`).
//! No field is called `message` or `cause`: those clash with `Throwable`.

use stridekit_core::pace as core;
use stridekit_core::pace::Stream;

/// The input stream a rejected sample belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum SensorStream {
    Gnss,
    Steps,
    Accelerometer,
}

impl std::fmt::Display for SensorStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SensorStream::Gnss => "GNSS",
            SensorStream::Steps => "step",
            SensorStream::Accelerometer => "accelerometer",
        })
    }
}

impl From<Stream> for SensorStream {
    fn from(s: Stream) -> Self {
        match s {
            Stream::Gnss => Self::Gnss,
            Stream::Steps => Self::Steps,
            Stream::Accelerometer => Self::Accelerometer,
        }
    }
}

/// Why a sample, a configuration, a snapshot or a buffer was rejected. A rejected
/// sample leaves the tracker exactly as it was.
#[derive(Clone, Debug, PartialEq, thiserror::Error, uniffi::Error)]
#[uniffi::export(Display)]
pub enum PaceError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: String },
    /// A field is outside its physical range (latitude beyond ±90°, negative accuracy, ...).
    #[error("{field} = {value} is out of range ({expected})")]
    OutOfRange {
        field: String,
        value: f64,
        expected: String,
    },
    /// A sample is not later than the previous sample of the same stream.
    #[error("{stream} sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing {
        stream: SensorStream,
        t_s: f64,
        last_t_s: f64,
    },
    /// Accelerometer samples look like g, not m/s² (multiply by 9.80665).
    #[error("acceleration magnitude averages {mean_magnitude:.2}: the samples look like g, expected m/s²")]
    AccelerationNotInMps2 { mean_magnitude: f64 },
    /// The configuration is not usable.
    #[error("invalid configuration: {reason}")]
    InvalidConfig { reason: String },
    /// Snapshot bytes could not be restored (corrupted, truncated, other engine or version).
    #[error("cannot restore snapshot: {reason}")]
    InvalidSnapshot { reason: String },
    /// A packed sample buffer has a length that is not a whole number of records.
    #[error("invalid packed buffer: {reason}")]
    InvalidBuffer { reason: String },
    /// A bug inside stridekit (a caught panic). The tracker stays usable.
    #[error("internal error in stridekit: {reason}")]
    Internal { reason: String },
}

impl From<core::PaceError> for PaceError {
    fn from(e: core::PaceError) -> Self {
        match e {
            core::PaceError::NonFinite { field } => Self::NonFinite {
                field: field.to_string(),
            },
            core::PaceError::OutOfRange {
                field,
                value,
                expected,
            } => Self::OutOfRange {
                field: field.to_string(),
                value,
                expected: expected.to_string(),
            },
            core::PaceError::TimeNotIncreasing {
                stream,
                t_s,
                last_t_s,
            } => Self::TimeNotIncreasing {
                stream: stream.into(),
                t_s,
                last_t_s,
            },
            core::PaceError::AccelerationNotInMps2 { mean_magnitude } => {
                Self::AccelerationNotInMps2 { mean_magnitude }
            }
            core::PaceError::InvalidConfig { reason } => Self::InvalidConfig { reason },
            core::PaceError::Snapshot(s) => Self::InvalidSnapshot {
                reason: s.to_string(),
            },
        }
    }
}

/// The message of a caught panic payload (logged: a panic at the boundary is a bug).
pub(crate) fn panic_reason(payload: Box<dyn std::any::Any + Send>) -> String {
    let reason = if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-string payload".to_string()
    };
    log::error!("stridekit: caught a panic at the FFI boundary: {reason}");
    reason
}

/// Run `f`; a panic becomes the error `internal(reason)` of the caller's error type.
pub(crate) fn guard_with<T, E>(
    f: impl FnOnce() -> Result<T, E>,
    internal: impl FnOnce(String) -> E,
) -> Result<T, E> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f))
        .unwrap_or_else(|p| Err(internal(panic_reason(p))))
}

impl PaceError {
    /// The error for a caught panic payload.
    pub(crate) fn from_panic(payload: Box<dyn std::any::Any + Send>) -> Self {
        Self::Internal {
            reason: panic_reason(payload),
        }
    }
}

/// Run `f`, turning a panic into [`PaceError::Internal`].
pub(crate) fn guard<T>(f: impl FnOnce() -> Result<T, PaceError>) -> Result<T, PaceError> {
    guard_with(f, |reason| PaceError::Internal { reason })
}

/// Lock an engine's mutex. A panic caught while it was held (reported as an
/// `Internal` error) poisons it; the engine's state is still consistent (every push
/// checks its input before changing anything), so the poison is cleared and the
/// object stays usable.
pub(crate) fn lock<T>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| {
        m.clear_poison();
        std::sync::PoisonError::into_inner(p)
    })
}
