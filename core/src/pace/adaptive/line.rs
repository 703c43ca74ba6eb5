//! The step-length line `L(c) = a + b·(c − c̄)`: its prior or imported start, reading
//! it at a cadence (blended with the walking line), moving c̄, rescaling it when steps
//! turn out to be strides, relearning it, and exporting it as a calibration.

use super::settings::*;
use super::state::{SessionLine, LA, LB, M8};
use super::AdaptiveFilter;
use crate::pace::walking::{is_walk, walk_weight, walking_step_m};
use crate::pace::{PaceCalibration, PaceConfig};

/// A step length for the current gait (`AdaptiveFilter::gait_step_length`).
pub(super) struct GaitStep {
    /// Step length, metres.
    pub(super) length_m: f64,
    /// Cadence the running line was read at, steps/s.
    pub(super) c_read: f64,
    /// Weight of the walking line.
    pub(super) walk_w: f64,
}

impl AdaptiveFilter {
    /// The line a session starts from: the prior (or the configured step length),
    /// replaced by an imported calibration that holds a learned line.
    pub(super) fn start_line(&mut self, config: &PaceConfig) {
        let (l0, sl) = match config.initial_step_length_m {
            Some(l) => (l, CONFIGURED_STEP_LENGTH_SIGMA_M),
            None => (DEFAULT_STEP_LENGTH_M, STEP_LENGTH_PRIOR_SIGMA_M),
        };
        self.x[LA] = l0;
        self.x[LB] = SLOPE_PRIOR;
        self.p[(LA, LA)] = sl * sl;
        self.p[(LB, LB)] = SLOPE_PRIOR_SIGMA * SLOPE_PRIOR_SIGMA;
        let learned = config
            .calibration
            .filter(|c| c.step_length_std_m < UNLEARNED_LINE_SIGMA_M);
        if let Some(c) = learned {
            // The line of an earlier session, read at its own cadence; a little less
            // certain than when exported (shoes, terrain, fatigue change between runs).
            self.x[LA] = c.step_length_m;
            self.x[LB] = c.slope_m_per_spm * S_PER_MIN;
            self.cadence_ref = c.cadence_spm / S_PER_MIN;
            let sa = c.step_length_std_m.max(CALIBRATION_MIN_SIGMA_M);
            self.p[(LA, LA)] = sa * sa + (CALIBRATION_DRIFT * c.step_length_m).powi(2);
            self.p[(LB, LB)] = CALIBRATED_SLOPE_SIGMA * CALIBRATED_SLOPE_SIGMA;
        }
    }

    /// The running line read at `cadence` (at c̄ before any), in its physical range.
    pub(super) fn step_length_at(&self, cadence: f64) -> f64 {
        let cref = if self.cadence_ref.is_finite() {
            self.cadence_ref
        } else {
            cadence
        };
        (self.x[LA] + self.x[LB] * (cadence - cref)).clamp(MIN_STEP_LENGTH_M, MAX_STEP_LENGTH_M)
    }

    /// The running line's level in its physical range.
    pub(super) fn level_in_range(&self) -> f64 {
        self.x[LA].clamp(MIN_STEP_LENGTH_M, MAX_STEP_LENGTH_M)
    }

    /// Step length for the current gait: the walking step length at the cadence `c`
    /// blended (weight `walk_w`, `walking::walk_weight`) with the running line read
    /// at the slow cadence (at `c` when the slow one still says walk: a run just
    /// started).
    pub(super) fn gait_step_length(&self, c: f64, c_slow: f64) -> GaitStep {
        let w = walk_weight(c);
        let c_read = if is_walk(c_slow) { c } else { c_slow };
        let run = if w < 1.0 {
            self.step_length_at(c_read)
        } else {
            0.0
        };
        let walk = if w > 0.0 { walking_step_m(c) } else { 0.0 };
        GaitStep {
            length_m: w * walk + (1.0 - w) * run,
            c_read,
            walk_w: w,
        }
    }

