//! Step length of a phone-carrying pedestrian, calibrated online from GNSS
//! (method 3 of docs/architecture.md).
//!
//! [`StepLengthEstimator`] takes the detector's [`StepEvent`]s and GNSS fixes (in a
//! local ENU frame) and returns a step length for every step. Models
//! ([`StepLengthModel`]): constant, linear `L = A·F + B·SV + C` (robust and as
//! published), linear on frequency only (cadence-only devices), Weinberg
//! `L = K·(a_max − a_min)^¼`, and the inverted pendulum `L = K·√h` (h the device's
//! vertical displacement over the step, which the phone navigator measures).
//!
//! **Gait initiation** ([`BoutPosition`]): the models are of steady steps;
//! the first two steps of a walk (the first step, or the first after a stop of
//! [`STOP_S`] or more) get [`GAIT_INITIATION`] (0.6, 0.85) of the model's length, and
//! they do not enter the calibration.
//!
//! **Calibration** follows the paper: while GNSS is good, every 5 steps give one
//! sample (GNSS distance / 5, with the mean features of those steps); every 20 steps
//! (4 samples) the model is refitted by least squares, and successive fits are
//! averaged (the private `calib` module documents both fitting schemes). Once
//! converged, refitting stops (configurable). Convergence: robust models, after
//! `min_fits` fits, when the 1-σ of the step length predicted at the user's mean
//! features is below `converged_rel_sigma` of it; as published, when the averaged
//! fit's prediction moved < 0.5 % on 3 successive fits. The calibration is per-user
//! state, kept by [`snapshot`](StepLengthEstimator::snapshot) /
//! [`restore`](StepLengthEstimator::restore).
//!
//! **Where a step was.** Step times are heel strikes from the detector; each step's
//! position is interpolated linearly between the two fixes around it (steps that
//! arrive ahead of GNSS wait, up to 64 of them, for the next fix; steps that arrive
//! late are located among the last 8 fixes). Sample distances come from these
//! positions.
//!
//! **Good GNSS** (a step is located only when all hold for the two fixes around it):
//! both report a 68 % horizontal accuracy ≤ `max_accuracy_m` (or none); they are at
//! most `max_fix_gap_s` apart; the motion between them is slower than
//! `max_fix_speed_mps` (no jump). A step that cannot be located, a first step of a
//! bout (unknown duration) or a pause longer than `max_step_gap_s` starts a new
//! block. A block's mean step length outside `min_step_length_m..=max_step_length_m`
//! is rejected, and so is a block whose step frequencies spread by more than 1.5×
//! (a missed or doubled detection would make one sample cover 4 or 6 steps).
//!
//! **Deviation from the paper (robust models).** A 5-step GNSS chord (3–6 m) is
//! inflated by position noise: E|d + n| ≈ √(d² + 2σ²), +5 % for 3.5 m and 0.8 m
//! noise per axis, which would bias every model long. The robust models therefore
//! take each sample's distance as its displacement projected on the local direction
//! of travel, the chord of a 10–15-step baseline centred on the sample (zero-mean
//! noise stays zero-mean; consecutive samples share end points, so noise nearly
//! telescopes along a chain of blocks), and reject blocks that are not straight
//! (summed sample chords > `max_detour_ratio` × block chord: a corner or a jump).
//! The as-published variant uses plain chords and has none of the block checks
//! except plausibility.
//!
//! **Measured** (`stridekit eval steplength`: 8 min of calibration, then a 5-minute
//! GNSS outage on the phone simulator, 35 runs over all placements): robust linear
//! mean |error| 0.9 % (worst 2.1 %) wherever calibration saw the outage's gait;
//! constant 5 % (17 % when the walking pace changes); as published 53 %
//! (ill-conditioned 4-sample fits). Known limitation: runners speed up by longer
//! steps at almost the same cadence; calibrated at one running pace, a 10 % faster
//! outage is read 4–5 % short by every model (on real runs with cadence only, up to
//! 10 %).

