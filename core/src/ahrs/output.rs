//! Samples going into the AHRS and the orientation coming out.

use nalgebra::{Quaternion, UnitQuaternion};

use super::error::AhrsError;
use super::flags::AhrsFlags;
use super::frame::EarthFrame;

/// One IMU sample, the SDK's one type for it: the AHRS
/// ([`Ahrs::push`](super::Ahrs::push)), the phone navigator and the
/// odometry take it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuSample {
    /// Time of the sample, seconds on the app's monotonic clock, strictly increasing.
    pub t_s: f64,
    /// Angular rate, rad/s, sensor frame.
    pub gyro_rads: [f64; 3],
    /// Specific force (reads +9.81 m/s² upwards at rest), m/s², sensor frame.
    pub accel_mps2: [f64; 3],
    /// Magnetic field, µT, sensor frame; `None` for an IMU-only sample.
    pub mag_ut: Option<[f64; 3]>,
}

/// A sample a batch update rejected, with its index in the batch.
pub type AhrsRejection = crate::batch::Rejected<AhrsError>;

/// The orientation after a sample, and what follows from it. All angles in radians,
/// all vectors in the earth frame `frame` unless named `_body`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AhrsOutput {
    /// Time of the sample, s.
    pub t_s: f64,
    /// Earth frame of the earth-frame quantities below.
    pub frame: EarthFrame,
    /// Orientation, body → earth, `[w, x, y, z]`: `v_earth = q ⊗ v_body ⊗ q*`.
    pub quaternion: [f64; 4],
    /// ZYX (yaw–pitch–roll, intrinsic) Euler angles of `quaternion`: roll about body
    /// x in −π..π, pitch about y in −π/2..π/2, yaw about earth z in −π..π.
    /// Yaw is counter-clockwise from East seen from above in ENU, clockwise from
    /// North seen from above in NED.
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    /// Compass heading, clockwise from magnetic north, 0..2π (wraps):
    /// - NED: the azimuth of body +x (aerospace forward), `= yaw`;
    /// - ENU: the azimuth of body +y (the top edge of a phone or watch in the
    ///   Android / iOS device frame, as Android's `getOrientation` azimuth), `= −yaw`.
    ///
    /// Both are tilt-compensated (taken from the ZYX yaw). Without a magnetometer it
    /// is relative to the initial heading, which the filter sets to yaw = 0.
    pub heading_rad: f64,
    /// What a still accelerometer would read given the estimated orientation: `g`
    /// times the up direction in the body frame, m/s².
    pub gravity_body_mps2: [f64; 3],
    /// Acceleration of the device with gravity removed (measured specific force −
    /// `gravity_body_mps2`), body frame, m/s².
    pub linear_accel_body_mps2: [f64; 3],
    /// The same in the earth frame, m/s² (ENU: +z up; NED: +z down).
    pub linear_accel_earth_mps2: [f64; 3],
    /// Estimated gyroscope bias, rad/s, body frame (already subtracted by the filter).
    pub gyro_bias_rads: [f64; 3],
    /// What the filter did with this sample.
    pub flags: AhrsFlags,
}

impl AhrsOutput {
    /// The orientation as an nalgebra unit quaternion (body → earth).
    pub fn unit_quaternion(&self) -> UnitQuaternion<f64> {
        let [w, x, y, z] = self.quaternion;
        UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z))
    }
}
