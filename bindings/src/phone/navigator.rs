//! `PhoneNavigator` at the FFI: pedestrian dead reckoning from raw phone IMU data,
//! corrected by GNSS (core: `stridekit_core::pdr`).
//!
//! IMU samples cross the FFI packed, in the 80-byte (9-axis) layout of
//! [`crate::packed`]: ten little-endian f64 `t_s, accel_x, accel_y, accel_z (m/s²,
//! gravity included), gyro_x, gyro_y, gyro_z (rad/s), mag_x, mag_y, mag_z (µT; NaN
//! when there is no magnetometer)`, device axes as the platform reports them.

use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::pdr as core;

use crate::pace::types::GnssFix;
use crate::packed::{imu_samples, sensor_events};

crate::error::engine_error! {
    /// Why the navigator rejected an input, a buffer or a snapshot (Kotlin
    /// `NavException`, Swift `NavError`): the typed input causes every engine shares,
    /// then the navigator's own. A rejected input changes nothing.
    pub enum NavError {
        /// An IMU sample was refused for a reason of the navigator's own (an external
        /// attitude that is not a unit quaternion, ...).
        #[error("IMU sample rejected: {reason}")]
        InvalidImuSample { reason: String },
        /// Snapshot bytes could not be restored (corrupted, truncated, other engine or
        /// version).
        #[error("cannot restore snapshot: {reason}")]
        InvalidSnapshot { reason: String },
        /// A packed buffer is not a whole number of 80-byte records.
        #[error("invalid packed buffer: {reason}")]
        InvalidBuffer { reason: String },
        /// A configuration was refused (the sentence names the setting).
        #[error("invalid navigator configuration: {reason}")]
        InvalidConfig { reason: String },
        /// A personal calibration was refused (wrong version, bad value, too large...).
        #[error("invalid PDR calibration: {reason}")]
        InvalidCalibration { reason: String },
        /// A bug inside stridekit (a caught panic). The navigator stays usable.
        #[error("internal error in stridekit: {reason}")]
        Internal { reason: String },
    }
}

impl From<core::NavError> for NavError {
    fn from(e: core::NavError) -> Self {
        match e {
            core::NavError::Input(e) => e.into(),
            // The snapshot error's own words: no second "cannot restore" prefix.
            core::NavError::Snapshot(s) => Self::InvalidSnapshot {
                reason: s.to_string(),
            },
            core::NavError::Calibration(c) => Self::InvalidCalibration {
                reason: c.to_string(),
            },
            core::NavError::Attitude { .. } => Self::InvalidImuSample {
                reason: e.to_string(),
            },
            core::NavError::Ahrs(_)
            | core::NavError::Steps(_)
            | core::NavError::StepLength(_)
            | core::NavError::Merge(_) => Self::InvalidConfig {
                reason: e.to_string(),
            },
        }
    }
}

pub(crate) fn guard<T>(f: impl FnOnce() -> Result<T, NavError>) -> Result<T, NavError> {
    crate::error::guard_with(f, |reason| NavError::Internal { reason })
}

/// Where the pedestrian is (see the core `NavEstimate`).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct NavEstimate {
    pub t_s: f64,
    /// Local East-North-Up position, metres (anchored at the first fix).
    pub east_m: f64,
    pub north_m: f64,
    /// 1-σ per axis, metres.
    pub position_std_m: f64,
    pub lat_deg: Option<f64>,
    pub lon_deg: Option<f64>,
    /// Walking direction, radians clockwise from north.
    pub walking_azimuth_rad: Option<f64>,
    /// Walking direction minus the phone's heading, radians.
    pub heading_offset_rad: Option<f64>,
    pub steps: i64,
    pub distance_m: f64,
    pub step_length_m: Option<f64>,
    /// Factor on every step length since GNSS stretches disagreed with them by more
    /// than 1.35× (1 until then).
    pub step_scale: f64,
    /// GNSS and the step lengths disagree by a factor now; the scale is being
    /// corrected.
    pub step_scale_disagrees: bool,
}

