//! stridekit's default pace filter: an adaptive extended Kalman filter fusing GNSS
//! positions with cadence × learned step length.
//!
//! State (8), local ENU frame:
//! `[east, north, v_east, v_north, gnss_err_east, gnss_err_north, a, b]`
//! - position and velocity of the runner (white-acceleration motion model);
//! - the slowly varying part of the GNSS error, a first-order Gauss–Markov process
//!   (multipath and atmosphere errors are correlated over tens of seconds; modelling
//!   them keeps a slow GNSS drift from being read as running speed);
//! - the step-length line `L(c) = a + b·(c − c̄)`: `a` is the step length at the
//!   runner's recent cadence `c̄` (an EMA over ~1 min), `b` how step length grows with
//!   cadence (runners speed up mostly by longer steps).
//!
//! Measurements:
//! - GNSS position = position + correlated error + white noise. Noise comes from the
//!   fix's horizontal accuracy when given. Robust: when the normalised innovation
//!   squared (NIS) exceeds the 99 % χ² gate the noise is inflated to meet the gate, so
//!   a multipath jump cannot yank the estimate;
//! - pedometer: `|v| = c · L(c)` with noise proportional to speed (gait variability
//!   and cadence error);
//! - stationary (step data flows but no steps): zero velocity.
//!
//! Step length is learned only from trustworthy GNSS (accurate, consistent fixes: NIS
//! average low, not just re-anchored), two ways: through the position residuals (fast,
//! follows interval changes, but reads turns between sparse fixes as shorter steps)
//! and by an explicit measurement, GNSS path length over a 20 s window divided by the
//! steps in it (unaffected by turns, slower). Otherwise the gains of `a`, `b` are
//! zeroed (Schmidt "consider" update, Joseph form so the covariance stays right).
//! During GNSS outages speed therefore comes from cadence × the held step length, and
//! distance keeps growing. After an outage longer than `outage_reset_s`, the position
//! is re-anchored on the first fix without touching velocity: no speed jump.
//!
//! Distance is the trapezoidal integral of the output speed; it does not grow while
//! stationary. Without any step data, a speed below its own 2-σ and below 0.5 m/s is
//! reported as stationary (GNSS jitter is not distance).

use nalgebra::{SMatrix, SVector};

use super::config::AdaptiveParams;
use super::published::{read_estimate, write_estimate};
use super::{Context, LocalFix, PaceConfig, PaceEstimate, PaceSource};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

use super::walking::{is_walk, walk_weight, walking_step_m, WALK_STEP_SIGMA_M};

type V8 = SVector<f64, 8>;
type M8 = SMatrix<f64, 8, 8>;

const PE: usize = 0;
const PN: usize = 1;
const VE: usize = 2;
const VN: usize = 3;
const BE: usize = 4;
const BN: usize = 5;
const LA: usize = 6;
const LB: usize = 7;

/// 99 % χ² gate with 2 degrees of freedom.
const GATE_2DOF: f64 = 9.21;
/// Gate violations in a row (and their minimum duration, s) after which the filter
/// re-anchors on GNSS instead of treating fixes as outliers.
const REANCHOR_AFTER_GATED: u32 = 3;
const REANCHOR_AFTER_S: f64 = 5.0;
/// 99 % χ² gate with 1 degree of freedom.
const GATE_1DOF: f64 = 6.63;
/// 68 % radius of a circular 2-D Gaussian is 1.515 σ per axis.
const RADIUS68_TO_SIGMA: f64 = 1.0 / 1.515;
/// Pedometer (and stationary) updates at most this often, seconds.
const PED_UPDATE_INTERVAL_S: f64 = 1.0;
/// Chords of the step-length path window join fixes at least this far apart, s.
const CHORD_MIN_S: f64 = 4.0;
/// Length of a step-length path window, s, and the fewest steps it needs.
const PATH_WINDOW_S: f64 = 20.0;
const PATH_MIN_STEPS: f64 = 20.0;
/// Without step data, fixes moving slower than this over 15–30 s mean standing, m/s.
const STILL_SPEED_MPS: f64 = 0.35;
const STILL_LEAVE_SPEED_MPS: f64 = 0.6;
const STILL_MIN_SPAN_S: f64 = 15.0;
const STILL_MAX_SPAN_S: f64 = 30.0;
/// Recent fixes kept for the displacement test.
const RECENT_FIXES: usize = 32;
/// Path windows starting sooner than this after a bout start teach no slope, s.
const SLOPE_SETTLE_S: f64 = 20.0;
/// Share of a fix's error that does not cancel between window ends.
const PATH_SIGMA_SHARE: f64 = 0.7;
/// Step data older than this is not used at a fix, seconds.
const STEP_DATA_FRESH_S: f64 = 3.0;
/// Window of the cadence estimate, seconds.
const CADENCE_WINDOW_S: f64 = 4.0;
/// Window of the slow cadence at which the step-length line is read, seconds.
const SLOW_CADENCE_WINDOW_S: f64 = 20.0;
/// Time constant of the reference cadence c̄, seconds.
const CADENCE_REF_TAU_S: f64 = 60.0;
/// ... and while the step length is still unknown, seconds.
const CADENCE_REF_FAST_TAU_S: f64 = 3.0;
/// Cadence at which the initial step length applies, steps/s (168 steps/min).
pub(crate) const PRIOR_CADENCE: f64 = 2.8;
/// Initial step length (at PRIOR_CADENCE) when none is configured, metres, and its 1-σ.
pub(crate) const DEFAULT_STEP_LENGTH_M: f64 = 1.0;
const STEP_LENGTH_PRIOR_SIGMA_M: f64 = 0.4;
/// Prior slope of step length against cadence, m per (step/s), and its 1-σ.
pub(crate) const SLOPE_PRIOR: f64 = 0.5;
const SLOPE_PRIOR_SIGMA: f64 = 0.3;
/// Random walk of the slope of the step-length line, per √s.
const SLOPE_RW: f64 = 0.003;
/// The slope is learned only while the slow cadence is this far from c̄, steps/s
/// (about 5× the noise of the slow cadence: real pace changes, not noise).
const SLOPE_MIN_CADENCE_DEV: f64 = 0.15;
/// Step length counts as learned once its 1-σ is below this, metres.
const LEARNED_SIGMA_M: f64 = 0.08;
/// Smallest cadence 1-σ used, steps/s (the smoothed cadence is correlated in time).
const MIN_CADENCE_SIGMA: f64 = 0.03;
/// Zero-velocity measurement noise while stationary, m/s.
const ZUPT_SIGMA_MPS: f64 = 0.05;
/// Trust in GNSS for learning needs the NIS average below this (2 expected).
const TRUST_NIS: f64 = 4.0;
/// ... with the latest fix at most this old, seconds ...
const TRUST_FIX_AGE_S: f64 = 5.0;
/// ... and this long since the last re-anchor, seconds.
const TRUST_AFTER_RESET_S: f64 = 10.0;
/// Share of a fix's reported error variance taken as white noise (rest: correlated).
const WHITE_SHARE: f64 = 0.35;
/// Initial velocity 1-σ, m/s.
const INITIAL_SPEED_SIGMA: f64 = 3.0;
/// Stationary contradicted by GNSS this many fixes in a row: step data is distrusted.
const CONTRADICTIONS_TO_DISTRUST: u32 = 5;

/// Smallest 1-σ of an imported step length, metres, and its relative change between
/// sessions (added in quadrature).
const CALIBRATION_MIN_SIGMA_M: f64 = 0.01;
/// An imported line at least this uncertain, metres, holds nothing learned (the
/// population prior's is 0.4 m; a line learned from GNSS is within a few cm): it is
/// not imported, so it does not override `initial_step_length_m` or the prior's
/// slope. A calibration exported for its accelerometer model alone (a walk) has one.
const UNLEARNED_LINE_SIGMA_M: f64 = 0.2;
const CALIBRATION_DRIFT: f64 = 0.02;
/// 1-σ of an imported slope, m per (step/s).
const CALIBRATED_SLOPE_SIGMA: f64 = 0.15;

