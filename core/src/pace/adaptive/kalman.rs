//! The Kalman machinery of the adaptive filter: prediction with anisotropic
//! acceleration noise, the Joseph-form (Schmidt) update, start, re-anchor, freeing the
//! direction and the zero-velocity update.

use nalgebra::{SMatrix, SVector};

use super::settings::*;
use super::state::{Learn, BE, BN, LA, LB, M8, PE, PN, VE, VN};
use super::AdaptiveFilter;
use crate::pace::LocalFix;

impl AdaptiveFilter {
    /// Propagate the state to time `t` (no-op for t ≤ filter time).
    pub(super) fn predict(&mut self, t: f64) {
        let dt = t - self.t_s;
        // NaN-safe: also returns for a NaN dt.
        if dt.is_nan() || dt <= 0.0 {
            return;
        }
        self.t_s = t;
        let phi = (-dt / self.params.gnss_bias_tau_s).exp();
        self.propagate_mean(dt, phi);
        let q = self.process_noise(dt, phi);
        self.propagate_covariance(dt, phi, &q);
    }

    /// x ← F x with F = I except F[p][v] = dt and F[b][b] = φ.
    fn propagate_mean(&mut self, dt: f64, phi: f64) {
        self.x[PE] += dt * self.x[VE];
        self.x[PN] += dt * self.x[VN];
        self.x[BE] *= phi;
        self.x[BN] *= phi;
    }

    /// Q over `dt`. Acceleration noise is anisotropic: runners change speed gently but
    /// turn hard (cornering v²/r ≈ 2 m/s²). In the (along, cross) basis of the motion
    /// the spectral density is diag(q_along, q_cross); rotated to east/north.
    fn process_noise(&self, dt: f64, phi: f64) -> M8 {
        let prm = &self.params;
        let mut q = M8::zeros();
        let qa = prm.accel_noise_mps2 * prm.accel_noise_mps2;
        let qc = prm.turn_accel_noise_mps2 * prm.turn_accel_noise_mps2;
        let s = self.x[VE].hypot(self.x[VN]);
        let (ue, un) = if s > ISOTROPIC_BELOW_MPS {
            (self.x[VE] / s, self.x[VN] / s)
        } else {
            (1.0, 0.0)
        };
        // Isotropic when slow.
        let w = ((s - ISOTROPIC_BELOW_MPS) / ANISOTROPY_RAMP_MPS).clamp(0.0, 1.0);
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
        q
    }

    /// P ← F P Fᵀ + Q, applying the sparse F to rows, then to columns; variances capped.
    fn propagate_covariance(&mut self, dt: f64, phi: f64, q: &M8) {
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
    pub(super) fn apply<const M: usize>(
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

    /// Update with one scalar measurement; returns the speed information it added
    /// (inverse variance gained along the direction of motion).
    pub(super) fn scalar_update(
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

    /// Start on the first fix: position from it, at rest, GNSS error unknown.
    pub(super) fn init(&mut self, fix: &LocalFix) {
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

    /// Re-anchor position on a fix after an outage; velocity and step length are kept.
    pub(super) fn reanchor(&mut self, fix: &LocalFix) {
        let sig = self.fix_sigma(fix);
        self.x[PE] = fix.east_m;
        self.x[PN] = fix.north_m;
        self.x[BE] = 0.0;
        self.x[BN] = 0.0;
        for i in [PE, PN, BE, BN] {
            self.decorrelate(i);
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

    /// Keep the speed but make its direction unknown (cross-track velocity variance
    /// as large as the speed), so the next fixes can turn it.
    pub(super) fn free_direction(&mut self) {
        let s = FREE_DIRECTION_SPEED_SHARE * self.speed().max(FREE_DIRECTION_MIN_SPEED_MPS);
        for i in [VE, VN] {
            self.decorrelate(i);
            self.p[(i, i)] = s * s;
        }
    }

    /// Zero-velocity update (standing).
    pub(super) fn zupt(&mut self) {
        let mut h = SMatrix::<f64, 2, 8>::zeros();
        h[(0, VE)] = 1.0;
        h[(1, VN)] = 1.0;
        let r = SMatrix::<f64, 2, 2>::identity() * (ZUPT_SIGMA_MPS * ZUPT_SIGMA_MPS);
        let y = SVector::<f64, 2>::new(-self.x[VE], -self.x[VN]);
        if let Some(s_inv) = (h * self.p * h.transpose() + r).try_inverse() {
            self.apply(&h, &y, &r, &s_inv, Learn::Nothing);
        }
    }
}

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