impl From<core::NavEstimate> for NavEstimate {
    fn from(e: core::NavEstimate) -> Self {
        Self {
            t_s: e.t_s,
            east_m: e.east_m,
            north_m: e.north_m,
            position_std_m: e.position_std_m,
            lat_deg: e.lat_deg,
            lon_deg: e.lon_deg,
            walking_azimuth_rad: e.walking_azimuth_rad,
            heading_offset_rad: e.heading_offset_rad,
            steps: i64::try_from(e.steps).unwrap_or(i64::MAX),
            distance_m: e.distance_m,
            step_length_m: e.step_length_m,
            step_scale: e.step_scale,
            step_scale_disagrees: e.step_scale_disagrees,
        }
    }
}

/// A sample a batch rejected (every engine that takes packed IMU or accelerometer
/// records reports them this way): its index in the batch, the typed cause and the
/// engine's sentence for it.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct RejectedImuSample {
    pub index: i32,
    pub error: crate::error::SampleError,
    pub reason: String,
}

impl RejectedImuSample {
    pub(crate) fn new(index: usize, e: &impl crate::error::InputCause) -> Self {
        Self {
            index: i32::try_from(index).unwrap_or(i32::MAX),
            error: e.sample_error(),
            reason: e.to_string(),
        }
    }
}

/// The counts and refusals of a phone engine's batch (the common part of every
/// phone batch result).
pub(crate) struct ImuBatch {
    pub accepted: i32,
    pub produced: i32,
    pub rejected: Vec<RejectedImuSample>,
}

/// The phone engines' batch at the FFI: the core's batch loop
/// ([`stridekit_core::batch::each`]) over the decoded samples, `push` answering
/// `Ok(true)` when the sample produced an estimate; refused samples are reported by
/// index, the rest of the batch goes on as if pushed one by one.
pub(crate) fn push_each<S, E: crate::error::InputCause>(
    samples: impl Iterator<Item = S>,
    mut push: impl FnMut(S) -> Result<bool, E>,
) -> ImuBatch {
    let (mut produced, mut rejected) = (0i32, Vec::new());
    let accepted = stridekit_core::batch::each(
        samples,
        |()| produced = produced.saturating_add(1),
        |r| rejected.push(RejectedImuSample::new(r.index, &r.error)),
        |s| push(s).map(|p| p.then_some(())),
    );
    ImuBatch {
        accepted: i32::try_from(accepted).unwrap_or(i32::MAX),
        produced,
        rejected,
    }
}

/// Why a sensor event of a packed batch was refused: the navigator's reason, or a
/// sensor type it does not take.
enum EventError {
    Nav(core::NavError),
    UnknownSensor(i64),
}

impl std::fmt::Display for EventError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Nav(e) => e.fmt(f),
            Self::UnknownSensor(code) => write!(
                f,
                "sensor_type {code} is not an accelerometer (1), magnetometer (2) or gyroscope (4)"
            ),
        }
    }
}

impl crate::error::InputCause for EventError {
    fn input(&self) -> Option<&stridekit_core::input::InputError> {
        match self {
            Self::Nav(e) => e.input(),
            Self::UnknownSensor(_) => None,
        }
    }
}

/// What the merge of separate sensor events did so far (core `MergeCounts`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Record)]
pub struct SensorEventCounts {
    /// IMU samples merged and pushed.
    pub samples: i64,
    /// Accelerometer events dropped: no gyroscope event within 0.1 s.
    pub without_gyro: i64,
    /// Events lost to a full queue (a stream far behind at a very high rate).
    pub overflow: i64,
    /// Merged samples the navigator refused (IMU samples also pushed directly, out
    /// of order with the events).
    pub refused: i64,
}

impl From<stridekit_core::imu::MergeCounts> for SensorEventCounts {
    fn from(c: stridekit_core::imu::MergeCounts) -> Self {
        let n = |v: u64| i64::try_from(v).unwrap_or(i64::MAX);
        Self {
            samples: n(c.samples),
            without_gyro: n(c.without_gyro),
            overflow: n(c.overflow),
            refused: n(c.refused),
        }
    }
}

/// A step placed on the track (see the core `NavStep`).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct NavStep {
    /// Time of the step (heel strike), s, on the samples' clock.
    pub t_s: f64,
    /// Position after the step, local ENU, metres.
    pub east_m: f64,
    pub north_m: f64,
    pub length_m: f64,
    /// Walking azimuth over the step, radians clockwise from north.
    pub azimuth_rad: f64,
    /// Peak-to-peak vertical displacement of the phone over the step, metres (what
    /// the `PENDULUM` step length uses); null when it could not be measured (no
    /// attitude yet, or the step's span not covered by samples).
    pub vertical_displacement_m: Option<f64>,
    /// Whether the step detector saw the step or credited it without seeing it (filled
    /// at the walk's cadence); a count or a distance may rest on filled steps.
    pub origin: StepOrigin,
}