/// A disagreement with GNSS this close to the mean cadence of the line's windows,
/// steps/s (15 steps/min), says the line's level is wrong (`on_pedometer_disagrees`).
const RELEARN_CADENCE_BAND: f64 = 0.25;

/// Steps in accepted path windows before the session mean is exported (≈ 3 min).
const SESSION_MIN_STEPS: f64 = 500.0;

/// What an update may teach the step-length line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Learn {
    Nothing,
    Level,
    LevelAndSlope,
}

impl Learn {
    fn level_if(trusted: bool) -> Self {
        if trusted {
            Learn::Level
        } else {
            Learn::Nothing
        }
    }
}

/// GNSS path length and steps accumulated over a window, to observe step length.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PathWindow {
    active: bool,
    start_t_s: f64,
    start_steps: f64,
    /// Last fix used as a chord end: east, north, t.
    anchor: (f64, f64, f64),
    path_m: f64,
}

impl PathWindow {
    const IDLE: Self = Self {
        active: false,
        start_t_s: 0.0,
        start_steps: 0.0,
        anchor: (0.0, 0.0, 0.0),
        path_m: 0.0,
    };

    fn start(fix: &LocalFix, steps: f64) -> Self {
        Self {
            active: true,
            start_t_s: fix.t_s,
            start_steps: steps,
            anchor: (fix.east_m, fix.north_m, fix.t_s),
            path_m: 0.0,
        }
    }
}

/// State of the adaptive filter.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveFilter {
    params: AdaptiveParams,
    x: V8,
    p: M8,
    initialized: bool,
    /// Filter time, seconds.
    t_s: f64,
    last_fix_t_s: f64,
    last_ped_t_s: f64,
    last_trusted_t_s: f64,
    reset_t_s: f64,
    nis_avg: f64,
    /// Reference cadence c̄ of the step-length line, steps/s (NaN until moving).
    cadence_ref: f64,
    distance_m: f64,
    stationary: bool,
    contradictions: u32,
    steps_distrusted: bool,
    /// Path window observing step length.
    window: PathWindow,
    /// Recent fixes (t, east, north) for GNSS-only stationarity.
    recent_fixes: Ring<[f64; 3], RECENT_FIXES>,
    /// GNSS-only stationarity verdict at the last fix.
    gnss_still: bool,
    /// Previous fix (east, north, t) for GNSS displacement checks.
    prev_fix: (f64, f64, f64),
    /// Consecutive fixes beyond the NIS gate, and since when.
    gated_run: u32,
    gated_since_t_s: f64,
    /// Unit vector of the last direction of motion (east, north); NaN until moving.
    last_dir: (f64, f64),
    /// The cadence is far enough from c̄ for the slope b to be observable.
    slope_observable: bool,
    /// Speed-information gained from GNSS and from the pedometer at the last epoch.
    info_gnss: f64,
    info_ped: f64,
    /// Cadence × step length from the pedometer alone, m/s (NaN before any step data):
    /// the output until GNSS gives a velocity (no GNSS at all, or before the second fix).
    ped_speed: f64,
    /// Step-weighted sums over the accepted path windows of this session: steps,
    /// steps × cadence, steps × step length (the calibration's level and cadence).
    session: [f64; 3],
    /// The latest cadence was a walk (`super::walking`): the pedometer uses the
    /// walking step length, and GNSS teaches the running line nothing.
    walking_gait: bool,
    out: PaceEstimate,
}

fn along(p: &M8, ue: f64, un: f64) -> f64 {
    ue * ue * p[(VE, VE)] + 2.0 * ue * un * p[(VE, VN)] + un * un * p[(VN, VN)]
}

impl AdaptiveFilter {
    pub fn new(config: &PaceConfig) -> Self {
        let mut f = Self {
            params: config.adaptive,
            x: V8::zeros(),
            p: M8::zeros(),
            initialized: false,
            t_s: f64::NAN,
            last_fix_t_s: f64::NAN,
            last_ped_t_s: f64::NEG_INFINITY,
            last_trusted_t_s: f64::NEG_INFINITY,
            reset_t_s: f64::NEG_INFINITY,
            nis_avg: 2.0,
            cadence_ref: f64::NAN,
            distance_m: 0.0,
            stationary: false,
            contradictions: 0,
            steps_distrusted: false,
            slope_observable: false,
            last_dir: (f64::NAN, f64::NAN),
            window: PathWindow::IDLE,
            recent_fixes: Ring::new(),
            gnss_still: false,
            prev_fix: (f64::NAN, f64::NAN, f64::NAN),
            gated_run: 0,
            gated_since_t_s: f64::NAN,
            info_gnss: 0.0,
            info_ped: 0.0,
            ped_speed: f64::NAN,
            session: [0.0; 3],
            walking_gait: false,
            out: PaceEstimate::initial(
                config
                    .calibration
                    .map(|c| c.step_length_m)
                    .or(config.initial_step_length_m),
            ),
        };
        let (l0, sl) = match config.initial_step_length_m {
            Some(l) => (l, 0.1),
            None => (DEFAULT_STEP_LENGTH_M, STEP_LENGTH_PRIOR_SIGMA_M),
        };
        f.x[LA] = l0;
        f.x[LB] = SLOPE_PRIOR;
        f.p[(LA, LA)] = sl * sl;
        f.p[(LB, LB)] = SLOPE_PRIOR_SIGMA * SLOPE_PRIOR_SIGMA;
        let learned = config
            .calibration
            .filter(|c| c.step_length_std_m < UNLEARNED_LINE_SIGMA_M);
        if let Some(c) = learned {
            // The line of an earlier session, read at its own cadence; a little less
            // certain than when exported (shoes, terrain, fatigue change between runs).
            f.x[LA] = c.step_length_m;
            f.x[LB] = c.slope_m_per_spm * 60.0;
            f.cadence_ref = c.cadence_spm / 60.0;
            let sa = c.step_length_std_m.max(CALIBRATION_MIN_SIGMA_M);
            f.p[(LA, LA)] = sa * sa + (CALIBRATION_DRIFT * c.step_length_m).powi(2);
            f.p[(LB, LB)] = CALIBRATED_SLOPE_SIGMA * CALIBRATED_SLOPE_SIGMA;
        }
        f
    }

    fn speed(&self) -> f64 {
        self.x[VE].hypot(self.x[VN])
    }

    /// Variance of the speed along the direction of motion.
    fn speed_var(&self) -> f64 {
        let s = self.speed();
        if s > 1e-3 {
            along(&self.p, self.x[VE] / s, self.x[VN] / s)
        } else {
            0.5 * (self.p[(VE, VE)] + self.p[(VN, VN)])
        }
    }

    fn step_length_at(&self, cadence: f64) -> f64 {
        let cref = if self.cadence_ref.is_finite() {
            self.cadence_ref
        } else {
            cadence
        };
        (self.x[LA] + self.x[LB] * (cadence - cref)).clamp(0.2, 3.0)
    }

    /// Step length for the current gait: the walking step length at the cadence `c`
    /// blended (weight `w`, `super::walking::walk_weight`) with the running line read
    /// at the slow cadence (at `c` when the slow one still says walk: a run just
    /// started). Returns the step length, the cadence the running line was read at,
    /// and `w`.
    fn gait_step_length(&self, c: f64, c_slow: f64) -> (f64, f64, f64) {
        let w = walk_weight(c);
        let c_read = if is_walk(c_slow) { c } else { c_slow };
        let run = if w < 1.0 {
            self.step_length_at(c_read)
        } else {
            0.0
        };
        let walk = if w > 0.0 { walking_step_m(c) } else { 0.0 };
        (w * walk + (1.0 - w) * run, c_read, w)
    }

