//! Records and enums mirroring `stridekit_core::pace`, with lossless conversions.
//!
//! Field names keep the core's SI-unit suffixes; uniffi turns them into camelCase
//! (`t_s` → Kotlin `tS`, `lat_deg` → `latDeg`).

use crate::PaceError;
use stridekit_core::pace as core;

/// One GNSS position fix (WGS84). Time is the app's monotonic clock in seconds
/// (e.g. `elapsedRealtimeNanos / 1e9`), never wall-clock time.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct GnssFix {
    /// Time of the fix, seconds on the app's monotonic clock.
    pub t_s: f64,
    /// Latitude, degrees, −90..=90.
    pub lat_deg: f64,
    /// Longitude, degrees, −180..=180.
    pub lon_deg: f64,
    /// Altitude, metres (only differences matter).
    #[uniffi(default = None)]
    pub alt_m: Option<f64>,
    /// Horizontal accuracy, 68 % radius, metres (Android `getAccuracy()`, iOS `horizontalAccuracy`).
    #[uniffi(default = None)]
    pub horizontal_accuracy_m: Option<f64>,
    /// Receiver (Doppler) speed, m/s; used only together with `speed_accuracy_mps`.
    #[uniffi(default = None)]
    pub speed_mps: Option<f64>,
    /// 68 % accuracy of `speed_mps`, m/s.
    #[uniffi(default = None)]
    pub speed_accuracy_mps: Option<f64>,
}

impl From<GnssFix> for core::GnssFix {
    fn from(f: GnssFix) -> Self {
        Self {
            t_s: f.t_s,
            lat_deg: f.lat_deg,
            lon_deg: f.lon_deg,
            alt_m: f.alt_m,
            horizontal_accuracy_m: f.horizontal_accuracy_m,
            speed_mps: f.speed_mps,
            speed_accuracy_mps: f.speed_accuracy_mps,
        }
    }
}

impl From<core::GnssFix> for GnssFix {
    fn from(f: core::GnssFix) -> Self {
        Self {
            t_s: f.t_s,
            lat_deg: f.lat_deg,
            lon_deg: f.lon_deg,
            alt_m: f.alt_m,
            horizontal_accuracy_m: f.horizontal_accuracy_m,
            speed_mps: f.speed_mps,
            speed_accuracy_mps: f.speed_accuracy_mps,
        }
    }
}

/// Step data from a pedometer, in one of the three shapes platforms report.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Enum)]
pub enum StepSample {
    /// Cumulative step count since any origin (Android `TYPE_STEP_COUNTER`, iOS
    /// `CMPedometerData.numberOfSteps`). A lower count than the previous one is a
    /// counter reset (reboot) and adds no steps. Negative counts are refused
    /// (`OutOfRange`).
    Count { t_s: f64, steps: i64 },
    /// One detected step (Android `TYPE_STEP_DETECTOR`).
    Event { t_s: f64 },
    /// Cadence of both feet, steps per minute (a watch or foot pod; FIT strides/min × 2).
    Cadence { t_s: f64, steps_per_min: f64 },
}

/// A step count as the core's unsigned count: negative counts are out of range.
pub(crate) fn step_count(steps: i64) -> Result<u64, core::PaceError> {
    u64::try_from(steps).map_err(|_| {
        core::PaceError::Input(stridekit_core::input::InputError::OutOfRange {
            field: "steps",
            value: steps as f64,
            min: 0.0,
            max: i64::MAX as f64,
            unit: "",
        })
    })
}

impl TryFrom<StepSample> for core::StepSample {
    type Error = core::PaceError;
    fn try_from(s: StepSample) -> Result<Self, core::PaceError> {
        Ok(match s {
            StepSample::Count { t_s, steps } => Self::Count {
                t_s,
                steps: step_count(steps)?,
            },
            StepSample::Event { t_s } => Self::Event { t_s },
            StepSample::Cadence { t_s, steps_per_min } => Self::Cadence { t_s, steps_per_min },
        })
    }
}

impl From<core::StepSample> for StepSample {
    fn from(s: core::StepSample) -> Self {
        match s {
            core::StepSample::Count { t_s, steps } => Self::Count {
                t_s,
                steps: i64::try_from(steps).unwrap_or(i64::MAX),
            },
            core::StepSample::Event { t_s } => Self::Event { t_s },
            core::StepSample::Cadence { t_s, steps_per_min } => {
                Self::Cadence { t_s, steps_per_min }
            }
        }
    }
}

/// One raw accelerometer sample: specific force (gravity included) in m/s², device
/// axes as the platform reports them (Android `TYPE_ACCELEROMETER`, iOS
/// `CMAccelerometerData` × 9.80665: iOS reports g).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct AccelSample {
    /// Time, seconds on the app's monotonic clock.
    pub t_s: f64,
    pub x_mps2: f64,
    pub y_mps2: f64,
    pub z_mps2: f64,
}

