//! Configuration of the foot navigator at the FFI (mirrors `stridekit_core::foot::FootConfig`).

use std::sync::Arc;
use stridekit_core::ahrs::AxisRemap;
use stridekit_core::foot as core;

use super::*;

/// Sensor → body axes: `body[i] = (negate_i ? −1 : +1) · sensor[i_from]`. Body: x
/// forward along the foot, y left, z up when the foot is flat. The sources must be a
/// permutation of 0, 1, 2 and the result a rotation (an even number of swaps and
/// negations), else `FootException.InvalidConfig`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Record)]
pub struct FootAxisRemap {
    /// Sensor axis (0 = x, 1 = y, 2 = z) feeding body x.
    #[uniffi(default = 0)]
    pub x_from: u8,
    #[uniffi(default = 1)]
    pub y_from: u8,
    #[uniffi(default = 2)]
    pub z_from: u8,
    #[uniffi(default = false)]
    pub negate_x: bool,
    #[uniffi(default = false)]
    pub negate_y: bool,
    #[uniffi(default = false)]
    pub negate_z: bool,
}

impl From<AxisRemap> for FootAxisRemap {
    fn from(r: AxisRemap) -> Self {
        let s = r.source();
        let n = r.negate();
        // Sources are 0..=2 by construction of AxisRemap.
        Self {
            x_from: s[0] as u8,
            y_from: s[1] as u8,
            z_from: s[2] as u8,
            negate_x: n[0],
            negate_y: n[1],
            negate_z: n[2],
        }
    }
}

impl TryFrom<FootAxisRemap> for AxisRemap {
    type Error = FootError;
    fn try_from(r: FootAxisRemap) -> Result<Self, FootError> {
        AxisRemap::new(
            [r.x_from.into(), r.y_from.into(), r.z_from.into()],
            [r.negate_x, r.negate_y, r.negate_z],
        )
        .map_err(|e| FootError::InvalidConfig {
            field: "axis_remap".into(),
            reason: e.to_string(),
        })
    }
}

/// The axes of the pyshoe / University of Toronto data set and of many shoe IMUs:
/// sensor x forward, y right, z down (body y and z are the sensor's negated).
#[uniffi::export]
pub fn foot_axes_pyshoe() -> FootAxisRemap {
    core::FootConfig::pyshoe_axes().into()
}

/// The sensor → body remap of a text spec: three letters telling where the sensor's
/// x, y, z point (`f`/`b`, `l`/`r`, `u`/`d`: `frd` = x forward, y right, z down;
/// `flu` = the body frame itself), or three signed sensor axes giving body forward,
/// left, up (`x,-y,-z` = `frd`). A bad spec or a mirror is
/// `FootException.InvalidConfig` (field `axes`).
#[uniffi::export]
pub fn foot_axes_from_spec(spec: String) -> Result<FootAxisRemap, FootError> {
    guard(|| Ok(core::FootConfig::axes_from_spec(&spec)?.into()))
}

/// The core's profile for a factory-calibrated IMU that integrates internally
/// (MicroStrain, Xsens, VectorNav class): gyro bias not taken from the start rest,
/// 1 mrad/s bias prior, interval-mean gyro timing; everything else default.
#[uniffi::export]
pub fn foot_config_calibrated_imu() -> FootConfig {
    core::FootConfig::calibrated_imu().into()
}

/// Thresholds of the multi-condition detector; all four must hold for stance.
/// Defaults: the core's walking thresholds (`FixedThresholds::WALK`).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct FootThresholds {
    /// | ‖f‖ − g | of the centre sample below this, m/s².
    #[uniffi(default = 2.0)]
    pub acc_dev_mps2: f64,
    /// ‖ω‖ of the centre sample below this, rad/s.
    #[uniffi(default = 0.6)]
    pub gyro_rads: f64,
    /// Every accelerometer axis' standard deviation over the window below this, m/s².
    #[uniffi(default = 2.4)]
    pub acc_std_mps2: f64,
    /// Every gyroscope axis' standard deviation over the window below this, rad/s.
    #[uniffi(default = 0.3)]
    pub gyro_std_rads: f64,
}

