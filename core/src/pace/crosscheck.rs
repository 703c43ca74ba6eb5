//! Cross-checks between the tracker's two sources: GNSS path speed against the steps,
//! over windows of good fixes. Does the input count steps or strides (a factor of 2
//! a population gait model tells apart), and does the pedometer's speed agree at all?
//!
//! **Windows.** Fixes with an accuracy ≤ 12 m (or none), ≤ 10 s apart, while steps
//! flow (fresh, not standing): the GNSS path is the sum of chords between fixes
//! ≥ 8 s apart (position noise stays small against 20–30 m chords), the steps are
//! the stream's total over the same span, the pedometer distance the integral of the
//! filter's cadence × step length. A window closes at the first chord end ≥ 25 s
//! after its start (three chords: long enough that a disturbed receiver's jumps
//! show, short enough for two windows to take a minute). Windows slower
//! than 1 m/s (noise) or faster than 12 m/s, or with fewer than 30 reports per
//! minute, say nothing.
//!
//! **Steps or strides.** From a window's GNSS speed v and reported cadence c the
//! step length the report implies is v/c. Under "steps" it is compared with the
//! population's step length at cadence c, under "strides" (every report is two steps)
//! v/(2c) with the population's at 2c; the population is the walking line below
//! 132 steps/min blended into the running prior above (`super::walking`, 1.0 m at
//! 168 steps/min), with a spread between people (1-σ of the log) of 0.2 walking and
//! 0.3 running. Each
//! window adds the log-likelihood ratio of the two (capped at ±8: one window cannot
//! decide); "strides" is impossible when 2c exceeds 300 steps/min, and a window
//! that neither fits within 3 σ (a bicycle, a car) says nothing. The sum, kept within
//! ±24, decides at ±12: two clear windows (about a minute) turn "strides" on, and
//! the step stream is doubled from then on (`StepStream::rescale`); the same
//! evidence the other way turns it off. The physics behind it: a walk takes
//! 90–130 steps/min at 0.8–1.8 m/s, a run 140–200 at 2–6 m/s; 70–100 "steps" per
//! minute at 2.5 m/s or more would be steps of over 1.6 m, which no one takes at
//! that cadence, but strides of that length are an ordinary jog.
//!
//! **Disagreement.** The ratio of the GNSS path to the pedometer's distance over
//! each window: two windows in a row beyond a factor of 1.35 the same way raise
//! [`PaceFlags::pedometer_disagrees`] (the filter then lowers the pedometer's
//! weight and learns the step length again: `super::adaptive`); a window within a
//! factor of 1.15 clears it.
//!
//! **No GNSS.** Without GNSS windows that settled the question, a cadence of
//! 60–100 per minute for a minute raises [`PaceFlags::cadence_may_be_strides`]: a slow
//! walk or strides, which steps alone cannot tell apart.

// The population's running step length (1.0 m at 168 steps/min, 0.5 m per step/s):
// the adaptive filter's prior.
use super::adaptive::{DEFAULT_STEP_LENGTH_M, PRIOR_CADENCE, SLOPE_PRIOR};
use super::steps::StepStream;
use super::types::PaceFlags;
use super::walking::{walk_weight, walking_step_m};
use super::LocalFix;
use crate::input::limits::MAX_CADENCE_SPM;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Shortest window, s.
const WINDOW_S: f64 = 25.0;
/// Chords of a window's GNSS path join fixes at least this far apart, s.
const CHORD_MIN_S: f64 = 8.0;
/// A longer gap between fixes restarts the window, s.
const MAX_FIX_GAP_S: f64 = 10.0;
/// Fixes with a worse 68 % accuracy restart the window, m.
const MAX_ACCURACY_M: f64 = 12.0;
/// Step data older than this at a fix restarts the window, s.
const STEP_DATA_FRESH_S: f64 = 3.0;
/// Windows slower than this (position noise dominates) or faster say nothing, m/s.
const MIN_SPEED_MPS: f64 = 1.0;
const MAX_SPEED_MPS: f64 = 12.0;
/// Windows with fewer step reports per second than this say nothing (30 per minute).
const MIN_REPORT_HZ: f64 = 0.5;
/// A window whose fix-to-fix path is longer than its chord path by more than this
/// factor is not consistent (positions jumping: multipath, a disturbed receiver) and
/// says nothing; a clean track's is within a few %.
const MAX_JITTER_RATIO: f64 = 1.3;