/// Where a step comes from (see the core `StepOrigin`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Enum)]
pub enum StepOrigin {
    /// A heel strike seen in the acceleration.
    Detected,
    /// Filled at the walk's cadence into an interval across dropped samples.
    FilledAcrossGap,
    /// Filled at the walk's cadence where a step inside a walk was too weak to see.
    FilledMissed,
    /// Filled at the walk's cadence between two bouts of one walk (a pause in its
    /// rhythm of up to 10 s: a turn, a message read on the way).
    FilledBetweenBouts,
}

impl From<stridekit_core::StepOrigin> for StepOrigin {
    fn from(o: stridekit_core::StepOrigin) -> Self {
        use stridekit_core::StepOrigin as O;
        match o {
            O::Detected => StepOrigin::Detected,
            O::FilledAcrossGap => StepOrigin::FilledAcrossGap,
            O::FilledMissed => StepOrigin::FilledMissed,
            O::FilledBetweenBouts => StepOrigin::FilledBetweenBouts,
        }
    }
}

impl From<core::NavStep> for NavStep {
    fn from(s: core::NavStep) -> Self {
        Self {
            t_s: s.t_s,
            east_m: s.east_m,
            north_m: s.north_m,
            length_m: s.length_m,
            azimuth_rad: s.azimuth_rad,
            vertical_displacement_m: Some(s.vertical_displacement_m).filter(|h| h.is_finite()),
            origin: s.origin.into(),
        }
    }
}

/// What a packed IMU push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct ImuBatchResult {
    /// Samples accepted (the batch minus the rejected ones).
    pub accepted: i32,
    /// Estimates produced during the batch: one per accepted sample.
    pub produced: i32,
    /// Steps placed during the batch, in time order (the trajectory: a step detected
    /// before the walking direction was known is placed later, at its own time).
    pub steps: Vec<NavStep>,
    pub rejected: Vec<RejectedImuSample>,
    /// The estimate after the batch (null while nothing was accepted yet).
    pub latest: Option<NavEstimate>,
}

/// Step-length model of a calibration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Enum)]
pub enum StepLengthModel {
    Constant,
    Linear,
    LinearAsPublished,
    LinearFrequencyOnly,
    Weinberg,
    /// The inverted pendulum, L = K·√h (h the phone's vertical displacement over the
    /// step, measured by the navigator from its attitude): the navigator's default.
    Pendulum,
}

impl From<StepLengthModel> for stridekit_core::steplength::StepLengthModel {
    fn from(m: StepLengthModel) -> Self {
        use stridekit_core::steplength::StepLengthModel as M;
        match m {
            StepLengthModel::Constant => M::Constant,
            StepLengthModel::Linear => M::Linear,
            StepLengthModel::LinearAsPublished => M::LinearAsPublished,
            StepLengthModel::LinearFrequencyOnly => M::LinearFrequencyOnly,
            StepLengthModel::Weinberg => M::Weinberg,
            StepLengthModel::Pendulum => M::Pendulum,
        }
    }
}

impl From<stridekit_core::steplength::StepLengthModel> for StepLengthModel {
    fn from(m: stridekit_core::steplength::StepLengthModel) -> Self {
        use stridekit_core::steplength::StepLengthModel as M;
        match m {
            M::Constant => Self::Constant,
            M::Linear => Self::Linear,
            M::LinearAsPublished => Self::LinearAsPublished,
            M::LinearFrequencyOnly => Self::LinearFrequencyOnly,
            M::Weinberg => Self::Weinberg,
            M::Pendulum => Self::Pendulum,
        }
    }
}

/// What is personal in PDR, learned once per user and phone (`stridekit calibrate
/// pdr`; the core's `PdrCalibration`): the step-length model's θ of `L = θ·x` with
/// 1-σ (three values each) and optionally the walking direction in the phone's body
/// frame (three values).
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct PdrCalibration {
    pub step_length_model: StepLengthModel,
    pub step_length_theta: Vec<f64>,
    pub step_length_sigma: Vec<f64>,
    pub carrying_body: Option<Vec<f64>>,
}

