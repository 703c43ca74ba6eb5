//! Settings of the decoupled filter, with named defaults and the physics behind each.

use std::f64::consts::PI;

use crate::ahrs::error::AhrsError;
use crate::input::limits::MAX_MAG_UT;

const DEG: f64 = PI / 180.0;

/// Averaging time of the accelerometer in the almost-inertial frame (the delay of the
/// second-order low-pass at low frequencies, √2/ω_c), s. Hand-held and body motion
/// has bounded velocity, so its mean acceleration over a window T is Δv/T: about
/// 0.2 m/s² (1°) over 3 s for a hand moving at up to 0.6 m/s, while the gyroscope
/// (bias-corrected) drifts by hundredths of a degree in that time. (The same value
/// as VQF's default τ_acc, which is defined the same way.)
pub const DEFAULT_ACCEL_TIME_CONSTANT_S: f64 = 3.0;
/// Time constant of the heading correction from the magnetometer, s. The horizontal
/// field (≈15–20 µT in Europe) meets magnetometer noise and field inhomogeneity of
/// ≈1 µT, i.e. ≈3–4° per sample; the bias-corrected gyroscope drifts ≈0.01°/s, so
/// averaging the magnetometer over ~10 s costs ~0.1° of drift and removes most noise.
pub const DEFAULT_MAG_TIME_CONSTANT_S: f64 = 10.0;
/// Time constant of the gyroscope bias estimate in motion (from the inclination
/// corrections), s; off (+∞) by default. The corrections carry more than bias: gait
/// accelerations of a phone in a pocket leak through the average, fast hand motion
/// makes any strapdown integration drift. Measured: on BROAD it changes nothing (the
/// rest phases teach the bias: 2.31 / 2.13 / 0.80° with 100 s, 2.30 / 2.12 / 0.80°
/// without), but in `stridekit eval pdr` without a magnetometer the bias estimate
/// wandering with the gait broke the navigator's model of a constant heading drift
/// (median end-point error 3.5 % → 42 %). Set 100 s for a device that is never still
/// and has no magnetometer-free heading model on top.
pub const DEFAULT_MOTION_BIAS_TIME_CONSTANT_S: f64 = f64::INFINITY;
/// Random walk of the gyroscope bias, rad/s per √s (0.003°/s/√s: consumer MEMS
/// gyroscopes wander by ≈0.03°/s in 100 s, more with temperature changes). Sets how
/// fast a bias learned at rest goes stale, and so how much motion may teach it.
pub const DEFAULT_BIAS_RANDOM_WALK: f64 = 0.003 * PI / 180.0;
/// How well the inclination corrections in motion can tell the bias, rad/s (0.05°/s:
/// linear acceleration leaking through the average and the drift of fast hand motion
/// in any strapdown integration are of this order and are not bias).
pub const DEFAULT_MOTION_BIAS_ACCURACY_RADS: f64 = 0.05 * PI / 180.0;
/// Time constant of the gyroscope bias about the vertical from the heading
/// corrections, s (+∞ switches it off). Slower than the motion bias: the
/// magnetometer is disturbed more often than gravity.
pub const DEFAULT_HEADING_BIAS_TIME_CONSTANT_S: f64 = f64::INFINITY;
/// Rest: deviation of the gyroscope from its 0.5 s mean below this, rad/s (2°/s).
pub const DEFAULT_REST_GYRO_RADS: f64 = 2.0 * DEG;
/// Rest: deviation of the accelerometer from its 0.5 s mean below this, m/s².
pub const DEFAULT_REST_ACCEL_MPS2: f64 = 0.5;
/// Rest must last this long before the bias is learned from it, s.
pub const DEFAULT_REST_TIME_S: f64 = 1.5;
/// Time constant of the bias estimate at rest, s: at rest the gyroscope reads its
/// bias plus white noise, so the estimate is a running mean over a few seconds.
pub const DEFAULT_REST_BIAS_TIME_CONSTANT_S: f64 = 2.0;
/// Largest bias estimated, rad/s (2°/s; also the largest mean rate that can be rest).
pub const DEFAULT_MAX_BIAS_RADS: f64 = 2.0 * DEG;
/// Magnetic disturbance: |m| off the learned field magnitude by more than this share.
pub const DEFAULT_MAG_NORM_THRESHOLD: f64 = 0.1;
/// Magnetic disturbance: dip angle off the learned one by more than this, rad (10°).
pub const DEFAULT_MAG_DIP_THRESHOLD_RAD: f64 = 10.0 * DEG;
/// After a disturbance, the field must look undisturbed this long before it corrects
/// the heading again, s.
pub const DEFAULT_MAG_MIN_UNDISTURBED_S: f64 = 0.5;
/// A disturbance lasting longer than this is taken to be the new local field (the
/// user moved): the reference is reset to it and the heading recovers, s.
pub const DEFAULT_MAG_MAX_REJECTION_S: f64 = 60.0;
/// Largest magnetometer offset (hard iron) learned, per body axis, µT; also its prior
/// standard deviation. Uncalibrated phone magnetometers carry offsets of tens to a few
/// hundred µT; 0 switches the online estimate off (for readings the app or the OS has
/// calibrated itself).
pub const DEFAULT_MAG_OFFSET_MAX_UT: f64 = 200.0;

