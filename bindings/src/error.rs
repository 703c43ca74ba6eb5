//! The one error type of the pace engine at the FFI: Kotlin `PaceException`
//! (a sealed class, one subclass per variant), Swift `PaceError`.
//!
//! Variants carry typed fields (Kotlin's `message` lists them); `toString()` in
//! Kotlin and `description` in Swift give the human sentence (Rust `Display`).
//! No field is called `message` or `cause`: those clash with `Throwable`.

use stridekit_core::input::{InputError, LikelyTimeUnit, Stream};
use stridekit_core::pace as core;

/// The input stream a rejected sample belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum SensorStream {
    Gnss,
    Steps,
    Accelerometer,
    Imu,
    /// Separate gyroscope events (`PhoneNavigator.pushSensorEventsPacked`).
    Gyroscope,
    /// Separate magnetometer events (`PhoneNavigator.pushSensorEventsPacked`).
    Magnetometer,
}

impl std::fmt::Display for SensorStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SensorStream::Gnss => "GNSS",
            SensorStream::Steps => "step",
            SensorStream::Accelerometer => "accelerometer",
            SensorStream::Imu => "IMU",
            SensorStream::Gyroscope => "gyroscope",
            SensorStream::Magnetometer => "magnetometer",
        })
    }
}

impl From<Stream> for SensorStream {
    fn from(s: Stream) -> Self {
        match s {
            Stream::Gnss => Self::Gnss,
            Stream::Steps => Self::Steps,
            Stream::Accelerometer => Self::Accelerometer,
            Stream::Imu => Self::Imu,
            Stream::Gyroscope => Self::Gyroscope,
            Stream::Magnetometer => Self::Magnetometer,
        }
    }
}

/// The unit refused timestamps are most likely in (`t_s` must be seconds).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum TimeUnit {
    Milliseconds,
    Microseconds,
    Nanoseconds,
}

impl std::fmt::Display for TimeUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TimeUnit::Milliseconds => "milliseconds",
            TimeUnit::Microseconds => "microseconds",
            TimeUnit::Nanoseconds => "nanoseconds",
        })
    }
}

impl From<LikelyTimeUnit> for TimeUnit {
    fn from(u: LikelyTimeUnit) -> Self {
        match u {
            LikelyTimeUnit::Milliseconds => Self::Milliseconds,
            LikelyTimeUnit::Microseconds => Self::Microseconds,
            LikelyTimeUnit::Nanoseconds => Self::Nanoseconds,
        }
    }
}

/// The allowed range of an out-of-range field, as text ("−2000 to 2000 m/s²").
pub(crate) fn range_text(min: f64, max: f64, unit: &str) -> String {
    format!("{min} to {max} {unit}").trim_end().to_string()
}

