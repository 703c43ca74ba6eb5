//! Zero-velocity (stance) detectors. Each looks at statistics of a short window of
//! samples centred on the sample being decided ([`WindowStats`]) and says whether
//! the foot is still.
//!
//! - [`FixedThresholds`]: the paper's multi-condition detector — the centre sample's
//!   | ‖f‖ − g | and ‖ω‖, and the per-axis standard deviations of f and ω over the
//!   window, must all be under their thresholds.
//! - [`AdaptiveThresholds`]: the same conditions with one threshold set per gait
//!   (walk / jog / run), the gait classified by the peak ‖f‖ over the last stride.
//! - [`SvmModel`](super::svm::SvmModel): six Gaussian-kernel SVMs on
//!   (peak ‖f‖, σ of one axis) pairs; stance only if all six agree (paper).
//! - [`SvmAdaptive`]: the SVM while walking, the adaptive detector's jog and run
//!   thresholds from the jog boundary up (the SVM's features overlap in running).
//! - [`ShoeDetector`]: the SHOE / GLRT detector of Skog et al. (2010), as in
//!   OpenShoe and pyshoe, as a reference.
//! - [`AdaptiveShoe`]: SHOE with a threshold that grows with the stride's peak
//!   specific force (the default).

use std::sync::Arc;

use super::error::FootError;
use super::svm::SvmModel;

/// Standard gravity, m/s².
pub const G_MPS2: f64 = 9.80665;

/// Span of the stillness floor ([`WindowStats::still_acc_ms2_sq`]), s: a walking foot
/// stands still at least once in it (a slow stride or a stair step takes up to 2 s).
pub const STILL_WINDOW_S: f64 = 3.0;

/// The adaptive SHOE's threshold is at least this many times the SHOE statistic of
/// the stillness floor. A vibration raises every window of a stance, by an amount that
/// varies with its phase (a 25 ms window holds a quarter period at 10 Hz), so one
/// stance's windows spread over a few times its quietest one; a swing is orders of
/// magnitude above. 3, 5 and 10 measure alike (`eval perturb --engine foot`).
pub const STILL_FLOOR_MARGIN: f64 = 5.0;

/// Statistics of the detector window around the sample being decided (body frame,
/// after the median pre-filter).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindowStats {
    /// ‖f‖ of the centre sample, m/s².
    pub acc_norm_mps2: f64,
    /// | ‖f‖ − g | of the centre sample, with g measured during alignment, m/s².
    pub acc_dev_mps2: f64,
    /// ‖ω‖ of the centre sample, rad/s.
    pub gyro_norm_rads: f64,
    /// Standard deviation of each accelerometer axis over the window, m/s².
    pub acc_std_mps2: [f64; 3],
    /// Standard deviation of each gyroscope axis over the window, rad/s.
    pub gyro_std_rads: [f64; 3],
    /// Peak ‖f‖ over the gait window (about one stride up to the newest sample), m/s².
    pub peak_acc_norm_mps2: f64,
    /// Σ_k ‖f_k − g·f̄/‖f̄‖‖² over the window, (m/s²)² (the SHOE accelerometer term).
    pub shoe_acc_ss: f64,
    /// Σ_k ‖ω_k‖² over the window, (rad/s)² (the SHOE gyroscope term).
    pub shoe_gyro_ss: f64,
    /// The accelerometer's stillness floor: the lowest `shoe_acc_ss / n` of the
    /// windows of the last [`STILL_WINDOW_S`], (m/s²)² (0: unknown).
    pub still_acc_ms2_sq: f64,
    /// The gyroscope's stillness floor: the lowest `shoe_gyro_ss / n` of the windows
    /// of the last [`STILL_WINDOW_S`], (rad/s)² (0: unknown).
    pub still_gyro_rads_sq: f64,
    /// Samples in the window.
    pub n: usize,
    /// A sample in the window hit the configured sensor range.
    pub saturated: bool,
}

