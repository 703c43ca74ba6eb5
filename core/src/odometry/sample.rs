//! The sample going in, and the checks at the door shared by every engine of the
//! module (learned pipeline and baselines).

use super::error::OdometryError;
use crate::input::{self, TimeGuard};

/// The module's engines take the one IMU sample type of the SDK (also the AHRS's and
/// the phone navigator's).
pub use crate::ahrs::ImuSample;

/// The door of the module's engines: finite values within the limits of
/// [`crate::input`] and a time the stream's guard accepts (the g-units check is the
/// AHRS's, applied when the sample reaches it).
pub(crate) fn check(s: &ImuSample, time: &TimeGuard) -> Result<(), OdometryError> {
    time.check(s.t_s)?;
    input::accel(&s.accel_mps2)?;
    input::gyro(&s.gyro_rads)?;
    if let Some(m) = &s.mag_ut {
        input::mag(m)?;
    }
    Ok(())
}