/// One input of either stream, for mixed batches in time order.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Enum)]
pub enum PaceSample {
    Fix { fix: GnssFix },
    Steps { sample: StepSample },
}

impl TryFrom<PaceSample> for core::PaceSample {
    type Error = core::PaceError;
    fn try_from(s: PaceSample) -> Result<Self, core::PaceError> {
        Ok(match s {
            PaceSample::Fix { fix } => Self::Fix(fix.into()),
            PaceSample::Steps { sample } => Self::Steps(sample.try_into()?),
        })
    }
}

impl From<core::PaceSample> for PaceSample {
    fn from(s: core::PaceSample) -> Self {
        match s {
            core::PaceSample::Fix(fix) => Self::Fix { fix: fix.into() },
            core::PaceSample::Steps(sample) => Self::Steps {
                sample: sample.into(),
            },
        }
    }
}

/// Where the speed of an estimate comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum PaceSource {
    /// Not enough data yet for a speed.
    Initializing,
    /// The runner stands still: speed 0, no distance added.
    Stationary,
    /// GNSS dominates (GNSS weight ≥ 0.8).
    Gnss,
    /// GNSS and pedometer both contribute.
    Fused,
    /// Pedometer dominates (GNSS weight ≤ 0.2, or GNSS lost).
    Pedometer,
}

impl From<core::PaceSource> for PaceSource {
    fn from(s: core::PaceSource) -> Self {
        match s {
            core::PaceSource::Initializing => Self::Initializing,
            core::PaceSource::Stationary => Self::Stationary,
            core::PaceSource::Gnss => Self::Gnss,
            core::PaceSource::Fused => Self::Fused,
            core::PaceSource::Pedometer => Self::Pedometer,
        }
    }
}

impl From<PaceSource> for core::PaceSource {
    fn from(s: PaceSource) -> Self {
        match s {
            PaceSource::Initializing => Self::Initializing,
            PaceSource::Stationary => Self::Stationary,
            PaceSource::Gnss => Self::Gnss,
            PaceSource::Fused => Self::Fused,
            PaceSource::Pedometer => Self::Pedometer,
        }
    }
}

/// A pace estimate, produced at every GNSS fix and on demand.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct PaceEstimate {
    /// Time the estimate refers to, seconds (the latest sample time seen).
    pub t_s: f64,
    /// Horizontal speed over ground, m/s (0 when stationary).
    pub speed_mps: f64,
    /// Pace, seconds per kilometre; null below 0.5 m/s.
    pub pace_s_per_km: Option<f64>,
    /// 1-σ uncertainty of `speed_mps`, m/s, when known.
    pub speed_std_mps: Option<f64>,
    /// Cadence, steps per minute (both feet); null without step data.
    pub cadence_spm: Option<f64>,
    /// Step length, metres: learned from good GNSS; before that the configured
    /// `initial_step_length_m`, else (while steps carry the speed: `PEDOMETER`,
    /// `FUSED`) the prior in use; null otherwise.
    pub step_length_m: Option<f64>,
    /// Weight of GNSS in the fused speed, 0..=1.
    pub gnss_weight: f64,
    /// Cumulative distance since start, metres.
    pub distance_m: f64,
    /// Where the speed comes from.
    pub source: PaceSource,
    /// What the cross-checks between GNSS and the steps found (all false while the
    /// sources agree).
    pub flags: PaceFlags,
}

/// What the tracker's cross-checks between GNSS and the steps found (docs/pace.md,
/// "Cross-checks"); each flag is the state at the estimate's time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, uniffi::Record)]
pub struct PaceFlags {
    /// GNSS showed that the step data counts strides (one foot), not steps: the step
    /// stream is doubled from then on; cadence, step length and speed are for steps.
    pub cadence_doubled: bool,
    /// No GNSS has checked the cadence and it has stayed at 60–100 per minute for a
    /// minute: a slow walk, or strides per minute given as steps per minute (speed
    /// about half the truth). Nothing is corrected.
    pub cadence_may_be_strides: bool,
    /// GNSS and cadence × step length disagreed by more than a factor of 1.35 over the
    /// last minute of good fixes: the pedometer's weight is lowered and, while running,
    /// the step length learned again, until they agree.
    pub pedometer_disagrees: bool,
}

impl From<core::PaceFlags> for PaceFlags {
    fn from(f: core::PaceFlags) -> Self {
        let core::PaceFlags {
            cadence_doubled,
            cadence_may_be_strides,
            pedometer_disagrees,
        } = f;
        Self {
            cadence_doubled,
            cadence_may_be_strides,
            pedometer_disagrees,
        }
    }
}

