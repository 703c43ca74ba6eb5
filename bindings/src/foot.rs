//! `FootNavigator` at the FFI: foot-mounted inertial navigation (core:
//! `stridekit_core::foot`; method and measured accuracy in `docs/foot.md`).
//!
//! Kotlin, as an app writes it (IMU on the shoe, axes x forward, y right, z down):
//!
//! ```kotlin
//! val config = footConfigDefault().copy(
//!     axisRemap = footAxesPyshoe(),
//!     detector = footDetectorDefault(FootDetectorKind.SVM),
//! )
//! FootNavigator(config).use { nav ->
//!     // 56-byte little-endian records: t_s, ax, ay, az (m/s²), gx, gy, gz (rad/s)
//!     val r = nav.pushPacked(buffer, FootOutput.STRIDE_ENDS)
//!     r.estimates.forEach { e -> println("stride ${e.stride?.lengthM} m") }
//!     val pos = r.latest?.positionM             // EnuVector(east, north, up)
//!     val saved = nav.snapshot()                // later: FootNavigator.restore(saved)
//! }
//! ```
//!
//! # Packed samples
//!
//! [`FOOT_SAMPLE_RECORD_BYTES`] = 56 bytes per sample, seven f64, little-endian:
//!
//! | offset | field                                        |
//! |-------:|----------------------------------------------|
//! | 0      | `t_s`, seconds (monotonic clock)             |
//! | 8      | `accel_x_mps2` (specific force, gravity included) |
//! | 16     | `accel_y_mps2`                               |
//! | 24     | `accel_z_mps2`                               |
//! | 32     | `gyro_x_rads`                                |
//! | 40     | `gyro_y_rads`                                |
//! | 48     | `gyro_z_rads`                                |
//!
//! Sensor axes as the IMU reports them; `FootConfig.axisRemap` maps them to the body
//! frame (x forward, y left, z up). Kotlin: `ByteBuffer.allocate(n * 56)
//! .order(ByteOrder.LITTLE_ENDIAN)` and `putDouble` seven times per sample
//! (`packFootSamples` does it from records). A buffer whose length is not a multiple of
//! 56 is rejected as a whole ([`FootError::InvalidBuffer`]); otherwise every record is
//! checked and pushed like its record counterpart and bad records are reported by index.
//!
//! # Errors
//!
//! [`FootError`] (Kotlin `FootException`, one subclass per variant). A rejected sample
//! leaves the navigator byte-for-byte unchanged. No panic crosses the FFI: calls that
//! return `Result` turn a caught panic into [`FootError::Internal`], batch pushes
//! report a panicking sample as rejected, and a mutex poisoned by a panic is recovered.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::ahrs::AxisRemap;
use stridekit_core::foot as core;
use stridekit_core::input::InputError;

use crate::error::{range_text, TimeUnit};

/// Bytes per packed foot IMU record (seven little-endian f64).
pub const FOOT_SAMPLE_RECORD_BYTES: usize = 56;

// ---------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------

/// Why the foot navigator rejected a sample, its configuration, a detector model, a
/// buffer or a snapshot (Kotlin `FootException`, Swift `FootError`). A rejected sample
/// changes nothing.
#[derive(Clone, Debug, PartialEq, thiserror::Error, uniffi::Error)]
#[uniffi::export(Display)]
pub enum FootError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: String },
    /// A value is outside what any foot-mounted IMU reports (|a| ≤ 2000 m/s², |ω| ≤
    /// 200 rad/s per axis).
    #[error("{field} = {value} is out of range ({reason})")]
    OutOfRange {
        field: String,
        value: f64,
        reason: String,
    },
    /// A sample is not later than the previous accepted one.
    #[error("IMU sample at t = {t_s} s is not after the previous one at {last_t_s} s")]
    TimeNotIncreasing { t_s: f64, last_t_s: f64 },
    /// The accelerometer looks like it reports g (|a| ≈ 1 at rest): multiply by 9.80665.
    #[error("acceleration magnitude {magnitude} at rest looks like units of g: accelerations must be m/s² (multiply by 9.80665)")]
    AccelerationNotInMps2 { magnitude: f64 },
    /// Timestamps are not seconds: they look like `likely_unit`.
    #[error("IMU timestamps look like {likely_unit}, not seconds (t = {t_s})")]
    TimeNotInSeconds { t_s: f64, likely_unit: TimeUnit },
    /// The clock jumped forward by more than a year (mixed clocks): start a new navigator.
    #[error("IMU sample at t = {t_s} s jumps from {last_t_s} s: the clock changed")]
    TimeJump { t_s: f64, last_t_s: f64 },
    /// A configuration value is not usable.
    #[error("invalid foot navigator setting {field}: {reason}")]
    InvalidConfig { field: String, reason: String },
    /// A custom zero-velocity SVM model text could not be read.
    #[error("invalid zero-velocity model: {reason}")]
    InvalidModel { reason: String },
    /// Snapshot bytes could not be restored (corrupted, truncated, other engine or version).
    #[error("cannot restore foot navigator snapshot: {reason}")]
    InvalidSnapshot { reason: String },
    /// A packed buffer is not a whole number of 56-byte records.
    #[error("invalid packed buffer: {reason}")]
    InvalidBuffer { reason: String },
    /// A bug inside stridekit (a caught panic). The navigator stays usable.
    #[error("internal error in stridekit: {reason}")]
    Internal { reason: String },
}