    fn step_length_learned(&self) -> bool {
        self.p[(LA, LA)].sqrt() < LEARNED_SIGMA_M
    }

    /// Propagate the state to time `t` (no-op for t ≤ filter time).
    fn predict(&mut self, t: f64) {
        let dt = t - self.t_s;
        // NaN-safe: also returns for a NaN dt.
        if dt.is_nan() || dt <= 0.0 {
            return;
        }
        self.t_s = t;
        let prm = &self.params;
        let phi = (-dt / prm.gnss_bias_tau_s).exp();
        // x ← F x with F = I except F[p][v] = dt and F[b][b] = φ.
        self.x[PE] += dt * self.x[VE];
        self.x[PN] += dt * self.x[VN];
        self.x[BE] *= phi;
        self.x[BN] *= phi;
        let mut q = M8::zeros();
        // Acceleration noise is anisotropic: runners change speed gently but turn
        // hard (cornering v²/r ≈ 2 m/s²). In the (along, cross) basis of the motion
        // the spectral density is diag(q_along, q_cross); rotate it to east/north.
        let qa = prm.accel_noise_mps2 * prm.accel_noise_mps2;
        let qc = prm.turn_accel_noise_mps2 * prm.turn_accel_noise_mps2;
        let s = self.x[VE].hypot(self.x[VN]);
        let (ue, un) = if s > 0.5 {
            (self.x[VE] / s, self.x[VN] / s)
        } else {
            (1.0, 0.0)
        };
        let w = ((s - 0.5) / 1.0).clamp(0.0, 1.0); // isotropic when slow
        let qmax = qa.max(qc);
        let aniso = [
            [qa * ue * ue + qc * un * un, (qa - qc) * ue * un],
            [(qa - qc) * ue * un, qa * un * un + qc * ue * ue],
        ];
        let (t1, t2, t3) = (dt * dt * dt / 3.0, dt * dt / 2.0, dt);
        for (a, (pa, va)) in [(PE, VE), (PN, VN)].into_iter().enumerate() {
            for (b, (pb, vb)) in [(PE, VE), (PN, VN)].into_iter().enumerate() {
                let iso = if a == b { qmax } else { 0.0 };
                let g = w * aniso[a][b] + (1.0 - w) * iso;
                q[(pa, pb)] = g * t1;
                q[(pa, vb)] = g * t2;
                q[(va, pb)] = g * t2;
                q[(va, vb)] = g * t3;
            }
        }
        let qb = prm.gnss_bias_sigma_m * prm.gnss_bias_sigma_m * (1.0 - phi * phi);
        q[(BE, BE)] = qb;
        q[(BN, BN)] = qb;
        if !self.walking_gait {
            // The running line drifts while running (fatigue, terrain); a walk
            // neither uses nor teaches it.
            q[(LA, LA)] = prm.step_length_rw_m_per_sqrt_s.powi(2) * dt;
            q[(LB, LB)] = SLOPE_RW * SLOPE_RW * dt;
        }
        // P ← F P Fᵀ + Q, applying the sparse F to rows, then to columns.
        let p = &mut self.p;
        for c in 0..8 {
            p[(PE, c)] += dt * p[(VE, c)];
            p[(PN, c)] += dt * p[(VN, c)];
            p[(BE, c)] *= phi;
            p[(BN, c)] *= phi;
        }
        for r in 0..8 {
            p[(r, PE)] += dt * p[(r, VE)];
            p[(r, PN)] += dt * p[(r, VN)];
            p[(r, BE)] *= phi;
            p[(r, BN)] *= phi;
        }
        *p += q;
        cap_variances(p);
    }

    /// Joseph-form update with gain `k`; rows of the step-length line zeroed unless
    /// `learn` (Schmidt update). Keeps P symmetric.
    fn apply<const M: usize>(
        &mut self,
        h: &SMatrix<f64, M, 8>,
        y: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        s_inv: &SMatrix<f64, M, M>,
        learn: Learn,
    ) {
        let mut k = self.p * h.transpose() * s_inv;
        // The slope is learned only from path windows (accurate mean cadence), once
        // the level is known and the cadence differs from c̄: start-up transients and
        // cadence noise would otherwise be read as a cadence dependence.
        let learn_level = learn != Learn::Nothing;
        let learn_slope =
            learn == Learn::LevelAndSlope && self.step_length_learned() && self.slope_observable;
        for c in 0..M {
            if !learn_level {
                k[(LA, c)] = 0.0;
            }
            if !learn_slope {
                k[(LB, c)] = 0.0;
            }
        }
        self.x += k * y;
        // Joseph form (I−KH)P(I−KH)ᵀ + KRKᵀ, valid for any gain (also the Schmidt
        // one), expanded to avoid 8×8×8 products: P − K·HP − (K·HP)ᵀ + K·S·Kᵀ.
        let hp = h * self.p;
        let s = hp * h.transpose() + r;
        let khp = k * hp;
        let p = self.p - khp - khp.transpose() + k * s * k.transpose();
        self.p = 0.5 * (p + p.transpose());
    }

    fn init(&mut self, fix: &LocalFix) {
        let sig = self.fix_sigma(fix);
        self.x[PE] = fix.east_m;
        self.x[PN] = fix.north_m;
        self.x[VE] = 0.0;
        self.x[VN] = 0.0;
        self.x[BE] = 0.0;
        self.x[BN] = 0.0;
        for i in [PE, PN] {
            self.p[(i, i)] = sig * sig;
        }
        for i in [VE, VN] {
            self.p[(i, i)] = INITIAL_SPEED_SIGMA * INITIAL_SPEED_SIGMA;
        }
        let sb = self.params.gnss_bias_sigma_m;
        for i in [BE, BN] {
            self.p[(i, i)] = sb * sb;
        }
        self.t_s = fix.t_s;
        self.reset_t_s = fix.t_s;
        self.initialized = true;
    }

    /// Per-axis 1-σ of a fix's total error, metres.
    fn fix_sigma(&self, fix: &LocalFix) -> f64 {
        match fix.accuracy_m {
            Some(a) if a > 0.0 => (a * RADIUS68_TO_SIGMA).max(0.5),
            _ => self.params.default_gnss_sigma_m,
        }
    }

    /// Re-anchor position on a fix after an outage; velocity and step length are kept.
    fn reanchor(&mut self, fix: &LocalFix) {
        let sig = self.fix_sigma(fix);
        self.x[PE] = fix.east_m;
        self.x[PN] = fix.north_m;
        self.x[BE] = 0.0;
        self.x[BN] = 0.0;
        for i in [PE, PN, BE, BN] {
            for j in 0..8 {
                self.p[(i, j)] = 0.0;
                self.p[(j, i)] = 0.0;
            }
        }
        for i in [PE, PN] {
            self.p[(i, i)] = sig * sig;
        }
        let sb = self.params.gnss_bias_sigma_m;
        for i in [BE, BN] {
            self.p[(i, i)] = sb * sb;
        }
        self.reset_t_s = fix.t_s;
    }

    /// Whether GNSS may teach step length at `t`: the latest fix was trustworthy and
    /// is recent (receivers and watches deliver fixes 1–5 s apart).
    fn gnss_trusted_at(&self, t: f64) -> bool {
        self.last_trusted_t_s == self.last_fix_t_s && t - self.last_fix_t_s <= TRUST_FIX_AGE_S
    }