impl From<PaceFlags> for core::PaceFlags {
    fn from(f: PaceFlags) -> Self {
        let PaceFlags {
            cadence_doubled,
            cadence_may_be_strides,
            pedometer_disagrees,
        } = f;
        Self {
            cadence_doubled,
            cadence_may_be_strides,
            pedometer_disagrees,
        }
    }
}

impl From<core::PaceEstimate> for PaceEstimate {
    fn from(e: core::PaceEstimate) -> Self {
        Self {
            t_s: e.t_s,
            speed_mps: e.speed_mps,
            pace_s_per_km: e.pace_s_per_km,
            speed_std_mps: e.speed_std_mps,
            cadence_spm: e.cadence_spm,
            step_length_m: e.step_length_m,
            gnss_weight: e.gnss_weight,
            distance_m: e.distance_m,
            source: e.source.into(),
            flags: e.flags.into(),
        }
    }
}

impl From<PaceEstimate> for core::PaceEstimate {
    fn from(e: PaceEstimate) -> Self {
        Self {
            t_s: e.t_s,
            speed_mps: e.speed_mps,
            pace_s_per_km: e.pace_s_per_km,
            speed_std_mps: e.speed_std_mps,
            cadence_spm: e.cadence_spm,
            step_length_m: e.step_length_m,
            gnss_weight: e.gnss_weight,
            distance_m: e.distance_m,
            source: e.source.into(),
            flags: e.flags.into(),
        }
    }
}

/// Which fusion filter a tracker runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum PaceMode {
    /// The published complementary filter (Skrzypczyk), for comparison.
    AsPublished,
    /// stridekit's default adaptive Kalman filter.
    Adaptive,
}

impl From<PaceMode> for core::PaceMode {
    fn from(m: PaceMode) -> Self {
        match m {
            PaceMode::AsPublished => Self::AsPublished,
            PaceMode::Adaptive => Self::Adaptive,
        }
    }
}

impl From<core::PaceMode> for PaceMode {
    fn from(m: core::PaceMode) -> Self {
        match m {
            core::PaceMode::AsPublished => Self::AsPublished,
            core::PaceMode::Adaptive => Self::Adaptive,
        }
    }
}

/// A runner's learned step-length line, carried between sessions: export it with
/// `PaceTracker.calibration()` after a run with good GNSS, store it with the user's
/// profile, pass it as `PaceConfig.calibration` next time (pedometer-only pace from
/// the first steps on a treadmill, an indoor track or a watch without GNSS).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct PaceCalibration {
    /// Step length at `cadence_spm`, metres.
    pub step_length_m: f64,
    /// Cadence at which the step length was learned, steps/min (both feet).
    pub cadence_spm: f64,
    /// How step length grows with cadence, metres per step/min.
    pub slope_m_per_spm: f64,
    /// 1-σ of `step_length_m` when exported, metres.
    pub step_length_std_m: f64,
    /// The step-length model of raw accelerometer input (`pushAccel`), learned with
    /// good GNSS; null when the app did not push raw acceleration. Imported, a session
    /// without GNSS is paced by each step's own acceleration from the first steps.
    #[uniffi(default = None)]
    pub accel_model: Option<AccelStepModel>,
}

/// The feature step-length model of raw accelerometer input: `L = A·F + B·SV + C`,
/// F the step frequency (steps/s), SV the variance of the acceleration magnitude over
/// the step ((m/s²)²); its uncertainty centred at the user's typical features (F₀,
/// SV₀). Store it as it was exported; the 1-σ values are the prior that GNSS refines in
/// the next session.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct AccelStepModel {
    /// A, metres per step/s (m·s), within ±2.
    pub a_m_s: f64,
    /// B, metres per (m/s²)², within ±0.1.
    pub b_m_per_m2ps4: f64,
    /// C, metres, within ±5.
    pub c_m: f64,
    /// F₀, the typical step frequency of the calibration, Hz, 0.5..=5.
    pub ref_frequency_hz: f64,
    /// SV₀, the typical acceleration variance of the calibration, (m/s²)², 0..=10⁴.
    pub ref_variance_m2ps4: f64,
    /// 1-σ of A, m·s, in (0, 10].
    pub a_std_m_s: f64,
    /// 1-σ of B, metres per (m/s²)², in (0, 10].
    pub b_std_m_per_m2ps4: f64,
    /// 1-σ of the modelled step length at (F₀, SV₀), metres, in (0, 10].
    pub length_std_m: f64,
}

impl From<AccelStepModel> for core::AccelStepModel {
    fn from(m: AccelStepModel) -> Self {
        Self {
            a_m_s: m.a_m_s,
            b_m_per_m2ps4: m.b_m_per_m2ps4,
            c_m: m.c_m,
            ref_frequency_hz: m.ref_frequency_hz,
            ref_variance_m2ps4: m.ref_variance_m2ps4,
            a_std_m_s: m.a_std_m_s,
            b_std_m_per_m2ps4: m.b_std_m_per_m2ps4,
            length_std_m: m.length_std_m,
        }
    }
}