/// Settings of the decoupled filter ([`AhrsAlgorithm::Decoupled`](crate::ahrs::AhrsAlgorithm)).
/// Time constants in seconds; a time constant of `f64::INFINITY` switches that
/// correction off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecoupledSettings {
    /// See [`DEFAULT_ACCEL_TIME_CONSTANT_S`].
    pub accel_time_constant_s: f64,
    /// See [`DEFAULT_MAG_TIME_CONSTANT_S`].
    pub mag_time_constant_s: f64,
    /// See [`DEFAULT_MOTION_BIAS_TIME_CONSTANT_S`].
    pub motion_bias_time_constant_s: f64,
    /// See [`DEFAULT_BIAS_RANDOM_WALK`].
    pub bias_random_walk: f64,
    /// See [`DEFAULT_MOTION_BIAS_ACCURACY_RADS`].
    pub motion_bias_accuracy_rads: f64,
    /// See [`DEFAULT_HEADING_BIAS_TIME_CONSTANT_S`].
    pub heading_bias_time_constant_s: f64,
    /// See [`DEFAULT_REST_GYRO_RADS`].
    pub rest_gyro_rads: f64,
    /// See [`DEFAULT_REST_ACCEL_MPS2`].
    pub rest_accel_mps2: f64,
    /// See [`DEFAULT_REST_TIME_S`].
    pub rest_time_s: f64,
    /// See [`DEFAULT_REST_BIAS_TIME_CONSTANT_S`].
    pub rest_bias_time_constant_s: f64,
    /// See [`DEFAULT_MAX_BIAS_RADS`].
    pub max_bias_rads: f64,
    /// See [`DEFAULT_MAG_NORM_THRESHOLD`] (+∞: never disturbed by magnitude).
    pub mag_norm_threshold: f64,
    /// See [`DEFAULT_MAG_DIP_THRESHOLD_RAD`] (+∞: never disturbed by dip).
    pub mag_dip_threshold_rad: f64,
    /// See [`DEFAULT_MAG_MIN_UNDISTURBED_S`].
    pub mag_min_undisturbed_s: f64,
    /// See [`DEFAULT_MAG_MAX_REJECTION_S`].
    pub mag_max_rejection_s: f64,
    /// See [`DEFAULT_MAG_OFFSET_MAX_UT`] (0: no online offset estimate).
    pub mag_offset_max_ut: f64,
}

impl Default for DecoupledSettings {
    fn default() -> Self {
        Self {
            accel_time_constant_s: DEFAULT_ACCEL_TIME_CONSTANT_S,
            mag_time_constant_s: DEFAULT_MAG_TIME_CONSTANT_S,
            motion_bias_time_constant_s: DEFAULT_MOTION_BIAS_TIME_CONSTANT_S,
            bias_random_walk: DEFAULT_BIAS_RANDOM_WALK,
            motion_bias_accuracy_rads: DEFAULT_MOTION_BIAS_ACCURACY_RADS,
            heading_bias_time_constant_s: DEFAULT_HEADING_BIAS_TIME_CONSTANT_S,
            rest_gyro_rads: DEFAULT_REST_GYRO_RADS,
            rest_accel_mps2: DEFAULT_REST_ACCEL_MPS2,
            rest_time_s: DEFAULT_REST_TIME_S,
            rest_bias_time_constant_s: DEFAULT_REST_BIAS_TIME_CONSTANT_S,
            max_bias_rads: DEFAULT_MAX_BIAS_RADS,
            mag_norm_threshold: DEFAULT_MAG_NORM_THRESHOLD,
            mag_dip_threshold_rad: DEFAULT_MAG_DIP_THRESHOLD_RAD,
            mag_min_undisturbed_s: DEFAULT_MAG_MIN_UNDISTURBED_S,
            mag_max_rejection_s: DEFAULT_MAG_MAX_REJECTION_S,
            mag_offset_max_ut: DEFAULT_MAG_OFFSET_MAX_UT,
        }
    }
}