impl From<core::FootError> for FootError {
    fn from(e: core::FootError) -> Self {
        match e {
            core::FootError::Input(e) => match e {
                InputError::NonFinite { field } => Self::NonFinite {
                    field: field.into(),
                },
                InputError::OutOfRange {
                    field,
                    value,
                    min,
                    max,
                    unit,
                } => Self::OutOfRange {
                    field: field.into(),
                    value,
                    reason: range_text(min, max, unit),
                },
                InputError::TimeNotIncreasing { t_s, last_t_s, .. } => {
                    Self::TimeNotIncreasing { t_s, last_t_s }
                }
                InputError::TimeUnit { t_s, likely, .. } => Self::TimeNotInSeconds {
                    t_s,
                    likely_unit: likely.into(),
                },
                InputError::TimeJump { t_s, last_t_s, .. } => Self::TimeJump { t_s, last_t_s },
                InputError::AccelerationInG { mean_magnitude } => Self::AccelerationNotInMps2 {
                    magnitude: mean_magnitude,
                },
            },
            core::FootError::InvalidConfig { field, reason } => Self::InvalidConfig {
                field: field.into(),
                reason: reason.into(),
            },
            core::FootError::InvalidModel(reason) => Self::InvalidModel { reason },
            core::FootError::Snapshot(s) => Self::InvalidSnapshot {
                reason: s.to_string(),
            },
        }
    }
}

impl FootError {
    fn from_panic(payload: Box<dyn std::any::Any + Send>) -> Self {
        Self::Internal {
            reason: crate::error::panic_reason(payload),
        }
    }
}

/// Run `f`, turning a panic into [`FootError::Internal`].
fn guard<T>(f: impl FnOnce() -> Result<T, FootError>) -> Result<T, FootError> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| Err(FootError::from_panic(p)))
}

// ---------------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------------

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
    pub median_window: u32,
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
    /// Initial 1-σ of the accelerometer bias, m/s².
    #[uniffi(default = 0.1)]
    pub initial_accel_bias_std_mps2: f64,
    /// Initial 1-σ of the gyroscope bias, rad/s.
    #[uniffi(default = 0.005)]
    pub initial_gyro_bias_std_rads: f64,
    /// Accelerometer range, m/s²: a sample at ≥ 99 % of it is saturated (null: unknown).
    #[uniffi(default = None)]
    pub accel_range_mps2: Option<f64>,
    /// Gyroscope range, rad/s (null: unknown).
    #[uniffi(default = None)]
    pub gyro_range_rads: Option<f64>,
    /// A time step longer than this is a gap (integrated at most this long), s.
    #[uniffi(default = 0.1)]
    pub max_gap_s: f64,
    /// Shortest swing that ends a stride at the next stance onset, s.
    #[uniffi(default = 0.1)]
    pub min_swing_s: f64,
}