/// Thresholds of the multi-condition detector; all conditions must hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedThresholds {
    /// | ‖f‖ − g | of the centre sample below this, m/s².
    pub acc_dev_mps2: f64,
    /// ‖ω‖ of the centre sample below this, rad/s.
    pub gyro_rads: f64,
    /// Every accelerometer axis' standard deviation over the window below this, m/s².
    pub acc_std_mps2: f64,
    /// Every gyroscope axis' standard deviation over the window below this, rad/s.
    pub gyro_std_rads: f64,
}

impl Default for FixedThresholds {
    /// [`FixedThresholds::WALK`].
    fn default() -> Self {
        Self::WALK
    }
}

impl FixedThresholds {
    /// The default set, one for every gait: chosen by a grid search on the training
    /// half of the pyshoe VICON trials (`stridekit eval foot --tune`, objective: the
    /// geometric mean of the position RMSE; see `docs/lab/2026-12-06-foot-history.md`), with the default
    /// 0.025 s detector window. The accelerometer σ criterion ended at the top of its
    /// grid (2.4 m/s²): on this data the centre-sample ‖ω‖ and | ‖f‖ − g | and the
    /// gyroscope σ do the work.
    pub const WALK: Self = Self {
        acc_dev_mps2: 2.0,
        gyro_rads: 0.6,
        acc_std_mps2: 2.4,
        gyro_std_rads: 0.3,
    };

    /// `self` with every threshold multiplied by `k`.
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            acc_dev_mps2: self.acc_dev_mps2 * k,
            gyro_rads: self.gyro_rads * k,
            acc_std_mps2: self.acc_std_mps2 * k,
            gyro_std_rads: self.gyro_std_rads * k,
        }
    }

    pub fn is_stance(&self, s: &WindowStats) -> bool {
        s.acc_dev_mps2 < self.acc_dev_mps2
            && s.gyro_norm_rads < self.gyro_rads
            && s.acc_std_mps2.iter().all(|&v| v < self.acc_std_mps2)
            && s.gyro_std_rads.iter().all(|&v| v < self.gyro_std_rads)
    }

    fn validate(&self) -> Result<(), FootError> {
        use super::error::positive;
        positive("acc_dev_mps2", self.acc_dev_mps2)?;
        positive("gyro_rads", self.gyro_rads)?;
        positive("acc_std_mps2", self.acc_std_mps2)?;
        positive("gyro_std_rads", self.gyro_std_rads)
    }
}

/// Gait-adaptive thresholds: the gait is classified by the peak ‖f‖ over the gait
/// window, then that gait's thresholds apply.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveThresholds {
    /// Peak ‖f‖ from which the gait is a jog, m/s².
    pub jog_peak_mps2: f64,
    /// Peak ‖f‖ from which the gait is a run, m/s².
    pub run_peak_mps2: f64,
    pub walk: FixedThresholds,
    pub jog: FixedThresholds,
    pub run: FixedThresholds,
}

impl Default for AdaptiveThresholds {
    /// Chosen on the training half of the pyshoe VICON trials (`stridekit eval foot
    /// --tune`): walk = [`FixedThresholds::WALK`], jog (peak ‖f‖ ≥ 50 m/s²) 1.5 ×
    /// wider, run (peak ‖f‖ ≥ 80 m/s²) 3 × wider: a running foot is never as still.
    fn default() -> Self {
        Self {
            jog_peak_mps2: 50.0,
            run_peak_mps2: 80.0,
            walk: FixedThresholds::WALK,
            jog: FixedThresholds::WALK.scaled(1.5),
            run: FixedThresholds::WALK.scaled(3.0),
        }
    }
}

/// Gait class used by the adaptive detector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gait {
    Walk,
    Jog,
    Run,
}

impl AdaptiveThresholds {
    pub fn gait(&self, s: &WindowStats) -> Gait {
        if s.peak_acc_norm_mps2 >= self.run_peak_mps2 {
            Gait::Run
        } else if s.peak_acc_norm_mps2 >= self.jog_peak_mps2 {
            Gait::Jog
        } else {
            Gait::Walk
        }
    }

