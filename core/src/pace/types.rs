//! Samples going into the [`PaceTracker`](super::PaceTracker) and estimates coming out.
//!
//! Time is the app's monotonic clock in seconds (`t_s`, f64), e.g.
//! `elapsedRealtimeNanos / 1e9` on Android or `ProcessInfo.systemUptime` on iOS.
//! Never wall-clock time: it can jump. Each stream (GNSS, steps) must be
//! strictly increasing in time on its own; the two streams may interleave freely.

/// One GNSS position fix (WGS84).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GnssFix {
    /// Time of the fix, seconds on the app's monotonic clock.
    pub t_s: f64,
    /// Latitude, degrees, −90..=90.
    pub lat_deg: f64,
    /// Longitude, degrees, −180..=180.
    pub lon_deg: f64,
    /// Altitude above the WGS84 ellipsoid (or MSL; only differences matter), metres.
    pub alt_m: Option<f64>,
    /// Horizontal accuracy as reported by the platform (68 % radius, metres,
    /// Android `Location.getAccuracy()`, iOS `horizontalAccuracy`). `None` when unknown.
    pub horizontal_accuracy_m: Option<f64>,
    /// Speed reported by the receiver (Doppler), m/s. Used by the default filter only
    /// when `speed_accuracy_mps` is also given.
    pub speed_mps: Option<f64>,
    /// 68 % accuracy of `speed_mps`, m/s (Android `getSpeedAccuracyMetersPerSecond`).
    pub speed_accuracy_mps: Option<f64>,
}

impl GnssFix {
    /// A fix with position only.
    pub fn new(t_s: f64, lat_deg: f64, lon_deg: f64) -> Self {
        Self {
            t_s,
            lat_deg,
            lon_deg,
            alt_m: None,
            horizontal_accuracy_m: None,
            speed_mps: None,
            speed_accuracy_mps: None,
        }
    }

    /// The same fix with a horizontal accuracy (68 % radius, metres).
    pub fn with_accuracy(mut self, horizontal_accuracy_m: f64) -> Self {
        self.horizontal_accuracy_m = Some(horizontal_accuracy_m);
        self
    }
}

/// Step data from a pedometer. Three shapes cover the platforms:
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepSample {
    /// Cumulative step count at `t_s` since any origin (Android `TYPE_STEP_COUNTER`,
    /// iOS `CMPedometerData.numberOfSteps`). A count lower than the previous one is
    /// taken as a counter reset (reboot): counting continues from the new value and no
    /// steps are added or removed across the reset.
    Count { t_s: f64, steps: u64 },
    /// One detected step at `t_s` (Android `TYPE_STEP_DETECTOR`, a step detector).
    Event { t_s: f64 },
    /// Cadence reported by a watch or foot pod at `t_s`, steps per minute (both feet:
    /// FIT `cadence` is strides per minute, i.e. half of this). Integrated over time.
    Cadence { t_s: f64, steps_per_min: f64 },
}

impl StepSample {
    /// Time of the sample, seconds.
    pub fn t_s(&self) -> f64 {
        match *self {
            StepSample::Count { t_s, .. }
            | StepSample::Event { t_s }
            | StepSample::Cadence { t_s, .. } => t_s,
        }
    }
}

/// One input of either stream, for batch pushes in time order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PaceSample {
    Fix(GnssFix),
    Steps(StepSample),
}

impl PaceSample {
    pub fn t_s(&self) -> f64 {
        match self {
            PaceSample::Fix(f) => f.t_s,
            PaceSample::Steps(s) => s.t_s(),
        }
    }
}

/// Where the speed of an estimate comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PaceSource {
    /// Not enough data yet for a speed (fewer than two fixes and no learned step length).
    Initializing,
    /// The runner stands still: speed 0, no distance added.
    Stationary,
    /// GNSS dominates (GNSS weight ≥ 0.8).
    Gnss,
    /// GNSS and pedometer both contribute.
    Fused,
    /// Pedometer dominates (GNSS weight ≤ 0.2, or GNSS lost): cadence × step length.
    Pedometer,
}

