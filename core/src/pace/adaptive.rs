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
//! Step length is learned only from trustworthy GNSS: the gains of `a`, `b` are zeroed
//! (Schmidt "consider" update, Joseph form so the covariance stays right) unless the
//! recent fixes are accurate and consistent (NIS average low, not just re-anchored).
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
use crate::snapshot::{Reader, SnapshotError, Writer};

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
/// 99 % χ² gate with 1 degree of freedom.
const GATE_1DOF: f64 = 6.63;
/// 68 % radius of a circular 2-D Gaussian is 1.515 σ per axis.
const RADIUS68_TO_SIGMA: f64 = 1.0 / 1.515;
/// Pedometer (and stationary) updates at most this often, seconds.
const PED_UPDATE_INTERVAL_S: f64 = 1.0;
/// Window of the cadence estimate, seconds.
const CADENCE_WINDOW_S: f64 = 5.0;
/// Time constant of the reference cadence c̄, seconds.
const CADENCE_REF_TAU_S: f64 = 60.0;
/// Initial step length when none is configured, metres, and its 1-σ.
const DEFAULT_STEP_LENGTH_M: f64 = 1.0;
const STEP_LENGTH_PRIOR_SIGMA_M: f64 = 0.4;
/// Prior slope of step length against cadence, m per (step/s), and its 1-σ.
const SLOPE_PRIOR: f64 = 0.5;
const SLOPE_PRIOR_SIGMA: f64 = 0.5;
/// Random walk of the step-length line, per √s.
const STEP_LENGTH_RW: f64 = 0.003;
const SLOPE_RW: f64 = 0.01;
/// Step length counts as learned once its 1-σ is below this, metres.
const LEARNED_SIGMA_M: f64 = 0.08;
/// Cadence error (1-σ), steps/s.
const CADENCE_SIGMA: f64 = 0.04;
/// Zero-velocity measurement noise while stationary, m/s.
const ZUPT_SIGMA_MPS: f64 = 0.05;
/// Trust in GNSS for learning needs the NIS average below this (2 expected).
const TRUST_NIS: f64 = 4.0;
/// ... and this long since the last re-anchor, seconds.
const TRUST_AFTER_RESET_S: f64 = 10.0;
/// Share of a fix's reported error variance taken as white noise (rest: correlated).
const WHITE_SHARE: f64 = 0.35;
/// Initial velocity 1-σ, m/s.
const INITIAL_SPEED_SIGMA: f64 = 3.0;
/// Stationary contradicted by GNSS this many fixes in a row: step data is distrusted.
const CONTRADICTIONS_TO_DISTRUST: u32 = 5;

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
    /// Speed-information gained from GNSS and from the pedometer at the last epoch.
    info_gnss: f64,
    info_ped: f64,
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
            info_gnss: 0.0,
            info_ped: 0.0,
            out: PaceEstimate {
                t_s: 0.0,
                speed_mps: 0.0,
                pace_s_per_km: None,
                speed_std_mps: None,
                cadence_spm: None,
                step_length_m: config.initial_step_length_m,
                gnss_weight: 1.0,
                distance_m: 0.0,
                source: PaceSource::Initializing,
            },
        };
        let (l0, sl) = match config.initial_step_length_m {
            Some(l) => (l, 0.1),
            None => (DEFAULT_STEP_LENGTH_M, STEP_LENGTH_PRIOR_SIGMA_M),
        };
        f.x[LA] = l0;
        f.x[LB] = SLOPE_PRIOR;
        f.p[(LA, LA)] = sl * sl;
        f.p[(LB, LB)] = SLOPE_PRIOR_SIGMA * SLOPE_PRIOR_SIGMA;
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

    fn step_length_learned(&self) -> bool {
        self.p[(LA, LA)].sqrt() < LEARNED_SIGMA_M
    }

    /// Propagate the state to time `t` (no-op for t ≤ filter time).
    fn predict(&mut self, t: f64) {
        let dt = t - self.t_s;
        if !(dt > 0.0) {
            return;
        }
        self.t_s = t;
        let prm = &self.params;
        let mut f = M8::identity();
        f[(PE, VE)] = dt;
        f[(PN, VN)] = dt;
        let phi = (-dt / prm.gnss_bias_tau_s).exp();
        f[(BE, BE)] = phi;
        f[(BN, BN)] = phi;
        self.x = f * self.x;
        let mut q = M8::zeros();
        let qa = prm.accel_noise_mps2 * prm.accel_noise_mps2;
        for (p, v) in [(PE, VE), (PN, VN)] {
            q[(p, p)] = qa * dt * dt * dt / 3.0;
            q[(p, v)] = qa * dt * dt / 2.0;
            q[(v, p)] = qa * dt * dt / 2.0;
            q[(v, v)] = qa * dt;
        }
        let qb = prm.gnss_bias_sigma_m * prm.gnss_bias_sigma_m * (1.0 - phi * phi);
        q[(BE, BE)] = qb;
        q[(BN, BN)] = qb;
        q[(LA, LA)] = STEP_LENGTH_RW * STEP_LENGTH_RW * dt;
        q[(LB, LB)] = SLOPE_RW * SLOPE_RW * dt;
        self.p = f * self.p * f.transpose() + q;
    }

    /// Joseph-form update with gain `k`; rows of the step-length line zeroed unless
    /// `learn` (Schmidt update). Keeps P symmetric.
    fn apply<const M: usize>(
        &mut self,
        h: &SMatrix<f64, M, 8>,
        y: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        s_inv: &SMatrix<f64, M, M>,
        learn: bool,
    ) {
        let mut k = self.p * h.transpose() * s_inv;
        if !learn {
            for c in 0..M {
                k[(LA, c)] = 0.0;
                k[(LB, c)] = 0.0;
            }
        }
        self.x += k * y;
        let ikh = M8::identity() - k * h;
        let p = ikh * self.p * ikh.transpose() + k * r * k.transpose();
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
        self.apply(&h, &y, &r, &s_inv, trusted);
        self.info_gnss += (1.0 / self.speed_var() - 1.0 / before).max(0.0);
        if let Some((v, acc)) = fix.speed {
            self.doppler_update(v, acc, trusted);
        }
        (nis, trusted)
    }

    /// Receiver (Doppler) speed as a measurement of |v|.
    fn doppler_update(&mut self, v: f64, acc: f64, learn: bool) {
        let s = self.speed();
        if s < 0.3 {
            return;
        }
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, VE)] = self.x[VE] / s;
        h[(0, VN)] = self.x[VN] / s;
        let r = SMatrix::<f64, 1, 1>::new(acc.max(0.05).powi(2));
        let y = SVector::<f64, 1>::new(v - s);
        let sv = (h * self.p * h.transpose() + r)[(0, 0)];
        if y[0] * y[0] / sv > GATE_1DOF {
            return;
        }
        let before = self.speed_var();
        self.apply(&h, &y, &r, &SMatrix::<f64, 1, 1>::new(1.0 / sv), learn);
        self.info_gnss += (1.0 / self.speed_var() - 1.0 / before).max(0.0);
    }

    fn zupt(&mut self) {
        let mut h = SMatrix::<f64, 2, 8>::zeros();
        h[(0, VE)] = 1.0;
        h[(1, VN)] = 1.0;
        let r = SMatrix::<f64, 2, 2>::identity() * (ZUPT_SIGMA_MPS * ZUPT_SIGMA_MPS);
        let y = SVector::<f64, 2>::new(-self.x[VE], -self.x[VN]);
        if let Some(s_inv) = (h * self.p * h.transpose() + r).try_inverse() {
            self.apply(&h, &y, &r, &s_inv, false);
        }
    }

    /// Move the reference cadence c̄ towards `c`, re-expressing `a` so that the
    /// step-length line itself does not change.
    fn track_cadence_ref(&mut self, c: f64, dt: f64) {
        if !self.cadence_ref.is_finite() {
            self.cadence_ref = c;
            return;
        }
        let delta = (dt / CADENCE_REF_TAU_S).min(1.0) * (c - self.cadence_ref);
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
        if dt < PED_UPDATE_INTERVAL_S {
            return;
        }
        let Some(c) = ctx
            .steps
            .cadence_at(t, CADENCE_WINDOW_S, ctx.config.stationary_after_s)
        else {
            return;
        };
        self.last_ped_t_s = t;
        self.stationary = c <= 0.0;
        if self.stationary {
            self.zupt();
            return;
        }
        self.track_cadence_ref(c, dt.min(10.0));
        let s = self.speed();
        if s < 0.3 {
            // No direction yet to put the pedometer speed on.
            return;
        }
        let l = self.step_length_at(c);
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, VE)] = self.x[VE] / s;
        h[(0, VN)] = self.x[VN] / s;
        h[(0, LA)] = -c;
        h[(0, LB)] = -c * (c - self.cadence_ref);
        let v_ped = c * l;
        let rel = self.params.pedometer_rel_sigma;
        let r = SMatrix::<f64, 1, 1>::new((rel * v_ped).powi(2) + (CADENCE_SIGMA * l).powi(2));
        let y = SVector::<f64, 1>::new(v_ped - s);
        let sv = (h * self.p * h.transpose() + r)[(0, 0)];
        let before = self.speed_var();
        self.apply(&h, &y, &r, &SMatrix::<f64, 1, 1>::new(1.0 / sv), learn);
        self.info_ped += (1.0 / self.speed_var() - 1.0 / before).max(0.0);
    }

    /// Integrate distance up to the filter time and refresh the output.
    fn publish(&mut self, ctx: &Context, t_out: f64) {
        let no_steps = !ctx.steps.has_data() || self.steps_distrusted;
        let sd = self.speed_var().sqrt();
        let raw = self.speed();
        let still = if no_steps {
            raw < 0.5 && raw < 2.0 * sd
        } else {
            self.stationary
        };
        let speed = if still { 0.0 } else { raw };
        let prev_t = self.out.t_s;
        if self.out.source != PaceSource::Initializing && t_out > prev_t {
            self.distance_m += 0.5 * (self.out.speed_mps + speed) * (t_out - prev_t);
        }
        let total = self.info_gnss + self.info_ped;
        let w = if total > 0.0 {
            self.info_gnss / total
        } else if t_out - self.last_fix_t_s > 2.0 {
            0.0
        } else {
            self.out.gnss_weight
        };
        let cadence = ctx
            .steps
            .cadence_at(t_out, CADENCE_WINDOW_S, ctx.config.stationary_after_s);
        let learned = self.step_length_learned();
        let step_length = match cadence {
            Some(c) if c > 0.0 && learned => Some(self.step_length_at(c)),
            _ if learned => Some(self.x[LA]),
            _ => ctx.config.initial_step_length_m,
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
        };
        self.info_gnss = 0.0;
        self.info_ped = 0.0;
    }

    pub fn on_fix(&mut self, fix: &LocalFix, ctx: &Context) -> PaceEstimate {
        if !self.initialized {
            self.init(fix);
            self.last_fix_t_s = fix.t_s;
            self.publish(ctx, fix.t_s);
            self.out.source = PaceSource::Initializing;
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
            // Step data that says "standing" while GNSS keeps moving far: distrust it.
            if self.stationary && nis > 4.0 * GATE_2DOF {
                self.contradictions += 1;
                if self.contradictions >= CONTRADICTIONS_TO_DISTRUST {
                    log::warn!("step data says stationary but GNSS moves: ignoring steps");
                    self.steps_distrusted = true;
                    self.stationary = false;
                }
            } else {
                self.contradictions = 0;
            }
        }
        let learn = fix.t_s - self.last_trusted_t_s <= 1.5;
        self.pedometer_update(fix.t_s, ctx, learn);
        let t_out = self.t_s.max(self.out.t_s);
        self.publish(ctx, t_out);
        self.out
    }

    pub fn on_steps(&mut self, t_s: f64, ctx: &Context) {
        if self.steps_distrusted && ctx.steps.total() > 0.0 {
            // New steps arrived: trust the step stream again.
            if ctx.steps.cadence_at(t_s, CADENCE_WINDOW_S, ctx.config.stationary_after_s)
                > Some(0.0)
            {
                self.steps_distrusted = false;
                self.contradictions = 0;
            }
        }
        if !self.initialized || t_s <= self.t_s {
            return;
        }
        // Between fixes the pedometer carries the state (at most once a second).
        if t_s - self.last_ped_t_s < PED_UPDATE_INTERVAL_S {
            return;
        }
        self.predict(t_s);
        let learn = t_s - self.last_trusted_t_s <= 1.5;
        self.pedometer_update(t_s, ctx, learn);
        self.publish(ctx, t_s);
    }

    pub fn estimate(&self, _ctx: &Context) -> PaceEstimate {
        self.out
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
        ]);
        w.bool(self.stationary);
        w.u64(self.contradictions as u64);
        w.bool(self.steps_distrusted);
        write_estimate(w, &self.out);
    }

    pub fn read(r: &mut Reader, config: &PaceConfig) -> Result<Self, SnapshotError> {
        let mut f = Self::new(config);
        r.f64s(f.x.as_mut_slice())?;
        r.f64s(f.p.as_mut_slice())?;
        f.initialized = r.bool()?;
        let mut v = [0.0; 10];
        r.f64s(&mut v)?;
        [
            f.t_s,
            f.last_fix_t_s,
            f.last_ped_t_s,
            f.last_trusted_t_s,
            f.reset_t_s,
            f.nis_avg,
            f.cadence_ref,
            f.distance_m,
            f.info_gnss,
            f.info_ped,
        ] = v;
        f.stationary = r.bool()?;
        f.contradictions = r.len(u32::MAX as usize)? as u32;
        f.steps_distrusted = r.bool()?;
        f.out = read_estimate(r)?;
        if f.x.iter().chain(f.p.iter()).any(|v| !v.is_finite()) {
            return Err(SnapshotError::Invalid("filter state"));
        }
        Ok(f)
    }
}