    pub fn is_stance(&self, s: &WindowStats) -> bool {
        match self.gait(s) {
            Gait::Walk => self.walk.is_stance(s),
            Gait::Jog => self.jog.is_stance(s),
            Gait::Run => self.run.is_stance(s),
        }
    }

    fn validate(&self) -> Result<(), FootError> {
        use super::error::positive;
        positive("jog_peak_mps2", self.jog_peak_mps2)?;
        positive("run_peak_mps2", self.run_peak_mps2)?;
        if self.run_peak_mps2 < self.jog_peak_mps2 {
            return Err(FootError::InvalidConfig {
                field: "run_peak_mps2",
                reason: "must not be below jog_peak_mps2",
            });
        }
        self.walk.validate()?;
        self.jog.validate()?;
        self.run.validate()
    }
}

/// The SVM while walking and the gait-adaptive thresholds when jogging or running:
/// the gait is classified by the peak ‖f‖ over the gait window as in
/// [`AdaptiveThresholds`]; below `jog_peak_mps2` the SVM decides, above it the jog
/// or run thresholds do. The SVM's (peak ‖f‖, σ) features separate walking stance
/// well but overlap in running, where "all six agree" misses whole stances
/// (docs/lab/2026-12-06-foot-history.md).
#[derive(Clone, Debug, PartialEq)]
pub struct SvmAdaptive {
    /// The walking detector; shared, immutable.
    pub svm: Arc<SvmModel>,
    /// Peak ‖f‖ from which the gait is a jog, m/s².
    pub jog_peak_mps2: f64,
    /// Peak ‖f‖ from which the gait is a run, m/s².
    pub run_peak_mps2: f64,
    pub jog: FixedThresholds,
    pub run: FixedThresholds,
}

impl Default for SvmAdaptive {
    /// The shipped SVM model and the jog / run part of [`AdaptiveThresholds::default`].
    fn default() -> Self {
        Self::with_model(SvmModel::shared_shipped())
    }
}

impl SvmAdaptive {
    /// `svm` with the jog / run part of [`AdaptiveThresholds::default`].
    pub fn with_model(svm: Arc<SvmModel>) -> Self {
        let a = AdaptiveThresholds::default();
        Self {
            svm,
            jog_peak_mps2: a.jog_peak_mps2,
            run_peak_mps2: a.run_peak_mps2,
            jog: a.jog,
            run: a.run,
        }
    }

    pub fn is_stance(&self, s: &WindowStats) -> bool {
        if s.peak_acc_norm_mps2 >= self.run_peak_mps2 {
            self.run.is_stance(s)
        } else if s.peak_acc_norm_mps2 >= self.jog_peak_mps2 {
            self.jog.is_stance(s)
        } else {
            self.svm.is_stance(s)
        }
    }

    fn validate(&self) -> Result<(), FootError> {
        AdaptiveThresholds {
            jog_peak_mps2: self.jog_peak_mps2,
            run_peak_mps2: self.run_peak_mps2,
            walk: FixedThresholds::WALK,
            jog: self.jog,
            run: self.run,
        }
        .validate()
    }
}

/// SHOE (stance hypothesis optimal estimation) / GLRT detector:
/// `T = (1/W) Σ_k ( ‖f_k − g·f̄/‖f̄‖‖² / σ_a² + ‖ω_k‖² / σ_ω² ) < γ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShoeDetector {
    /// Accelerometer noise σ_a, m/s² (pyshoe: 0.01).
    pub acc_noise_mps2: f64,
    /// Gyroscope noise σ_ω, rad/s (pyshoe: 0.1 °/s).
    pub gyro_noise_rads: f64,
    /// Threshold γ on the statistic (dimensionless). Default 3·10⁵, chosen on the
    /// training half of the pyshoe VICON trials with the 0.025 s window (pyshoe's
    /// per-trial optimum ranges 5·10⁵…10⁹: those labels are more liberal than what
    /// is best for this filter).
    pub threshold: f64,
}

