//! Configuration of the foot navigator. Every field has a documented unit and a
//! default that works for a consumer MEMS IMU on the shoe at 100–1000 Hz.

use super::detect::ZeroVelocityDetector;
use super::error::{positive, FootError};
use super::median::MAX_MEDIAN_WINDOW;
use crate::ahrs::AxisRemap;

/// Which parts of the estimated error state a zero-velocity update feeds back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Correction {
    /// All 15 states: position, velocity, attitude (including yaw), accelerometer
    /// and gyroscope biases (standard error-state feedback).
    #[default]
    Full,
    /// The paper: velocity, pitch and roll only (position, heading and biases are
    /// estimated but not fed back).
    AsPublished,
}

/// What the gyroscope's samples stand for in time (the mechanisation pairs them with
/// the accelerometer's accordingly).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GyroTiming {
    /// Each sample is the rate at its timestamp (consumer MEMS read out as filtered
    /// instantaneous rates): the attitude over `[t_{k−1}, t_k]` integrates the
    /// average of the two samples.
    #[default]
    Instantaneous,
    /// Each sample is the mean rate over the interval that ends at its timestamp
    /// (IMUs that integrate the angle internally at a high rate and output
    /// `ΔΘ/Δt`, such as the MicroStrain 3DM-GX3 of the UofT data set, Xsens or
    /// VectorNav units): the attitude over `[t_{k−1}, t_k]` integrates sample k alone.
    /// Read as instantaneous, such a gyroscope's attitude lags the accelerometer by
    /// half a sample, which during the fast pitch rotations of a swing tips the
    /// specific force (docs/lab/2026-12-06-foot-history.md: the height gained per stride on the UofT trials).
    IntervalMean,
}

/// Largest supported detector window, samples.
pub const MAX_DETECTOR_WINDOW: usize = 31;

/// Default of [`FootConfig::zupt_gate_nis`]: ≈ 10 σ for three degrees of freedom,
/// only gross disagreement is bounded. Chosen on the training split of the UofT
/// VICON trials among 30, 50, 100, 200, 300 (`stridekit eval foot
/// --tune-adaptive-shoe` run with each; docs/lab/2026-12-06-foot-history.md): a flat optimum at 50–200.
pub const ZUPT_GATE_NIS: f64 = 100.0;