    /// GNSS-only stationarity: over the last 15–30 s the fixes moved less than a
    /// slow walk would (`STILL_SPEED_MPS` × span). Used without step data, where GNSS
    /// jitter would otherwise read as motion.
    fn displacement_says_still(&self, fix: &LocalFix) -> Option<bool> {
        let old = self
            .recent_fixes
            .iter()
            .rev()
            .find(|p| fix.t_s - p[0] >= STILL_MIN_SPAN_S)?;
        let span = fix.t_s - old[0];
        if span > STILL_MAX_SPAN_S {
            return None;
        }
        let disp = (fix.east_m - old[1]).hypot(fix.north_m - old[2]);
        // Hysteresis: leaving "still" needs clearly more than entering it.
        let limit = if self.gnss_still {
            STILL_LEAVE_SPEED_MPS
        } else {
            STILL_SPEED_MPS
        };
        Some(disp < limit * span)
    }

    /// Keep the speed but make its direction unknown (cross-track velocity variance
    /// as large as the speed), so the next fixes can turn it.
    fn free_direction(&mut self) {
        let s = 0.5 * self.speed().max(1.0);
        for i in [VE, VN] {
            for j in 0..8 {
                if j != i {
                    self.p[(i, j)] = 0.0;
                    self.p[(j, i)] = 0.0;
                }
            }
            self.p[(i, i)] = s * s;
        }
    }

    fn gnss_update(&mut self, fix: &LocalFix) -> (f64, bool) {
        let total = self.fix_sigma(fix);
        let white = (WHITE_SHARE * total * total).max(0.3 * 0.3);
        // Let the correlated-error state follow what the receiver reports.
        let bias_var = ((1.0 - WHITE_SHARE) * total * total)
            .max(self.params.gnss_bias_sigma_m * self.params.gnss_bias_sigma_m);
        for i in [BE, BN] {
            if self.p[(i, i)] < 0.1 * bias_var {
                self.p[(i, i)] = 0.1 * bias_var;
            }
        }
        let mut h = SMatrix::<f64, 2, 8>::zeros();
        h[(0, PE)] = 1.0;
        h[(0, BE)] = 1.0;
        h[(1, PN)] = 1.0;
        h[(1, BN)] = 1.0;
        let y = SVector::<f64, 2>::new(
            fix.east_m - self.x[PE] - self.x[BE],
            fix.north_m - self.x[PN] - self.x[BN],
        );
        let mut r = SMatrix::<f64, 2, 2>::identity() * white;
        let hp = h * self.p * h.transpose();
        let Some(mut s_inv) = (hp + r).try_inverse() else {
            return (f64::INFINITY, false);
        };
        let nis = (y.transpose() * s_inv * y)[(0, 0)];
        if nis > GATE_2DOF {
            self.gated_run = self.gated_run.saturating_add(1);
            if self.gated_since_t_s.is_nan() {
                self.gated_since_t_s = fix.t_s;
            }
            // GNSS velocity over the last interval: a direction reversal at a plausible
            // speed is a turn between sparse fixes, not an outlier.
            let (pe, pn, pt) = self.prev_fix;
            let dt = fix.t_s - pt;
            let (ue, un) = ((fix.east_m - pe) / dt, (fix.north_m - pn) / dt);
            let u = ue.hypot(un);
            let s = self.speed();
            let reversal = dt > 0.0
                && u > 1.0
                && s > 1.0
                && (ue * self.x[VE] + un * self.x[VN]) < 0.0
                && (0.5..2.0).contains(&(u / s));
            let persistent = self.gated_run >= REANCHOR_AFTER_GATED
                && fix.t_s - self.gated_since_t_s >= REANCHOR_AFTER_S;
            if reversal || persistent {
                // Not a multipath jump but a track the filter lost (a sharp turn
                // between fixes): start again from the fix, keeping the speed and
                // taking the direction from the GNSS displacement.
                log::debug!(
                    "GNSS inconsistent ({} gated fixes): re-anchoring",
                    self.gated_run
                );
                self.reanchor(fix);
                if u > 0.5 {
                    self.x[VE] = s * ue / u;
                    self.x[VN] = s * un / u;
                }
                self.free_direction();
                self.gated_run = 0;
                self.gated_since_t_s = f64::NAN;
                return (nis, false);
            }
        } else {
            self.gated_run = 0;
            self.gated_since_t_s = f64::NAN;
        }
        if nis > GATE_2DOF {
            // Inflate the noise so the innovation sits on the gate (robust update).
            let scale = nis / GATE_2DOF;
            r = (hp + r) * scale - hp;
            match (hp + r).try_inverse() {
                Some(si) => s_inv = si,
                None => return (nis, false),
            }
        }
        self.nis_avg = 0.7 * self.nis_avg + 0.3 * nis.min(50.0);
        let trusted = fix
            .accuracy_m
            .is_none_or(|a| a <= self.params.learn_max_accuracy_m)
            && nis <= GATE_2DOF
            && self.nis_avg < TRUST_NIS
            && fix.t_s - self.reset_t_s > TRUST_AFTER_RESET_S;
        let before = self.speed_var();
        // While walking the speed is the walking line's: GNSS must not teach the
        // running line through the correlations its pedometer updates left.
        self.apply(
            &h,
            &y,
            &r,
            &s_inv,
            Learn::level_if(trusted && !self.walking_gait),
        );
        self.info_gnss += (1.0 / self.speed_var() - 1.0 / before).max(0.0);
        if let Some((v, acc)) = fix.speed {
            self.doppler_update(v, acc);
        }
        (nis, trusted)
    }