impl Default for ShoeDetector {
    fn default() -> Self {
        Self {
            acc_noise_mps2: 0.01,
            gyro_noise_rads: 0.1_f64.to_radians(),
            threshold: 3.0e5,
        }
    }
}

impl ShoeDetector {
    /// The GLRT statistic of the window.
    pub fn statistic(&self, s: &WindowStats) -> f64 {
        let n = s.n.max(1) as f64;
        (s.shoe_acc_ss / (self.acc_noise_mps2 * self.acc_noise_mps2)
            + s.shoe_gyro_ss / (self.gyro_noise_rads * self.gyro_noise_rads))
            / n
    }

    /// The statistic of the stillness floor (the quietest windows of the last
    /// [`STILL_WINDOW_S`], accelerometer and gyroscope each).
    pub fn floor_statistic(&self, s: &WindowStats) -> f64 {
        s.still_acc_ms2_sq / (self.acc_noise_mps2 * self.acc_noise_mps2)
            + s.still_gyro_rads_sq / (self.gyro_noise_rads * self.gyro_noise_rads)
    }

    pub fn is_stance(&self, s: &WindowStats) -> bool {
        self.statistic(s) < self.threshold
    }

    fn validate(&self) -> Result<(), FootError> {
        use super::error::positive;
        positive("acc_noise_mps2", self.acc_noise_mps2)?;
        positive("gyro_noise_rads", self.gyro_noise_rads)?;
        positive("threshold", self.threshold)
    }
}

/// SHOE with a threshold that follows the gait's intensity: `T < γ₀ ·
/// max(1, peak‖f‖ / p₀)^k`, peak ‖f‖ over the gait window (about one stride).
///
/// Why: SHOE's statistic compares the window with sensor noise alone, but a foot in
/// stance is not still to sensor noise: the sole compresses, the foot rolls, the
/// shank's vibration reaches the shoe, and all of it grows with how hard the foot
/// lands. A fixed γ that calls slow-walking stances right misses whole running
/// stances, and one that finds running stances calls half of a slow swing stance
/// (pyshoe's per-trial optimum moves over four orders of magnitude on the UofT
/// trials, with the gait). Scaling γ with a power of the stride's peak specific
/// force keeps the walking detector below `p₀` and widens it with the impacts;
/// one setting for every gait, no learned model, the same cost as SHOE.
///
/// A shoe that vibrates (a treadmill, a vehicle floor, a loose mount) raises every
/// window's statistic by the vibration's energy, while the foot still stands still
/// (2 m/s² at 50 Hz moves it by 20 µm): the threshold is also at least
/// [`STILL_FLOOR_MARGIN`] × the statistic of the stillness floor, the quietest
/// windows of the last [`STILL_WINDOW_S`] (issue 39).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveShoe {
    /// Noise levels and γ₀, the threshold at and below `ref_peak_mps2`.
    pub shoe: ShoeDetector,
    /// p₀, m/s²: the peak ‖f‖ up to which the threshold stays γ₀.
    pub ref_peak_mps2: f64,
    /// k: the threshold grows as (peak / p₀)^k above p₀.
    pub exponent: f64,
}

impl Default for AdaptiveShoe {
    /// γ₀ = 2.5·10³, p₀ = 15 m/s², k = 3.5 (σ_a, σ_ω as SHOE's default): chosen on
    /// the training half of the UofT VICON trials with `stridekit eval foot
    /// --tune-adaptive-shoe` (docs/lab/2026-12-06-foot-history.md; the neighbours in the grid score within
    /// 3 %).
    fn default() -> Self {
        Self {
            shoe: ShoeDetector {
                threshold: 2.5e3,
                ..ShoeDetector::default()
            },
            ref_peak_mps2: 15.0,
            exponent: 3.5,
        }
    }
}

impl AdaptiveShoe {
    /// The threshold for a window: the gait's, raised to [`STILL_FLOOR_MARGIN`] × the
    /// stillness floor's statistic when that is higher.
    #[inline]
    pub fn threshold(&self, s: &WindowStats) -> f64 {
        let r = (s.peak_acc_norm_mps2 / self.ref_peak_mps2).max(1.0);
        let gait = self.shoe.threshold * r.powf(self.exponent);
        gait.max(STILL_FLOOR_MARGIN * self.shoe.floor_statistic(s))
    }