impl From<core::FootConfig> for FootConfig {
    fn from(c: core::FootConfig) -> Self {
        Self {
            detector: c.detector.into(),
            correction: c.correction.into(),
            axis_remap: c.axis_remap.into(),
            median_window: u32::try_from(c.median_window).unwrap_or(u32::MAX),
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
            initial_accel_bias_std_mps2: c.initial_accel_bias_std_mps2,
            initial_gyro_bias_std_rads: c.initial_gyro_bias_std_rads,
            accel_range_mps2: c.accel_range_mps2,
            gyro_range_rads: c.gyro_range_rads,
            max_gap_s: c.max_gap_s,
            min_swing_s: c.min_swing_s,
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
            initial_accel_bias_std_mps2: c.initial_accel_bias_std_mps2,
            initial_gyro_bias_std_rads: c.initial_gyro_bias_std_rads,
            accel_range_mps2: c.accel_range_mps2,
            gyro_range_rads: c.gyro_range_rads,
            max_gap_s: c.max_gap_s,
            min_swing_s: c.min_swing_s,
        })
    }
}

/// The core's default configuration (identity axes, adaptive SHOE detector, full correction).
#[uniffi::export]
pub fn foot_config_default() -> FootConfig {
    core::FootConfig::default().into()
}

// ---------------------------------------------------------------------------------
// Samples and estimates
// ---------------------------------------------------------------------------------

/// One IMU sample from the foot, sensor axes.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct FootImuSample {
    /// Time, seconds on the app's monotonic clock, strictly increasing.
    pub t_s: f64,
    /// Specific force, m/s² (gravity included: +9.8 along "up" at rest).
    pub accel_x_mps2: f64,
    pub accel_y_mps2: f64,
    pub accel_z_mps2: f64,
    /// Angular rate, rad/s.
    pub gyro_x_rads: f64,
    pub gyro_y_rads: f64,
    pub gyro_z_rads: f64,
}

impl From<FootImuSample> for core::FootSample {
    fn from(s: FootImuSample) -> Self {
        Self {
            t_s: s.t_s,
            accel_mps2: [s.accel_x_mps2, s.accel_y_mps2, s.accel_z_mps2],
            gyro_rads: [s.gyro_x_rads, s.gyro_y_rads, s.gyro_z_rads],
        }
    }
}

/// A vector in the local level East-North-Up frame.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct EnuVector {
    pub east: f64,
    pub north: f64,
    pub up: f64,
}

impl From<[f64; 3]> for EnuVector {
    fn from(v: [f64; 3]) -> Self {
        Self {
            east: v[0],
            north: v[1],
            up: v[2],
        }
    }
}

/// A vector in body axes (x forward, y left, z up).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct BodyVector {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl From<[f64; 3]> for BodyVector {
    fn from(v: [f64; 3]) -> Self {
        Self {
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }
}

/// A unit quaternion.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct Quaternion {
    pub w: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// One stride: from one stance onset of the instrumented foot to the next.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct FootStride {
    /// Time of the stance onset that ends the stride, s.
    pub t_s: f64,
    /// Horizontal distance between the two stance onsets, m.
    pub length_m: f64,
    /// Time between them, s.
    pub duration_s: f64,
    /// `length_m / duration_s`, m/s.
    pub speed_mps: f64,
    /// Height change, m (up positive).
    pub climb_m: f64,
}

impl From<core::Stride> for FootStride {
    fn from(s: core::Stride) -> Self {
        Self {
            t_s: s.t_s,
            length_m: s.length_m,
            duration_s: s.duration_s,
            speed_mps: s.speed_mps,
            climb_m: s.climb_m,
        }
    }
}