    /// Move the reference cadence c̄ towards `c`, re-expressing `a` so that the
    /// step-length line itself does not change.
    pub(super) fn track_cadence_ref(&mut self, c: f64, dt: f64) {
        if !self.cadence_ref.is_finite() {
            // The prior step length is stated at PRIOR_CADENCE: read the prior line at
            // the first cadence seen, so a start at low cadence is not taken as the
            // runner's typical cadence.
            self.cadence_ref = c;
            if !self.step_length_learned() {
                self.x[LA] = (self.x[LA] + self.x[LB] * (c - PRIOR_CADENCE))
                    .clamp(MIN_PRIOR_STEP_LENGTH_M, MAX_PRIOR_STEP_LENGTH_M);
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

    /// The step stream now counts every reported step as `k` steps (strides found,
    /// `super::super::crosscheck`): the step-length line is re-expressed for the new
    /// cadence so that cadence × step length does not change (a learned line), or
    /// restarts from the prior at the new cadence (a line nothing taught: it was read
    /// at a cadence that was not the runner's). The path window restarts.
    pub fn rescale_steps(&mut self, k: f64) {
        self.window = super::state::PathWindow::IDLE;
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
        self.session.steps *= k;
        self.session.steps_x_cadence *= k * k;
    }

    /// GNSS and the pedometer disagree by a factor (`super::super::crosscheck`) at a
    /// cadence of `cadence_hz` steps/s. Where the running line was learned (within
    /// `RELEARN_CADENCE_BAND` of the cadence of its windows, or anywhere when nothing
    /// taught it) its level is wrong: it is learned again from GNSS, its uncertainty
    /// reopened to the prior's. Far from there (a shuffle at 135 steps/min in a run
    /// at 170, a sprint) it is the line's extrapolation that fails, and relearning the
    /// level there would spoil it for the runner's own pace: only the pedometer's
    /// weight is lowered, as always while the disagreement lasts
    /// (`Context::pedometer_extra_rel_sigma`). A walk does not use the line.
    pub fn on_pedometer_disagrees(&mut self, cadence_hz: f64) {
        let SessionLine {
            steps: n,
            steps_x_cadence: nc,
            ..
        } = self.session;
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
            self.decorrelate(i);
        }
        let c = if self.cadence_ref.is_finite() {
            self.cadence_ref
        } else {
            PRIOR_CADENCE
        };
        self.x[LA] = (DEFAULT_STEP_LENGTH_M + SLOPE_PRIOR * (c - PRIOR_CADENCE))
            .clamp(MIN_PRIOR_STEP_LENGTH_M, MAX_PRIOR_STEP_LENGTH_M);
        self.x[LB] = SLOPE_PRIOR;
        self.p[(LA, LA)] = STEP_LENGTH_PRIOR_SIGMA_M * STEP_LENGTH_PRIOR_SIGMA_M;
        self.p[(LB, LB)] = SLOPE_PRIOR_SIGMA * SLOPE_PRIOR_SIGMA;
    }

    /// The learned step-length line, once learned (1-σ below 8 cm). Its level is the
    /// session's mean (step length over all trusted GNSS windows, at their mean
    /// cadence): the value at the end of a run follows its last minutes (a finish,
    /// a cool-down), the mean is what the next session should start from. Without
    /// such windows (a calibration imported, no GNSS), the filter's line is exported.
    pub fn calibration(&self, imported: Option<PaceCalibration>) -> Option<PaceCalibration> {
        let SessionLine {
            steps: n,
            steps_x_cadence: nc,
            steps_x_length: nl,
        } = self.session;
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
    pub fn current_line(&self) -> Option<PaceCalibration> {
        if !self.cadence_ref.is_finite() {
            return None;
        }
        self.line_at(self.x[LA], self.cadence_ref)
    }

    /// The line with level `level` at `cadence` (steps/s), the filter's slope and σ.
    fn line_at(&self, level: f64, cadence: f64) -> Option<PaceCalibration> {
        let c = PaceCalibration {
            step_length_m: level.clamp(MIN_STEP_LENGTH_M, MAX_STEP_LENGTH_M),
            cadence_spm: (cadence * S_PER_MIN)
                .clamp(EXPORT_MIN_CADENCE_SPM, EXPORT_MAX_CADENCE_SPM),
            slope_m_per_spm: (self.x[LB] / S_PER_MIN)
                .clamp(-EXPORT_MAX_SLOPE_M_PER_SPM, EXPORT_MAX_SLOPE_M_PER_SPM),
            step_length_std_m: self.p[(LA, LA)].max(0.0).sqrt().min(EXPORT_MAX_SIGMA_M),
            // Added by the tracker, which holds the accelerometer input.
            accel_model: None,
        };
        c.validate().is_ok().then_some(c)
    }
}
