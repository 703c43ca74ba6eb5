//! Typed errors of the AHRS. A rejected sample leaves the filter's state untouched.

use crate::input::InputError;
use crate::snapshot::SnapshotError;

/// Why a sample, the settings or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AhrsError {
    /// A sample was refused at the door (see [`crate::input`]): not finite, beyond
    /// the IMU limits, not after the previous one, time not in seconds, or
    /// accelerations in g — at (re)initialisation a single sample at rest (gyro below
    /// 0.5 rad/s) with |a| in 0.8..=1.2, later the mean |a| over about one second
    /// below 2.5 (see [`Ahrs`](super::Ahrs)). Multiply by 9.80665 (and on iOS also by
    /// −1: Core Motion reports acceleration, the filter wants specific force,
    /// +9.8 m/s² upwards at rest).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A setting is not usable.
    #[error("invalid AHRS setting {field}: {reason}")]
    InvalidSettings {
        field: &'static str,
        reason: &'static str,
    },
    /// A snapshot could not be restored.
    #[error("cannot restore AHRS snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}