fn three(v: &[f64], field: &str) -> Result<[f64; 3], NavError> {
    <[f64; 3]>::try_from(v).map_err(|_| NavError::InvalidCalibration {
        reason: format!("{field} must have 3 values, has {}", v.len()),
    })
}

impl TryFrom<&PdrCalibration> for core::PdrCalibration {
    type Error = NavError;
    fn try_from(c: &PdrCalibration) -> Result<Self, NavError> {
        let out = core::PdrCalibration {
            step_length_model: c.step_length_model.into(),
            step_length_theta: three(&c.step_length_theta, "step_length_theta")?,
            step_length_sigma: three(&c.step_length_sigma, "step_length_sigma")?,
            carrying_body: c
                .carrying_body
                .as_deref()
                .map(|v| three(v, "carrying_body"))
                .transpose()?,
        };
        out.validate().map_err(|e| NavError::InvalidCalibration {
            reason: e.to_string(),
        })?;
        Ok(out)
    }
}

impl From<&core::PdrCalibration> for PdrCalibration {
    fn from(c: &core::PdrCalibration) -> Self {
        Self {
            step_length_model: c.step_length_model.into(),
            step_length_theta: c.step_length_theta.to_vec(),
            step_length_sigma: c.step_length_sigma.to_vec(),
            carrying_body: c.carrying_body.map(|v| v.to_vec()),
        }
    }
}

/// Parse a calibration file's text (format version 1, see `stridekit calibrate pdr`).
#[uniffi::export]
pub fn pdr_calibration_from_text(text: String) -> Result<PdrCalibration, NavError> {
    guard(|| {
        core::PdrCalibration::parse(&text)
            .map(|c| (&c).into())
            .map_err(|e| NavError::InvalidCalibration {
                reason: e.to_string(),
            })
    })
}

/// A calibration as the text `pdr_calibration_from_text` reads.
#[uniffi::export]
pub fn pdr_calibration_to_text(calibration: PdrCalibration) -> Result<String, NavError> {
    guard(|| Ok(core::PdrCalibration::try_from(&calibration)?.to_text(&[])))
}

/// Which step detector a [`PhoneNavigator`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Enum)]
pub enum StepDetectorMode {
    /// The robust detector (the default): autocorrelation-confirmed gait, any carry.
    Robust,
    /// The published peak detector with its documented parameters (a comparison).
    AsPublished,
}

/// Configuration of a [`PhoneNavigator`]: what an app may change; every other
/// parameter keeps the core's default (`stridekit_core::pdr::NavigatorConfig`).
/// `navigatorConfigDefault()` returns the default record; the literal defaults below
/// are the core's, and a test checks that both agree. Enum fields have no literal
/// default (uniffi 0.32 cannot give enum fields one): start from
/// `navigatorConfigDefault().copy(...)` in Kotlin or change a `var` in Swift.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct NavigatorConfig {
    /// Attitude filter (default: `orientationSettingsDefault()`, ENU frame).
    pub orientation: crate::phone::orientation::OrientationSettings,
    /// Step detector (default: `ROBUST`).
    pub step_detector: StepDetectorMode,
    /// Step-length model (default: `PENDULUM`; a calibration replaces it).
    pub step_length_model: StepLengthModel,
    /// Prior step length of the `CONSTANT` model before GNSS teaches one, metres.
    #[uniffi(default = 0.75)]
    pub prior_step_length_m: f64,
    /// Prior K of the `WEINBERG` model (L = K·(a_max − a_min)^¼, a in m/s²).
    #[uniffi(default = 0.4)]
    pub prior_weinberg_k: f64,
    /// Prior K of the `PENDULUM` model (L = K·√h, h in m): 2·√(2·l) for a leg length
    /// l of 0.9 m.
    #[uniffi(default = 2.6832815729997477)]
    pub prior_pendulum_k: f64,
    /// GNSS fixes reporting a worse horizontal accuracy (68 %) are not used to learn
    /// step length, metres.
    #[uniffi(default = 10.0)]
    pub max_fix_accuracy_m: f64,
    /// The platform removes the gyroscope's bias (Android `TYPE_GYROSCOPE`, iOS
    /// `CMDeviceMotion.rotationRate`): the magnetometer then corrects the heading
    /// slowly (120 s) and indoor steel stays out of it. `false` for a raw gyroscope
    /// (`TYPE_GYROSCOPE_UNCALIBRATED`, `CMGyroData`), whose drift needs the fast loop
    /// (10 s).
    #[uniffi(default = true)]
    pub gyro_calibrated: bool,
    /// How long, in event time, a sample waits for the gyroscope and magnetometer
    /// events around an accelerometer event (`pushSensorEventsPacked`), seconds
    /// (0–10): sensor batches delivered later than this lose their exact pairing. The
    /// default suits `maxReportLatencyUs` up to 0.5 s; set it to the latency you
    /// register with when larger (docs/api.md, "Separate sensor events").
    #[uniffi(default = 0.5)]
    pub max_event_delay_s: f64,
}

