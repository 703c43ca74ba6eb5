//! The GNSS side of the adaptive filter: a fix's noise, the robust position update
//! (gate, re-anchor on a lost track), the receiver speed, trust for learning and
//! GNSS-only stationarity.

use nalgebra::{SMatrix, SVector};

use super::settings::*;
use super::state::{FixPoint, Learn, BE, BN, PE, PN, VE, VN};
use super::AdaptiveFilter;
use crate::pace::{Context, LocalFix};
use crate::stats::{CHI2_99_1DOF, CHI2_99_2DOF, RADIUS68_TO_SIGMA};

/// A fix's position update: measurement matrix, innovation, white noise.
struct PositionUpdate {
    h: SMatrix<f64, 2, 8>,
    y: SVector<f64, 2>,
    r: SMatrix<f64, 2, 2>,
}

impl AdaptiveFilter {
    /// The GNSS update of a fix in the track (no outage before it), what it teaches,
    /// and the step stream's distrust when GNSS contradicts "stationary".
    pub(super) fn update_on_fix(&mut self, fix: &LocalFix, ctx: &Context) {
        let (nis, trusted) = self.gnss_update(fix);
        if trusted {
            self.last_trusted_t_s = fix.t_s;
        }
        self.learn_from_path(fix, ctx, trusted);
        self.check_stationary_against(nis);
    }

