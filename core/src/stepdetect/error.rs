//! Typed errors of the step detector. A rejected sample leaves the detector untouched.

use crate::input::InputError;
use crate::snapshot::SnapshotError;

/// Why a sample, a configuration or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepDetectError {
    /// A sample was refused at the door (see [`crate::input`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The configuration is not usable.
    #[error("invalid configuration: {reason}")]
    InvalidConfig { reason: String },
    /// A snapshot could not be restored.
    #[error("cannot restore snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}