mod calib;
mod config;
mod error;
mod initiation;

pub use config::{StepLengthConfig, StepLengthModel, PRIOR_LEG_LENGTH_M, PRIOR_PENDULUM_K};
pub use error::StepLengthError;
pub use initiation::{BoutPosition, GAIT_INITIATION, STOP_S};

use crate::input::{self, in_range, Stream};
use calib::{PublishedFit, Regression};

use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stepdetect::StepEvent;

/// Snapshot engine kind byte of the step-length estimator.
const SNAPSHOT_KIND: u8 = 4;
/// Snapshot format version written by this build (3: the pendulum feature per step).
const SNAPSHOT_VERSION: u16 = 3;
/// Steps per calibration sample (paper: 5).
pub const STEPS_PER_SAMPLE: usize = 5;
/// Samples per fit (paper: 4, i.e. every 20 steps).
pub const SAMPLES_PER_FIT: usize = 4;
const BLOCK_STEPS: usize = STEPS_PER_SAMPLE * SAMPLES_PER_FIT;
/// Steps waiting for the next fix.
const PENDING: usize = 64;
/// Recent fixes kept to locate steps.
const FIXES: usize = 8;
/// Step frequency assumed before any step duration is known, steps/s.
const DEFAULT_FREQUENCY_HZ: f64 = 1.8;
/// Longest plausible step duration, seconds (0.2 steps/s).
const MAX_STEP_DURATION_S: f64 = 5.0;
/// A block whose fastest step frequency exceeds its slowest by this factor is
/// rejected: a missed or doubled detection, or a gait change inside the block.
const MAX_BLOCK_FREQUENCY_RATIO: f64 = 1.5;
/// Largest plausible acceleration magnitude, m/s² (±16 g sensors).
const MAX_ACCEL_MPS2: f64 = 400.0;
/// Vertical displacement assumed for the typical step before calibration, m (the
/// prior K then gives 0.76 m).
const DEFAULT_VERTICAL_M: f64 = 0.08;

/// A GNSS fix in the local frame, with its "good" verdict.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Fix {
    t_s: f64,
    east_m: f64,
    north_m: f64,
    good: bool,
}

/// A step's time and features (frequency NaN when unknown), and its position once
/// located.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct StepRec {
    t_s: f64,
    f_hz: f64,
    sv: f64,
    w: f64,
    /// √h of the pendulum model (NaN when unknown).
    sqrt_h: f64,
    east_m: f64,
    north_m: f64,
}

/// Calibration status of an estimator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    /// Current parameters (A, B, C) of `L = θ·x` (x per model: constant (0, 0, 1),
    /// linear (F, SV, 1), F only (F, 0, 1), Weinberg ((a_max − a_min)^¼, 0, 0),
    /// pendulum (√h, 0, 0); for Weinberg and the pendulum, K is the first; for the
    /// constant model, L is the third).
    pub theta: [f64; 3],
    /// Accepted 5-step samples.
    pub samples: u64,
    /// 20-step fits done (blocks accepted).
    pub fits: u32,
    /// Blocks rejected (not straight, implausible, or unsolvable as published).
    pub rejected_blocks: u64,
    /// Whether calibration converged (and, with `freeze_when_converged`, stopped).
    pub converged: bool,
    /// The model's step length at the user's mean calibration features, metres
    /// (the prior's at default features before any sample).
    pub typical_step_length_m: f64,
}

/// Online step-length estimator. See the module documentation for the method.
/// Equality is equality of the state a snapshot keeps (unused buffer slots ignored).
#[derive(Clone, Debug)]
pub struct StepLengthEstimator {
    model: StepLengthModel,
    config: StepLengthConfig,
    fixes: Ring<Fix, FIXES>,
    last_step_t_s: Option<f64>,
    /// Where the last step was in its walk (gait initiation).
    bout: BoutPosition,
    /// Last known step frequency, steps/s (NaN before any).
    last_f_hz: f64,
    pending: Ring<StepRec, PENDING>,
    block: [StepRec; BLOCK_STEPS + 1],
    block_len: usize,
    reg: Regression,
    published: PublishedFit,
    /// Sum of the feature vectors of accepted samples.
    feature_sum: [f64; 3],
    samples: u64,
    fits: u32,
    rejected_blocks: u64,
    converged: bool,
}