/// Range of the running line read far from its cadence, m.
const RUN_STEP_RANGE_M: (f64, f64) = (0.3, 2.5);
/// Spread of step length between people at one cadence, 1-σ of its logarithm: walking
/// (the walking line's 0.12 m of 0.72 m, `super::walking`, rounded up) and running
/// (the running prior's 0.4 m of 1.0 m, less the part the speed explains).
const WALK_LN_SIGMA: f64 = 0.2;
const RUN_LN_SIGMA: f64 = 0.3;
/// A window whose implied step length is beyond this many σ of both hypotheses
/// says nothing about them.
const FIT_SIGMAS: f64 = 3.0;
/// Log-likelihood ratio one window may add (it cannot decide alone), the sum that
/// decides, and the bound of the sum (how far evidence can be undone).
const WINDOW_EVIDENCE_CAP: f64 = 8.0;
const DECIDE_EVIDENCE: f64 = 12.0;
const MAX_EVIDENCE: f64 = 24.0;

/// A window whose GNSS path and pedometer distance differ by more than this factor
/// disagrees (a factor, not noise: the learned line is within a few %, the walking
/// line within ≈ 20 % of a walker's own), and one within the second agrees.
const DISAGREE_RATIO: f64 = 1.35;
const AGREE_RATIO: f64 = 1.15;
/// Disagreeing windows in a row (the same way) that raise the flag.
const DISAGREE_WINDOWS: u32 = 2;

/// Reported cadence, per minute, that could be strides as well as a slow walk.
const LOW_CADENCE_SPM: (f64, f64) = (60.0, 100.0);
/// ... held this long before the flag is raised, s.
const LOW_CADENCE_FOR_S: f64 = 60.0;
/// Window of the cadence judged for it, s.
const LOW_CADENCE_WINDOW_S: f64 = 20.0;

/// Population step length at a cadence (steps/s), m: the walking line blended into
/// the running prior, as the adaptive filter's prior reads them.
pub(crate) fn population_step_m(cadence: f64) -> f64 {
    let w = walk_weight(cadence);
    let (lo, hi) = RUN_STEP_RANGE_M;
    let run = (DEFAULT_STEP_LENGTH_M + SLOPE_PRIOR * (cadence - PRIOR_CADENCE)).clamp(lo, hi);
    w * walking_step_m(cadence) + (1.0 - w) * run
}

/// The spread of step length between people at a cadence (steps/s): the walking
/// one blended into the running one as the step lengths are.
fn gait_ln_sigma(cadence: f64) -> f64 {
    let w = walk_weight(cadence);
    w * WALK_LN_SIGMA + (1.0 - w) * RUN_LN_SIGMA
}

/// Log-likelihood ratio "strides" against "steps" of a window with GNSS speed
/// `v_mps` and reported cadence `c` (per second).
fn stride_evidence(v_mps: f64, c: f64) -> f64 {
    if 2.0 * c * 60.0 > MAX_CADENCE_SPM {
        return -WINDOW_EVIDENCE_CAP;
    }
    let implied = v_mps / c;
    let e_steps = (implied / population_step_m(c)).ln() / gait_ln_sigma(c);
    let e_strides = (implied / (2.0 * population_step_m(2.0 * c))).ln() / gait_ln_sigma(2.0 * c);
    if e_steps.abs() > FIT_SIGMAS && e_strides.abs() > FIT_SIGMAS {
        return 0.0;
    }
    (0.5 * (e_steps * e_steps - e_strides * e_strides))
        .clamp(-WINDOW_EVIDENCE_CAP, WINDOW_EVIDENCE_CAP)
}

/// What a fix told the cross-check, for the tracker to act on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Finding {
    Nothing,
    /// Count every reported step as this many steps more (2: strides found; ½: back).
    Rescale(f64),
    /// The pedometer started to disagree with GNSS, at this cadence (steps/s, the
    /// last window's mean).
    Disagrees {
        cadence_hz: f64,
    },
}

/// A window of good fixes being summed.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Window {
    active: bool,
    start_t_s: f64,
    /// Step total (the stream's, in steps) at the start.
    start_steps: f64,
    /// Last chord end: east, north, t.
    anchor: [f64; 3],
    path_m: f64,
    /// Sum of the fix-to-fix chords (the path with every fix's noise in it), m.
    fix_path_m: f64,
    pedometer_m: f64,
    /// Previous fix of the window (east, north, t) and the pedometer speed there.
    last: [f64; 3],
    last_pedometer_mps: f64,
}