impl From<&core::NavigatorConfig> for NavigatorConfig {
    fn from(c: &core::NavigatorConfig) -> Self {
        Self {
            orientation: c.ahrs.into(),
            step_detector: match c.detector.mode {
                stridekit_core::stepdetect::DetectorMode::Default => StepDetectorMode::Robust,
                stridekit_core::stepdetect::DetectorMode::AsPublished => {
                    StepDetectorMode::AsPublished
                }
            },
            step_length_model: c.step_length_model.into(),
            prior_step_length_m: c.step_length.prior_step_length_m,
            prior_weinberg_k: c.step_length.prior_weinberg_k,
            prior_pendulum_k: c.step_length.prior_pendulum_k,
            max_fix_accuracy_m: c.step_length.max_accuracy_m,
            gyro_calibrated: c.gyro_calibrated,
            max_event_delay_s: c.merge.max_delay_s,
        }
    }
}

impl TryFrom<NavigatorConfig> for core::NavigatorConfig {
    type Error = NavError;
    fn try_from(c: NavigatorConfig) -> Result<Self, NavError> {
        let base = core::NavigatorConfig::default();
        let ahrs = c.orientation.try_into().map_err(
            |e: crate::phone::orientation::OrientationError| NavError::InvalidConfig {
                reason: e.to_string(),
            },
        )?;
        let detector = match c.step_detector {
            StepDetectorMode::Robust => stridekit_core::stepdetect::StepDetectorConfig::default(),
            StepDetectorMode::AsPublished => {
                stridekit_core::stepdetect::StepDetectorConfig::as_published()
            }
        };
        Ok(Self {
            ahrs,
            detector,
            step_length_model: c.step_length_model.into(),
            step_length: stridekit_core::steplength::StepLengthConfig {
                prior_step_length_m: c.prior_step_length_m,
                prior_weinberg_k: c.prior_weinberg_k,
                prior_pendulum_k: c.prior_pendulum_k,
                max_accuracy_m: c.max_fix_accuracy_m,
                ..base.step_length
            },
            gyro_calibrated: c.gyro_calibrated,
            merge: stridekit_core::imu::MergeConfig {
                max_delay_s: c.max_event_delay_s,
                ..base.merge
            },
        })
    }
}

/// The core's default navigator configuration.
#[uniffi::export]
pub fn navigator_config_default() -> NavigatorConfig {
    (&core::NavigatorConfig::default()).into()
}

/// Append the steps placed since `placed` (and update it).
pub(crate) fn collect_new_steps(
    nav: &core::PhoneNavigator,
    placed: &mut u64,
    out: &mut Vec<NavStep>,
) {
    out.extend(nav.steps_since(*placed).map(NavStep::from));
    *placed = nav.recent_steps().1;
}

/// Pedestrian dead reckoning with a phone. Safe to call from several threads.
#[derive(Debug, uniffi::Object)]
pub struct PhoneNavigator {
    inner: Mutex<core::PhoneNavigator>,
}

impl PhoneNavigator {
    fn lock(&self) -> MutexGuard<'_, core::PhoneNavigator> {
        crate::error::lock(&self.inner)
    }
}