impl From<core::AccelStepModel> for AccelStepModel {
    fn from(m: core::AccelStepModel) -> Self {
        Self {
            a_m_s: m.a_m_s,
            b_m_per_m2ps4: m.b_m_per_m2ps4,
            c_m: m.c_m,
            ref_frequency_hz: m.ref_frequency_hz,
            ref_variance_m2ps4: m.ref_variance_m2ps4,
            a_std_m_s: m.a_std_m_s,
            b_std_m_per_m2ps4: m.b_std_m_per_m2ps4,
            length_std_m: m.length_std_m,
        }
    }
}

impl From<PaceCalibration> for core::PaceCalibration {
    fn from(c: PaceCalibration) -> Self {
        Self {
            step_length_m: c.step_length_m,
            cadence_spm: c.cadence_spm,
            slope_m_per_spm: c.slope_m_per_spm,
            step_length_std_m: c.step_length_std_m,
            accel_model: c.accel_model.map(Into::into),
        }
    }
}

impl From<core::PaceCalibration> for PaceCalibration {
    fn from(c: core::PaceCalibration) -> Self {
        Self {
            step_length_m: c.step_length_m,
            cadence_spm: c.cadence_spm,
            slope_m_per_spm: c.slope_m_per_spm,
            step_length_std_m: c.step_length_std_m,
            accel_model: c.accel_model.map(Into::into),
        }
    }
}

/// Settings of a [`PaceTracker`](crate::PaceTracker) an app may change; every other
/// filter parameter keeps the core's default (`stridekit_core::pace::PaceConfig::default()`).
///
/// The field defaults below are those of the core default; `default_pace_config()`
/// returns the same record and a test checks both agree.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct PaceConfig {
    /// Fusion filter (default: `Adaptive`).
    pub mode: PaceMode,
    /// Step length at 168 steps/min used before one is learned from GNSS, metres,
    /// 0.2..=3.0 (null: a population prior of 1.0 m, uncertain, learned from GNSS).
    /// Without GNSS the pedometer speed uses it from the first steps. It is the
    /// running step length: below 132 steps/min (a walk) a population walking step
    /// length (0.72 m at 112 steps/min) is used instead.
    #[uniffi(default = None)]
    pub initial_step_length_m: Option<f64>,
    /// Without a step for this long while step data flows, the runner is stationary, seconds.
    #[uniffi(default = 2.0)]
    pub stationary_after_s: f64,
    /// A calibration exported by `PaceTracker.calibration()` in an earlier session
    /// (takes precedence over `initial_step_length_m`; null: none).
    #[uniffi(default = None)]
    pub calibration: Option<PaceCalibration>,
}

impl Default for PaceConfig {
    fn default() -> Self {
        core::PaceConfig::default().into()
    }
}

impl From<PaceConfig> for core::PaceConfig {
    fn from(c: PaceConfig) -> Self {
        Self {
            mode: c.mode.into(),
            initial_step_length_m: c.initial_step_length_m,
            stationary_after_s: c.stationary_after_s,
            calibration: c.calibration.map(Into::into),
            ..core::PaceConfig::default()
        }
    }
}

impl From<core::PaceConfig> for PaceConfig {
    fn from(c: core::PaceConfig) -> Self {
        Self {
            mode: c.mode.into(),
            initial_step_length_m: c.initial_step_length_m,
            stationary_after_s: c.stationary_after_s,
            calibration: c.calibration.map(Into::into),
        }
    }
}

/// The default configuration (adaptive filter, core defaults).
#[uniffi::export]
pub fn default_pace_config() -> PaceConfig {
    PaceConfig::default()
}

/// Parse a stored pace calibration (text format version 1, as
/// `pace_calibration_to_text` writes it and `stridekit pace --save-calibration`;
/// `InvalidConfig` when it is refused, with the reason).
#[uniffi::export]
pub fn pace_calibration_from_text(text: String) -> Result<PaceCalibration, PaceError> {
    crate::error::guard(|| {
        core::PaceCalibration::parse(&text)
            .map(Into::into)
            .map_err(|e| PaceError::InvalidConfig {
                reason: e.to_string(),
            })
    })
}

/// A pace calibration as text to store with the user's profile (exact: reading it
/// back gives the same record); `InvalidConfig` for a record the tracker would refuse.
#[uniffi::export]
pub fn pace_calibration_to_text(calibration: PaceCalibration) -> Result<String, PaceError> {
    crate::error::guard(|| {
        let c: core::PaceCalibration = calibration.into();
        c.validate()?;
        Ok(c.to_text(&[]))
    })
}
