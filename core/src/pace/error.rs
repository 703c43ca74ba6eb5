//! Typed errors of the pace engine. A rejected sample leaves the tracker's state untouched.

use crate::snapshot::SnapshotError;

use crate::input::InputError;
pub use crate::input::Stream;

/// Why a sample, a configuration or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PaceError {
    /// A sample was refused at the door (see [`crate::input`]): not finite, out of
    /// range, not after the previous one of its stream, time not in seconds,
    /// accelerations in g.
    #[error(transparent)]
    Input(#[from] InputError),
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
            D::Input(e) => Self::Input(e),
            D::InvalidConfig { reason } => Self::InvalidConfig { reason },
            D::Snapshot(s) => Self::Snapshot(s),
        }
    }
}