#[uniffi::export]
impl PhoneNavigator {
    /// A navigator with the given configuration (typed `InvalidConfig` error when a
    /// setting is refused).
    #[uniffi::constructor]
    pub fn new(config: NavigatorConfig) -> Result<Arc<Self>, NavError> {
        guard(|| {
            let n = core::PhoneNavigator::new(config.try_into()?)?;
            Ok(Arc::new(Self {
                inner: Mutex::new(n),
            }))
        })
    }

    /// The configuration the navigator runs with.
    pub fn config(&self) -> NavigatorConfig {
        (self.lock().config()).into()
    }

    /// A navigator with the default configuration (`navigatorConfigDefault()`: ENU,
    /// robust step detector, pendulum step length).
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(
                core::PhoneNavigator::new(core::NavigatorConfig::default())
                    .expect("the core default configuration is valid"),
            ),
        })
    }

    /// A navigator with the default configuration and a personal calibration
    /// (typed `InvalidCalibration` error when it is refused).
    #[uniffi::constructor]
    pub fn with_calibration(calibration: PdrCalibration) -> Result<Arc<Self>, NavError> {
        guard(|| {
            let c = core::PdrCalibration::try_from(&calibration)?;
            let n = core::PhoneNavigator::with_calibration(core::NavigatorConfig::default(), &c)
                .map_err(|e| NavError::InvalidCalibration {
                    reason: e.to_string(),
                })?;
            Ok(Arc::new(Self {
                inner: Mutex::new(n),
            }))
        })
    }

    /// Load a personal calibration (best before the first sample; state unchanged
    /// on error).
    pub fn set_calibration(&self, calibration: PdrCalibration) -> Result<(), NavError> {
        guard(|| {
            let c = core::PdrCalibration::try_from(&calibration)?;
            self.lock()
                .set_calibration(&c)
                .map_err(|e| NavError::InvalidCalibration {
                    reason: e.to_string(),
                })
        })
    }

    /// The personal calibration loaded, if any (kept in the snapshot).
    pub fn calibration(&self) -> Option<PdrCalibration> {
        self.lock().calibration().map(Into::into)
    }

    /// A navigator continuing exactly where `snapshot()` was taken.
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, NavError> {
        guard(|| {
            let n = core::PhoneNavigator::restore(&snapshot)?;
            Ok(Arc::new(Self {
                inner: Mutex::new(n),
            }))
        })
    }

    /// Push IMU samples packed as 80-byte little-endian records of ten f64 `t_s,
    /// accel_x, accel_y, accel_z (m/s²), gyro_x, gyro_y, gyro_z (rad/s), mag_x, mag_y,
    /// mag_z (µT, NaN: none)` (`packImuSamples` builds them).
    pub fn push_imu_packed(&self, data: Vec<u8>) -> Result<ImuBatchResult, NavError> {
        guard(|| {
            let samples =
                imu_samples(&data).map_err(|reason| NavError::InvalidBuffer { reason })?;
            let mut nav = self.lock();
            let mut steps = Vec::new();
            let mut placed = nav.recent_steps().1;
            // One estimate per accepted sample.
            let b = push_each(samples, |s| {
                let pushed = nav.push_imu(&s).map(|()| true);
                collect_new_steps(&nav, &mut placed, &mut steps);
                pushed
            });
            Ok(ImuBatchResult {
                accepted: b.accepted,
                produced: b.produced,
                steps,
                rejected: b.rejected,
                latest: nav.estimate().map(Into::into),
            })
        })
    }

    /// Push separate sensor events packed as 40-byte little-endian records `t_s`
    /// (f64, s), `sensor_type` (i64: Android's `Sensor.TYPE_ACCELEROMETER` 1,
    /// `TYPE_MAGNETIC_FIELD` 2, `TYPE_GYROSCOPE` 4), `x, y, z` (f64: m/s², µT, rad/s)
    /// (`packImuEvents` builds them): each stream with its own times, in any
    /// interleaving. They are merged into IMU samples by the SDK's one rule (one per
    /// accelerometer event, gyroscope and magnetometer interpolated; docs/api.md,
    /// "Separate sensor events"), each pushed as by `pushImuPacked`. `accepted`
    /// counts events, `produced` the samples merged and pushed during the call;
    /// rejected events are reported by index. Samples wait for the other streams'
    /// later events: `flushSensorEvents()` releases them at the end.
    pub fn push_sensor_events_packed(&self, data: Vec<u8>) -> Result<ImuBatchResult, NavError> {
        guard(|| {
            let events =
                sensor_events(&data).map_err(|reason| NavError::InvalidBuffer { reason })?;
            let mut nav = self.lock();
            let mut steps = Vec::new();
            let mut placed = nav.recent_steps().1;
            let before = nav.merge_counts().samples;
            let b = push_each(events, |e| {
                let pushed = match e {
                    Ok(e) => nav.push_event(&e).map(|()| false).map_err(EventError::Nav),
                    Err(code) => Err(EventError::UnknownSensor(code)),
                };
                collect_new_steps(&nav, &mut placed, &mut steps);
                pushed
            });
            let produced = nav.merge_counts().samples - before;
            Ok(ImuBatchResult {
                accepted: b.accepted,
                produced: i32::try_from(produced).unwrap_or(i32::MAX),
                steps,
                rejected: b.rejected,
                latest: nav.estimate().map(Into::into),
            })
        })
    }

    /// Push the IMU samples still waiting for later gyroscope or magnetometer
    /// events (`pushSensorEventsPacked`), with what those streams have: when the
    /// sensors stop (end of a session, before a final estimate). Events pushed
    /// afterwards merge as before.
    pub fn flush_sensor_events(&self) -> ImuBatchResult {
        let mut nav = self.lock();
        let mut steps = Vec::new();
        let mut placed = nav.recent_steps().1;
        let before = nav.merge_counts().samples;
        nav.flush_events();
        collect_new_steps(&nav, &mut placed, &mut steps);
        let produced = nav.merge_counts().samples - before;
        ImuBatchResult {
            accepted: 0,
            produced: i32::try_from(produced).unwrap_or(i32::MAX),
            steps,
            rejected: Vec::new(),
            latest: nav.estimate().map(Into::into),
        }
    }

    /// What the sensor-event merge did so far (`pushSensorEventsPacked`).
    pub fn sensor_event_counts(&self) -> SensorEventCounts {
        self.lock().merge_counts().into()
    }

    /// Push one GNSS fix: anchors the local frame (first fix), corrects position,
    /// calibrates step length and walking direction.
    pub fn push_fix(&self, fix: GnssFix) -> Result<NavEstimate, NavError> {
        guard(|| {
            self.lock()
                .push_fix(&fix.into())
                .map(Into::into)
                .map_err(NavError::from)
        })
    }

    /// Where the pedestrian is now: null before the first accepted sample. Before
    /// the first GNSS fix positions are relative to the start; at the first fix the
    /// local frame is anchored there (the position becomes 0, 0 and lat/lon appear).
    pub fn estimate(&self) -> Option<NavEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// The whole state as bytes (sub-engines included).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_defaults_agree_with_the_core_and_a_bad_setting_is_typed() {
        let d = navigator_config_default();
        let c = core::NavigatorConfig::try_from(d.clone()).unwrap();
        assert_eq!(c, core::NavigatorConfig::default());
        // The record's literal defaults (used by the Kotlin/Swift constructors).
        let s = c.step_length;
        assert_eq!(
            (
                s.prior_step_length_m,
                s.prior_weinberg_k,
                s.prior_pendulum_k,
                s.max_accuracy_m
            ),
            (0.75, 0.4, 2.6832815729997477, 10.0)
        );
        let nav = PhoneNavigator::new(d.clone()).unwrap();
        assert_eq!(nav.config(), d);
        let mut bad = d;
        bad.orientation.accel_time_constant_s = -1.0;
        match PhoneNavigator::new(bad) {
            Err(NavError::InvalidConfig { reason }) => assert!(!reason.is_empty()),
            other => panic!("expected InvalidConfig, got {other:?}"),
        }
    }

    #[test]
    fn sensor_events_merge_into_the_samples_a_packed_imu_push_takes() {
        use crate::packed::{pack_imu_events, pack_imu_samples, ImuEvent};
        let samples: Vec<crate::ImuSample> = (0..1500)
            .map(|i| {
                let t = f64::from(i) * 0.01;
                crate::ImuSample {
                    t_s: t,
                    accel_x_mps2: 0.5 * (11.0 * t).sin(),
                    accel_y_mps2: 0.3 * (6.0 * t).sin(),
                    accel_z_mps2: 9.81 + 2.0 * (11.0 * t).sin(),
                    gyro_x_rads: 0.01,
                    gyro_y_rads: 0.0,
                    gyro_z_rads: 0.1 * t.sin(),
                    mag_x_ut: Some(20.0),
                    mag_y_ut: Some(0.0),
                    mag_z_ut: Some(-40.0),
                }
            })
            .collect();
        let direct = PhoneNavigator::with_defaults();
        direct
            .push_imu_packed(pack_imu_samples(samples.clone()))
            .unwrap();
        // The same samples as separate events, the gyroscope and magnetometer 100 ms
        // late, one of an unknown sensor among them.
        let mut events = Vec::new();
        for (i, s) in samples.iter().enumerate() {
            events.push(ImuEvent {
                t_s: s.t_s,
                sensor_type: 1,
                x: s.accel_x_mps2,
                y: s.accel_y_mps2,
                z: s.accel_z_mps2,
            });
            if i >= 10 {
                let late = &samples[i - 10];
                events.push(ImuEvent {
                    t_s: late.t_s,
                    sensor_type: 4,
                    x: late.gyro_x_rads,
                    y: late.gyro_y_rads,
                    z: late.gyro_z_rads,
                });
                events.push(ImuEvent {
                    t_s: late.t_s,
                    sensor_type: 2,
                    x: 20.0,
                    y: 0.0,
                    z: -40.0,
                });
            }
        }
        for late in &samples[samples.len() - 10..] {
            events.push(ImuEvent {
                t_s: late.t_s,
                sensor_type: 4,
                x: late.gyro_x_rads,
                y: late.gyro_y_rads,
                z: late.gyro_z_rads,
            });
        }
        events.insert(
            7,
            ImuEvent {
                sensor_type: 5,
                ..events[6]
            },
        );
        let nav = PhoneNavigator::with_defaults();
        let mut rejected = Vec::new();
        for chunk in events.chunks(1000) {
            let r = nav
                .push_sensor_events_packed(pack_imu_events(chunk.to_vec()))
                .unwrap();
            rejected.extend(r.rejected);
        }
        let end = nav.flush_sensor_events();
        assert_eq!(rejected.len(), 1);
        assert_eq!(rejected[0].index, 7);
        assert!(matches!(
            rejected[0].error,
            crate::error::SampleError::Other { .. }
        ));
        assert!(
            end.produced > 0,
            "the last samples waited for their gyroscope"
        );
        assert_eq!(nav.estimate(), direct.estimate());
        let counts = nav.sensor_event_counts();
        assert_eq!((counts.samples, counts.without_gyro), (1500, 0));
        assert!(matches!(
            nav.push_sensor_events_packed(vec![0; 39]),
            Err(NavError::InvalidBuffer { .. })
        ));
    }

    #[test]
    fn a_corrupt_snapshot_is_invalid_snapshot() {
        let nav = PhoneNavigator::with_defaults();
        let samples: Vec<crate::ImuSample> = (0..300)
            .map(|i| crate::ImuSample {
                t_s: f64::from(i) * 0.01,
                accel_x_mps2: 0.0,
                accel_y_mps2: 0.3 * (f64::from(i) * 0.1).sin(),
                accel_z_mps2: 9.81,
                gyro_x_rads: 0.01,
                gyro_y_rads: 0.0,
                gyro_z_rads: 0.0,
                mag_x_ut: Some(20.0),
                mag_y_ut: Some(0.0),
                mag_z_ut: Some(-40.0),
            })
            .collect();
        let r = nav
            .push_imu_packed(crate::packed::pack_imu_samples(samples))
            .unwrap();
        assert!(r.rejected.is_empty() && r.latest.is_some());
        let good = nav.snapshot();
        assert_eq!(
            PhoneNavigator::restore(good.clone()).unwrap().snapshot(),
            good
        );
        let mut flipped = good.clone();
        let mid = flipped.len() / 2;
        flipped[mid] ^= 0x40;
        for bad in [vec![1, 2, 3], good[..good.len() - 1].to_vec(), flipped] {
            match PhoneNavigator::restore(bad) {
                Err(NavError::InvalidSnapshot { reason }) => assert!(!reason.is_empty()),
                other => panic!("expected InvalidSnapshot, got {other:?}"),
            }
        }
    }
}