#[derive(Clone, Debug, PartialEq)]
pub struct FootConfig {
    /// Sensor → body axes. Body: x forward along the foot, y left, z up when the
    /// foot is flat. The pyshoe / UofT data (x forward, y right, z down) needs
    /// `AxisRemap::new([0, 1, 2], [false, true, true])`.
    pub axis_remap: AxisRemap,
    /// Median pre-filter window, samples, odd, 1..=15 (1 = off).
    pub median_window: usize,
    /// Detector window, s (converted to an odd number of samples, 3..=31, at the
    /// sample rate measured during alignment). Default 0.025 s (5 samples at
    /// 200 Hz), chosen among 0.025 / 0.05 / 0.1 s on the training half of the pyshoe
    /// VICON trials (`stridekit eval foot --tune`, see `docs/lab/2026-12-06-foot-history.md`).
    pub detector_window_s: f64,
    /// Window of the peak ‖f‖ used to classify the gait (about one stride), s.
    pub gait_window_s: f64,
    pub detector: ZeroVelocityDetector,
    /// Rest period at the start used to level the navigator (roll and pitch from
    /// gravity, gyro bias from the mean rate), s.
    pub alignment_s: f64,
    /// Estimate the gyroscope bias as the mean rate over the alignment period.
    pub gyro_bias_from_alignment: bool,
    /// What a gyroscope sample stands for in time (default: instantaneous).
    pub gyro_timing: GyroTiming,
    /// Initial yaw, rad, counter-clockwise from East (0: body +x points East).
    pub initial_yaw_rad: f64,
    pub correction: Correction,
    /// Accelerometer white noise (process noise on velocity), m/s²/√Hz. Larger than
    /// the data sheet on purpose: it also covers vibration and model errors.
    pub accel_noise_density: f64,
    /// Gyroscope white noise (process noise on attitude), rad/s/√Hz.
    pub gyro_noise_density: f64,
    /// Random walk of the accelerometer bias, m/s²/√s.
    pub accel_bias_walk: f64,
    /// Random walk of the gyroscope bias, rad/s/√s.
    pub gyro_bias_walk: f64,
    /// Standard deviation of the zero-velocity pseudo-measurement, m/s.
    pub zupt_noise_mps: f64,
    /// Largest normalised innovation squared (χ² with 3 degrees of freedom) at which a
    /// zero-velocity update is taken at face value. Beyond it the filter's velocity
    /// and its uncertainty say the foot is moving, by far more than the update allows
    /// (a detector calling stance in a swing, or a velocity error the covariance does
    /// not hold): the update's innovation covariance is inflated to meet the bound, so
    /// the update pulls part of the way; repeated over the samples of a true stance it
    /// still brings the velocity to zero. `None`: every update at face value (the
    /// paper). Default [`ZUPT_GATE_NIS`]; at least 1. It holds at 200 Hz; below,
    /// it grows in proportion to the sample interval so that a stance pulls as much
    /// per second at any rate.
    pub zupt_gate_nis: Option<f64>,
    /// Initial 1-σ of the accelerometer and gyroscope biases.
    pub initial_accel_bias_std_mps2: f64,
    pub initial_gyro_bias_std_rads: f64,
    /// Sensor range, m/s² (≥ 1.5 g; e.g. 39.23 for ±4 g); a sample with any axis at
    /// ≥ 99 % of it is flagged saturated and no zero-velocity update uses its window.
    /// `None`: unknown (the navigator finds a ceiling in the data).
    pub accel_range_mps2: Option<f64>,
    /// With a gyroscope range, a run of samples at ≥ 99 % of it on an axis is also
    /// taken as clipped, and the rotation above the ceiling is restored after the run
    /// (a parabolic peak at the slope it had when it reached the ceiling; `clip.rs`):
    /// a foot's pitch rate in the swing can exceed a consumer gyroscope's range.
    pub gyro_range_rads: Option<f64>,
    /// A time step longer than this is a gap: the mechanisation integrates at most
    /// this long and the covariance grows with the real gap, s.
    pub max_gap_s: f64,
    /// Shortest swing that ends a stride at the next stance onset, s.
    pub min_swing_s: f64,
    /// Rotation of the accelerometer's axes onto the gyroscope's (the body frame), as a
    /// rotation vector in the body frame, rad: the specific force used is
    /// `exp([α×]) · f` after [`axis_remap`](Self::axis_remap). A device calibration,
    /// zero by default: consumer IMUs can have their accelerometer and gyroscope
    /// triads misaligned by a degree or more, which tips the swing's forward
    /// acceleration into the vertical (the height climbs at every stride) while the
    /// velocity at the next stance is back to zero, so no zero-velocity update sees
    /// it. Learn it from a level walk with `stridekit calibrate foot` (docs/foot.md).
    /// Each component within ±[`MAX_ACCEL_ALIGNMENT_RAD`].
    pub accel_alignment_rad: [f64; 3],
    /// Level-floor constraint: a stride whose height change is at most this grade
    /// (rise / horizontal stride length) is taken as level, and the height is set
    /// back to the previous stance onset's ([`Stride::levelled_m`](super::Stride)
    /// says by how much). Strides that climb more (stairs, ramps) keep the filter's
    /// height. `None`: off, the height is the filter's alone. Default
    /// [`LEVEL_STRIDE_MAX_GRADE`]; within 0..=[`MAX_LEVEL_STRIDE_GRADE`].
    pub level_stride_max_grade: Option<f64>,
}