/// Where the foot is after one sample. Frame: local level East-North-Up, origin where
/// the navigator started, yaw 0 = body +x pointing East at start (set
/// `FootConfig.initialYawRad` for a known heading).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct FootEstimate {
    /// Time of the sample this estimate is for (the pipeline lags the newest input
    /// by `delaySamples()`), s.
    pub t_s: f64,
    pub position_m: EnuVector,
    pub velocity_mps: EnuVector,
    /// Orientation body → ENU.
    pub quaternion: Quaternion,
    /// ZYX Euler angles, rad: roll about body x, pitch about body y, yaw about up
    /// (counter-clockwise from East).
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    /// Heading of body +x, clockwise from North, 0..2π.
    pub heading_rad: f64,
    /// 1-σ of position and velocity per ENU axis.
    pub position_std_m: EnuVector,
    pub velocity_std_mps: EnuVector,
    /// 1-σ of the tilt about East and about North, rad.
    pub tilt_east_std_rad: f64,
    pub tilt_north_std_rad: f64,
    /// 1-σ of the heading, rad.
    pub heading_std_rad: f64,
    /// Bias estimates, body axes.
    pub accel_bias_mps2: BodyVector,
    pub gyro_bias_rads: BodyVector,
    /// The foot is still: a zero-velocity update was applied.
    pub stance: bool,
    /// Strides counted so far and the sum of their horizontal lengths, m.
    pub strides: u64,
    pub distance_m: f64,
    /// The stride that ended on this sample (null on every other sample).
    pub stride: Option<FootStride>,
    /// The sample hit the configured sensor range.
    pub saturated: bool,
    /// The time step before this sample exceeded `maxGapS`.
    pub gap: bool,
}

impl From<core::FootEstimate> for FootEstimate {
    fn from(e: core::FootEstimate) -> Self {
        Self {
            t_s: e.t_s,
            position_m: e.position_m.into(),
            velocity_mps: e.velocity_mps.into(),
            quaternion: Quaternion {
                w: e.quaternion[0],
                x: e.quaternion[1],
                y: e.quaternion[2],
                z: e.quaternion[3],
            },
            roll_rad: e.roll_rad,
            pitch_rad: e.pitch_rad,
            yaw_rad: e.yaw_rad,
            heading_rad: e.heading_rad,
            position_std_m: e.position_std_m.into(),
            velocity_std_mps: e.velocity_std_mps.into(),
            tilt_east_std_rad: e.tilt_std_rad[0],
            tilt_north_std_rad: e.tilt_std_rad[1],
            heading_std_rad: e.heading_std_rad,
            accel_bias_mps2: e.accel_bias_mps2.into(),
            gyro_bias_rads: e.gyro_bias_rads.into(),
            stance: e.stance,
            strides: e.strides,
            distance_m: e.distance_m,
            stride: e.stride.map(Into::into),
            saturated: e.saturated,
            gap: e.gap,
        }
    }
}

/// Which estimates a batch push returns (each one crossing the FFI costs ~300 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum FootOutput {
    /// Every estimate produced (one per accepted sample once aligned, after the delay).
    All,
    /// Only the estimates on which a stride ended (`stride` not null).
    StrideEnds,
    /// None: only `latest`.
    LatestOnly,
}

/// A sample a batch rejected; the rest of the batch was still processed.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct FootRejectedSample {
    /// Position of the sample in the batch (record in a packed buffer), from 0.
    pub index: u32,
    pub error: FootError,
    /// The same as a sentence, for logs.
    pub description: String,
}

/// What a batch push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct FootBatchResult {
    /// The estimates selected by the `FootOutput` argument, in time order.
    pub estimates: Vec<FootEstimate>,
    /// How many estimates the batch produced (returned or not).
    pub produced: u32,
    /// Rejected samples, in batch order.
    pub rejected: Vec<FootRejectedSample>,
    /// The newest estimate after the batch (what `estimate()` returns; null before
    /// the alignment is complete).
    pub latest: Option<FootEstimate>,
}

/// Pack samples into the 56-byte little-endian layout of `pushPacked`.
#[uniffi::export]
pub fn pack_foot_samples(samples: Vec<FootImuSample>) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * FOOT_SAMPLE_RECORD_BYTES);
    for s in samples {
        for v in [
            s.t_s,
            s.accel_x_mps2,
            s.accel_y_mps2,
            s.accel_z_mps2,
            s.gyro_x_rads,
            s.gyro_y_rads,
            s.gyro_z_rads,
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// Decode packed samples; the buffer must be a whole number of records.
pub fn unpack_foot_samples(
    bytes: &[u8],
) -> Result<impl Iterator<Item = core::FootSample> + '_, FootError> {
    if bytes.len() % FOOT_SAMPLE_RECORD_BYTES != 0 {
        return Err(FootError::InvalidBuffer {
            reason: format!(
                "{} bytes is not a whole number of {FOOT_SAMPLE_RECORD_BYTES}-byte foot IMU records",
                bytes.len()
            ),
        });
    }
    Ok(bytes.chunks_exact(FOOT_SAMPLE_RECORD_BYTES).map(|c| {
        let f = |i: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&c[8 * i..8 * i + 8]);
            f64::from_le_bytes(b)
        };
        core::FootSample {
            t_s: f(0),
            accel_mps2: [f(1), f(2), f(3)],
            gyro_rads: [f(4), f(5), f(6)],
        }
    }))
}