/// Declares an engine's FFI error (one per engine: Kotlin `…Exception`, Swift
/// `…Error`) with, first, the six typed variants of the shared input checks
/// (`stridekit_core::input`: the same names, fields and sentences in every engine, so
/// code that handles a refused sample handles it the same way for all of them), then
/// the engine's own variants, which must include `Internal { reason: String }`. Also
/// writes `From<InputError>`.
macro_rules! engine_error {
    ($(#[$meta:meta])* pub enum $name:ident { $($own:tt)* }) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq, thiserror::Error, uniffi::Error)]
        #[uniffi::export(Display)]
        pub enum $name {
            /// A field is NaN or infinite.
            #[error("{field} is not a finite number")]
            NonFinite { field: String },
            /// A field is outside its physical range (latitude beyond ±90°, negative
            /// accuracy, an acceleration beyond any phone's sensor, ...).
            #[error("{field} = {value} is out of range ({expected})")]
            OutOfRange {
                field: String,
                value: f64,
                expected: String,
            },
            /// A sample is not later than the previous sample of the same stream
            /// (equal times included: see docs/api.md).
            #[error("{stream} sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
            TimeNotIncreasing {
                stream: $crate::error::SensorStream,
                t_s: f64,
                last_t_s: f64,
            },
            /// Accelerometer samples look like g, not m/s² (multiply by 9.80665; on
            /// iOS by −9.80665, see ios/README.md).
            #[error("acceleration magnitude averages {mean_magnitude:.2}: the samples look like g, expected m/s² (multiply by 9.80665)")]
            AccelerationNotInMps2 { mean_magnitude: f64 },
            /// Timestamps are not seconds: they look like `likely_unit` (divide
            /// accordingly).
            #[error("{stream} timestamps look like {likely_unit}, not seconds (t = {t_s})")]
            TimeNotInSeconds {
                stream: $crate::error::SensorStream,
                t_s: f64,
                likely_unit: $crate::error::TimeUnit,
            },
            /// Timestamps advance by less than a microsecond per sample, yet are not
            /// equal: not seconds but a smaller unit (milliseconds divided by 10⁹ as if
            /// nanoseconds give this: multiply such times by 10⁶).
            #[error("{stream} timestamps advance by {interval_s:e} s (t = {t_s}), finer than any sensor samples: not seconds (milliseconds divided by 10⁹ as if nanoseconds give this)")]
            TimeTooFine {
                stream: $crate::error::SensorStream,
                t_s: f64,
                interval_s: f64,
            },
            /// The clock jumped forward by more than a year within one stream (mixed
            /// clocks): start a new engine.
            #[error("{stream} sample at t = {t_s} s jumps from {last_t_s} s: the clock changed")]
            TimeJump {
                stream: $crate::error::SensorStream,
                t_s: f64,
                last_t_s: f64,
            },
            $($own)*
        }

        impl From<stridekit_core::input::InputError> for $name {
            fn from(e: stridekit_core::input::InputError) -> Self {
                use $crate::error::SampleError as S;
                match S::from(e) {
                    S::NonFinite { field } => Self::NonFinite { field },
                    S::OutOfRange { field, value, expected } => Self::OutOfRange { field, value, expected },
                    S::TimeNotIncreasing { stream, t_s, last_t_s } => {
                        Self::TimeNotIncreasing { stream, t_s, last_t_s }
                    }
                    S::AccelerationNotInMps2 { mean_magnitude } => {
                        Self::AccelerationNotInMps2 { mean_magnitude }
                    }
                    S::TimeNotInSeconds { stream, t_s, likely_unit } => {
                        Self::TimeNotInSeconds { stream, t_s, likely_unit }
                    }
                    S::TimeTooFine { stream, t_s, interval_s } => {
                        Self::TimeTooFine { stream, t_s, interval_s }
                    }
                    S::TimeJump { stream, t_s, last_t_s } => Self::TimeJump { stream, t_s, last_t_s },
                    S::Other { reason } => Self::Internal { reason },
                }
            }
        }
    };
}
pub(crate) use engine_error;

engine_error! {
    /// Why a sample, a configuration, a snapshot or a buffer was rejected. A rejected
    /// sample leaves the tracker exactly as it was.
    pub enum PaceError {
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
}

impl From<core::PaceError> for PaceError {
    fn from(e: core::PaceError) -> Self {
        match e {
            core::PaceError::Input(e) => e.into(),
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

/// Why a sample was refused at the door, as every engine's batch reports it
/// ([`crate::phone::navigator::RejectedImuSample::error`]): the typed causes of the
/// shared input checks (`stridekit_core::input`, the same limits in every engine), or
/// the engine's own cause in words.
#[derive(Clone, Debug, PartialEq, uniffi::Enum)]
pub enum SampleError {
    /// A field is NaN or infinite.
    NonFinite { field: String },
    /// A field is outside its physical range.
    OutOfRange {
        field: String,
        value: f64,
        expected: String,
    },
    /// The sample is not later than the previous one of its stream (equal times
    /// included).
    TimeNotIncreasing {
        stream: SensorStream,
        t_s: f64,
        last_t_s: f64,
    },
    /// Accelerations look like g, not m/s² (multiply by 9.80665).
    AccelerationNotInMps2 { mean_magnitude: f64 },
    /// Timestamps are not seconds: they look like `likely_unit`.
    TimeNotInSeconds {
        stream: SensorStream,
        t_s: f64,
        likely_unit: TimeUnit,
    },
    /// Timestamps advance by less than a microsecond per sample: not seconds but a
    /// smaller unit (milliseconds divided by 10⁹ as if nanoseconds).
    TimeTooFine {
        stream: SensorStream,
        t_s: f64,
        interval_s: f64,
    },
    /// The clock jumped forward by more than a year: start a new engine.
    TimeJump {
        stream: SensorStream,
        t_s: f64,
        last_t_s: f64,
    },
    /// Another cause, the engine's own (a malformed record, an attitude that is not a
    /// unit quaternion, ...).
    Other { reason: String },
}

impl From<InputError> for SampleError {
    fn from(e: InputError) -> Self {
        match e {
            InputError::NonFinite { field } => Self::NonFinite {
                field: field.to_string(),
            },
            InputError::OutOfRange {
                field,
                value,
                min,
                max,
                unit,
            } => Self::OutOfRange {
                field: field.to_string(),
                value,
                expected: range_text(min, max, unit),
            },
            InputError::TimeNotIncreasing {
                stream,
                t_s,
                last_t_s,
            } => Self::TimeNotIncreasing {
                stream: stream.into(),
                t_s,
                last_t_s,
            },
            InputError::TimeUnit {
                stream,
                t_s,
                likely,
                ..
            } => Self::TimeNotInSeconds {
                stream: stream.into(),
                t_s,
                likely_unit: likely.into(),
            },
            InputError::TimeTooFine {
                stream,
                t_s,
                interval_s,
            } => Self::TimeTooFine {
                stream: stream.into(),
                t_s,
                interval_s,
            },
            InputError::TimeJump {
                stream,
                t_s,
                last_t_s,
            } => Self::TimeJump {
                stream: stream.into(),
                t_s,
                last_t_s,
            },
            InputError::AccelerationInG { mean_magnitude } => {
                Self::AccelerationNotInMps2 { mean_magnitude }
            }
        }
    }
}

/// A core engine error that may be a refusal of the shared input checks.
pub(crate) trait InputCause: std::fmt::Display {
    fn input(&self) -> Option<&InputError>;

    /// The typed cause of a rejected sample.
    fn sample_error(&self) -> SampleError {
        match self.input() {
            Some(e) => SampleError::from(*e),
            None => SampleError::Other {
                reason: self.to_string(),
            },
        }
    }
}

impl InputCause for stridekit_core::pdr::NavError {
    fn input(&self) -> Option<&InputError> {
        match self {
            Self::Input(e) => Some(e),
            _ => None,
        }
    }
}

impl InputCause for stridekit_core::odometry::OdometryError {
    fn input(&self) -> Option<&InputError> {
        match self {
            Self::Input(e) => Some(e),
            _ => None,
        }
    }
}

impl InputCause for stridekit_core::placement::PlacementError {
    fn input(&self) -> Option<&InputError> {
        match self {
            Self::Input(e) => Some(e),
            _ => None,
        }
    }
}

impl InputCause for stridekit_core::ahrs::AhrsError {
    fn input(&self) -> Option<&InputError> {
        match self {
            Self::Input(e) => Some(e),
            _ => None,
        }
    }
}
