//! The sample going in, and the checks at the door shared by every engine of the
//! module (learned pipeline and baselines).

use super::error::OdometryError;

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

impl From<&crate::sim::phone::ImuSample> for OdometrySample {
    fn from(s: &crate::sim::phone::ImuSample) -> Self {
        Self {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
            gyro_rads: s.gyro_radps,
            mag_ut: Some(s.mag_ut),
        }
    }
}

/// Largest accepted |component| of each sensor.
pub const MAX_ACCEL_MPS2: f64 = 2000.0;
pub const MAX_GYRO_RADS: f64 = 200.0;
pub const MAX_MAG_UT: f64 = 5000.0;

fn check3(field: &'static str, v: &[f64; 3], max: f64) -> Result<(), OdometryError> {
    for &x in v {
        if !x.is_finite() {
            return Err(OdometryError::NonFinite { field });
        }
        if x.abs() > max {
            return Err(OdometryError::OutOfRange { field, value: x });
        }
    }
    Ok(())
}

/// Finite values in range and a time after `last_t_s` (the g-units heuristic is
/// the AHRS's, applied when the sample reaches it).
pub(crate) fn check(s: &OdometrySample, last_t_s: Option<f64>) -> Result<(), OdometryError> {
    if !s.t_s.is_finite() {
        return Err(OdometryError::NonFinite { field: "t_s" });
    }
    check3("accel_mps2", &s.accel_mps2, MAX_ACCEL_MPS2)?;
    check3("gyro_rads", &s.gyro_rads, MAX_GYRO_RADS)?;
    if let Some(m) = &s.mag_ut {
        check3("mag_ut", m, MAX_MAG_UT)?;
    }
    if let Some(last) = last_t_s {
        if s.t_s <= last {
            return Err(OdometryError::TimeNotIncreasing {
                t_s: s.t_s,
                last_t_s: last,
            });
        }
    }
    Ok(())
}