impl StepLengthEstimator {
    /// An estimator with a validated configuration, uncalibrated (population prior).
    pub fn new(model: StepLengthModel, config: StepLengthConfig) -> Result<Self, StepLengthError> {
        config.validate()?;
        Ok(Self {
            model,
            config,
            fixes: Ring::new(),
            last_step_t_s: None,
            bout: BoutPosition::STEADY,
            last_f_hz: f64::NAN,
            pending: Ring::new(),
            block: [StepRec::default(); BLOCK_STEPS + 1],
            block_len: 0,
            reg: prior(model, &config),
            published: PublishedFit::NEW,
            feature_sum: [0.0; 3],
            samples: 0,
            fits: 0,
            rejected_blocks: 0,
            converged: false,
        })
    }

    /// An estimator starting from a personal calibration (θ with 1-σ `sigma`, e.g.
    /// learned from earlier walks) instead of the population prior; GNSS still
    /// refines it.
    pub fn calibrated(
        model: StepLengthModel,
        config: StepLengthConfig,
        theta: [f64; 3],
        sigma: [f64; 3],
    ) -> Result<Self, StepLengthError> {
        let mut s = Self::new(model, config)?;
        if !(theta.iter().all(|v| v.is_finite()) && sigma.iter().all(|v| v.is_finite() && *v > 0.0))
        {
            return Err(StepLengthError::InvalidConfig {
                reason: "calibration θ must be finite and σ positive".into(),
            });
        }
        s.reg = Regression::new(theta, sigma);
        Ok(s)
    }

