//! Typed errors of the placement classifier. A rejected sample leaves the classifier
//! untouched.

/// Why a sample or a model file was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlacementError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A field is outside its physical range.
    #[error("{field} = {value} is out of range ({expected})")]
    OutOfRange {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// The sample is not later than the previous one.
    #[error("sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The acceleration magnitude averages about 1 instead of about 9.8: the samples
    /// are in g, not m/s².
    #[error(
        "acceleration magnitude averages {mean_magnitude:.2}: the samples look like g, \
         expected m/s² (about 9.8 at rest; multiply by 9.80665)"
    )]
    LooksLikeG { mean_magnitude: f64 },
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
    /// Training data cannot produce a model.
    #[error("cannot train: {reason}")]
    Training { reason: String },
}