impl Window {
    const IDLE: Self = Self {
        active: false,
        start_t_s: 0.0,
        start_steps: 0.0,
        anchor: [0.0; 3],
        path_m: 0.0,
        fix_path_m: 0.0,
        pedometer_m: 0.0,
        last: [0.0; 3],
        last_pedometer_mps: 0.0,
    };

    fn start(fix: &LocalFix, steps: f64, pedometer_mps: f64) -> Self {
        Self {
            active: true,
            start_t_s: fix.t_s,
            start_steps: steps,
            anchor: [fix.east_m, fix.north_m, fix.t_s],
            path_m: 0.0,
            fix_path_m: 0.0,
            pedometer_m: 0.0,
            last: [fix.east_m, fix.north_m, fix.t_s],
            last_pedometer_mps: pedometer_mps,
        }
    }
}

/// State of the cross-checks (kept in the tracker's snapshot).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CrossCheck {
    window: Window,
    /// Summed log-likelihood ratio "strides" against "steps".
    stride_evidence: f64,
    /// Disagreeing windows in a row, and their sign (+1: GNSS longer).
    disagree_run: u32,
    disagree_sign: f64,
    /// |log| of the GNSS / pedometer ratio of the last window while disagreeing (0
    /// while they agree).
    disagreement_ln: f64,
    /// Since when the reported cadence is in the low band (NaN: it is not).
    low_cadence_since_t_s: f64,
    flags: PaceFlags,
}

impl CrossCheck {
    pub fn new() -> Self {
        Self {
            window: Window::IDLE,
            stride_evidence: 0.0,
            disagree_run: 0,
            disagree_sign: 0.0,
            disagreement_ln: 0.0,
            low_cadence_since_t_s: f64::NAN,
            flags: PaceFlags::default(),
        }
    }

    pub fn flags(&self) -> PaceFlags {
        self.flags
    }

    /// Relative 1-σ to add to the pedometer's speed while it disagrees with GNSS
    /// (the |log| of their ratio over the last window; 0 while they agree).
    pub fn pedometer_extra_rel_sigma(&self) -> f64 {
        if self.flags.pedometer_disagrees {
            self.disagreement_ln
        } else {
            0.0
        }
    }

    /// A fix the tracker accepted; `pedometer_mps` the filter's cadence × step
    /// length after it (`None` when it has none).
    pub fn on_fix(
        &mut self,
        fix: &LocalFix,
        steps: &StepStream,
        pedometer_mps: Option<f64>,
        stationary_after_s: f64,
    ) -> Finding {
        let fresh = steps
            .last_t_s()
            .is_some_and(|t| fix.t_s - t <= STEP_DATA_FRESH_S);
        let total = steps.total_at(fix.t_s);
        let usable = fix.accuracy_m.is_none_or(|a| a <= MAX_ACCURACY_M)
            && fresh
            && !steps.stationary_at(fix.t_s, stationary_after_s);
        let (Some(total), true) = (total, usable) else {
            self.window = Window::IDLE;
            return Finding::Nothing;
        };
        let ped = pedometer_mps.filter(|v| v.is_finite()).unwrap_or(0.0);
        let w = &mut self.window;
        let [le, ln, lt] = w.last;
        if !w.active || fix.t_s - lt > MAX_FIX_GAP_S {
            *w = Window::start(fix, total, ped);
            return Finding::Nothing;
        }
        w.pedometer_m += 0.5 * (w.last_pedometer_mps + ped) * (fix.t_s - lt);
        w.fix_path_m += (fix.east_m - le).hypot(fix.north_m - ln);
        w.last = [fix.east_m, fix.north_m, fix.t_s];
        w.last_pedometer_mps = ped;
        let [ae, an, at] = w.anchor;
        if fix.t_s - at < CHORD_MIN_S {
            return Finding::Nothing;
        }
        w.path_m += (fix.east_m - ae).hypot(fix.north_m - an);
        w.anchor = [fix.east_m, fix.north_m, fix.t_s];
        let span = fix.t_s - w.start_t_s;
        if span < WINDOW_S {
            return Finding::Nothing;
        }
        let done = *w;
        *w = Window::start(fix, total, ped);
        let reported = (total - done.start_steps) / steps.steps_per_report();
        self.judge(&done, span, reported, steps.steps_per_report())
    }

