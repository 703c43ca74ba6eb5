//! Typed errors of the placement classifier. A rejected sample leaves the classifier
//! untouched.

/// Why a sample or a model file was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlacementError {
    /// A sample was refused at the door (see [`crate::input`]).
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The model file is not a placement model of a version this build reads.
    #[error(
        "unsupported placement model: {found:?} (this build reads 'stridekit-placement-lr 1')"
    )]
    ModelVersion { found: String },
    /// The model was trained on a different feature set.
    #[error("model has {found} features, this build computes {expected}")]
    ModelFeatureCount { expected: usize, found: usize },
    /// The model file is corrupt (1-based line number; 0 = the file as a whole).
    #[error("placement model line {line}: {reason}")]
    Model { line: usize, reason: String },
    /// A snapshot could not be restored.
    #[error("cannot restore snapshot: {0}")]
    Snapshot(#[from] crate::snapshot::SnapshotError),
}
