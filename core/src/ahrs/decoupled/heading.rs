//! Heading: a rotation about the vertical, corrected by the magnetometer on its own.
//!
//! The orientation is `Rz(δ) ⊗ q_inc ⊗ q_gyr`: the gyroscope and the inclination
//! correction give body → E', and δ turns E' about the vertical into the earth frame.
//! The magnetometer only ever changes δ, so a disturbed field can never tilt the
//! estimate (in Madgwick's filter both corrections share one gradient step).
//!
//! The field rotated into E' should point north; its horizontal azimuth (clockwise
//! from E' north) is the heading offset it measures, and δ follows it through a
//! first-order low-pass (`mag_time_constant_s`). Right after a (re)start or a
//! recovery, δ is instead the running mean of the measurements (gain 1/(n+1)) until
//! that gain falls below the nominal one: the first seconds converge as fast as the
//! noise allows.

use crate::angle::wrap;

/// Heading state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Heading {
    /// Rotation E' → earth about the vertical, counter-clockwise seen from above, rad.
    pub(crate) delta_rad: f64,
    /// δ has been set from the magnetometer since the (re)start.
    pub(crate) valid: bool,
    /// Measurements averaged since the (re)start or recovery (capped).
    pub(crate) averaged: f64,
}

/// Cap of [`Heading::averaged`] (beyond it 1/(n+1) is below any nominal gain).
const AVERAGED_CAP: f64 = 1e9;

impl Heading {
    /// Set δ from a measurement and restart the averaging.
    pub(crate) fn reset_to(&mut self, measured_rad: f64) {
        self.delta_rad = measured_rad;
        self.valid = true;
        self.averaged = 1.0;
    }

    /// Restart the averaging (the next measurements dominate).
    pub(crate) fn restart_averaging(&mut self) {
        self.averaged = 0.0;
    }

    /// Whether δ is still a running mean rather than the low-pass (gain `k`).
    #[inline(always)]
    pub(crate) fn averaging(&self, k: f64) -> bool {
        self.averaged * k < 1.0 - k
    }

    /// Move δ towards the measurement: `innovation` = measured − δ (wrapped), nominal
    /// gain `k` = dt / τ (at most 1). Returns the change of δ, rad.
    #[inline(always)]
    pub(crate) fn correct(&mut self, innovation: f64, k: f64) -> f64 {
        // The running mean's gain 1/(n+1) while it exceeds k (a division only then).
        let g = if self.averaging(k) {
            1.0 / (self.averaged + 1.0)
        } else {
            k
        };
        self.averaged = if self.averaged < AVERAGED_CAP {
            self.averaged + 1.0
        } else {
            AVERAGED_CAP
        };
        let d = g * innovation;
        self.delta_rad = wrap(self.delta_rad + d);
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn averages_first_then_low_passes() {
        let mut h = Heading::default();
        h.reset_to(0.1);
        let k = 0.01;
        // Running mean of 0.1 and 0.3 → 0.2, then the low-pass gain.
        h.correct(0.3 - h.delta_rad, k);
        assert!((h.delta_rad - 0.2).abs() < 1e-12);
        for _ in 0..200 {
            h.correct(0.2 - h.delta_rad, k);
        }
        assert!(!h.averaging(k));
        let before = h.delta_rad;
        let d = h.correct(1.0, k);
        assert!((d - k).abs() < 1e-15 && (h.delta_rad - before - k).abs() < 1e-15);
        // Wraps at ±π.
        h.delta_rad = 3.1;
        h.correct(0.2 / k, k);
        assert!((h.delta_rad - (3.3 - TAU)).abs() < 1e-12);
    }
}
