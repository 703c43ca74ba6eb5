//! Rest detection: the device lies still.
//!
//! At rest the gyroscope reads its bias plus noise and the accelerometer reads
//! gravity plus noise: both stay close to their recent means. So the device is at
//! rest when, sample after sample for `rest_time_s`, the gyroscope deviates from its
//! 0.5 s mean by less than `rest_gyro_rads`, the accelerometer from its mean by less
//! than `rest_accel_mps2`, and the mean rate itself is small enough to be a bias
//! (`max_bias_rads` per axis: a steady turn faster than that is motion, not bias).
//! Deviations from the mean, not from zero, so an unknown bias does not hide rest.
//!
//! Vibration (a device on a vibrating table, in a running car, next to a motor) fails
//! those sample thresholds while the device does not turn, and its bias is still its
//! mean rate. So while the accelerometer carries vibration (its deviation from a 0.1 s
//! mean above [`VIBRATION_MPS2`] RMS), the same test on short means (two 0.1 s stages:
//! vibration above ~10 Hz averages out of them, body motion below a few Hz does not), with
//! thresholds a tenth as wide, also counts as still. Without vibration only the sample
//! test counts: a hand-held device moving slowly passes the mean test and must not
//! teach the bias.

use crate::ahrs::quat::min;

/// Time constant of the means the deviations are taken from, s.
pub const REST_MEAN_TIME_CONSTANT_S: f64 = 0.5;
/// Time constant of each of the two first-order stages of the short means, s (a 10 Hz
/// vibration passes at 1/40 of its amplitude, 50 Hz at 1/1000).
pub const REST_SHORT_TIME_CONSTANT_S: f64 = 0.1;
/// Share of the sample thresholds the short means are held to (noise no longer counts
/// in them).
pub const SHORT_SHARE: f64 = 0.1;
/// The accelerometer carries vibration above this RMS deviation from its short mean,
/// m/s² (ten times a phone accelerometer's noise).
pub const VIBRATION_MPS2: f64 = 0.2;

/// Rest detector state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Rest {
    /// Means of the raw gyroscope (rad/s) and accelerometer (m/s²), body frame.
    pub(crate) gyro_mean: [f64; 3],
    pub(crate) accel_mean: [f64; 3],
    /// Their short means (two stages each: `_short` feeds `_short2`), and the mean
    /// square of the accelerometer's deviation from its first stage, (m/s²)².
    pub(crate) gyro_short: [f64; 3],
    pub(crate) accel_short: [f64; 3],
    pub(crate) gyro_short2: [f64; 3],
    pub(crate) accel_short2: [f64; 3],
    pub(crate) vibration2: f64,
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
        self.gyro_short = *gyro;
        self.accel_short = *accel;
        self.gyro_short2 = *gyro;
        self.accel_short2 = *accel;
        self.vibration2 = 0.0;
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
        let ks = super::magnetic::gain(dt, 1.0 / REST_SHORT_TIME_CONSTANT_S);
        let (mut dg2, mut da2, mut sg2, mut sa2, mut hf2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut slow = true;
        for i in 0..3 {
            self.gyro_mean[i] += k * (gyro[i] - self.gyro_mean[i]);
            self.accel_mean[i] += k * (accel[i] - self.accel_mean[i]);
            self.gyro_short[i] += ks * (gyro[i] - self.gyro_short[i]);
            self.accel_short[i] += ks * (accel[i] - self.accel_short[i]);
            self.gyro_short2[i] += ks * (self.gyro_short[i] - self.gyro_short2[i]);
            self.accel_short2[i] += ks * (self.accel_short[i] - self.accel_short2[i]);
            let dg = gyro[i] - self.gyro_mean[i];
            let da = accel[i] - self.accel_mean[i];
            let sg = self.gyro_short2[i] - self.gyro_mean[i];
            let sa = self.accel_short2[i] - self.accel_mean[i];
            let hf = accel[i] - self.accel_short[i];
            dg2 += dg * dg;
            da2 += da * da;
            sg2 += sg * sg;
            sa2 += sa * sa;
            hf2 += hf * hf;
            slow &= self.gyro_mean[i].abs() <= lim.max_bias;
        }
        self.vibration2 += k * (hf2 - self.vibration2);
        let quiet = (dg2 < lim.gyro2) & (da2 < lim.accel2);
        let f2 = SHORT_SHARE * SHORT_SHARE;
        let smooth = (self.vibration2 > VIBRATION_MPS2 * VIBRATION_MPS2)
            & (sg2 < f2 * lim.gyro2)
            & (sa2 < f2 * lim.accel2);
        let still = slow & (quiet | smooth);
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
            let a = 9.81 + 2.0 * (std::f64::consts::TAU * i as f64 * 0.01).sin();
            assert!(!r2.step(&bias, &[0.0, 0.0, a], 0.01, &lim));
        }
        // A vibrating table is rest: 5 m/s² at 50 Hz, sampled at 1 kHz.
        let mut r3 = r;
        r3.start(&bias, &[0.0, 0.0, 9.81]);
        let rest = (0..3000)
            .filter(|&i| {
                let a = 9.81 + 5.0 * (std::f64::consts::TAU * 50.0 * i as f64 * 0.001 + 0.3).sin();
                r3.step(&bias, &[0.0, 0.0, a], 0.001, &lim)
            })
            .count();
        assert!(rest > 1000, "{rest}");
    }
}