    /// Step data that says "standing" while GNSS keeps moving far: distrust it.
    fn check_stationary_against(&mut self, nis: f64) {
        if self.stationary && nis > CONTRADICTION_GATES * CHI2_99_2DOF {
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

    /// Without step data, decide from the fixes' displacement whether the runner
    /// stands, and hold the speed at zero while so.
    pub(super) fn track_gnss_still(&mut self, fix: &LocalFix, ctx: &Context) {
        let no_steps = !ctx.steps.has_data() || self.steps_distrusted;
        self.gnss_still = no_steps
            && self
                .displacement_says_still(fix)
                .unwrap_or(self.gnss_still && fix.t_s - self.last_fix_t_s < STILL_MAX_SPAN_S);
        self.recent_fixes.push(FixPoint::of(fix));
        if self.gnss_still {
            self.zupt();
        }
    }

    /// Per-axis 1-σ of a fix's total error, metres.
    pub(super) fn fix_sigma(&self, fix: &LocalFix) -> f64 {
        match fix.accuracy_m {
            Some(a) if a > 0.0 => (a * RADIUS68_TO_SIGMA).max(MIN_FIX_SIGMA_M),
            _ => self.params.default_gnss_sigma_m,
        }
    }

    /// Whether GNSS may teach step length at `t`: the latest fix was trustworthy and
    /// is recent (receivers and watches deliver fixes 1–5 s apart).
    pub(super) fn gnss_trusted_at(&self, t: f64) -> bool {
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
            .find(|p| fix.t_s - p.t_s >= STILL_MIN_SPAN_S)?;
        let span = fix.t_s - old.t_s;
        if span > STILL_MAX_SPAN_S {
            return None;
        }
        let disp = (fix.east_m - old.east_m).hypot(fix.north_m - old.north_m);
        // Hysteresis: leaving "still" needs clearly more than entering it.
        let limit = if self.gnss_still {
            STILL_LEAVE_SPEED_MPS
        } else {
            STILL_SPEED_MPS
        };
        Some(disp < limit * span)
    }

    /// The robust position update of a fix; returns its NIS and whether GNSS may
    /// teach the step length.
    fn gnss_update(&mut self, fix: &LocalFix) -> (f64, bool) {
        let PositionUpdate { h, y, mut r } = self.position_update(fix);
        let hp = h * self.p * h.transpose();
        let Some(mut s_inv) = (hp + r).try_inverse() else {
            return (f64::INFINITY, false);
        };
        let nis = (y.transpose() * s_inv * y)[(0, 0)];
        if self.track_lost(fix, nis) {
            return (nis, false);
        }
        if nis > CHI2_99_2DOF {
            // Inflate the noise so the innovation sits on the gate (robust update).
            let scale = nis / CHI2_99_2DOF;
            r = (hp + r) * scale - hp;
            match (hp + r).try_inverse() {
                Some(si) => s_inv = si,
                None => return (nis, false),
            }
        }
        self.nis_avg = NIS_AVG_KEEP * self.nis_avg + NIS_AVG_GAIN * nis.min(NIS_AVG_CAP);
        let trusted = self.trusted_fix(fix, nis);
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
        let var = self.fix_sigma(fix).powi(2) + self.params.gnss_bias_sigma_m.powi(2);
        // A fix within the gate was used at its own variance: it speaks for the speed.
        self.chord.on_fix(fix.t_s, var, nis <= CHI2_99_2DOF);
        if let Some((v, acc)) = fix.speed {
            self.doppler_update(v, acc);
        }
        (nis, trusted)
    }

    /// The measurement of a fix (position + correlated error + white noise), with the
    /// correlated-error state raised to follow what the receiver reports.
    fn position_update(&mut self, fix: &LocalFix) -> PositionUpdate {
        let total = self.fix_sigma(fix);
        let white = (WHITE_SHARE * total * total).max(MIN_WHITE_SIGMA_M * MIN_WHITE_SIGMA_M);
        let bias_var = ((1.0 - WHITE_SHARE) * total * total)
            .max(self.params.gnss_bias_sigma_m * self.params.gnss_bias_sigma_m);
        for i in [BE, BN] {
            if self.p[(i, i)] < BIAS_VAR_FLOOR_SHARE * bias_var {
                self.p[(i, i)] = BIAS_VAR_FLOOR_SHARE * bias_var;
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
        let r = SMatrix::<f64, 2, 2>::identity() * white;
        PositionUpdate { h, y, r }
    }

    /// Count fixes beyond the gate; when they say the filter lost the track (a
    /// reversal, or gated too long), re-anchor on the fix and return true.
    fn track_lost(&mut self, fix: &LocalFix, nis: f64) -> bool {
        if nis > CHI2_99_2DOF {
            self.gated_fix_loses_track(fix)
        } else {
            self.gated_run = 0;
            self.gated_since_t_s = f64::NAN;
            false
        }
    }

    /// A fix beyond the gate: counted; true (after a re-anchor) when it and the ones
    /// before say the track is lost.
    fn gated_fix_loses_track(&mut self, fix: &LocalFix) -> bool {
        self.gated_run = self.gated_run.saturating_add(1);
        if self.gated_since_t_s.is_nan() {
            self.gated_since_t_s = fix.t_s;
        }
        // GNSS velocity over the last interval: a direction reversal at a plausible
        // speed is a turn between sparse fixes, not an outlier.
        let FixPoint {
            east_m: pe,
            north_m: pn,
            t_s: pt,
        } = self.prev_fix;
        let dt = fix.t_s - pt;
        let (ue, un) = ((fix.east_m - pe) / dt, (fix.north_m - pn) / dt);
        let u = ue.hypot(un);
        let s = self.speed();
        let reversal = dt > 0.0
            && u > REVERSAL_MIN_SPEED_MPS
            && s > REVERSAL_MIN_SPEED_MPS
            && (ue * self.x[VE] + un * self.x[VN]) < 0.0
            && REVERSAL_SPEED_RATIO.contains(&(u / s));
        let persistent = self.gated_run >= REANCHOR_AFTER_GATED
            && fix.t_s - self.gated_since_t_s >= REANCHOR_AFTER_S;
        if !(reversal || persistent) {
            return false;
        }
        // Not a multipath jump but a track the filter lost (a sharp turn between
        // fixes): start again from the fix, keeping the speed and taking the
        // direction from the GNSS displacement.
        log::debug!(
            "GNSS inconsistent ({} gated fixes): re-anchoring",
            self.gated_run
        );
        self.reanchor(fix);
        if u > REANCHOR_DIRECTION_MIN_MPS {
            self.x[VE] = s * ue / u;
            self.x[VN] = s * un / u;
        }
        self.free_direction();
        self.gated_run = 0;
        self.gated_since_t_s = f64::NAN;
        true
    }

    /// Whether a fix may teach the step length: accurate, within the gate, the NIS
    /// average low, and not just after a re-anchor.
    fn trusted_fix(&self, fix: &LocalFix, nis: f64) -> bool {
        fix.accuracy_m
            .is_none_or(|a| a <= self.params.learn_max_accuracy_m)
            && nis <= CHI2_99_2DOF
            && self.nis_avg < TRUST_NIS
            && fix.t_s - self.reset_t_s > TRUST_AFTER_RESET_S
    }

    /// Receiver (Doppler) speed as a measurement of |v|. It informs velocity only: a
    /// precise speed every second would otherwise drag the step length onto each
    /// second's speed/cadence ratio (gait variability, cadence lag), and the value held
    /// into an outage would be a noisy snapshot instead of an average.
    fn doppler_update(&mut self, v: f64, acc: f64) {
        let s = self.speed();
        if s < MIN_DIRECTED_SPEED_MPS {
            return;
        }
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, VE)] = self.x[VE] / s;
        h[(0, VN)] = self.x[VN] / s;
        let r = acc.max(MIN_DOPPLER_SIGMA_MPS).powi(2);
        let sv = (h * self.p * h.transpose())[(0, 0)] + r;
        if (v - s) * (v - s) / sv > CHI2_99_1DOF {
            return;
        }
        self.info_gnss += self.scalar_update(&h, v - s, r, Learn::Nothing);
    }
}