    /// Evidence from a closed window: `reported` step reports over `span` seconds.
    fn judge(&mut self, w: &Window, span: f64, reported: f64, steps_per_report: f64) -> Finding {
        let v = w.path_m / span;
        let c = reported / span;
        let consistent = w.fix_path_m <= MAX_JITTER_RATIO * w.path_m;
        if !(MIN_SPEED_MPS..=MAX_SPEED_MPS).contains(&v) || c < MIN_REPORT_HZ || !consistent {
            return Finding::Nothing;
        }
        self.stride_evidence =
            (self.stride_evidence + stride_evidence(v, c)).clamp(-MAX_EVIDENCE, MAX_EVIDENCE);
        let want = if self.stride_evidence >= DECIDE_EVIDENCE {
            2.0
        } else if self.stride_evidence <= -DECIDE_EVIDENCE {
            1.0
        } else {
            steps_per_report
        };
        if want != steps_per_report {
            log::warn!(
                "step data counts {}: {} steps per report from now on",
                if want == 2.0 { "strides" } else { "steps" },
                want
            );
            self.flags.cadence_doubled = want == 2.0;
            self.flags.cadence_may_be_strides = false;
            self.clear_disagreement();
            // The window's sums are in the old unit.
            self.window = Window::IDLE;
            return Finding::Rescale(want / steps_per_report);
        }
        if w.pedometer_m > 0.0 {
            return self.judge_agreement(w.path_m / w.pedometer_m, c * steps_per_report);
        }
        Finding::Nothing
    }

    /// The GNSS path over the pedometer distance of a window with a mean cadence of
    /// `cadence_hz` steps/s.
    fn judge_agreement(&mut self, ratio: f64, cadence_hz: f64) -> Finding {
        let ln = ratio.ln();
        if ln.abs() < AGREE_RATIO.ln() {
            self.clear_disagreement();
            return Finding::Nothing;
        }
        if ln.abs() <= DISAGREE_RATIO.ln() {
            // Neither agreement nor a factor: the run of disagreeing windows breaks,
            // the flag (if raised) stays.
            self.disagree_run = 0;
            return Finding::Nothing;
        }
        let sign = ln.signum();
        self.disagree_run = if sign == self.disagree_sign {
            self.disagree_run.saturating_add(1)
        } else {
            1
        };
        self.disagree_sign = sign;
        if self.flags.pedometer_disagrees {
            self.disagreement_ln = ln.abs();
            return Finding::Nothing;
        }
        if self.disagree_run < DISAGREE_WINDOWS {
            return Finding::Nothing;
        }
        log::warn!(
            "GNSS and the pedometer disagree by a factor of {ratio:.2}: pedometer weight lowered"
        );
        self.flags.pedometer_disagrees = true;
        self.disagreement_ln = ln.abs();
        Finding::Disagrees { cadence_hz }
    }

    fn clear_disagreement(&mut self) {
        self.disagree_run = 0;
        self.disagree_sign = 0.0;
        self.disagreement_ln = 0.0;
        self.flags.pedometer_disagrees = false;
    }

    /// A step sample the tracker accepted at `t`: the no-GNSS judgement of the
    /// cadence.
    pub fn on_steps(&mut self, t: f64, steps: &StepStream, stationary_after_s: f64) {
        let settled = self.flags.cadence_doubled || self.stride_evidence <= -DECIDE_EVIDENCE;
        let reported_spm = steps
            .cadence_at(t, LOW_CADENCE_WINDOW_S, stationary_after_s)
            .map(|c| 60.0 * c / steps.steps_per_report());
        let (lo, hi) = LOW_CADENCE_SPM;
        let low = !settled && reported_spm.is_some_and(|c| (lo..hi).contains(&c));
        if !low {
            self.low_cadence_since_t_s = f64::NAN;
            self.flags.cadence_may_be_strides = false;
            return;
        }
        if self.low_cadence_since_t_s.is_nan() {
            self.low_cadence_since_t_s = t;
        }
        self.flags.cadence_may_be_strides = t - self.low_cadence_since_t_s >= LOW_CADENCE_FOR_S;
    }

