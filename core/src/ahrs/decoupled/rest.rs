//! Rest detection: the device lies still.
//!
//! At rest the gyroscope reads its bias plus noise and the accelerometer reads
//! gravity plus noise: both stay close to their recent means. So the device is at
//! rest when, sample after sample for `rest_time_s`, the gyroscope deviates from its
//! 0.5 s mean by less than `rest_gyro_rads`, the accelerometer from its mean by less
//! than `rest_accel_mps2`, and the mean rate itself is small enough to be a bias
//! (`max_bias_rads` per axis: a steady turn faster than that is motion, not bias).
//! Deviations from the mean, not from zero, so an unknown bias does not hide rest.

use crate::ahrs::quat::min;

/// Time constant of the means the deviations are taken from, s.
pub const REST_MEAN_TIME_CONSTANT_S: f64 = 0.5;

/// Rest detector state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Rest {
    /// Means of the raw gyroscope (rad/s) and accelerometer (m/s²), body frame.
    pub(crate) gyro_mean: [f64; 3],
    pub(crate) accel_mean: [f64; 3],
    /// Time the rest conditions have held, s (capped at `rest_time_s`).
    pub(crate) still_s: f64,
}

/// Thresholds, squared where compared squared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RestLimits {
    pub(crate) gyro2: f64,
    pub(crate) accel2: f64,
    pub(crate) max_bias: f64,
    pub(crate) time_s: f64,
}

impl Rest {
    pub(crate) fn start(&mut self, gyro: &[f64; 3], accel: &[f64; 3]) {
        self.gyro_mean = *gyro;
        self.accel_mean = *accel;
        self.still_s = 0.0;
    }

    /// Feed one sample; returns whether the device is at rest.
    #[inline(always)]
    pub(crate) fn step(
        &mut self,
        gyro: &[f64; 3],
        accel: &[f64; 3],
        dt: f64,
        lim: &RestLimits,
    ) -> bool {
        let k = super::magnetic::gain(dt, 1.0 / REST_MEAN_TIME_CONSTANT_S);
        let (mut dg2, mut da2) = (0.0, 0.0);
        let mut slow = true;
        for i in 0..3 {
            self.gyro_mean[i] += k * (gyro[i] - self.gyro_mean[i]);
            self.accel_mean[i] += k * (accel[i] - self.accel_mean[i]);
            let dg = gyro[i] - self.gyro_mean[i];
            let da = accel[i] - self.accel_mean[i];
            dg2 += dg * dg;
            da2 += da * da;
            slow &= self.gyro_mean[i].abs() <= lim.max_bias;
        }
        let still = slow & (dg2 < lim.gyro2) & (da2 < lim.accel2);
        self.still_s = if still {
            min(self.still_s + dt, lim.time_s)
        } else {
            0.0
        };
        still & (self.still_s >= lim.time_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_after_the_rest_time_and_not_while_turning() {
        let lim = RestLimits {
            gyro2: 0.035f64.powi(2),
            accel2: 0.25,
            max_bias: 0.035,
            time_s: 1.5,
        };
        let mut r = Rest::default();
        let bias = [0.01, -0.005, 0.002];
        r.start(&bias, &[0.0, 0.0, 9.81]);
        let mut first = None;
        for i in 1..400 {
            if r.step(&bias, &[0.0, 0.0, 9.81], 0.01, &lim) && first.is_none() {
                first = Some(i);
            }
        }
        assert!((149..=152).contains(&first.unwrap()), "{first:?}");
        // A steady turn at 0.1 rad/s is not rest, however smooth.
        for _ in 0..400 {
            assert!(!r.step(&[0.0, 0.0, 0.1], &[0.0, 0.0, 9.81], 0.01, &lim));
        }
        // A shake is not rest.
        let mut r2 = r;
        r2.start(&bias, &[0.0, 0.0, 9.81]);
        for i in 0..400 {
            let a = if i % 2 == 0 { 10.8 } else { 8.8 };
            assert!(!r2.step(&bias, &[0.0, 0.0, a], 0.01, &lim));
        }
    }
}