// ---------------------------------------------------------------------------------
// Simulated walk
// ---------------------------------------------------------------------------------

/// Most laps `simulate_foot_walk` accepts.
pub const MAX_SIM_FOOT_LAPS: u32 = 20;

/// A simulated foot-mounted IMU walk (core `sim::foot`: laps of a 20 m × 10 m
/// rectangle at 200 Hz, 2 s rest at both ends, body axes = sensor axes, z up) and
/// what Rust computes from it, so host tests can check the FFI path.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct SimulatedFootWalk {
    pub seed: u64,
    pub laps: u32,
    /// The samples as 56-byte records (layout in the module docs).
    pub samples_packed: Vec<u8>,
    pub sample_count: u32,
    /// True path length (sum of stride lengths), m, and true number of strides.
    pub true_distance_m: f64,
    pub true_strides: u32,
    /// True position at the last sample (the walk ends where it started), ENU, m.
    pub true_end_m: EnuVector,
    /// `estimate()` of a default-configuration navigator fed every sample in Rust.
    pub reference_final: Option<FootEstimate>,
    /// Estimates that navigator produced and samples it rejected (0).
    pub reference_produced: u32,
    pub reference_rejected: u32,
}

/// Simulate `laps` (1..=20) laps of walking from `seed`. Deterministic: the same
/// seed gives the same samples on every platform.
#[uniffi::export]
pub fn simulate_foot_walk(seed: u64, laps: u32) -> Result<SimulatedFootWalk, FootError> {
    if !(1..=MAX_SIM_FOOT_LAPS).contains(&laps) {
        return Err(FootError::InvalidConfig {
            field: "laps".into(),
            reason: format!("must be 1..={MAX_SIM_FOOT_LAPS}"),
        });
    }
    guard(|| {
        let sim = stridekit_sim::simulate_foot(&stridekit_sim::FootScenario::walk(seed, laps));
        let mut nav = core::FootNavigator::new(core::FootConfig::default())?;
        let outcome = nav.push_batch(&sim.samples, |_| {});
        let mut packed = Vec::with_capacity(sim.samples.len() * FOOT_SAMPLE_RECORD_BYTES);
        for s in &sim.samples {
            for v in [s.t_s].iter().chain(&s.accel_mps2).chain(&s.gyro_rads) {
                packed.extend_from_slice(&v.to_le_bytes());
            }
        }
        let count = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        Ok(SimulatedFootWalk {
            seed,
            laps,
            samples_packed: packed,
            sample_count: count(sim.samples.len()),
            true_distance_m: sim.distance_m,
            true_strides: count(sim.strides.len()),
            true_end_m: sim.truth.last().map_or([0.0; 3], |t| t.position_m).into(),
            reference_final: nav.estimate().map(Into::into),
            reference_produced: count(outcome.estimates),
            reference_rejected: count(outcome.rejected.len()),
        })
    })
}

// ---------------------------------------------------------------------------------
// The navigator
// ---------------------------------------------------------------------------------

/// Foot-mounted inertial navigation: median pre-filter, zero-velocity detector,
/// strapdown mechanisation and a 15-state error-state Kalman filter with
/// zero-velocity updates. The first `alignmentS` seconds must be a rest. Safe to call
/// from several threads: calls are serialised and a batch is applied as a whole.
#[derive(Debug, uniffi::Object)]
pub struct FootNavigator {
    inner: Mutex<core::FootNavigator>,
}

