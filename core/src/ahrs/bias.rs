//! Gyroscope bias estimation at rest (the idea of Fusion's `FusionOffset`).
//!
//! A MEMS gyroscope reads a small non-zero rate when still (bias, typically
//! 0.1–1 °/s on phones, drifting with temperature). Integrated, a 0.02 rad/s bias
//! turns the heading by 1.2 rad per minute; the accelerometer corrects roll and pitch
//! but nothing corrects heading without a magnetometer. While the device is still,
//! the bias-corrected rate is pure bias error, so the estimate follows it through a
//! first-order low-pass filter (cut-off 0.02 Hz, time constant 8 s). "Still" means
//! every bias-corrected axis below 3 °/s and |a| within 1 m/s² of gravity without
//! interruption for 5 s: slow deliberate rotations then do not teach a false bias.

use std::f64::consts::PI;

use super::quat::min;

/// An axis faster than this is moving, rad/s (3 °/s).
pub const STILL_RATE_RADS: f64 = 3.0 * PI / 180.0;
/// |a| further than this from gravity is moving, m/s².
pub const STILL_ACCEL_MPS2: f64 = 1.0;
/// Stillness needed before learning starts, s.
pub const STILL_TIMEOUT_S: f64 = 5.0;
/// Cut-off frequency of the bias low-pass filter, Hz.
pub const BIAS_CUTOFF_HZ: f64 = 0.02;

/// Gyroscope bias estimator state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct GyroBias {
    /// Current bias estimate, rad/s, body frame.
    pub(crate) bias_rads: [f64; 3],
    /// Time the device has been still, s (capped at the timeout).
    pub(crate) still_s: f64,
}

impl GyroBias {
    /// Feed one bias-corrected rate; returns whether the estimate learned from it.
    /// Branch-free: stillness flips with the data, and a mispredicted branch costs
    /// more than the arithmetic.
    #[inline]
    pub(crate) fn update(
        &mut self,
        corrected_rads: &[f64; 3],
        dt_s: f64,
        accel_still: bool,
    ) -> bool {
        let still = accel_still
            & (corrected_rads[0].abs() <= STILL_RATE_RADS)
            & (corrected_rads[1].abs() <= STILL_RATE_RADS)
            & (corrected_rads[2].abs() <= STILL_RATE_RADS);
        let learning = still & (self.still_s >= STILL_TIMEOUT_S);
        // The stillness timer counts up to the timeout and restarts on any motion.
        self.still_s = if still {
            min(self.still_s + dt_s, STILL_TIMEOUT_S)
        } else {
            0.0
        };
        let k = if learning {
            min(2.0 * PI * BIAS_CUTOFF_HZ * dt_s, 1.0)
        } else {
            0.0
        };
        for (b, c) in self.bias_rads.iter_mut().zip(corrected_rads) {
            *b += k * c;
        }
        learning
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn learns_a_constant_bias_after_the_timeout() {
        let mut g = GyroBias::default();
        let truth = [0.02, -0.01, 0.005];
        let dt = 0.01;
        let mut learned_at = None;
        for i in 0..6000 {
            let c = [
                truth[0] - g.bias_rads[0],
                truth[1] - g.bias_rads[1],
                truth[2] - g.bias_rads[2],
            ];
            if g.update(&c, dt, true) && learned_at.is_none() {
                learned_at = Some(i);
            }
        }
        // Starts after 5 s of stillness.
        assert!((499..=502).contains(&learned_at.unwrap()), "{learned_at:?}");
        for (b, t) in g.bias_rads.iter().zip(truth) {
            assert!((b - t).abs() < 1e-4);
        }
        // Motion resets the stillness timer.
        assert!(!g.update(&[0.2, 0.0, 0.0], dt, true));
        assert_eq!(g.still_s, 0.0);
    }
}