    /// Receiver (Doppler) speed as a measurement of |v|. It informs velocity only: a
    /// precise speed every second would otherwise drag the step length onto each
    /// second's speed/cadence ratio (gait variability, cadence lag), and the value held
    /// into an outage would be a noisy snapshot instead of an average.
    fn doppler_update(&mut self, v: f64, acc: f64) {
        let s = self.speed();
        if s < 0.3 {
            return;
        }
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, VE)] = self.x[VE] / s;
        h[(0, VN)] = self.x[VN] / s;
        let r = acc.max(0.05).powi(2);
        let sv = (h * self.p * h.transpose())[(0, 0)] + r;
        if (v - s) * (v - s) / sv > GATE_1DOF {
            return;
        }
        self.info_gnss += self.scalar_update(&h, v - s, r, Learn::Nothing);
    }

    /// Update with one scalar measurement; returns the speed information it added
    /// (inverse variance gained along the direction of motion).
    fn scalar_update(
        &mut self,
        h: &SMatrix<f64, 1, 8>,
        innovation: f64,
        r: f64,
        learn: Learn,
    ) -> f64 {
        let sv = (h * self.p * h.transpose())[(0, 0)] + r;
        let before = self.speed_var();
        self.apply(
            h,
            &SVector::<f64, 1>::new(innovation),
            &SMatrix::<f64, 1, 1>::new(r),
            &SMatrix::<f64, 1, 1>::new(1.0 / sv),
            learn,
        );
        (1.0 / self.speed_var() - 1.0 / before).max(0.0)
    }

    fn zupt(&mut self) {
        let mut h = SMatrix::<f64, 2, 8>::zeros();
        h[(0, VE)] = 1.0;
        h[(1, VN)] = 1.0;
        let r = SMatrix::<f64, 2, 2>::identity() * (ZUPT_SIGMA_MPS * ZUPT_SIGMA_MPS);
        let y = SVector::<f64, 2>::new(-self.x[VE], -self.x[VN]);
        if let Some(s_inv) = (h * self.p * h.transpose() + r).try_inverse() {
            self.apply(&h, &y, &r, &s_inv, Learn::Nothing);
        }
    }

    /// Observe step length from GNSS path length over steps (trusted fixes only).
    ///
    /// Chords between fixes at least `CHORD_MIN_S` apart are summed over a window of
    /// `PATH_WINDOW_S`; path / steps measures the step-length line at the window's
    /// mean cadence. Summing chords keeps turns from being read as shorter steps (a
    /// position residual would be), and long chords keep position noise from
    /// inflating the path: along-track errors telescope to the two window ends.
    fn learn_from_path(&mut self, fix: &LocalFix, ctx: &Context, trusted: bool) {
        let steps_now = ctx.steps.total_at(fix.t_s);
        let usable = trusted && !self.stationary && !self.steps_distrusted;
        let (Some(steps_now), true) = (steps_now, usable) else {
            self.window = PathWindow::IDLE;
            return;
        };
        if !self.window.active {
            self.window = PathWindow::start(fix, steps_now);
            return;
        }
        let (ae, an, at) = self.window.anchor;
        if fix.t_s - at < CHORD_MIN_S {
            return;
        }
        self.window.path_m += (fix.east_m - ae).hypot(fix.north_m - an);
        self.window.anchor = (fix.east_m, fix.north_m, fix.t_s);
        let span = fix.t_s - self.window.start_t_s;
        let steps = steps_now - self.window.start_steps;
        if span < PATH_WINDOW_S {
            return;
        }
        let path = self.window.path_m;
        let start_t = self.window.start_t_s;
        self.window = PathWindow::start(fix, steps_now);
        if steps < PATH_MIN_STEPS {
            return;
        }
        let c_mean = steps / span;
        if is_walk(c_mean) {
            // A walk teaches the running line nothing (and the walking step length is
            // not learned: see `super::walking`).
            return;
        }
        let cref = if self.cadence_ref.is_finite() {
            self.cadence_ref
        } else {
            c_mean
        };
        // Windows right after a start (acceleration from standing) say nothing about
        // how step length grows with cadence.
        let settled = start_t - ctx.steps.bout_start_t_s() >= SLOPE_SETTLE_S;
        self.slope_observable = settled && (c_mean - cref).abs() > SLOPE_MIN_CADENCE_DEV;
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, LA)] = 1.0;
        h[(0, LB)] = c_mean - cref;
        let y = path / steps - (self.x[LA] + self.x[LB] * (c_mean - cref));
        let sigma_path = std::f64::consts::SQRT_2 * PATH_SIGMA_SHARE * self.fix_sigma(fix);
        let r = (sigma_path / steps).powi(2);
        let sv = (h * self.p * h.transpose())[(0, 0)] + r;
        if y * y / sv > GATE_1DOF {
            return;
        }
        self.scalar_update(&h, y, r, Learn::LevelAndSlope);
        // The session's mean line for the calibration record: every accepted window,
        // weighted by its steps.
        let l_obs = path / steps;
        let s = &mut self.session;
        s[0] += steps;
        s[1] += steps * c_mean;
        s[2] += steps * l_obs;
    }

    /// Move the reference cadence c̄ towards `c`, re-expressing `a` so that the
    /// step-length line itself does not change.
    fn track_cadence_ref(&mut self, c: f64, dt: f64) {
        if !self.cadence_ref.is_finite() {
            // The prior step length is stated at PRIOR_CADENCE: read the prior line at
            // the first cadence seen, so a start at low cadence is not taken as the
            // runner's typical cadence.
            self.cadence_ref = c;
            if !self.step_length_learned() {
                self.x[LA] = (self.x[LA] + self.x[LB] * (c - PRIOR_CADENCE)).clamp(0.3, 2.0);
            }
            return;
        }
        // Until the step length is learned the reference follows cadence closely, so
        // start-up transients teach `a`, not the slope `b`.
        let tau = if self.step_length_learned() {
            CADENCE_REF_TAU_S
        } else {
            CADENCE_REF_FAST_TAU_S
        };
        // dt < 0 when the step stream runs behind the fix stream: no move then.
        let delta = (dt / tau).clamp(0.0, 1.0) * (c - self.cadence_ref);
        self.cadence_ref += delta;
        // a' = a + b·Δ  →  T = I with T[LA][LB] = Δ.
        self.x[LA] += self.x[LB] * delta;
        let mut t = M8::identity();
        t[(LA, LB)] = delta;
        self.p = t * self.p * t.transpose();
    }

    fn pedometer_update(&mut self, t: f64, ctx: &Context, learn: bool) {
        if !ctx.steps.has_data() || self.steps_distrusted {
            return;
        }
        let dt = t - self.last_ped_t_s;
        let Some((c, c_sigma)) = ctx.steps.smoothed_cadence(t, ctx.config.stationary_after_s)
        else {
            return;
        };
        self.last_ped_t_s = t;
        let was_stationary = self.stationary;
        self.stationary = c <= 0.0;
        self.walking_gait = is_walk(c);
        if self.stationary {
            self.ped_speed = 0.0;
            self.zupt();
            return;
        }
        // The step-length line is read at a slow cadence: cadence noise in its
        // regressor would otherwise teach b ≈ −a/c (the slope that hides the noise).
        let c_slow = ctx
            .steps
            .cadence_at(t, SLOW_CADENCE_WINDOW_S, ctx.config.stationary_after_s)
            .filter(|&v| v > 0.0)
            .unwrap_or(c);
        self.track_cadence_ref(c_slow, dt.min(10.0));
        let walking = self.walking_gait;
        let (mut l, c_read, mut w) = self.gait_step_length(c, c_slow);
        // GNSS cannot teach the step length now (an outage, a disturbed stretch): with
        // raw acceleration, the calibrated model of these steps' features follows a
        // pace change at the same cadence that the line cannot (see `super::accel`).
        let from_features = if learn {
            None
        } else {
            ctx.accel.and_then(|a| a.step_length_m(t))
        };
        if let Some(lf) = from_features {
            l = lf;
            w = 1.0; // not a state: the line neither enters nor learns
        }
        self.ped_speed = c * l;
        let mut s = self.speed();
        if s < 0.3 {
            if !(was_stationary && self.last_dir.0.is_finite()) {
                // No direction to put the pedometer speed on (start, or a U-turn
                // passing through zero): GNSS will give one.
                return;
            }
            // Moving again after a stop: start from cadence × step length along the
            // last direction of motion, uncertain enough for GNSS to correct quickly.
            let v = c * l;
            self.x[VE] = v * self.last_dir.0;
            self.x[VN] = v * self.last_dir.1;
            for i in [VE, VN] {
                for j in 0..8 {
                    self.p[(i, j)] = 0.0;
                    self.p[(j, i)] = 0.0;
                }
                self.p[(i, i)] = (0.5 * v).powi(2) + 0.25;
            }
            s = v;
        }
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, VE)] = self.x[VE] / s;
        h[(0, VN)] = self.x[VN] / s;
        let v_ped = c * l;
        let rel = self.params.pedometer_rel_sigma;
        let c_sigma = c_sigma.max(MIN_CADENCE_SIGMA);
        let mut r = (rel * v_ped).powi(2)
            + (c_sigma * l).powi(2)
            + (ctx.pedometer_extra_rel_sigma * v_ped).powi(2);
        // The walking line is not a state: its uncertainty is measurement noise here;
        // the running line enters with its weight and learns nothing from a walk.
        if from_features.is_none() {
            r += (c * w * WALK_STEP_SIGMA_M).powi(2);
        }
        h[(0, LA)] = -c * (1.0 - w);
        h[(0, LB)] = -c * (1.0 - w) * (c_read - self.cadence_ref);
        let teach = if walking {
            Learn::Nothing
        } else {
            Learn::level_if(learn)
        };
        self.info_ped += self.scalar_update(&h, v_ped - s, r, teach);
    }

    /// Cadence × step length of the pedometer, m/s (`None` before any step data).
    pub fn pedometer_speed_mps(&self) -> Option<f64> {
        self.ped_speed.is_finite().then_some(self.ped_speed)
    }

    /// The step stream now counts every reported step as `k` steps (strides found,
    /// `super::crosscheck`): the step-length line is re-expressed for the new cadence
    /// so that cadence × step length does not change (a learned line), or restarts
    /// from the prior at the new cadence (a line nothing taught: it was read at a
    /// cadence that was not the runner's). The path window restarts.
    pub fn rescale_steps(&mut self, k: f64) {
        self.window = PathWindow::IDLE;
        let learned = self.step_length_learned();
        if self.cadence_ref.is_finite() {
            self.cadence_ref *= k;
        }
        if learned {
            // L'(c') = L(c)/k with c' = k·c: a' = a/k, b' = b/k².
            let mut t = M8::identity();
            t[(LA, LA)] = 1.0 / k;
            t[(LB, LB)] = 1.0 / (k * k);
            self.x = t * self.x;
            self.p = t * self.p * t.transpose();
        } else {
            self.reset_line();
        }
        // Session sums: steps, steps × cadence, steps × step length.
        self.session[0] *= k;
        self.session[1] *= k * k;
    }

    /// GNSS and the pedometer disagree by a factor (`super::crosscheck`) at a cadence
    /// of `cadence_hz` steps/s. Where the running line was learned (within
    /// `RELEARN_CADENCE_BAND` of the cadence of its windows, or anywhere when nothing
    /// taught it) its level is wrong: it is learned again from GNSS, its uncertainty
    /// reopened to the prior's. Far from there (a shuffle at 135 steps/min in a run
    /// at 170, a sprint) it is the line's extrapolation that fails, and relearning the
    /// level there would spoil it for the runner's own pace: only the pedometer's
    /// weight is lowered, as always while the disagreement lasts
    /// (`Context::pedometer_extra_rel_sigma`). A walk does not use the line.
    pub fn on_pedometer_disagrees(&mut self, cadence_hz: f64) {
        let [n, nc, _] = self.session;
        let learned_at = if n > 0.0 { nc / n } else { f64::NAN };
        let where_learned =
            learned_at.is_nan() || (cadence_hz - learned_at).abs() <= RELEARN_CADENCE_BAND;
        if !self.walking_gait && where_learned {
            let keep_cadence = self.cadence_ref;
            let level = self.x[LA];
            self.reset_line();
            // Reopened around its current level (GNSS corrects it from there).
            self.x[LA] = level;
            self.cadence_ref = keep_cadence;
        }
    }

    /// The step-length line back to the prior (1.0 m at 168 steps/min on the prior
    /// slope) read at the reference cadence, with the prior's uncertainty and no
    /// correlation with the rest of the state.
    fn reset_line(&mut self) {
        for i in [LA, LB] {
            for j in 0..8 {
                self.p[(i, j)] = 0.0;
                self.p[(j, i)] = 0.0;
            }
        }
        let c = if self.cadence_ref.is_finite() {
            self.cadence_ref
        } else {
            PRIOR_CADENCE
        };
        self.x[LA] = (DEFAULT_STEP_LENGTH_M + SLOPE_PRIOR * (c - PRIOR_CADENCE)).clamp(0.3, 2.0);
        self.x[LB] = SLOPE_PRIOR;
        self.p[(LA, LA)] = STEP_LENGTH_PRIOR_SIGMA_M * STEP_LENGTH_PRIOR_SIGMA_M;
        self.p[(LB, LB)] = SLOPE_PRIOR_SIGMA * SLOPE_PRIOR_SIGMA;
    }

    /// Integrate distance up to the filter time and refresh the output.
    fn publish(&mut self, ctx: &Context, t_out: f64) {
        let no_steps = !ctx.steps.has_data() || self.steps_distrusted;
        let ped_only = self.pedometer_only_output(ctx);
        let cadence = ctx
            .steps
            .smoothed_cadence(t_out, ctx.config.stationary_after_s)
            .map(|(c, _)| c);
        let slow =
            ctx.steps
                .cadence_at(t_out, SLOW_CADENCE_WINDOW_S, ctx.config.stationary_after_s);
        // The walking line's share of the step length now (0 when not moving).
        let walk_w = cadence.map_or(0.0, walk_weight);
        // The step length the pedometer speed uses when GNSS cannot teach it and raw
        // acceleration gives one (see `pedometer_update`).
        let from_features = match cadence {
            Some(c) if c > 0.0 && !self.gnss_trusted_at(t_out) => {
                ctx.accel.and_then(|a| a.step_length_m(t_out))
            }
            _ => None,
        };
        let (raw, sd) = if ped_only {
            // σ of cadence × step length: the step length's (the accelerometer
            // model's when it sets it, else the lines') and the gait's.
            let l_run = self.x[LA].max(0.2);
            let s_run = self.p[(LA, LA)].max(0.0).sqrt() / l_run;
            let s_walk = cadence.map_or(0.0, |c| WALK_STEP_SIGMA_M / walking_step_m(c));
            let s_len = from_features
                .and(ctx.accel.and_then(|a| a.rel_sigma()))
                .unwrap_or(walk_w * s_walk + (1.0 - walk_w) * s_run);
            let rel = s_len.hypot(self.params.pedometer_rel_sigma);
            (self.ped_speed, rel * self.ped_speed)
        } else {
            (self.speed(), self.speed_var().sqrt())
        };
        let still = if no_steps {
            self.gnss_still
        } else {
            self.stationary
        };
        let speed = if still { 0.0 } else { raw };
        if raw > 1.0 && !ped_only {
            self.last_dir = (self.x[VE] / raw, self.x[VN] / raw);
        }
        let prev_t = self.out.t_s;
        let dt = t_out - prev_t;
        if self.out.source != PaceSource::Initializing
            && dt > 0.0
            && dt <= super::MAX_INTEGRATION_GAP_S
        {
            self.distance_m += 0.5 * (self.out.speed_mps + speed) * dt;
        }
        let total = self.info_gnss + self.info_ped;
        let w = if ped_only {
            0.0
        } else if total > 0.0 {
            self.info_gnss / total
        } else if t_out - self.last_fix_t_s > 2.0 && !no_steps {
            // GNSS silent, steps arriving: the pedometer carries the speed.
            0.0
        } else {
            self.out.gnss_weight
        };
        let learned = self.step_length_learned();
        let step_length = match (slow, cadence) {
            _ if from_features.is_some() => from_features,
            // Walking or near it (the walking line has a population value from the
            // start): the same blend the pedometer speed uses.
            (_, Some(c)) if walk_w > 0.0 && (learned || walk_w >= 1.0) => Some(
                self.gait_step_length(c, slow.filter(|&v| v > 0.0).unwrap_or(c))
                    .0,
            ),
            (Some(c), _) if c > 0.0 && learned => Some(self.step_length_at(c)),
            // The same physical range as every other reading of the line.
            _ if learned => Some(self.x[LA].clamp(0.2, 3.0)),
            // Not learned yet: the configured one, else the prior the pedometer speed
            // is using whenever steps carry it (a `Pedometer` or `Fused` source).
            _ => ctx.config.initial_step_length_m.or_else(|| {
                (!no_steps && w < 0.8 && cadence.is_some()).then(|| self.x[LA].clamp(0.2, 3.0))
            }),
        };
        self.out = PaceEstimate {
            t_s: t_out,
            speed_mps: speed,
            pace_s_per_km: PaceEstimate::pace_for(speed),
            speed_std_mps: Some(sd),
            cadence_spm: cadence.map(|c| c * 60.0),
            step_length_m: step_length,
            gnss_weight: w,
            distance_m: self.distance_m,
            source: if still {
                PaceSource::Stationary
            } else {
                PaceSource::from_gnss_weight(w)
            },
            flags: super::PaceFlags::default(),
        };
        self.info_gnss = 0.0;
        self.info_ped = 0.0;
    }

    pub fn on_fix(&mut self, fix: &LocalFix, ctx: &Context) -> PaceEstimate {
        if !self.initialized {
            self.init(fix);
            self.last_fix_t_s = fix.t_s;
            self.prev_fix = (fix.east_m, fix.north_m, fix.t_s);
            let t_out = fix.t_s.max(self.out.t_s);
            self.publish(ctx, t_out);
            if !self.pedometer_only_output(ctx) {
                self.out.source = PaceSource::Initializing;
            }
            return self.out;
        }
        let gap = fix.t_s - self.last_fix_t_s;
        self.last_fix_t_s = fix.t_s;
        self.predict(fix.t_s);
        if gap > self.params.outage_reset_s {
            self.reanchor(fix);
        } else {
            let (nis, trusted) = self.gnss_update(fix);
            if trusted {
                self.last_trusted_t_s = fix.t_s;
            }
            self.learn_from_path(fix, ctx, trusted);
            // Step data that says "standing" while GNSS keeps moving far: distrust it.
            if self.stationary && nis > 4.0 * GATE_2DOF {
                self.contradictions = self.contradictions.saturating_add(1);
                if self.contradictions >= CONTRADICTIONS_TO_DISTRUST {
                    log::warn!("step data says stationary but GNSS moves: ignoring steps");
                    self.steps_distrusted = true;
                    self.stationary = false;
                }
            } else {
                self.contradictions = 0;
            }
        }
        self.prev_fix = (fix.east_m, fix.north_m, fix.t_s);
        let no_steps = !ctx.steps.has_data() || self.steps_distrusted;
        self.gnss_still = no_steps
            && self
                .displacement_says_still(fix)
                .unwrap_or(self.gnss_still && fix.t_s - self.last_fix_t_s < STILL_MAX_SPAN_S);
        self.recent_fixes.push([fix.t_s, fix.east_m, fix.north_m]);
        if self.gnss_still {
            self.zupt();
        }
        let learn = self.gnss_trusted_at(fix.t_s);
        // The pedometer constrains speed after every GNSS update, when its data is fresh.
        if ctx
            .steps
            .last_t_s()
            .is_some_and(|ts| fix.t_s - ts <= STEP_DATA_FRESH_S)
            || ctx
                .steps
                .stationary_at(fix.t_s, ctx.config.stationary_after_s)
        {
            self.pedometer_update(fix.t_s, ctx, learn);
        }
        let t_out = self.t_s.max(self.out.t_s);
        self.publish(ctx, t_out);
        self.out
    }

    pub fn on_steps(&mut self, t_s: f64, ctx: &Context) {
        if self.steps_distrusted && ctx.steps.total() > 0.0 {
            // New steps arrived: trust the step stream again.
            if ctx
                .steps
                .cadence_at(t_s, CADENCE_WINDOW_S, ctx.config.stationary_after_s)
                > Some(0.0)
            {
                self.steps_distrusted = false;
                self.contradictions = 0;
            }
        }
        if !self.initialized {
            self.pedometer_only(t_s, ctx);
            return;
        }
        if t_s <= self.t_s {
            return;
        }
        // Between fixes the pedometer carries the state (at most once a second); at a
        // fix it runs right after the GNSS update (see on_fix).
        if t_s - self.last_ped_t_s < PED_UPDATE_INTERVAL_S
            || t_s - self.last_fix_t_s < PED_UPDATE_INTERVAL_S
        {
            return;
        }
        self.predict(t_s);
        let learn = self.gnss_trusted_at(t_s);
        self.pedometer_update(t_s, ctx, learn);
        self.publish(ctx, t_s);
    }

    pub fn estimate(&self, _ctx: &Context) -> PaceEstimate {
        self.out
    }

    /// Whether the output comes from the pedometer alone: step data flows and GNSS has
    /// not given a velocity yet (no fix, or a single one).
    fn pedometer_only_output(&self, ctx: &Context) -> bool {
        ctx.steps.has_data()
            && !self.steps_distrusted
            && self.ped_speed.is_finite()
            && !self.last_dir.0.is_finite()
            && self.speed() < 0.3
    }

    /// Before any GNSS fix: speed is cadence × step length (the calibrated, configured
    /// or prior line read at the cadence, or with raw acceleration and an imported
    /// model the mean modelled length of the last steps), at most once a second;
    /// distance grows.
    fn pedometer_only(&mut self, t: f64, ctx: &Context) {
        if t - self.last_ped_t_s < PED_UPDATE_INTERVAL_S || t <= self.out.t_s {
            return;
        }
        let Some((c, _)) = ctx.steps.smoothed_cadence(t, ctx.config.stationary_after_s) else {
            return;
        };
        let dt = t - self.last_ped_t_s;
        self.last_ped_t_s = t;
        self.stationary = c <= 0.0;
        if self.stationary {
            self.ped_speed = 0.0;
        } else {
            let c_slow = ctx
                .steps
                .cadence_at(t, SLOW_CADENCE_WINDOW_S, ctx.config.stationary_after_s)
                .filter(|&v| v > 0.0)
                .unwrap_or(c);
            self.track_cadence_ref(c_slow, dt.min(10.0));
            // An imported accelerometer model paces these steps by their own
            // features, as in an outage (see `pedometer_update`).
            let l = ctx
                .accel
                .and_then(|a| a.step_length_m(t))
                .unwrap_or_else(|| self.gait_step_length(c, c_slow).0);
            self.ped_speed = c * l;
        }
        self.publish(ctx, t);
    }

    /// The learned step-length line, once learned (1-σ below 8 cm). Its level is the
    /// session's mean (step length over all trusted GNSS windows, at their mean
    /// cadence): the value at the end of a run follows its last minutes (a finish,
    /// a cool-down), the mean is what the next session should start from. Without
    /// such windows (a calibration imported, no GNSS), the filter's line is exported.
    /// The runner's position in the local ENU frame (east, north of the first fix),
    /// metres: the filter's own position state, GNSS-corrected and dead-reckoned in
    /// outages. `None` before the first fix.
    pub fn position_enu_m(&self) -> Option<[f64; 2]> {
        self.initialized.then(|| [self.x[PE], self.x[PN]])
    }

    pub fn calibration(
        &self,
        imported: Option<super::PaceCalibration>,
    ) -> Option<super::PaceCalibration> {
        let [n, nc, nl] = self.session;
        // Enough trusted running windows make the session's line known even if the
        // filter's uncertainty grew since (stops and walks teach the running line
        // nothing); an imported line that no window refined is exported as it came.
        let session_known = n >= SESSION_MIN_STEPS;
        if n == 0.0 && !self.step_length_learned() {
            return imported;
        }
        if !((session_known || self.step_length_learned()) && self.cadence_ref.is_finite()) {
            return None;
        }
        let (level, cadence) = if session_known {
            (nl / n, nc / n)
        } else {
            (self.x[LA], self.cadence_ref)
        };
        self.line_at(level, cadence)
    }

    /// The filter's running line as it stands, learned or not (the prior's, moved to
    /// the first cadence, with its wide 1-σ), once a cadence was seen: what a
    /// calibration holds when only the accelerometer model was learned (a walk).
    pub fn current_line(&self) -> Option<super::PaceCalibration> {
        if !self.cadence_ref.is_finite() {
            return None;
        }
        self.line_at(self.x[LA], self.cadence_ref)
    }

    /// The line with level `level` at `cadence` (steps/s), the filter's slope and σ.
    fn line_at(&self, level: f64, cadence: f64) -> Option<super::PaceCalibration> {
        let c = super::PaceCalibration {
            step_length_m: level.clamp(0.2, 3.0),
            cadence_spm: (cadence * 60.0).clamp(30.0, 300.0),
            slope_m_per_spm: (self.x[LB] / 60.0).clamp(-0.05, 0.05),
            step_length_std_m: self.p[(LA, LA)].max(0.0).sqrt().min(1.0),
            // Added by the tracker, which holds the accelerometer input.
            accel_model: None,
        };
        c.validate().is_ok().then_some(c)
    }

    pub fn write(&self, w: &mut Writer) {
        w.f64s(self.x.as_slice());
        w.f64s(self.p.as_slice());
        w.bool(self.initialized);
        w.f64s(&[
            self.t_s,
            self.last_fix_t_s,
            self.last_ped_t_s,
            self.last_trusted_t_s,
            self.reset_t_s,
            self.nis_avg,
            self.cadence_ref,
            self.distance_m,
            self.info_gnss,
            self.info_ped,
            self.ped_speed,
        ]);
        w.f64s(&self.session);
        w.bool(self.walking_gait);
        w.bool(self.stationary);
        w.u64(self.contradictions as u64);
        w.bool(self.steps_distrusted);
        w.bool(self.slope_observable);
        w.f64s(&[self.last_dir.0, self.last_dir.1]);
        w.u64(self.recent_fixes.len() as u64);
        for p in self.recent_fixes.iter() {
            w.f64s(&p);
        }
        w.bool(self.gnss_still);
        let pw = &self.window;
        w.bool(pw.active);
        w.f64s(&[
            pw.start_t_s,
            pw.start_steps,
            pw.anchor.0,
            pw.anchor.1,
            pw.anchor.2,
            pw.path_m,
        ]);
        w.f64s(&[self.prev_fix.0, self.prev_fix.1, self.prev_fix.2]);
        w.u64(self.gated_run as u64);
        w.f64(self.gated_since_t_s);
        write_estimate(w, &self.out);
    }

    pub fn read(r: &mut Reader, config: &PaceConfig) -> Result<Self, SnapshotError> {
        let mut f = Self::new(config);
        r.f64s(f.x.as_mut_slice())?;
        r.f64s(f.p.as_mut_slice())?;
        f.initialized = r.bool()?;
        // Times start as NaN or −∞ ("none yet"); the cadence reference and the
        // pedometer speed are NaN until moving.
        f.t_s = r.f64_or_nan()?;
        f.last_fix_t_s = r.f64_or_nan()?;
        f.last_ped_t_s = r.time_or_marker()?;
        f.last_trusted_t_s = r.time_or_marker()?;
        f.reset_t_s = r.time_or_marker()?;
        f.nis_avg = r.f64()?;
        f.cadence_ref = r.f64_or_nan()?;
        f.distance_m = r.f64()?;
        f.info_gnss = r.f64()?;
        f.info_ped = r.f64()?;
        f.ped_speed = r.f64_or_nan()?;
        r.f64s(&mut f.session)?;
        f.walking_gait = r.bool()?;
        f.stationary = r.bool()?;
        f.contradictions = r.len(u32::MAX as usize)? as u32;
        f.steps_distrusted = r.bool()?;
        f.slope_observable = r.bool()?;
        // NaN until moving / before the first fix.
        f.last_dir = (r.f64_or_nan()?, r.f64_or_nan()?);
        for _ in 0..r.len(RECENT_FIXES)? {
            let mut p = [0.0; 3];
            r.f64s(&mut p)?;
            f.recent_fixes.push(p);
        }
        f.gnss_still = r.bool()?;
        let active = r.bool()?;
        let mut pw = [0.0; 6];
        r.f64s(&mut pw)?;
        f.window = PathWindow {
            active,
            start_t_s: pw[0],
            start_steps: pw[1],
            anchor: (pw[2], pw[3], pw[4]),
            path_m: pw[5],
        };
        f.prev_fix = (r.f64_or_nan()?, r.f64_or_nan()?, r.f64_or_nan()?);
        f.gated_run = r.len(u32::MAX as usize)? as u32;
        f.gated_since_t_s = r.f64_or_nan()?;
        f.out = read_estimate(r)?;
        f.check_state().map_err(SnapshotError::Invalid)?;
        Ok(f)
    }

    /// Whether a restored state is one the filter can reach: a covariance
    /// (symmetric, non-negative variances), the filter time set once initialised,
    /// non-negative statistics.
    fn check_state(&self) -> Result<(), &'static str> {
        let p = &self.p;
        crate::snapshot::check_covariance(p)?;
        if self.initialized && self.t_s.is_nan() {
            return Err("filter time");
        }
        // Bounds a running filter stays within even on garbage (fixes teleporting
        // across the globe, gaps of months): the variance cap of the prediction. A
        // larger restored variance loses every digit of a later update to rounding and
        // drives a variance negative.
        if self.x.iter().any(|v| v.abs() > 1e12)
            || (0..p.nrows()).any(|i| p[(i, i)] > MAX_VARIANCE * (1.0 + 1e-9))
        {
            return Err("filter state out of range");
        }
        let t_ok = |t: f64| t.is_nan() || t == f64::NEG_INFINITY || t.abs() <= 1e11 + 1.0;
        if ![
            self.t_s,
            self.last_fix_t_s,
            self.last_ped_t_s,
            self.last_trusted_t_s,
            self.reset_t_s,
            self.gated_since_t_s,
            self.window.start_t_s,
        ]
        .into_iter()
        .all(t_ok)
        {
            return Err("filter times");
        }
        let pos_ok = |v: f64| v.is_nan() || v.abs() <= 1e12;
        let positions_ok = pos_ok(self.prev_fix.0)
            && pos_ok(self.prev_fix.1)
            && t_ok(self.prev_fix.2)
            && self
                .recent_fixes
                .iter()
                .all(|f| t_ok(f[0]) && f[1].abs() <= 1e12 && f[2].abs() <= 1e12)
            && pos_ok(self.window.anchor.0)
            && pos_ok(self.window.anchor.1)
            && t_ok(self.window.anchor.2);
        if !positions_ok {
            return Err("filter positions");
        }
        let dir = self.last_dir.0.hypot(self.last_dir.1);
        if !(dir.is_nan() || (dir - 1.0).abs() < 1e-6) {
            return Err("filter direction not a unit vector");
        }
        if !(self.cadence_ref.is_nan() || (0.0..=10.0).contains(&self.cadence_ref)) {
            return Err("filter reference cadence out of range");
        }
        if self.nis_avg > 1e6 || self.info_gnss > 1e12 || self.info_ped > 1e12 {
            return Err("filter statistics out of range");
        }
        if !(0.0..=1e12).contains(&self.window.start_steps)
            || self.window.path_m > 1e13
            || self.distance_m > 1e13
        {
            return Err("filter distances out of range");
        }
        if self.nis_avg < 0.0
            || self.distance_m < 0.0
            || self.info_gnss < 0.0
            || self.info_ped < 0.0
            || self.window.path_m < 0.0
        {
            return Err("filter statistics");
        }
        Ok(())
    }
}

/// Largest variance the filter keeps, in its own units (m², (m/s)², ...): (100 km)².
/// A prediction across a gap of months (the input layer allows jumps up to a year)
/// would otherwise grow P as dt³ past what a snapshot stores (1e30); nothing is
/// known better than this after such a gap anyway.
const MAX_VARIANCE: f64 = 1e10;

/// Scale P as D·P·D with D = diag(min(1, √(MAX_VARIANCE / Pᵢᵢ))): variances capped,
/// correlations kept, P stays symmetric positive semi-definite. A no-op in normal
/// operation.
fn cap_variances(p: &mut M8) {
    let mut d = [1.0; 8];
    let mut any = false;
    for (i, di) in d.iter_mut().enumerate() {
        if p[(i, i)] > MAX_VARIANCE {
            *di = (MAX_VARIANCE / p[(i, i)]).sqrt();
            any = true;
        }
    }
    if any {
        for r in 0..8 {
            for c in 0..8 {
                p[(r, c)] *= d[r] * d[c];
            }
        }
    }
}