impl DecoupledSettings {
    /// The values in snapshot order.
    pub(crate) fn to_array(self) -> [f64; 16] {
        // Exhaustive on purpose: a new setting must be added here (and so to the
        // snapshot).
        let Self {
            accel_time_constant_s,
            mag_time_constant_s,
            motion_bias_time_constant_s,
            bias_random_walk,
            motion_bias_accuracy_rads,
            heading_bias_time_constant_s,
            rest_gyro_rads,
            rest_accel_mps2,
            rest_time_s,
            rest_bias_time_constant_s,
            max_bias_rads,
            mag_norm_threshold,
            mag_dip_threshold_rad,
            mag_min_undisturbed_s,
            mag_max_rejection_s,
            mag_offset_max_ut,
        } = self;
        [
            accel_time_constant_s,
            mag_time_constant_s,
            motion_bias_time_constant_s,
            bias_random_walk,
            motion_bias_accuracy_rads,
            heading_bias_time_constant_s,
            rest_gyro_rads,
            rest_accel_mps2,
            rest_time_s,
            rest_bias_time_constant_s,
            max_bias_rads,
            mag_norm_threshold,
            mag_dip_threshold_rad,
            mag_min_undisturbed_s,
            mag_max_rejection_s,
            mag_offset_max_ut,
        ]
    }

    pub(crate) fn from_array(v: [f64; 16]) -> Self {
        Self {
            accel_time_constant_s: v[0],
            mag_time_constant_s: v[1],
            motion_bias_time_constant_s: v[2],
            bias_random_walk: v[3],
            motion_bias_accuracy_rads: v[4],
            heading_bias_time_constant_s: v[5],
            rest_gyro_rads: v[6],
            rest_accel_mps2: v[7],
            rest_time_s: v[8],
            rest_bias_time_constant_s: v[9],
            max_bias_rads: v[10],
            mag_norm_threshold: v[11],
            mag_dip_threshold_rad: v[12],
            mag_min_undisturbed_s: v[13],
            mag_max_rejection_s: v[14],
            mag_offset_max_ut: v[15],
        }
    }

    /// Checks every value (called by `AhrsSettings::validate`).
    pub fn validate(&self) -> Result<(), AhrsError> {
        fn bad(field: &'static str, reason: &'static str) -> AhrsError {
            AhrsError::InvalidSettings { field, reason }
        }
        let finite_in = |v: f64, lo: f64, hi: f64| v.is_finite() && (lo..=hi).contains(&v);
        if !finite_in(self.accel_time_constant_s, 0.01, 100.0) {
            return Err(bad("accel_time_constant_s", "must be in 0.01..=100 s"));
        }
        if !finite_in(self.mag_time_constant_s, 0.01, 1000.0) {
            return Err(bad("mag_time_constant_s", "must be in 0.01..=1000 s"));
        }
        for (field, v) in [
            (
                "motion_bias_time_constant_s",
                self.motion_bias_time_constant_s,
            ),
            (
                "heading_bias_time_constant_s",
                self.heading_bias_time_constant_s,
            ),
        ] {
            // The bias loops must be much slower than the corrections they feed on.
            if v.is_nan() || v < 1.0 {
                return Err(bad(field, "must be at least 1 s (or +∞ to switch it off)"));
            }
        }
        for (field, v) in [
            ("rest_gyro_rads", self.rest_gyro_rads),
            ("rest_accel_mps2", self.rest_accel_mps2),
            ("mag_norm_threshold", self.mag_norm_threshold),
            ("mag_dip_threshold_rad", self.mag_dip_threshold_rad),
        ] {
            if v.is_nan() || v <= 0.0 {
                return Err(bad(field, "must be positive (or +∞ to switch it off)"));
            }
        }
        if !finite_in(self.bias_random_walk, 0.0, 0.1) {
            return Err(bad("bias_random_walk", "must be in 0..=0.1 rad/s/√s"));
        }
        if !finite_in(self.motion_bias_accuracy_rads, 1e-6, 1.0) {
            return Err(bad(
                "motion_bias_accuracy_rads",
                "must be in 1e-6..=1 rad/s",
            ));
        }
        if !finite_in(self.rest_time_s, 0.0, 60.0) {
            return Err(bad("rest_time_s", "must be in 0..=60 s"));
        }
        if !finite_in(self.rest_bias_time_constant_s, 0.01, 1000.0) {
            return Err(bad("rest_bias_time_constant_s", "must be in 0.01..=1000 s"));
        }
        if !finite_in(self.max_bias_rads, 0.0, 1.0) {
            return Err(bad("max_bias_rads", "must be in 0..=1 rad/s"));
        }
        if !finite_in(self.mag_min_undisturbed_s, 0.0, 60.0) {
            return Err(bad("mag_min_undisturbed_s", "must be in 0..=60 s"));
        }
        if !finite_in(self.mag_offset_max_ut, 0.0, MAX_MAG_UT) {
            return Err(bad(
                "mag_offset_max_ut",
                "must be in 0..=5000 µT (the input limit)",
            ));
        }
        if self.mag_max_rejection_s.is_nan() || self.mag_max_rejection_s <= 0.0 {
            return Err(bad(
                "mag_max_rejection_s",
                "must be positive (or +∞ never to give up on the learned field)",
            ));
        }
        Ok(())
    }
}
