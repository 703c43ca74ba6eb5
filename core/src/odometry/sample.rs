//! The sample going in, and the checks at the door shared by every engine of the
//! module (learned pipeline and baselines).

use super::error::OdometryError;
use crate::input::{self, TimeGuard};

/// One phone IMU sample, body (sensor) frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OdometrySample {
    /// Seconds on the app's monotonic clock, strictly increasing.
    pub t_s: f64,
    /// Specific force, gravity included (+9.81 m/s² upwards at rest), m/s².
    pub accel_mps2: [f64; 3],
    /// Angular rate, rad/s.
    pub gyro_rads: [f64; 3],
    /// Magnetic field, µT; `None` for an IMU-only sample (the heading is then
    /// relative to the initial one).
    pub mag_ut: Option<[f64; 3]>,
}

/// The door of the module's engines: finite values within the limits of
/// [`crate::input`] and a time the stream's guard accepts (the g-units check is the
/// AHRS's, applied when the sample reaches it).
pub(crate) fn check(s: &OdometrySample, time: &TimeGuard) -> Result<(), OdometryError> {
    time.check(s.t_s)?;
    input::accel(&s.accel_mps2)?;
    input::gyro(&s.gyro_rads)?;
    if let Some(m) = &s.mag_ut {
        input::mag(m)?;
    }
    Ok(())
}