impl From<core::FixedThresholds> for FootThresholds {
    fn from(t: core::FixedThresholds) -> Self {
        Self {
            acc_dev_mps2: t.acc_dev_mps2,
            gyro_rads: t.gyro_rads,
            acc_std_mps2: t.acc_std_mps2,
            gyro_std_rads: t.gyro_std_rads,
        }
    }
}

impl From<FootThresholds> for core::FixedThresholds {
    fn from(t: FootThresholds) -> Self {
        Self {
            acc_dev_mps2: t.acc_dev_mps2,
            gyro_rads: t.gyro_rads,
            acc_std_mps2: t.acc_std_mps2,
            gyro_std_rads: t.gyro_std_rads,
        }
    }
}

/// The zero-velocity (stance) detector that drives the updates. Start from
/// `footDetectorDefault(kind)` and `copy` the values to change.
#[derive(Clone, Debug, PartialEq, uniffi::Enum)]
pub enum FootDetector {
    /// Fixed thresholds (magnitude and standard-deviation criteria, all must agree).
    Fixed { thresholds: FootThresholds },
    /// One threshold set per gait, the gait classified by the peak ‖f‖ over about
    /// one stride: walk below `jog_peak_mps2`, run from `run_peak_mps2`.
    Adaptive {
        jog_peak_mps2: f64,
        run_peak_mps2: f64,
        walk: FootThresholds,
        jog: FootThresholds,
        run: FootThresholds,
    },
    /// Six Gaussian-kernel SVMs on (peak ‖f‖, σ of one axis) pairs, stance when all
    /// agree. `model_text`: null for the model that ships with the SDK, or the text of
    /// a model file written by `stridekit train zupt` (a bad text is
    /// `FootException.InvalidModel` when the navigator is built).
    Svm { model_text: Option<String> },
    /// The SVM while walking (peak ‖f‖ below `jog_peak_mps2`), the jog and run
    /// thresholds above it. `model_text` as for `Svm`. The default before the
    /// adaptive SHOE; its SVM does not carry over to recording sessions it was not
    /// trained on (docs/foot.md, leave-one-session-out).
    SvmAdaptive {
        model_text: Option<String>,
        jog_peak_mps2: f64,
        run_peak_mps2: f64,
        jog: FootThresholds,
        run: FootThresholds,
    },
    /// The SHOE / GLRT detector (Skog et al. 2010, as in OpenShoe and pyshoe).
    Shoe {
        /// Accelerometer noise σ_a, m/s².
        acc_noise_mps2: f64,
        /// Gyroscope noise σ_ω, rad/s.
        gyro_noise_rads: f64,
        /// Threshold γ on the statistic.
        threshold: f64,
    },
    /// SHOE with a threshold that follows the gait: `γ₀ · max(1, peak‖f‖ / p₀)^k`,
    /// peak ‖f‖ over about one stride. The default detector; measured best on the
    /// real VICON trials (docs/foot.md).
    AdaptiveShoe {
        /// Accelerometer noise σ_a, m/s².
        acc_noise_mps2: f64,
        /// Gyroscope noise σ_ω, rad/s.
        gyro_noise_rads: f64,
        /// γ₀, the threshold up to `ref_peak_mps2`.
        threshold: f64,
        /// p₀, m/s².
        ref_peak_mps2: f64,
        /// k, 0..=10.
        exponent: f64,
    },
}

/// The kinds of [`FootDetector`], to ask for one with its default parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum FootDetectorKind {
    Fixed,
    Adaptive,
    Svm,
    SvmAdaptive,
    Shoe,
    AdaptiveShoe,
}

