//! Errors of the foot navigator at the FFI.

use std::panic::{catch_unwind, AssertUnwindSafe};
use stridekit_core::foot as core;

crate::error::engine_error! {
    /// Why the foot navigator rejected a sample, its configuration, a detector model,
    /// a buffer or a snapshot (Kotlin `FootException`, Swift `FootError`): the typed
    /// input causes every engine shares, then the navigator's own. A rejected sample
    /// changes nothing.
    pub enum FootError {
        /// A configuration value is not usable.
        #[error("invalid foot navigator setting {field}: {reason}")]
        InvalidConfig { field: String, reason: String },
        /// A custom zero-velocity SVM model text could not be read.
        #[error("invalid zero-velocity model: {reason}")]
        InvalidModel { reason: String },
        /// Snapshot bytes could not be restored (corrupted, truncated, other engine or
        /// version).
        #[error("cannot restore foot navigator snapshot: {reason}")]
        InvalidSnapshot { reason: String },
        /// A packed buffer is not a whole number of 56-byte records.
        #[error("invalid packed buffer: {reason}")]
        InvalidBuffer { reason: String },
        /// A bug inside stridekit (a caught panic). The navigator stays usable.
        #[error("internal error in stridekit: {reason}")]
        Internal { reason: String },
    }
}

impl From<core::FootError> for FootError {
    fn from(e: core::FootError) -> Self {
        match e {
            core::FootError::Input(e) => e.into(),
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
