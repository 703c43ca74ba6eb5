//! Typed errors of the step-length estimator. A rejected input leaves the state untouched.

use crate::input::InputError;
use crate::snapshot::SnapshotError;

/// Why a step, a fix, a configuration or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepLengthError {
    /// A step or fix was refused at the door (see [`crate::input`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The configuration is not usable.
    #[error("invalid step-length configuration: {reason}")]
    InvalidConfig { reason: String },
    /// A snapshot could not be restored.
    #[error("cannot restore step-length snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}