/// A detector of the given kind with its default parameters (`Svm`: the shipped model).
#[uniffi::export]
pub fn foot_detector_default(kind: FootDetectorKind) -> FootDetector {
    match kind {
        FootDetectorKind::Fixed => {
            core::ZeroVelocityDetector::Fixed(core::FixedThresholds::WALK).into()
        }
        FootDetectorKind::Adaptive => {
            core::ZeroVelocityDetector::Adaptive(core::AdaptiveThresholds::default()).into()
        }
        FootDetectorKind::Svm => FootDetector::Svm { model_text: None },
        FootDetectorKind::SvmAdaptive => {
            core::ZeroVelocityDetector::SvmAdaptive(core::SvmAdaptive::default()).into()
        }
        FootDetectorKind::Shoe => {
            core::ZeroVelocityDetector::Shoe(core::ShoeDetector::default()).into()
        }
        FootDetectorKind::AdaptiveShoe => {
            core::ZeroVelocityDetector::AdaptiveShoe(core::AdaptiveShoe::default()).into()
        }
    }
}

/// The text of the zero-velocity SVM model that ships with the SDK (its comment
/// lines say how it was trained).
#[uniffi::export]
pub fn foot_shipped_svm_model() -> String {
    core::SvmModel::shared_shipped().to_text()
}

impl From<core::ZeroVelocityDetector> for FootDetector {
    fn from(d: core::ZeroVelocityDetector) -> Self {
        match d {
            core::ZeroVelocityDetector::Fixed(t) => Self::Fixed {
                thresholds: t.into(),
            },
            core::ZeroVelocityDetector::Adaptive(a) => Self::Adaptive {
                jog_peak_mps2: a.jog_peak_mps2,
                run_peak_mps2: a.run_peak_mps2,
                walk: a.walk.into(),
                jog: a.jog.into(),
                run: a.run.into(),
            },
            core::ZeroVelocityDetector::Svm(m) => Self::Svm {
                model_text: (!m.is_shipped()).then(|| m.to_text()),
            },
            core::ZeroVelocityDetector::SvmAdaptive(d) => Self::SvmAdaptive {
                model_text: (!d.svm.is_shipped()).then(|| d.svm.to_text()),
                jog_peak_mps2: d.jog_peak_mps2,
                run_peak_mps2: d.run_peak_mps2,
                jog: d.jog.into(),
                run: d.run.into(),
            },
            core::ZeroVelocityDetector::Shoe(s) => Self::Shoe {
                acc_noise_mps2: s.acc_noise_mps2,
                gyro_noise_rads: s.gyro_noise_rads,
                threshold: s.threshold,
            },
            core::ZeroVelocityDetector::AdaptiveShoe(a) => Self::AdaptiveShoe {
                acc_noise_mps2: a.shoe.acc_noise_mps2,
                gyro_noise_rads: a.shoe.gyro_noise_rads,
                threshold: a.shoe.threshold,
                ref_peak_mps2: a.ref_peak_mps2,
                exponent: a.exponent,
            },
        }
    }
}