    #[inline]
    pub fn is_stance(&self, s: &WindowStats) -> bool {
        let t = self.shoe.statistic(s);
        // The threshold is never below γ₀: the rest only when it can matter.
        t < self.shoe.threshold
            || ((s.peak_acc_norm_mps2 > self.ref_peak_mps2
                || STILL_FLOOR_MARGIN * self.shoe.floor_statistic(s) > self.shoe.threshold)
                && t < self.threshold(s))
    }

    fn validate(&self) -> Result<(), FootError> {
        use super::error::positive;
        self.shoe.validate()?;
        positive("ref_peak_mps2", self.ref_peak_mps2)?;
        if !(self.exponent.is_finite() && (0.0..=10.0).contains(&self.exponent)) {
            return Err(FootError::InvalidConfig {
                field: "exponent",
                reason: "must be finite and 0..=10",
            });
        }
        Ok(())
    }
}

/// Which zero-velocity detector drives the updates.
#[derive(Clone, Debug, PartialEq)]
pub enum ZeroVelocityDetector {
    Fixed(FixedThresholds),
    Adaptive(AdaptiveThresholds),
    /// Six Gaussian-kernel SVMs on (peak ‖f‖, σ of one axis); shared, immutable.
    Svm(Arc<SvmModel>),
    /// The SVM while walking, adaptive thresholds when jogging or running.
    SvmAdaptive(SvmAdaptive),
    Shoe(ShoeDetector),
    /// SHOE with a threshold that follows the gait's intensity (the default).
    AdaptiveShoe(AdaptiveShoe),
}

impl Default for ZeroVelocityDetector {
    /// [`AdaptiveShoe::default`].
    fn default() -> Self {
        ZeroVelocityDetector::AdaptiveShoe(AdaptiveShoe::default())
    }
}

impl ZeroVelocityDetector {
    /// The SVM detector with the model that ships with the SDK.
    pub fn default_svm() -> Self {
        ZeroVelocityDetector::Svm(SvmModel::shared_shipped())
    }

    /// Whether the window says the foot is still. Saturated windows never are.
    #[inline]
    pub fn is_stance(&self, s: &WindowStats) -> bool {
        if s.saturated {
            return false;
        }
        match self {
            ZeroVelocityDetector::Fixed(d) => d.is_stance(s),
            ZeroVelocityDetector::Adaptive(d) => d.is_stance(s),
            ZeroVelocityDetector::Svm(m) => m.is_stance(s),
            ZeroVelocityDetector::SvmAdaptive(d) => d.is_stance(s),
            ZeroVelocityDetector::Shoe(d) => d.is_stance(s),
            ZeroVelocityDetector::AdaptiveShoe(d) => d.is_stance(s),
        }
    }

    pub(crate) fn validate(&self) -> Result<(), FootError> {
        match self {
            ZeroVelocityDetector::Fixed(d) => d.validate(),
            ZeroVelocityDetector::Adaptive(d) => d.validate(),
            ZeroVelocityDetector::Svm(_) => Ok(()),
            ZeroVelocityDetector::SvmAdaptive(d) => d.validate(),
            ZeroVelocityDetector::Shoe(d) => d.validate(),
            ZeroVelocityDetector::AdaptiveShoe(d) => d.validate(),
        }
    }

    /// Short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            ZeroVelocityDetector::Fixed(_) => "fixed",
            ZeroVelocityDetector::Adaptive(_) => "adaptive",
            ZeroVelocityDetector::Svm(_) => "svm",
            ZeroVelocityDetector::SvmAdaptive(_) => "svm+adaptive",
            ZeroVelocityDetector::Shoe(_) => "shoe",
            ZeroVelocityDetector::AdaptiveShoe(_) => "adaptive shoe",
        }
    }
}