    /// An estimator starting from a personal calibration given as θ, the features x₀
    /// it was calibrated at, the 1-σ of the first two parameters (the slopes of the
    /// linear models) and the 1-σ of the step length at x₀. Centred like this the
    /// parts are nearly independent, where θ's own components are not (a user's
    /// features span a narrow range, so A and C move together); the prior's
    /// covariance is built from them. GNSS still refines it.
    pub fn calibrated_at(
        model: StepLengthModel,
        config: StepLengthConfig,
        theta: [f64; 3],
        x0: [f64; 3],
        slope_sigma: [f64; 2],
        level_sigma: f64,
    ) -> Result<Self, StepLengthError> {
        let mut s = Self::new(model, config)?;
        let bad = || StepLengthError::InvalidConfig {
            reason: "calibration θ, x₀ must be finite and σ positive".into(),
        };
        let finite = theta.iter().chain(&x0).all(|v| v.is_finite());
        let positive = slope_sigma
            .iter()
            .chain([&level_sigma])
            .all(|v| v.is_finite() && *v > 0.0);
        if !(finite && positive && x0[2] != 0.0) {
            return Err(bad());
        }
        // (A, B, L₀) independent with L₀ = θ·x₀, so θ₂ = (L₀ − A·x₀₀ − B·x₀₁) / x₀₂:
        // cov(θ) = J diag(σA², σB², σL²) Jᵀ.
        let d = [
            slope_sigma[0] * slope_sigma[0],
            slope_sigma[1] * slope_sigma[1],
            level_sigma * level_sigma,
        ];
        let j = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-x0[0] / x0[2], -x0[1] / x0[2], 1.0 / x0[2]],
        ];
        let mut cov = [0.0; 9];
        for r in 0..3 {
            for c in 0..3 {
                cov[3 * r + c] = (0..3).map(|k| j[r][k] * d[k] * j[c][k]).sum();
            }
        }
        s.reg = Regression::from_covariance(theta, cov).ok_or_else(bad)?;
        Ok(s)
    }

    /// Mean features of the calibration samples so far (`None` before any).
    pub fn typical_features(&self) -> Option<[f64; 3]> {
        (self.samples > 0).then(|| self.mean_features())
    }

    /// 1-σ of the modelled step length at features `x` (the calibration's
    /// uncertainty), metres.
    pub fn prediction_sigma(&self, x: [f64; 3]) -> f64 {
        self.reg.prediction_sigma(x)
    }

    pub fn model(&self) -> StepLengthModel {
        self.model
    }

    pub fn config(&self) -> &StepLengthConfig {
        &self.config
    }

    /// Whether calibration has stopped learning (converged and frozen).
    fn frozen(&self) -> bool {
        self.converged && self.config.freeze_when_converged
    }

    /// The model's feature vector for a step.
    fn features(&self, f_hz: f64, sv: f64, w: f64, sqrt_h: f64) -> [f64; 3] {
        Self::model_features(self.model, f_hz, sv, w, sqrt_h)
    }

    /// The feature vector x of `L = θ·x` for a step of frequency `f_hz`, magnitude
    /// variance `sv`, Weinberg feature `w` = (a_max − a_min)^¼ and pendulum feature
    /// `sqrt_h` = √(vertical displacement, m) (for calibration done elsewhere, e.g.
    /// from surveyed walks).
    pub fn model_features(
        model: StepLengthModel,
        f_hz: f64,
        sv: f64,
        w: f64,
        sqrt_h: f64,
    ) -> [f64; 3] {
        match model {
            StepLengthModel::Constant => [0.0, 0.0, 1.0],
            StepLengthModel::Linear | StepLengthModel::LinearAsPublished => [f_hz, sv, 1.0],
            StepLengthModel::LinearFrequencyOnly => [f_hz, 0.0, 1.0],
            StepLengthModel::Weinberg => [w, 0.0, 0.0],
            StepLengthModel::Pendulum => [sqrt_h, 0.0, 0.0],
        }
    }

    /// Current parameters.
    fn theta(&self) -> [f64; 3] {
        match self.model {
            StepLengthModel::LinearAsPublished => self.published.theta().unwrap_or(self.reg.theta),
            _ => self.reg.theta,
        }
    }

    fn predict(&self, x: [f64; 3]) -> f64 {
        let t = self.theta();
        let l = t[0] * x[0] + t[1] * x[1] + t[2] * x[2];
        if l.is_finite() {
            l.clamp(self.config.min_step_length_m, self.config.max_step_length_m)
        } else {
            self.config.prior_step_length_m
        }
    }

    /// Mean feature vector of the calibration samples (default features before any).
    fn mean_features(&self) -> [f64; 3] {
        if self.samples == 0 {
            let w = 9.81f64.powf(0.25);
            return self.features(DEFAULT_FREQUENCY_HZ, 0.0, w, DEFAULT_VERTICAL_M.sqrt());
        }
        self.feature_sum.map(|s| s / self.samples as f64)
    }

    /// Marginal 1-σ of θ (robust calibration; the prior's before any sample), for
    /// carrying a calibration to [`Self::calibrated`] in a later session.
    pub fn theta_sigma(&self) -> [f64; 3] {
        self.reg.sigma()
    }

    /// Calibration status.
    pub fn calibration(&self) -> Calibration {
        Calibration {
            theta: self.theta(),
            samples: self.samples,
            fits: self.fits,
            rejected_blocks: self.rejected_blocks,
            converged: self.converged,
            typical_step_length_m: self.predict(self.mean_features()),
        }
    }

    fn validate_step(&self, e: &StepEvent) -> Result<(), StepLengthError> {
        input::time_after(Stream::Steps, e.t_s, self.last_step_t_s)?;
        if !e.duration_s.is_nan() {
            in_range(
                "duration_s",
                e.duration_s,
                1e-3,
                f64::INFINITY,
                "> 0 s or NaN",
            )?;
        }
        in_range(
            "accel_variance_m2ps4",
            e.accel_variance_m2ps4,
            0.0,
            MAX_ACCEL_MPS2 * MAX_ACCEL_MPS2,
            "0..=160000 (m/s²)²",
        )?;
        in_range(
            "accel_min_mps2",
            e.accel_min_mps2,
            0.0,
            MAX_ACCEL_MPS2,
            "0..=400 m/s²",
        )?;
        in_range(
            "accel_max_mps2",
            e.accel_max_mps2,
            e.accel_min_mps2,
            MAX_ACCEL_MPS2,
            "accel_min_mps2..=400 m/s²",
        )?;
        if !e.vertical_displacement_m.is_nan() {
            in_range(
                "vertical_displacement_m",
                e.vertical_displacement_m,
                0.0,
                input::limits::MAX_STEP_VERTICAL_M,
                "0..=2 m or NaN",
            )?;
        }
        Ok(())
    }

    /// The step length of one detected step, metres; the step also feeds the
    /// calibration while GNSS is good. Steps must come in time order.
    pub fn push_step(&mut self, event: &StepEvent) -> Result<f64, StepLengthError> {
        self.validate_step(event)?;
        let f_hz = if event.duration_s.is_finite() && event.duration_s <= MAX_STEP_DURATION_S {
            1.0 / event.duration_s
        } else {
            f64::NAN
        };
        let w = (event.accel_max_mps2 - event.accel_min_mps2).powf(0.25);
        let sv = event.accel_variance_m2ps4;
        let sqrt_h = event.vertical_displacement_m.sqrt();
        let f_for_model = if f_hz.is_finite() {
            f_hz
        } else if self.last_f_hz.is_finite() {
            self.last_f_hz
        } else {
            DEFAULT_FREQUENCY_HZ
        };
        // The model is of steady steps; the first steps from standing are shorter.
        let share = self.bout.next_step(event.t_s, self.last_step_t_s);
        // A feature the model needs but the step lacks (NaN) gives the prior length.
        let x = self.features(f_for_model, sv, w, sqrt_h);
        let length = share * self.predict(x);
        self.last_step_t_s = Some(event.t_s);
        if f_hz.is_finite() {
            self.last_f_hz = f_hz;
        }
        if !self.frozen() {
            let rec = StepRec {
                t_s: event.t_s,
                // An initiation step, or one without the model's feature, only
                // anchors the next calibration block (a NaN frequency does not
                // continue one): the model learns steady, measured steps.
                f_hz: if self.bout.is_steady() && x.iter().all(|v| v.is_finite()) {
                    f_hz
                } else {
                    f64::NAN
                },
                sv,
                w,
                sqrt_h,
                east_m: 0.0,
                north_m: 0.0,
            };
            match self.fixes.newest() {
                Some(f) if f.t_s >= event.t_s => self.locate(rec),
                // Ahead of GNSS (or no fix yet): wait for the next fix.
                _ => self.pending.push(rec),
            }
        }
        Ok(length)
    }

    /// Push one GNSS fix in the local ENU frame (metres) with its 68 % horizontal
    /// accuracy if known. Fixes must come in time order.
    pub fn push_gnss_fix(
        &mut self,
        t_s: f64,
        east_m: f64,
        north_m: f64,
        accuracy_m: Option<f64>,
    ) -> Result<(), StepLengthError> {
        input::time_after(Stream::Gnss, t_s, self.fixes.newest().map(|f| f.t_s))?;
        in_range("east_m", east_m, -1e7, 1e7, "m")?;
        in_range("north_m", north_m, -1e7, 1e7, "m")?;
        if let Some(a) = accuracy_m {
            in_range("accuracy_m", a, 0.0, input::limits::MAX_ACCURACY_M, "m")?;
        }
        self.fixes.push(Fix {
            t_s,
            east_m,
            north_m,
            good: accuracy_m.is_none_or(|a| a <= self.config.max_accuracy_m),
        });
        while let Some(s) = self.pending.get(0) {
            if s.t_s > t_s {
                break;
            }
            self.pending.pop_front();
            if !self.frozen() {
                self.locate(s);
            }
        }
        Ok(())
    }

    /// Position of a step between the two fixes around it, if GNSS there is good.
    fn position(&self, t: f64) -> Option<(f64, f64)> {
        let mut after: Option<Fix> = None;
        for f in self.fixes.iter().rev() {
            if f.t_s >= t {
                after = Some(f);
                continue;
            }
            let a = after?;
            let c = &self.config;
            let dt = a.t_s - f.t_s;
            let d = (a.east_m - f.east_m).hypot(a.north_m - f.north_m);
            if !(f.good && a.good && dt <= c.max_fix_gap_s && d <= c.max_fix_speed_mps * dt) {
                return None;
            }
            let k = (t - f.t_s) / dt;
            return Some((
                f.east_m + k * (a.east_m - f.east_m),
                f.north_m + k * (a.north_m - f.north_m),
            ));
        }
        // A step exactly at the oldest kept fix, or before it.
        match after {
            Some(a) if a.t_s == t && a.good => Some((a.east_m, a.north_m)),
            _ => None,
        }
    }

    /// Locate a step and add it to the current block.
    fn locate(&mut self, mut rec: StepRec) {
        let Some((e, n)) = self.position(rec.t_s) else {
            self.block_len = 0;
            return;
        };
        rec.east_m = e;
        rec.north_m = n;
        let continues = self.block_len > 0
            && rec.f_hz.is_finite()
            && rec.t_s - self.block[self.block_len - 1].t_s <= self.config.max_step_gap_s;
        if !continues {
            self.block[0] = rec;
            self.block_len = 1;
            return;
        }
        self.block[self.block_len] = rec;
        self.block_len += 1;
        if self.block_len == BLOCK_STEPS + 1 {
            self.process_block();
            if !self.frozen() {
                // The next block starts where this one ended (a chain of blocks).
                self.block[0] = self.block[BLOCK_STEPS];
                self.block_len = 1;
            }
        }
    }

    /// Turn a full block (21 located steps: an anchor and 20 steps) into 4 samples
    /// and refit.
    fn process_block(&mut self) {
        let b = &self.block;
        let (be, bn) = (
            b[BLOCK_STEPS].east_m - b[0].east_m,
            b[BLOCK_STEPS].north_m - b[0].north_m,
        );
        let block_chord = be.hypot(bn);
        let mut xs = [[0.0; 3]; SAMPLES_PER_FIT];
        let mut ys = [0.0; SAMPLES_PER_FIT];
        let mut chord_sum = 0.0;
        for j in 0..SAMPLES_PER_FIT {
            let (s0, s1) = (&b[STEPS_PER_SAMPLE * j], &b[STEPS_PER_SAMPLE * (j + 1)]);
            let (de, dn) = (s1.east_m - s0.east_m, s1.north_m - s0.north_m);
            let chord = de.hypot(dn);
            chord_sum += chord;
            // Direction of travel at the sample: the chord of a baseline centred on
            // it (up to 3 samples, inside the block). On a steady curve a centred
            // chord is parallel to the path at its middle, so curvature costs only
            // second-order length.
            let (a0, a1) = (j.saturating_sub(1), (j + 2).min(SAMPLES_PER_FIT));
            let (ue, un) = (
                b[STEPS_PER_SAMPLE * a1].east_m - b[STEPS_PER_SAMPLE * a0].east_m,
                b[STEPS_PER_SAMPLE * a1].north_m - b[STEPS_PER_SAMPLE * a0].north_m,
            );
            let base = ue.hypot(un);
            let dist = match self.model {
                StepLengthModel::LinearAsPublished => chord,
                _ if base > 0.0 => (de * ue + dn * un) / base,
                _ => 0.0,
            };
            ys[j] = dist / STEPS_PER_SAMPLE as f64;
            let steps = &b[STEPS_PER_SAMPLE * j + 1..=STEPS_PER_SAMPLE * (j + 1)];
            let n = STEPS_PER_SAMPLE as f64;
            let f = steps.iter().map(|s| s.f_hz).sum::<f64>() / n;
            let sv = steps.iter().map(|s| s.sv).sum::<f64>() / n;
            let w = steps.iter().map(|s| s.w).sum::<f64>() / n;
            let sqrt_h = steps.iter().map(|s| s.sqrt_h).sum::<f64>() / n;
            xs[j] = self.features(f, sv, w, sqrt_h);
        }
        let c = &self.config;
        let mean_len = ys.iter().sum::<f64>() / SAMPLES_PER_FIT as f64;
        let plausible = (c.min_step_length_m..=c.max_step_length_m).contains(&mean_len);
        let straight = self.model == StepLengthModel::LinearAsPublished
            || chord_sum <= c.max_detour_ratio * block_chord;
        let (f_lo, f_hi) = b[1..].iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), s| {
            (lo.min(s.f_hz), hi.max(s.f_hz))
        });
        let regular = self.model == StepLengthModel::LinearAsPublished
            || f_hi <= MAX_BLOCK_FREQUENCY_RATIO * f_lo;
        if !(plausible && straight && regular) {
            self.rejected_blocks = self.rejected_blocks.saturating_add(1);
            return;
        }
        let mut x_mean = self.feature_sum;
        for x in &xs {
            for i in 0..3 {
                x_mean[i] += x[i];
            }
        }
        let n_after = (self.samples + SAMPLES_PER_FIT as u64) as f64;
        let x_mean = x_mean.map(|s| s / n_after);
        if self.model == StepLengthModel::LinearAsPublished {
            if !self.published.add_block(&xs, &ys, x_mean) {
                self.rejected_blocks = self.rejected_blocks.saturating_add(1);
                return;
            }
        } else {
            for (x, &y) in xs.iter().zip(&ys) {
                self.reg.add(*x, y, c.sample_sigma_m);
            }
            self.reg.solve();
        }
        self.feature_sum = x_mean.map(|m| m * n_after);
        self.samples += SAMPLES_PER_FIT as u64;
        self.fits = self.fits.saturating_add(1);
        self.converged = self.fits >= c.min_fits
            && match self.model {
                StepLengthModel::LinearAsPublished => self.published.converged(c.min_fits),
                _ => {
                    let l = self.predict(x_mean);
                    self.reg.prediction_sigma(x_mean) < c.converged_rel_sigma * l
                }
            };
        if self.frozen() {
            self.pending.clear();
            self.block_len = 0;
        }
    }
}