impl TryFrom<FootDetector> for core::ZeroVelocityDetector {
    type Error = FootError;
    fn try_from(d: FootDetector) -> Result<Self, FootError> {
        Ok(match d {
            FootDetector::Fixed { thresholds } => Self::Fixed(thresholds.into()),
            FootDetector::Adaptive {
                jog_peak_mps2,
                run_peak_mps2,
                walk,
                jog,
                run,
            } => Self::Adaptive(core::AdaptiveThresholds {
                jog_peak_mps2,
                run_peak_mps2,
                walk: walk.into(),
                jog: jog.into(),
                run: run.into(),
            }),
            FootDetector::Svm { model_text: None } => Self::default_svm(),
            FootDetector::Svm {
                model_text: Some(text),
            } => Self::Svm(Arc::new(core::SvmModel::parse(&text)?)),
            FootDetector::SvmAdaptive {
                model_text,
                jog_peak_mps2,
                run_peak_mps2,
                jog,
                run,
            } => Self::SvmAdaptive(core::SvmAdaptive {
                svm: match model_text {
                    None => core::SvmModel::shared_shipped(),
                    Some(text) => Arc::new(core::SvmModel::parse(&text)?),
                },
                jog_peak_mps2,
                run_peak_mps2,
                jog: jog.into(),
                run: run.into(),
            }),
            FootDetector::Shoe {
                acc_noise_mps2,
                gyro_noise_rads,
                threshold,
            } => Self::Shoe(core::ShoeDetector {
                acc_noise_mps2,
                gyro_noise_rads,
                threshold,
            }),
            FootDetector::AdaptiveShoe {
                acc_noise_mps2,
                gyro_noise_rads,
                threshold,
                ref_peak_mps2,
                exponent,
            } => Self::AdaptiveShoe(core::AdaptiveShoe {
                shoe: core::ShoeDetector {
                    acc_noise_mps2,
                    gyro_noise_rads,
                    threshold,
                },
                ref_peak_mps2,
                exponent,
            }),
        })
    }
}

/// What a gyroscope sample stands for in time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum FootGyroTiming {
    /// The rate at the sample's timestamp (consumer MEMS; the default).
    #[default]
    Instantaneous,
    /// The mean rate over the interval ending at the timestamp (IMUs that integrate
    /// internally and output ΔΘ/Δt: MicroStrain, Xsens, VectorNav).
    IntervalMean,
}

impl From<core::GyroTiming> for FootGyroTiming {
    fn from(t: core::GyroTiming) -> Self {
        match t {
            core::GyroTiming::Instantaneous => Self::Instantaneous,
            core::GyroTiming::IntervalMean => Self::IntervalMean,
        }
    }
}

impl From<FootGyroTiming> for core::GyroTiming {
    fn from(t: FootGyroTiming) -> Self {
        match t {
            FootGyroTiming::Instantaneous => Self::Instantaneous,
            FootGyroTiming::IntervalMean => Self::IntervalMean,
        }
    }
}

/// Which parts of the estimated error state a zero-velocity update feeds back.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum FootCorrection {
    /// All 15 states: position, velocity, attitude (yaw included), both biases.
    Full,
    /// The paper: velocity, pitch and roll only.
    AsPublished,
}

impl From<core::Correction> for FootCorrection {
    fn from(c: core::Correction) -> Self {
        match c {
            core::Correction::Full => Self::Full,
            core::Correction::AsPublished => Self::AsPublished,
        }
    }
}

impl From<FootCorrection> for core::Correction {
    fn from(c: FootCorrection) -> Self {
        match c {
            FootCorrection::Full => Self::Full,
            FootCorrection::AsPublished => Self::AsPublished,
        }
    }
}

