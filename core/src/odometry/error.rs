//! Typed errors of the phone odometry. A rejected sample leaves the state untouched.

use crate::ahrs::AhrsError;
use crate::input::InputError;
use crate::snapshot::SnapshotError;

/// Why a sample, the configuration, a model file or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OdometryError {
    /// A sample was refused at the door (see [`crate::input`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A configuration value is not usable.
    #[error("invalid odometry setting {field}: {reason}")]
    InvalidConfig {
        field: &'static str,
        reason: &'static str,
    },
    /// A model file could not be read (line number, 1-based, and why).
    #[error("invalid odometry model (line {line}): {reason}")]
    InvalidModel { line: usize, reason: String },
    /// A model file of another format version (e.g. a version-1 file, which keyed
    /// the regressors by the simulator's placements): retrain it.
    #[error(
        "odometry model file version {found}, this build reads version {supported} \
         (retrain with `stridekit train odometry`)"
    )]
    ModelVersion { found: u32, supported: u32 },
    /// A snapshot could not be restored.
    #[error("cannot restore odometry snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

impl From<AhrsError> for OdometryError {
    fn from(e: AhrsError) -> Self {
        match e {
            AhrsError::Input(e) => OdometryError::Input(e),
            AhrsError::InvalidSettings { field, reason } => {
                OdometryError::InvalidConfig { field, reason }
            }
            AhrsError::Snapshot(s) => OdometryError::Snapshot(s),
        }
    }
}