impl PartialEq for StepLengthEstimator {
    fn eq(&self, other: &Self) -> bool {
        self.snapshot() == other.snapshot()
    }
}

/// The population prior of a model: means and 1-σ of θ.
pub fn prior_of(model: StepLengthModel, c: &StepLengthConfig) -> ([f64; 3], [f64; 3]) {
    let r = prior(model, c);
    let s = [0, 4, 8].map(|i| 1.0 / r.info_diagonal(i).sqrt());
    (r.theta, s)
}

/// The population prior of a model.
fn prior(model: StepLengthModel, c: &StepLengthConfig) -> Regression {
    match model {
        StepLengthModel::Constant => Regression::new(
            [0.0, 0.0, c.prior_step_length_m],
            [1.0, 1.0, c.prior_step_length_sigma_m],
        ),
        StepLengthModel::Weinberg => Regression::new(
            [c.prior_weinberg_k, 0.0, 0.0],
            [c.prior_weinberg_k_sigma, 1.0, 1.0],
        ),
        StepLengthModel::Pendulum => Regression::new(
            [c.prior_pendulum_k, 0.0, 0.0],
            [c.prior_pendulum_k_sigma, 1.0, 1.0],
        ),
        _ => Regression::new(
            [c.prior_a, c.prior_b, c.prior_c],
            [c.prior_a_sigma, c.prior_b_sigma, c.prior_c_sigma],
        ),
    }
}

mod snapshot;
