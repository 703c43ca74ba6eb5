//! Heading: a rotation about the vertical, corrected by the magnetometer on its own.
//!
//! The orientation is `Rz(δ) ⊗ q_inc ⊗ q_gyr`: the gyroscope and the inclination
//! correction give body → E', and δ turns E' about the vertical into the earth frame.
//! The magnetometer only ever changes δ, so a disturbed field can never tilt the
//! estimate (in Madgwick's filter both corrections share one gradient step).
//!
//! The field rotated into E' should point north; its horizontal azimuth (clockwise
//! from E' north) is the heading offset it measures. δ is a scalar Kalman filter: its
//! variance grows as the gyroscope carries it (a random walk whose density makes the
//! steady-state gain dt/τ, `mag_time_constant_s`) and by whatever rotation a gap may
//! have hidden; a measurement's variance is the magnetometer's (white, density
//! [`MAG_HEADING_NOISE_RAD2_S`]) plus what an unconverged inclination adds through the
//! dip (a tilt error ε turns the measured heading by up to ε·tan(dip)). So right after
//! a start the measurements are averaged (gain 1/(n+1)), in steady state low-passed
//! with τ, after a gap the heading re-converges as fast as the gap was long, and
//! while the inclination is still converging its measurements count for little.

use crate::angle::wrap;

/// Heading measurement noise density of the magnetometer, rad²·s: ≈1 µT of noise and
/// field inhomogeneity on a 15–20 µT horizontal field is ≈3.4° per sample at 100 Hz.
pub const MAG_HEADING_NOISE_RAD2_S: f64 = 0.06 * 0.06 * 0.01;
/// Variance of a heading nothing is known about, rad² (any measurement then takes
/// over in full).
pub const UNKNOWN_VAR_RAD2: f64 = 1e4;

/// Heading state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Heading {
    /// Rotation E' → earth about the vertical, counter-clockwise seen from above, rad.
    pub(crate) delta_rad: f64,
    /// δ has been set from the magnetometer since the (re)start.
    pub(crate) valid: bool,
    /// Variance of δ, rad².
    pub(crate) var_rad2: f64,
}

impl Heading {
    /// Set δ from a measurement; nothing else is known yet.
    pub(crate) fn reset_to(&mut self, measured_rad: f64) {
        self.delta_rad = measured_rad;
        self.valid = true;
        self.var_rad2 = UNKNOWN_VAR_RAD2;
    }

    /// Forget δ's accuracy: the next measurements take over.
    pub(crate) fn forget(&mut self) {
        self.var_rad2 = UNKNOWN_VAR_RAD2;
    }

    /// δ may be off by another `var` rad² (a rotation the gyroscope missed).
    pub(crate) fn widen(&mut self, var: f64) {
        self.var_rad2 = (self.var_rad2 + var).min(UNKNOWN_VAR_RAD2);
    }

    /// One measurement: `innovation` = measured − δ (wrapped), `q` the variance δ
    /// gained since the last one, `r` the measurement's, of which `common` is shared
    /// with the next measurements (what the inclination's error turns them by: it
    /// changes slowly, so averaging more of them does not remove it). The variance
    /// after the update stays at least `common` (and never grows by it, nor beyond
    /// [`UNKNOWN_VAR_RAD2`], what a restored snapshot may hold), so while the
    /// inclination converges the heading follows its measurements instead of
    /// freezing on the first, worst ones. Returns the change of δ and the gain.
    #[inline(always)]
    pub(crate) fn correct(&mut self, innovation: f64, q: f64, r: f64, common: f64) -> (f64, f64) {
        let p = self.var_rad2 + q;
        let k = p / (p + r);
        self.var_rad2 = ((1.0 - k) * p).max(common.min(p)).min(UNKNOWN_VAR_RAD2);
        let d = k * innovation;
        self.delta_rad = wrap(self.delta_rad + d);
        (d, k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn averages_first_then_low_passes_and_reopens_after_a_gap() {
        let mut h = Heading::default();
        h.reset_to(0.1);
        let (dt, tau) = (0.01, 10.0);
        let r = MAG_HEADING_NOISE_RAD2_S / dt;
        let q = MAG_HEADING_NOISE_RAD2_S / (tau * tau) * dt;
        // The first measurements are averaged: 0.1 then 0.3 → 0.2.
        h.correct(0.1 - h.delta_rad, q, r, 0.0);
        h.correct(0.3 - h.delta_rad, q, r, 0.0);
        assert!((h.delta_rad - 0.2).abs() < 1e-3, "{}", h.delta_rad);
        // Steady state: the gain of a first-order low-pass with τ.
        let mut k = 0.0;
        for _ in 0..20_000 {
            k = h.correct(0.2 - h.delta_rad, q, r, 0.0).1;
        }
        assert!((k / (dt / tau) - 1.0).abs() < 0.01, "{k}");
        // A gap that may have hidden 20°: the next measurement counts for much more.
        h.widen(20f64.to_radians().powi(2));
        let k_gap = h.correct(0.0, q, r, 0.0).1;
        assert!(k_gap > 0.5, "{k_gap}");
        // Wraps at ±π.
        h.delta_rad = 3.1;
        h.forget();
        h.correct(0.2, q, r, 0.0);
        assert!((h.delta_rad - (3.3 - TAU)).abs() < 1e-3, "{}", h.delta_rad);
    }
}