    pub fn write(&self, w: &mut Writer) {
        // Exhaustive on purpose: a new field must be written.
        let Self {
            window,
            stride_evidence,
            disagree_run,
            disagree_sign,
            disagreement_ln,
            low_cadence_since_t_s,
            flags,
        } = self;
        let Window {
            active,
            start_t_s,
            start_steps,
            anchor,
            path_m,
            fix_path_m,
            pedometer_m,
            last,
            last_pedometer_mps,
        } = window;
        w.bool(*active);
        w.f64s(&[*start_t_s, *start_steps]);
        w.f64s(anchor);
        w.f64s(last);
        w.f64s(&[*path_m, *fix_path_m, *pedometer_m, *last_pedometer_mps]);
        w.f64s(&[*stride_evidence, *disagree_sign, *disagreement_ln]);
        w.u64(u64::from(*disagree_run));
        w.f64(*low_cadence_since_t_s);
        let PaceFlags {
            cadence_doubled,
            cadence_may_be_strides,
            pedometer_disagrees,
        } = flags;
        w.bool(*cadence_doubled);
        w.bool(*cadence_may_be_strides);
        w.bool(*pedometer_disagrees);
    }

    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let active = r.bool()?;
        let mut v = [0.0; 2];
        r.f64s(&mut v)?;
        let mut anchor = [0.0; 3];
        r.f64s(&mut anchor)?;
        let mut last = [0.0; 3];
        r.f64s(&mut last)?;
        let mut sums = [0.0; 4];
        r.f64s(&mut sums)?;
        let mut ev = [0.0; 3];
        r.f64s(&mut ev)?;
        let disagree_run = r.len(u32::MAX as usize)? as u32;
        let low_cadence_since_t_s = r.f64_or_nan()?;
        let flags = PaceFlags {
            cadence_doubled: r.bool()?,
            cadence_may_be_strides: r.bool()?,
            pedometer_disagrees: r.bool()?,
        };
        let c = Self {
            window: Window {
                active,
                start_t_s: v[0],
                start_steps: v[1],
                anchor,
                path_m: sums[0],
                fix_path_m: sums[1],
                pedometer_m: sums[2],
                last,
                last_pedometer_mps: sums[3],
            },
            stride_evidence: ev[0],
            disagree_run,
            disagree_sign: ev[1],
            disagreement_ln: ev[2],
            low_cadence_since_t_s,
            flags,
        };
        c.check_state().map_err(SnapshotError::Invalid)?;
        Ok(c)
    }

    /// Whether a restored state is one the check can reach.
    fn check_state(&self) -> Result<(), &'static str> {
        let w = &self.window;
        let time_ok = |t: f64| t.abs() <= crate::input::limits::MAX_ABS_T_S + 1.0;
        if !(time_ok(w.start_t_s) && time_ok(w.anchor[2]) && time_ok(w.last[2]))
            || !(self.low_cadence_since_t_s.is_nan() || time_ok(self.low_cadence_since_t_s))
        {
            return Err("cross-check times");
        }
        if !(0.0..=1e13).contains(&w.path_m)
            || !(0.0..=1e13).contains(&w.fix_path_m)
            || !(0.0..=1e13).contains(&w.pedometer_m)
            || !(0.0..=1e12).contains(&w.start_steps)
            || !(0.0..=1e4).contains(&w.last_pedometer_mps)
            || [w.anchor[0], w.anchor[1], w.last[0], w.last[1]]
                .iter()
                .any(|v| v.abs() > 1e12)
        {
            return Err("cross-check window");
        }
        if self.stride_evidence.abs() > MAX_EVIDENCE
            || ![-1.0, 0.0, 1.0].contains(&self.disagree_sign)
            || !(0.0..=1e3).contains(&self.disagreement_ln)
        {
            return Err("cross-check evidence");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_population_gait_tells_strides_from_steps() {
        // A run at 2.8 m/s and 170 steps/min reported as 85 strides/min.
        assert!(stride_evidence(2.8, 85.0 / 60.0) > 5.0);
        // The same run reported as steps: strides would be 340 steps/min.
        assert_eq!(stride_evidence(2.8, 170.0 / 60.0), -WINDOW_EVIDENCE_CAP);
        // A walk at 1.4 m/s, 110 steps/min, and the same walk in strides (55/min).
        assert!(stride_evidence(1.4, 110.0 / 60.0) < -5.0);
        assert!(stride_evidence(1.4, 55.0 / 60.0) > 5.0);
        // A slow walk at 1.1 m/s and 88 steps/min stays steps.
        assert!(stride_evidence(1.1, 88.0 / 60.0) < -2.0);
        // A bus at 8 m/s with a few steps a second: neither.
        assert_eq!(stride_evidence(8.0, 1.0), 0.0);
    }
}