impl FootNavigator {
    fn wrap(nav: core::FootNavigator) -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(nav),
        })
    }

    /// The core navigator; a mutex poisoned by an earlier panic is recovered (the
    /// panic was already reported as an error) instead of panicking again.
    fn lock(&self) -> MutexGuard<'_, core::FootNavigator> {
        crate::error::lock(&self.inner)
    }

    /// Push every sample under one lock, keeping the estimates `output` asks for.
    fn batch(
        &self,
        samples: impl Iterator<Item = core::FootSample>,
        capacity: usize,
        output: FootOutput,
    ) -> FootBatchResult {
        let mut nav = self.lock();
        let mut estimates = Vec::with_capacity(match output {
            FootOutput::All => capacity,
            FootOutput::StrideEnds | FootOutput::LatestOnly => 0,
        });
        let mut produced = 0u32;
        let mut rejected = Vec::new();
        for (index, s) in samples.enumerate() {
            let error = match catch_unwind(AssertUnwindSafe(|| nav.push(&s))) {
                Ok(Ok(Some(e))) => {
                    produced = produced.saturating_add(1);
                    match output {
                        FootOutput::All => estimates.push(e.into()),
                        FootOutput::StrideEnds if e.stride.is_some() => estimates.push(e.into()),
                        FootOutput::StrideEnds | FootOutput::LatestOnly => {}
                    }
                    continue;
                }
                Ok(Ok(None)) => continue,
                Ok(Err(e)) => FootError::from(e),
                Err(panic) => FootError::from_panic(panic),
            };
            rejected.push(FootRejectedSample {
                index: u32::try_from(index).unwrap_or(u32::MAX),
                description: error.to_string(),
                error,
            });
        }
        FootBatchResult {
            estimates,
            produced,
            rejected,
            latest: nav.estimate().map(Into::into),
        }
    }
}

#[uniffi::export]
impl FootNavigator {
    /// A navigator with the given configuration; `FootException.InvalidConfig` (or
    /// `InvalidModel` for a bad custom SVM model) when it is not usable.
    #[uniffi::constructor]
    pub fn new(config: FootConfig) -> Result<Arc<Self>, FootError> {
        guard(|| Ok(Self::wrap(core::FootNavigator::new(config.try_into()?)?)))
    }

    /// A navigator continuing exactly where `snapshot()` was taken (same
    /// configuration, same state: bit-identical estimates from there on).
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, FootError> {
        guard(|| Ok(Self::wrap(core::FootNavigator::restore(&snapshot)?)))
    }

