//! Errors of the foot navigator at the FFI.

use crate::error::{range_text, TimeUnit};
use std::panic::{catch_unwind, AssertUnwindSafe};
use stridekit_core::foot as core;
use stridekit_core::input::InputError;

/// Why the foot navigator rejected a sample, its configuration, a detector model, a
/// buffer or a snapshot (Kotlin `FootException`, Swift `FootError`). A rejected sample
/// changes nothing.
#[derive(Clone, Debug, PartialEq, thiserror::Error, uniffi::Error)]
#[uniffi::export(Display)]
pub enum FootError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: String },
    /// A value is outside what any foot-mounted IMU reports (|a| ≤ 2000 m/s², |ω| ≤
    /// 200 rad/s per axis).
    #[error("{field} = {value} is out of range ({reason})")]
    OutOfRange {
        field: String,
        value: f64,
        reason: String,
    },
    /// A sample is not later than the previous accepted one.
    #[error("IMU sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The accelerometer looks like it reports g (|a| ≈ 1 at rest): multiply by 9.80665.
    #[error("acceleration magnitude {magnitude} at rest looks like units of g: accelerations must be m/s² (multiply by 9.80665)")]
    AccelerationNotInMps2 { magnitude: f64 },
    /// Timestamps are not seconds: they look like `likely_unit`.
    #[error("IMU timestamps look like {likely_unit}, not seconds (t = {t_s})")]
    TimeNotInSeconds { t_s: f64, likely_unit: TimeUnit },
    /// The clock jumped forward by more than a year (mixed clocks): start a new navigator.
    #[error("IMU sample at t = {t_s} s jumps from {last_t_s} s: the clock changed")]
    TimeJump { t_s: f64, last_t_s: f64 },
    /// A configuration value is not usable.
    #[error("invalid foot navigator setting {field}: {reason}")]
    InvalidConfig { field: String, reason: String },
    /// A custom zero-velocity SVM model text could not be read.
    #[error("invalid zero-velocity model: {reason}")]
    InvalidModel { reason: String },
    /// Snapshot bytes could not be restored (corrupted, truncated, other engine or version).
    #[error("cannot restore foot navigator snapshot: {reason}")]
    InvalidSnapshot { reason: String },
    /// A packed buffer is not a whole number of 56-byte records.
    #[error("invalid packed buffer: {reason}")]
    InvalidBuffer { reason: String },
    /// A bug inside stridekit (a caught panic). The navigator stays usable.
    #[error("internal error in stridekit: {reason}")]
    Internal { reason: String },
}

impl From<core::FootError> for FootError {
    fn from(e: core::FootError) -> Self {
        match e {
            core::FootError::Input(e) => match e {
                InputError::NonFinite { field } => Self::NonFinite {
                    field: field.into(),
                },
                InputError::OutOfRange {
                    field,
                    value,
                    min,
                    max,
                    unit,
                } => Self::OutOfRange {
                    field: field.into(),
                    value,
                    reason: range_text(min, max, unit),
                },
                InputError::TimeNotIncreasing { t_s, last_t_s, .. } => {
                    Self::TimeNotIncreasing { t_s, last_t_s }
                }
                InputError::TimeUnit { t_s, likely, .. } => Self::TimeNotInSeconds {
                    t_s,
                    likely_unit: likely.into(),
                },
                InputError::TimeJump { t_s, last_t_s, .. } => Self::TimeJump { t_s, last_t_s },
                InputError::AccelerationInG { mean_magnitude } => Self::AccelerationNotInMps2 {
                    magnitude: mean_magnitude,
                },
            },
            core::FootError::InvalidConfig { field, reason } => Self::InvalidConfig {
                field: field.into(),
                reason: reason.into(),
            },
            core::FootError::InvalidModel(reason) => Self::InvalidModel { reason },
            core::FootError::Snapshot(s) => Self::InvalidSnapshot {
                reason: s.to_string(),
            },
        }
    }
}

impl FootError {
    pub(crate) fn from_panic(payload: Box<dyn std::any::Any + Send>) -> Self {
        Self::Internal {
            reason: crate::error::panic_reason(payload),
        }
    }
}

/// Run `f`, turning a panic into [`FootError::Internal`].
pub(crate) fn guard<T>(f: impl FnOnce() -> Result<T, FootError>) -> Result<T, FootError> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| Err(FootError::from_panic(p)))
}