/// Configuration of a [`FootNavigator`]: every core setting. The literal defaults
/// below are the core's (`stridekit_core::foot::FootConfig::default()`);
/// `footConfigDefault()` returns the whole default record (adaptive SHOE detector,
/// full correction), and a test checks that both agree.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct FootConfig {
    /// Zero-velocity detector (default: SHOE with a threshold that follows the gait,
    /// `footDetectorDefault(ADAPTIVE_SHOE)`).
    pub detector: FootDetector,
    /// Which error states an update corrects (default: `FULL`).
    pub correction: FootCorrection,
    /// Sensor → body axes (default: identity; `footAxesPyshoe()` for x fwd, y right, z down).
    #[uniffi(default)]
    pub axis_remap: FootAxisRemap,
    /// Median pre-filter window, samples, odd, 1..=15 (1 = off).
    #[uniffi(default = 1)]
    pub median_window: i32,
    /// Detector window, s (an odd number of samples, 3..=31, at the measured rate).
    #[uniffi(default = 0.025)]
    pub detector_window_s: f64,
    /// Window of the peak ‖f‖ that classifies the gait (about one stride), s, ≤ 5.
    #[uniffi(default = 1.0)]
    pub gait_window_s: f64,
    /// Rest period at the start used to level the navigator, s.
    #[uniffi(default = 0.25)]
    pub alignment_s: f64,
    /// Estimate the gyroscope bias as the mean rate over the alignment period.
    #[uniffi(default = true)]
    pub gyro_bias_from_alignment: bool,
    /// What a gyroscope sample stands for in time (`footConfigDefault()`:
    /// `INSTANTANEOUS`; `footConfigCalibratedImu()`: `INTERVAL_MEAN`).
    pub gyro_timing: FootGyroTiming,
    /// Initial yaw, rad, counter-clockwise from East (0: body +x points East).
    #[uniffi(default = 0.0)]
    pub initial_yaw_rad: f64,
    /// Accelerometer white noise (process noise on velocity), m/s²/√Hz.
    #[uniffi(default = 0.035)]
    pub accel_noise_density: f64,
    /// Gyroscope white noise (process noise on attitude), rad/s/√Hz.
    #[uniffi(default = 0.0006)]
    pub gyro_noise_density: f64,
    /// Random walk of the accelerometer bias, m/s²/√s.
    #[uniffi(default = 0.0001)]
    pub accel_bias_walk: f64,
    /// Random walk of the gyroscope bias, rad/s/√s.
    #[uniffi(default = 0.00001)]
    pub gyro_bias_walk: f64,
    /// Standard deviation of the zero-velocity pseudo-measurement, m/s.
    #[uniffi(default = 0.01)]
    pub zupt_noise_mps: f64,
    /// Largest normalised innovation squared (3 degrees of freedom) at which a
    /// zero-velocity update is taken at face value; beyond it the update is inflated
    /// to meet it and pulls part of the way (a stance called in a swing cannot yank
    /// the track). Null: every update at face value (the paper). Default 100; at least 1.
    #[uniffi(default = Some(100.0))]
    pub zupt_gate_nis: Option<f64>,
    /// Initial 1-σ of the accelerometer bias, m/s².
    #[uniffi(default = 0.1)]
    pub initial_accel_bias_std_mps2: f64,
    /// Initial 1-σ of the gyroscope bias, rad/s.
    #[uniffi(default = 0.005)]
    pub initial_gyro_bias_std_rads: f64,
    /// Accelerometer range, m/s² (at least 1.5 g, e.g. 39.23 for ±4 g; a range in g is
    /// refused with `InvalidConfig`): a sample at ≥ 99 % of it is saturated (null:
    /// unknown, the navigator finds a ceiling in the data).
    #[uniffi(default = None)]
    pub accel_range_mps2: Option<f64>,
    /// Gyroscope range, rad/s (null: unknown). A run of samples at ≥ 99 % of it on an
    /// axis is taken as clipped and the rotation above the ceiling is restored after it.
    #[uniffi(default = None)]
    pub gyro_range_rads: Option<f64>,
    /// A time step longer than this is a gap (integrated at most this long), s.
    #[uniffi(default = 0.1)]
    pub max_gap_s: f64,
    /// Shortest swing that ends a stride at the next stance onset, s.
    #[uniffi(default = 0.1)]
    pub min_swing_s: f64,
    /// Rotation of the accelerometer's axes onto the gyroscope's, a rotation vector in
    /// the body frame (x, y, z components), rad, each within ±0.1: a device calibration
    /// (`stridekit calibrate foot` learns it from a level walk; docs/foot.md). Default 0.
    #[uniffi(default = 0.0)]
    pub accel_alignment_x_rad: f64,
    #[uniffi(default = 0.0)]
    pub accel_alignment_y_rad: f64,
    #[uniffi(default = 0.0)]
    pub accel_alignment_z_rad: f64,
    /// Level-floor constraint: a stride whose height change is at most this grade
    /// (rise / horizontal length) is taken as level and its height change set to zero
    /// (`FootStride.levelledM` says by how much); stairs and ramps keep theirs. Null:
    /// off. Default 0.05 (1:20, the steepest walk that is not a ramp); 0..=0.2.
    #[uniffi(default = Some(0.05))]
    pub level_stride_max_grade: Option<f64>,
}