/// Default of [`FootConfig::level_stride_max_grade`]: 5 %, the steepest slope that
/// building codes call a walking surface rather than a ramp (1:20; a 7 cm rise on a
/// 1.4 m stride). A stair stride rises 15–40 cm over 0.3–0.7 m (25–60 %). The height a
/// consumer IMU gains per level stride from a degree of accelerometer misalignment is
/// 1–5 cm on a 1.1 m stride, and the filter's stride-to-stride height noise on the
/// UofT runs reaches ±9 % (docs/lab/2026-12-06-foot-history.md, "The level floor").
pub const LEVEL_STRIDE_MAX_GRADE: f64 = 0.05;

/// Largest [`FootConfig::level_stride_max_grade`] accepted (a grade beyond it would
/// flatten shallow stairs).
pub const MAX_LEVEL_STRIDE_GRADE: f64 = 0.2;

/// Largest accelerometer-to-gyroscope alignment component accepted, rad (≈ 5.7°: a
/// misalignment beyond that is a mounting, to be set with the axis remap).
pub const MAX_ACCEL_ALIGNMENT_RAD: f64 = 0.1;

impl Default for FootConfig {
    fn default() -> Self {
        Self {
            axis_remap: AxisRemap::IDENTITY,
            median_window: 1,
            detector_window_s: 0.025,
            gait_window_s: 1.0,
            detector: ZeroVelocityDetector::default(),
            alignment_s: 0.25,
            gyro_bias_from_alignment: true,
            gyro_timing: GyroTiming::Instantaneous,
            initial_yaw_rad: 0.0,
            correction: Correction::Full,
            accel_noise_density: 0.035,
            gyro_noise_density: 6.0e-4,
            accel_bias_walk: 1.0e-4,
            gyro_bias_walk: 1.0e-5,
            zupt_noise_mps: 0.01,
            zupt_gate_nis: Some(ZUPT_GATE_NIS),
            initial_accel_bias_std_mps2: 0.1,
            initial_gyro_bias_std_rads: 0.005,
            accel_range_mps2: None,
            gyro_range_rads: None,
            max_gap_s: 0.1,
            min_swing_s: 0.1,
            accel_alignment_rad: [0.0; 3],
            level_stride_max_grade: Some(LEVEL_STRIDE_MAX_GRADE),
        }
    }
}

impl FootConfig {
    /// Settings for a factory-calibrated IMU (tactical or calibrated industrial MEMS,
    /// such as the MicroStrain 3DM-GX3-25 of the UofT data set) whose gyroscope bias
    /// is smaller than what a short rest can measure: the alignment rest does not
    /// set the gyro bias (its mean is dominated by noise and foot micro-motion) and
    /// the bias prior is 1 mrad/s. The defaults ([`Default`]) are for consumer MEMS
    /// (phones, watches, shoe pods) whose turn-on gyro bias of ~0.005 rad/s must be
    /// taken out at the start, or the heading drifts by ~0.3 rad/min. Such IMUs
    /// integrate the angle internally and report the mean rate over each output
    /// interval ([`GyroTiming::IntervalMean`]). On the UofT trials this profile
    /// lowers the median position error of every detector on the training split
    /// (docs/foot.md).
    pub fn calibrated_imu() -> Self {
        Self {
            gyro_bias_from_alignment: false,
            initial_gyro_bias_std_rads: 1.0e-3,
            gyro_timing: GyroTiming::IntervalMean,
            ..Self::default()
        }
    }

    /// The axis convention of the pyshoe / University of Toronto data set
    /// (x forward, y right, z down): [`FootConfig::axes_from_spec`]`("frd")`.
    pub fn pyshoe_axes() -> AxisRemap {
        AxisRemap::new([0, 1, 2], [false, true, true]).expect("a rotation")
    }

