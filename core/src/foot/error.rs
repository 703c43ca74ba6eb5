//! Typed errors of the foot-mounted navigator. A rejected sample leaves the state
//! untouched.

use crate::input::InputError;
use crate::snapshot::SnapshotError;

/// Why a sample, the configuration, a detector model or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FootError {
    /// A sample was refused at the door (see [`crate::input`]): not finite, beyond
    /// the IMU limits, not after the previous one, time not in seconds, or
    /// accelerations in g (the mean |a| over the alignment period below 2.5).
    #[error(transparent)]
    Input(#[from] InputError),
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