    /// A navigator with the default configuration (identity axes, adaptive SHOE detector).
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Self::wrap(
            core::FootNavigator::new(core::FootConfig::default())
                .expect("the core default configuration is valid"),
        )
    }

    /// The configuration the navigator runs with.
    pub fn config(&self) -> FootConfig {
        self.lock().config().clone().into()
    }

    /// Push one sample. Returns the estimate of the sample the pipeline finished
    /// (`delaySamples()` back), or null while filling or aligning. A rejected sample
    /// throws and changes nothing.
    pub fn push(&self, sample: FootImuSample) -> Result<Option<FootEstimate>, FootError> {
        guard(|| Ok(self.lock().push(&sample.into())?.map(Into::into)))
    }

    /// Push one sample whose stance is known from outside (a pressure insole, data-set
    /// labels): the detector is bypassed for it. Otherwise like `push`.
    pub fn push_with_stance(
        &self,
        sample: FootImuSample,
        stance: bool,
    ) -> Result<Option<FootEstimate>, FootError> {
        guard(|| {
            Ok(self
                .lock()
                .push_with_stance(&sample.into(), stance)?
                .map(Into::into))
        })
    }

    /// Push samples in time order. Rejected samples are skipped and reported by
    /// index; the others are processed as if pushed one by one.
    pub fn push_samples(&self, samples: Vec<FootImuSample>, output: FootOutput) -> FootBatchResult {
        let n = samples.len();
        self.batch(samples.into_iter().map(Into::into), n, output)
    }

    /// Fast path: samples packed as 56-byte little-endian records (layout in the
    /// module docs). Fails as a whole only if the length is not a multiple of 56;
    /// otherwise behaves like `pushSamples`.
    pub fn push_packed(
        &self,
        data: Vec<u8>,
        output: FootOutput,
    ) -> Result<FootBatchResult, FootError> {
        guard(|| {
            let samples = unpack_foot_samples(&data)?;
            Ok(self.batch(samples, data.len() / FOOT_SAMPLE_RECORD_BYTES, output))
        })
    }

    /// The newest estimate (null before the alignment is complete).
    pub fn estimate(&self) -> Option<FootEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// How many samples the estimates lag the newest input (median filter and
    /// detector windows are centred; 0 before alignment).
    pub fn delay_samples(&self) -> u32 {
        u32::try_from(self.lock().delay_samples()).unwrap_or(u32::MAX)
    }

    /// The alignment rest is over and samples are being integrated.
    pub fn is_aligned(&self) -> bool {
        self.lock().is_aligned()
    }

    /// Sample rate measured during alignment, Hz (0 before).
    pub fn sample_rate_hz(&self) -> f64 {
        self.lock().sample_rate_hz()
    }

    /// Times the divergence guard zeroed an absurd velocity (0 in normal use).
    pub fn divergence_resets(&self) -> u64 {
        self.lock().divergence_resets()
    }

    /// The whole state as bytes (configuration included; versioned, checksummed), to
    /// survive the app being killed; give them to `FootNavigator.restore`. With the
    /// SVM detector the model travels as text (a few hundred kB).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rest(t_s: f64) -> FootImuSample {
        FootImuSample {
            t_s,
            accel_x_mps2: 0.0,
            accel_y_mps2: 0.0,
            accel_z_mps2: 9.81,
            gyro_x_rads: 0.0,
            gyro_y_rads: 0.0,
            gyro_z_rads: 0.0,
        }
    }

    #[test]
    fn config_round_trips_and_defaults_agree() {
        let d = foot_config_default();
        let core: core::FootConfig = d.clone().try_into().unwrap();
        assert_eq!(core, core::FootConfig::default());
        assert_eq!(FootConfig::from(core), d);
        for kind in [
            FootDetectorKind::Fixed,
            FootDetectorKind::Adaptive,
            FootDetectorKind::Svm,
            FootDetectorKind::SvmAdaptive,
            FootDetectorKind::Shoe,
            FootDetectorKind::AdaptiveShoe,
        ] {
            let det = foot_detector_default(kind);
            let c: core::ZeroVelocityDetector = det.clone().try_into().unwrap();
            assert_eq!(FootDetector::from(c), det);
        }
        // The record's literal defaults (used by Kotlin/Swift constructors).
        let t = core::FixedThresholds::WALK;
        assert_eq!(
            (t.acc_dev_mps2, t.gyro_rads, t.acc_std_mps2, t.gyro_std_rads),
            (2.0, 0.6, 2.4, 0.3)
        );
        let c = core::FootConfig::default();
        assert_eq!(c.axis_remap, AxisRemap::IDENTITY);
        assert_eq!(
            (
                c.median_window,
                c.detector_window_s,
                c.gait_window_s,
                c.alignment_s,
                c.gyro_bias_from_alignment,
                c.initial_yaw_rad
            ),
            (1, 0.025, 1.0, 0.25, true, 0.0)
        );
        assert_eq!(
            (
                c.accel_noise_density,
                c.gyro_noise_density,
                c.accel_bias_walk,
                c.gyro_bias_walk,
                c.zupt_noise_mps,
                c.initial_accel_bias_std_mps2,
                c.initial_gyro_bias_std_rads
            ),
            (0.035, 0.0006, 0.0001, 0.00001, 0.01, 0.1, 0.005)
        );
        assert_eq!(
            (
                c.accel_range_mps2,
                c.gyro_range_rads,
                c.max_gap_s,
                c.min_swing_s
            ),
            (None, None, 0.1, 0.1)
        );
    }

    #[test]
    fn custom_model_text_round_trips_and_bad_text_is_invalid_model() {
        let text = foot_shipped_svm_model();
        let det = FootDetector::Svm {
            model_text: Some(text),
        };
        let c: core::ZeroVelocityDetector = det.try_into().unwrap();
        // The shipped model given as text reads back as "the shipped model".
        assert_eq!(
            FootDetector::from(c),
            FootDetector::Svm { model_text: None }
        );
        let bad = FootConfig {
            detector: FootDetector::Svm {
                model_text: Some("not a model".into()),
            },
            ..foot_config_default()
        };
        assert!(matches!(
            FootNavigator::new(bad),
            Err(FootError::InvalidModel { .. })
        ));
    }

    #[test]
    fn bad_config_and_mirror_axes_are_invalid_config() {
        let mut c = foot_config_default();
        c.median_window = 4;
        assert!(matches!(
            FootNavigator::new(c),
            Err(FootError::InvalidConfig { field, .. }) if field == "median_window"
        ));
        let mut c = foot_config_default();
        c.axis_remap.negate_z = true;
        assert!(matches!(
            FootNavigator::new(c),
            Err(FootError::InvalidConfig { field, .. }) if field == "axis_remap"
        ));
        assert_eq!(
            AxisRemap::try_from(foot_axes_pyshoe()).unwrap(),
            core::FootConfig::pyshoe_axes()
        );
    }

    #[test]
    fn packed_and_records_agree_and_rejections_are_reported() {
        let mut samples: Vec<FootImuSample> = (0..200).map(|i| rest(i as f64 * 0.005)).collect();
        samples[50].accel_y_mps2 = f64::NAN;
        samples[60].t_s = 0.0;
        let a = FootNavigator::with_defaults();
        let b = FootNavigator::with_defaults();
        let ra = a.push_samples(samples.clone(), FootOutput::All);
        let rb = b
            .push_packed(pack_foot_samples(samples), FootOutput::All)
            .unwrap();
        assert_eq!(ra, rb);
        assert_eq!(ra.rejected.len(), 2);
        assert_eq!(ra.rejected[0].index, 50);
        assert!(matches!(ra.rejected[0].error, FootError::NonFinite { .. }));
        assert!(matches!(
            ra.rejected[1].error,
            FootError::TimeNotIncreasing { .. }
        ));
        assert!(a.is_aligned());
        assert_eq!(ra.produced as usize, ra.estimates.len());
        assert!(ra.produced > 100);
        assert_eq!(ra.latest, a.estimate());
        let only = FootNavigator::with_defaults()
            .push_packed(
                pack_foot_samples((0..200).map(|i| rest(i as f64 * 0.005)).collect()),
                FootOutput::LatestOnly,
            )
            .unwrap();
        assert!(only.estimates.is_empty());
        assert!(only.produced >= ra.produced);
        assert!(matches!(
            a.push_packed(vec![0; 55], FootOutput::All),
            Err(FootError::InvalidBuffer { .. })
        ));
    }

    #[test]
    fn simulated_walk_matches_the_ffi_path_and_snapshots_resume() {
        let sim = simulate_foot_walk(7, 1).unwrap();
        assert_eq!(sim.reference_rejected, 0);
        assert_eq!(
            sim.samples_packed.len(),
            sim.sample_count as usize * FOOT_SAMPLE_RECORD_BYTES
        );
        let nav = FootNavigator::with_defaults();
        let half =
            sim.samples_packed.len() / 2 / FOOT_SAMPLE_RECORD_BYTES * FOOT_SAMPLE_RECORD_BYTES;
        let a = nav
            .push_packed(sim.samples_packed[..half].to_vec(), FootOutput::LatestOnly)
            .unwrap();
        let restored = FootNavigator::restore(nav.snapshot()).unwrap();
        assert_eq!(restored.snapshot(), nav.snapshot());
        let rest = sim.samples_packed[half..].to_vec();
        let b = nav.push_packed(rest.clone(), FootOutput::All).unwrap();
        let c = restored.push_packed(rest, FootOutput::All).unwrap();
        assert_eq!(b, c);
        assert_eq!(a.produced + b.produced, sim.reference_produced);
        assert_eq!(b.latest, sim.reference_final);
        assert!(matches!(
            FootNavigator::restore(vec![1, 2, 3]),
            Err(FootError::InvalidSnapshot { .. })
        ));
        assert!(simulate_foot_walk(1, 0).is_err());
    }

    #[test]
    fn a_poisoned_mutex_is_recovered() {
        let n = FootNavigator::with_defaults();
        let n2 = Arc::clone(&n);
        let poisoner = std::thread::spawn(move || {
            let _guard = n2.inner.lock().unwrap();
            panic!("poisoning the navigator's mutex on purpose");
        });
        assert!(poisoner.join().is_err());
        assert!(n.inner.is_poisoned());
        assert!(n.push(rest(0.0)).unwrap().is_none());
        assert!(!n.inner.is_poisoned());
    }
}