impl From<core::FootConfig> for FootConfig {
    fn from(c: core::FootConfig) -> Self {
        Self {
            detector: c.detector.into(),
            correction: c.correction.into(),
            axis_remap: c.axis_remap.into(),
            median_window: i32::try_from(c.median_window).unwrap_or(i32::MAX),
            detector_window_s: c.detector_window_s,
            gait_window_s: c.gait_window_s,
            alignment_s: c.alignment_s,
            gyro_bias_from_alignment: c.gyro_bias_from_alignment,
            gyro_timing: c.gyro_timing.into(),
            initial_yaw_rad: c.initial_yaw_rad,
            accel_noise_density: c.accel_noise_density,
            gyro_noise_density: c.gyro_noise_density,
            accel_bias_walk: c.accel_bias_walk,
            gyro_bias_walk: c.gyro_bias_walk,
            zupt_noise_mps: c.zupt_noise_mps,
            zupt_gate_nis: c.zupt_gate_nis,
            initial_accel_bias_std_mps2: c.initial_accel_bias_std_mps2,
            initial_gyro_bias_std_rads: c.initial_gyro_bias_std_rads,
            accel_range_mps2: c.accel_range_mps2,
            gyro_range_rads: c.gyro_range_rads,
            max_gap_s: c.max_gap_s,
            min_swing_s: c.min_swing_s,
            accel_alignment_x_rad: c.accel_alignment_rad[0],
            accel_alignment_y_rad: c.accel_alignment_rad[1],
            accel_alignment_z_rad: c.accel_alignment_rad[2],
            level_stride_max_grade: c.level_stride_max_grade,
        }
    }
}

impl TryFrom<FootConfig> for core::FootConfig {
    type Error = FootError;
    fn try_from(c: FootConfig) -> Result<Self, FootError> {
        Ok(Self {
            axis_remap: c.axis_remap.try_into()?,
            median_window: usize::try_from(c.median_window).unwrap_or(usize::MAX),
            detector_window_s: c.detector_window_s,
            gait_window_s: c.gait_window_s,
            detector: c.detector.try_into()?,
            alignment_s: c.alignment_s,
            gyro_bias_from_alignment: c.gyro_bias_from_alignment,
            gyro_timing: c.gyro_timing.into(),
            initial_yaw_rad: c.initial_yaw_rad,
            correction: c.correction.into(),
            accel_noise_density: c.accel_noise_density,
            gyro_noise_density: c.gyro_noise_density,
            accel_bias_walk: c.accel_bias_walk,
            gyro_bias_walk: c.gyro_bias_walk,
            zupt_noise_mps: c.zupt_noise_mps,
            zupt_gate_nis: c.zupt_gate_nis,
            initial_accel_bias_std_mps2: c.initial_accel_bias_std_mps2,
            initial_gyro_bias_std_rads: c.initial_gyro_bias_std_rads,
            accel_range_mps2: c.accel_range_mps2,
            gyro_range_rads: c.gyro_range_rads,
            max_gap_s: c.max_gap_s,
            min_swing_s: c.min_swing_s,
            accel_alignment_rad: [
                c.accel_alignment_x_rad,
                c.accel_alignment_y_rad,
                c.accel_alignment_z_rad,
            ],
            level_stride_max_grade: c.level_stride_max_grade,
        })
    }
}

/// The core's default configuration (identity axes, adaptive SHOE detector, full correction).
#[uniffi::export]
pub fn foot_config_default() -> FootConfig {
    core::FootConfig::default().into()
}