    /// The sensor → body remap described by a text spec (body: x forward, y left,
    /// z up). Two forms, case-insensitive, spaces ignored:
    ///
    /// - **three letters**, where the sensor's axes point, in the order x, y, z:
    ///   `f`/`b` forward/back, `l`/`r` left/right, `u`/`d` up/down. `flu` is the body
    ///   frame itself (no remap); `frd` is x forward, y right, z down (pyshoe, UofT,
    ///   aerospace); `rfu` is x right, y forward, z up;
    /// - **three signed sensor axes**, comma-separated, which sensor axis gives body
    ///   x (forward), y (left) and z (up): `x,-y,-z` is the same as `frd`; `y,-x,z`
    ///   the same as `rfu`.
    ///
    /// Every axis must appear exactly once and the remap must be a rotation (a
    /// mirror such as `x,y,-z` would make gyroscope and accelerometer disagree);
    /// anything else is [`FootError::InvalidConfig`] with field `axes`.
    pub fn axes_from_spec(spec: &str) -> Result<AxisRemap, FootError> {
        let bad = |reason: &'static str| FootError::InvalidConfig {
            field: "axes",
            reason,
        };
        let s: String = spec
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
        let mut source = [usize::MAX; 3];
        let mut negate = [false; 3];
        if s.contains(',') || s.contains('-') || s.contains('+') {
            let parts: Vec<&str> = s.split(',').collect();
            if parts.len() != 3 {
                return Err(bad(
                    "the signed form needs three comma-separated axes, e.g. x,-y,-z",
                ));
            }
            for (body, p) in parts.iter().enumerate() {
                let (neg, axis) = match p.strip_prefix('-') {
                    Some(a) => (true, a),
                    None => (false, p.strip_prefix('+').unwrap_or(p)),
                };
                source[body] = match axis {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    _ => return Err(bad(
                        "each signed axis must be x, y or z with an optional sign, e.g. x,-y,-z",
                    )),
                };
                negate[body] = neg;
            }
        } else {
            let letters: Vec<char> = s.chars().collect();
            if letters.len() != 3 {
                return Err(bad("use three letters from f/b, l/r, u/d (e.g. frd, flu) or three signed axes (e.g. x,-y,-z)"));
            }
            for (sensor, c) in letters.iter().enumerate() {
                let (body, neg) = match c {
                    'f' => (0, false),
                    'b' => (0, true),
                    'l' => (1, false),
                    'r' => (1, true),
                    'u' => (2, false),
                    'd' => (2, true),
                    _ => {
                        return Err(bad(
                            "each letter must be one of f, b, l, r, u, d (e.g. frd, flu)",
                        ))
                    }
                };
                if source[body] != usize::MAX {
                    return Err(bad(
                        "each of forward/back, left/right, up/down must appear exactly once",
                    ));
                }
                source[body] = sensor;
                negate[body] = neg;
            }
        }
        let mut seen = [false; 3];
        for &src in &source {
            if seen[src] {
                return Err(bad("each sensor axis x, y, z must appear exactly once"));
            }
            seen[src] = true;
        }
        AxisRemap::new(source, negate)
            .map_err(|_| bad("a mirror (determinant −1), not a rotation: flip one more sign"))
    }

    pub fn validate(&self) -> Result<(), FootError> {
        if self.median_window == 0
            || self.median_window % 2 == 0
            || self.median_window > MAX_MEDIAN_WINDOW
        {
            return Err(FootError::InvalidConfig {
                field: "median_window",
                reason: "must be odd and 1..=15 samples",
            });
        }
        positive("detector_window_s", self.detector_window_s)?;
        positive("gait_window_s", self.gait_window_s)?;
        if self.gait_window_s > 5.0 {
            return Err(FootError::InvalidConfig {
                field: "gait_window_s",
                reason: "must be at most 5 s",
            });
        }
        positive("alignment_s", self.alignment_s)?;
        if !self.initial_yaw_rad.is_finite() {
            return Err(FootError::InvalidConfig {
                field: "initial_yaw_rad",
                reason: "must be finite",
            });
        }
        positive("accel_noise_density", self.accel_noise_density)?;
        positive("gyro_noise_density", self.gyro_noise_density)?;
        positive("accel_bias_walk", self.accel_bias_walk)?;
        positive("gyro_bias_walk", self.gyro_bias_walk)?;
        positive("zupt_noise_mps", self.zupt_noise_mps)?;
        if let Some(g) = self.zupt_gate_nis {
            // A bound under 1 would inflate nearly every update by orders of magnitude
            // (the mean NIS of a consistent update is 3); a tiny one overflows.
            if !(g.is_finite() && g >= 1.0) {
                return Err(FootError::InvalidConfig {
                    field: "zupt_gate_nis",
                    reason: "must be finite and at least 1",
                });
            }
        }
        positive(
            "initial_accel_bias_std_mps2",
            self.initial_accel_bias_std_mps2,
        )?;
        positive(
            "initial_gyro_bias_std_rads",
            self.initial_gyro_bias_std_rads,
        )?;
        if let Some(r) = self.accel_range_mps2 {
            positive("accel_range_mps2", r)?;
            if r < super::accel_clip::MIN_ACCEL_CEILING_MPS2 {
                return Err(FootError::InvalidConfig {
                    field: "accel_range_mps2",
                    reason: "must be at least 1.5 g (14.7 m/s²): gravity and a step exceed a smaller range (given in g instead of m/s²?)",
                });
            }
        }
        if let Some(r) = self.gyro_range_rads {
            positive("gyro_range_rads", r)?;
        }
        positive("max_gap_s", self.max_gap_s)?;
        if !(self.min_swing_s.is_finite() && self.min_swing_s >= 0.0) {
            return Err(FootError::InvalidConfig {
                field: "min_swing_s",
                reason: "must be finite and ≥ 0",
            });
        }
        if !self
            .accel_alignment_rad
            .iter()
            .all(|a| a.abs() <= MAX_ACCEL_ALIGNMENT_RAD)
        {
            return Err(FootError::InvalidConfig {
                field: "accel_alignment_rad",
                reason: "each component must be finite and within ±0.1 rad",
            });
        }
        if let Some(g) = self.level_stride_max_grade {
            if !(0.0..=MAX_LEVEL_STRIDE_GRADE).contains(&g) {
                return Err(FootError::InvalidConfig {
                    field: "level_stride_max_grade",
                    reason: "must be within 0..=0.2",
                });
            }
        }
        self.detector.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_specs() {
        let frd = FootConfig::axes_from_spec("frd").unwrap();
        assert_eq!(frd, FootConfig::pyshoe_axes());
        assert_eq!(FootConfig::axes_from_spec("x,-y,-z").unwrap(), frd);
        assert_eq!(FootConfig::axes_from_spec(" FRD ").unwrap(), frd);
        assert_eq!(FootConfig::axes_from_spec("+x, -y, -z").unwrap(), frd);
        assert_eq!(
            FootConfig::axes_from_spec("flu").unwrap(),
            AxisRemap::IDENTITY
        );
        assert_eq!(
            FootConfig::axes_from_spec("x,y,z").unwrap(),
            AxisRemap::IDENTITY
        );
        // Sensor x right, y forward, z up: body forward = sensor y, left = −sensor x.
        let rfu = FootConfig::axes_from_spec("rfu").unwrap();
        assert_eq!(rfu, FootConfig::axes_from_spec("y,-x,z").unwrap());
        assert_eq!(rfu.apply([1.0, 2.0, 3.0]), [2.0, -1.0, 3.0]);
        // A sensor pointing x forward, y right, z down reads +g on −z at rest;
        // in the body frame that is +g on z (up).
        assert_eq!(frd.apply([0.0, 0.0, -9.8]), [0.0, 0.0, 9.8]);
    }

    #[test]
    fn bad_axis_specs_are_typed_errors() {
        for spec in [
            "", "fr", "frdd", "ffu", "xyz", "frx", "x,y", "x,y,z,x", "x,x,z", "x,y,-z", "fld",
            "q,-y,-z", "x,--y,-z", "-,y,z",
        ] {
            match FootConfig::axes_from_spec(spec) {
                Err(FootError::InvalidConfig { field: "axes", .. }) => {}
                other => panic!("{spec:?}: {other:?}"),
            }
        }
    }
}
