//! Gyroscope bias, estimated at rest and in motion.
//!
//! A MEMS gyroscope reads a slowly varying offset (bias). Integrated, 0.1°/s turns
//! the orientation by 6° a minute. Two sources tell the bias:
//! - **at rest** ([`super::rest`]) the reading *is* the bias plus white noise: the
//!   estimate follows it through a first-order low-pass (`rest_bias_time_constant_s`);
//! - **in motion** the inclination correction ([`super::tilt`]) is what the residual
//!   bias turned the almost-inertial frame by. A bias error e (body frame) makes the
//!   estimate rotate by R·e·dt extra (R: body → earth); the accelerometer correction
//!   undoes its horizontal part, c ≈ −(R·e·dt)_horizontal. So e ≈ −Rᵀc/dt along the
//!   horizontal earth axes, and integrating b ← b − Rᵀc/τ pulls the bias towards the
//!   truth with time constant τ (`motion_bias_time_constant_s`) — the integral term of
//!   a PI loop whose proportional term is the inclination correction itself. The
//!   heading correction does the same about the vertical, with the magnetometer
//!   (`heading_bias_time_constant_s`, off by default: the field is disturbed far more
//!   often than gravity).
//!
//! The estimate is clipped to ±`max_bias_rads` per axis.

use crate::ahrs::quat::{max, min};

/// Gyroscope bias estimate, rad/s, body frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Bias {
    pub(crate) b: [f64; 3],
}

impl Bias {
    /// At rest: follow the raw reading with gain `k` (= dt / (τ + dt)).
    #[inline(always)]
    pub(crate) fn rest(&mut self, gyro: &[f64; 3], k: f64, limit: f64) {
        for i in 0..3 {
            self.b[i] = clip(self.b[i] + k * (gyro[i] - self.b[i]), limit);
        }
    }

    /// In motion: integrate a correction rotation `c_body` (rad, body frame) with
    /// gain `g` = 1/τ.
    #[inline(always)]
    pub(crate) fn motion(&mut self, c_body: &[f64; 3], g: f64, limit: f64) {
        for i in 0..3 {
            self.b[i] = clip(self.b[i] - g * c_body[i], limit);
        }
    }
}

#[inline(always)]
fn clip(v: f64, limit: f64) -> f64 {
    min(max(v, -limit), limit)
}
