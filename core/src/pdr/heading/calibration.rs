//! Calibration of the carrying by GNSS: over a stretch, the angle between the GNSS and
//! the dead-reckoned displacement feeds a Kalman filter on the azimuth error and,
//! without a magnetometer, on the drift rate of the gyro-integrated yaw (which the
//! stretch's mean error lags by half its length); a wrong forward sign flips once.

use std::f64::consts::PI;

use super::WalkingDirection;
use crate::angle::wrap;

/// Prior σ of the carrying azimuth, rad, and of the yaw drift rate, rad/s.
const CAL_OFFSET_SIGMA0_RAD: f64 = 0.5;
const CAL_RATE_SIGMA0_RADS: f64 = 0.02;
/// Random walks of the azimuth error, rad²/s, and of the drift rate, rad²/s³.
const CAL_OFFSET_Q: f64 = 1e-4;
const CAL_RATE_Q: f64 = 1e-11;

/// Covariance of the calibration filter's two error states.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CalibrationFilter {
    /// Variance of the azimuth error, rad².
    pub(super) offset_var: f64,
    /// Covariance of the azimuth and drift-rate errors, rad²/s.
    pub(super) cross_cov: f64,
    /// Variance of the drift-rate error, rad²/s².
    pub(super) rate_var: f64,
}

impl Default for CalibrationFilter {
    fn default() -> Self {
        Self {
            offset_var: CAL_OFFSET_SIGMA0_RAD * CAL_OFFSET_SIGMA0_RAD,
            cross_cov: 0.0,
            rate_var: CAL_RATE_SIGMA0_RADS * CAL_RATE_SIGMA0_RADS,
        }
    }
}

impl CalibrationFilter {
    /// A new carrying: its azimuth is unknown again (the drift rate is not).
    pub(super) fn forget_offset(&mut self) {
        self.offset_var = Self::default().offset_var;
    }

    /// A stretch of `t` s whose mean azimuth error was measured with 1-σ `sigma_rad`:
    /// predict over it (offset += rate · t), update, and give the gains of the offset
    /// and (with `use_rate`) of the drift rate.
    fn update(&mut self, t: f64, sigma_rad: f64, use_rate: bool) -> (f64, f64) {
        let (mut p00, mut p01, mut p11) = (self.offset_var, self.cross_cov, self.rate_var);
        if !use_rate {
            p01 = 0.0;
            p11 = 0.0;
        }
        p00 += 2.0 * t * p01 + t * t * p11 + CAL_OFFSET_Q * t;
        p01 += t * p11;
        if use_rate {
            p11 += CAL_RATE_Q * t;
        }
        // The stretch's mean error = offset − rate · t/2 (both as errors now).
        let h1 = if use_rate { -0.5 * t } else { 0.0 };
        let s = p00 + 2.0 * h1 * p01 + h1 * h1 * p11 + sigma_rad * sigma_rad;
        let k0 = (p00 + h1 * p01) / s;
        let k1 = (p01 + h1 * p11) / s;
        // Update; applying the correction brings the error states back to zero.
        let (ph0, ph1) = (p00 + h1 * p01, p01 + h1 * p11);
        p00 -= k0 * ph0;
        p01 -= k0 * ph1;
        p11 -= k1 * ph1;
        *self = Self {
            offset_var: p00,
            cross_cov: p01,
            rate_var: p11,
        };
        (k0, k1)
    }
}

impl WalkingDirection {
    /// GNSS says the dead-reckoned displacement over a stretch of `window_s` seconds
    /// was `err_rad` anticlockwise of the true one (true azimuth − dead-reckoned
    /// azimuth), with a 1-σ of `sigma_rad`. A wrong forward sign is resolved once; the
    /// filter rotates the carrying and, without a magnetometer, corrects the drift rate.
    pub fn observe_rotation(&mut self, err_rad: f64, window_s: f64, sigma_rad: f64) {
        if !self.carrying.forward_known
            || !err_rad.is_finite()
            || sigma_rad.is_nan()
            || sigma_rad <= 0.0
        {
            return;
        }
        let mut err = wrap(err_rad);
        if !self.carrying.calibrated && err.abs() > 0.5 * PI {
            self.carrying.rotate(PI);
            err = wrap(err - PI);
        }
        self.carrying.calibrated = true;
        let t = if window_s.is_finite() {
            window_s.max(0.0)
        } else {
            0.0
        };
        let use_rate = !self.yaw.mag_seen;
        let (k0, k1) = self.calibration.update(t, sigma_rad, use_rate);
        self.carrying.rotate(k0 * err);
        if use_rate {
            // True azimuth = AHRS azimuth − μ: a growing error wants μ to grow slower.
            self.yaw.mu_rate_rads -= k1 * err;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stretch_shrinks_the_variances_and_without_the_rate_drops_it() {
        let mut f = CalibrationFilter::default();
        let before = f;
        let (k0, k1) = f.update(20.0, 0.1, true);
        assert!(k0 > 0.5 && k1 != 0.0, "{k0} {k1}");
        assert!(f.offset_var < before.offset_var && f.rate_var < before.rate_var);
        let (_, k1) = f.update(20.0, 0.1, false);
        assert_eq!(k1, 0.0);
        assert_eq!((f.cross_cov, f.rate_var), (0.0, 0.0));
        f.forget_offset();
        assert_eq!(f.offset_var, before.offset_var);
    }
}
