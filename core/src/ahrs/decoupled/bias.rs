//! Gyroscope bias, estimated at rest and in motion, weighted by how well it is known.
//!
//! A MEMS gyroscope reads a slowly varying offset (bias). Integrated, 0.1°/s turns
//! the orientation by 6° a minute. Two sources tell the bias:
//! - **at rest** ([`super::rest`]) the reading *is* the bias plus white noise: the
//!   estimate follows it through a first-order low-pass (`rest_bias_time_constant_s`)
//!   and becomes accurate to [`REST_BIAS_ACCURACY_RADS`] within seconds;
//! - **in motion** the inclination correction ([`super::tilt`]) is what the residual
//!   bias turned the almost-inertial frame by. A bias error e (body frame) makes the
//!   estimate rotate by R·e·dt extra (R: body → earth); the accelerometer correction
//!   undoes its horizontal part, c ≈ −(R·e·dt)_horizontal. So e ≈ −Rᵀc/dt along the
//!   horizontal earth axes, and integrating b ← b − Rᵀc/τ pulls the bias towards the
//!   truth with time constant τ (`motion_bias_time_constant_s`): the integral term of
//!   a PI loop whose proportional term is the inclination correction itself. The
//!   heading correction does the same about the vertical, with the magnetometer
//!   (`heading_bias_time_constant_s`, off by default: the field is disturbed far more
//!   often than gravity).
//!
//! The corrections in motion also carry what is not bias: linear acceleration that
//! leaks through the average, and the drift that fast hand motion causes in any
//! gyroscope integration (coning with a sensor's finite bandwidth). So motion teaches
//! the bias only as much as it is unknown: the estimate keeps a variance σ² that
//! starts at `max_bias_rads²`, grows with the bias's random walk
//! (`bias_random_walk`), shrinks at rest, and in motion relaxes towards the accuracy
//! motion alone can give (`motion_bias_accuracy_rads`, σ_m). The motion gain is
//! w/τ with w = σ²/(σ² + σ_m²): right after a rest w ≈ 0 (the rest estimate is far
//! better), with no rest for a long time w → 1.
//!
//! The estimate is clipped to ±`max_bias_rads` per axis.

use crate::ahrs::quat::{max, min};

/// How well a rest estimate knows the bias, rad/s (0.01°/s).
pub const REST_BIAS_ACCURACY_RADS: f64 = 0.01 * std::f64::consts::PI / 180.0;

/// Gyroscope bias estimate, rad/s, body frame, and its variance, (rad/s)².
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Bias {
    pub(crate) b: [f64; 3],
    pub(crate) var: f64,
}

impl Bias {
    /// Time passes: the bias may have wandered.
    #[inline(always)]
    pub(crate) fn predict(&mut self, q_dt: f64, max_var: f64) {
        self.var = min(self.var + q_dt, max_var);
    }

    /// At rest: follow the raw reading with gain `k` (= dt / τ, at most 1).
    #[inline(always)]
    pub(crate) fn rest(&mut self, gyro: &[f64; 3], k: f64, limit: f64) {
        for (b, g) in self.b.iter_mut().zip(gyro) {
            *b = clip(*b + k * (g - *b), limit);
        }
        let rest_var = REST_BIAS_ACCURACY_RADS * REST_BIAS_ACCURACY_RADS;
        self.var += k * (rest_var - self.var);
    }

    /// In motion: integrate a correction rotation `c_body` (rad, body frame) with
    /// gain w·`g` (g = 1/τ, w from the variance against `accuracy_var` = σ_m²), and
    /// relax the variance with `g·dt`.
    #[inline(always)]
    pub(crate) fn motion(
        &mut self,
        c_body: &[f64; 3],
        g: f64,
        g_dt: f64,
        accuracy_var: f64,
        limit: f64,
    ) {
        let w = self.var / (self.var + accuracy_var);
        let gw = g * w;
        for (b, c) in self.b.iter_mut().zip(c_body) {
            *b = clip(*b - gw * c, limit);
        }
        self.var -= min(w * g_dt, 1.0) * (self.var - accuracy_var * w);
    }

    /// Heading corrections (about the vertical): plain gain, no variance bookkeeping.
    #[inline(always)]
    pub(crate) fn heading(&mut self, c_body: &[f64; 3], g: f64, limit: f64) {
        for (b, c) in self.b.iter_mut().zip(c_body) {
            *b = clip(*b - g * c, limit);
        }
    }
}

#[inline(always)]
fn clip(v: f64, limit: f64) -> f64 {
    min(max(v, -limit), limit)
}
