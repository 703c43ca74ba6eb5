//! Typed errors of the AHRS. A rejected sample leaves the filter's state untouched.

use crate::snapshot::SnapshotError;

/// Why a sample, the settings or a snapshot was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AhrsError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A sample is not later than the previous accepted one (timestamps going
    /// backwards or duplicated).
    #[error("IMU sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The accelerometer looks like it reports in units of g, not m/s².
    ///
    /// `magnitude` is the |a| that gave it away: at (re)initialisation a single sample
    /// at rest (gyro below 0.5 rad/s) with |a| in 0.8..=1.2; later the mean |a| over
    /// about one second below 2.5. See [`Ahrs`](super::Ahrs) for the heuristic.
    /// Multiply by 9.80665 (and on iOS also by −1: Core Motion reports acceleration,
    /// the filter wants specific force, +9.8 m/s² upwards at rest).
    #[error(
        "acceleration magnitude {magnitude} looks like units of g: accelerations must be m/s² \
         (multiply by 9.80665)"
    )]
    AccelerationNotInMps2 { magnitude: f64 },
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

pub(crate) fn finite3(field: &'static str, v: &[f64; 3]) -> Result<(), AhrsError> {
    if v[0].is_finite() && v[1].is_finite() && v[2].is_finite() {
        Ok(())
    } else {
        Err(AhrsError::NonFinite { field })
    }
}