impl PaceSource {
    /// Classify a GNSS weight into a source (moving case).
    pub fn from_gnss_weight(w: f64) -> Self {
        if w >= 0.8 {
            PaceSource::Gnss
        } else if w <= 0.2 {
            PaceSource::Pedometer
        } else {
            PaceSource::Fused
        }
    }
}

/// A pace estimate. Produced at every GNSS epoch and on demand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaceEstimate {
    /// Time the estimate refers to, seconds (the latest sample time seen).
    pub t_s: f64,
    /// Horizontal speed over ground, m/s (0 when stationary).
    pub speed_mps: f64,
    /// Pace, seconds per kilometre; `None` below 0.5 m/s (33 min/km), where pace is meaningless.
    pub pace_s_per_km: Option<f64>,
    /// 1-σ uncertainty of `speed_mps`, m/s, when the filter knows it.
    pub speed_std_mps: Option<f64>,
    /// Cadence, steps per minute (both feet); `None` without step data.
    pub cadence_spm: Option<f64>,
    /// Current step length, metres: learned from trustworthy GNSS; before that the
    /// configured `initial_step_length_m`, else (while steps carry the speed, source
    /// `Pedometer` or `Fused`) the prior the filter is using; `None` otherwise.
    pub step_length_m: Option<f64>,
    /// Weight of GNSS in the fused speed, 0..=1 (1 − pedometer weight).
    pub gnss_weight: f64,
    /// Cumulative distance since start, metres (not increased while stationary).
    pub distance_m: f64,
    /// Where the speed comes from.
    pub source: PaceSource,
    /// What the cross-checks between GNSS and the steps found (all `false` when the
    /// sources agree or cannot be compared).
    pub flags: PaceFlags,
}

/// What the tracker's cross-checks between its two sources found
/// (`core/src/pace/crosscheck.rs`, docs/pace.md "Cross-checks"). Each flag is the
/// state at the estimate's time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PaceFlags {
    /// GNSS showed that the step data counts strides (one foot: FIT's and Garmin's
    /// "cadence"), not steps: the step stream is doubled from then on, and cadence,
    /// step length and speed are given for steps.
    pub cadence_doubled: bool,
    /// No GNSS has checked the cadence yet and it has stayed at 60–100 per minute for
    /// a minute: a slow walk, or strides per minute given as steps per minute (then
    /// the speed is about half the truth). Nothing is corrected: without GNSS the two
    /// cannot be told apart.
    pub cadence_may_be_strides: bool,
    /// Over the last minute of good fixes, GNSS speed and cadence × step length
    /// disagreed by more than a factor of 1.35 (a wrong step length or calibration, a
    /// pedometer that miscounts): the pedometer's weight is lowered and, while
    /// running, the step length is learned again from GNSS, until they agree.
    pub pedometer_disagrees: bool,
}

/// Speed below which no pace is given, m/s.
pub const MIN_PACE_SPEED_MPS: f64 = 0.5;

impl PaceEstimate {
    /// The estimate before any data: zero speed and distance, `Initializing`.
    pub fn initial(step_length_m: Option<f64>) -> Self {
        Self {
            t_s: 0.0,
            speed_mps: 0.0,
            pace_s_per_km: None,
            speed_std_mps: None,
            cadence_spm: None,
            step_length_m,
            gnss_weight: 1.0,
            distance_m: 0.0,
            source: PaceSource::Initializing,
            flags: PaceFlags::default(),
        }
    }

    /// Pace (s/km) for a speed, `None` below [`MIN_PACE_SPEED_MPS`].
    pub fn pace_for(speed_mps: f64) -> Option<f64> {
        (speed_mps >= MIN_PACE_SPEED_MPS).then(|| 1000.0 / speed_mps)
    }
}
