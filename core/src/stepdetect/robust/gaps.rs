//! Gaps in a walk. Dropped samples (input gaps up to `MAX_INPUT_GAP_S`, bridged by the
//! grid) hide steps that are counted at the cadence when the bout resumes; a bout that
//! lost its periodicity (not by silence) and is followed within 10 s by one at the same
//! cadence is one walk (a turn, a message read on the way): the gap is filled too.

use super::bout::{CADENCE_TOLERANCE, GAP_END_PERIODS};
use super::{RobustDetector, Sink, StepEvent, DATA_GAP_S};
use crate::signal::Ring;
use crate::stepdetect::StepOrigin;

/// Longest gap filled between two bouts of one walk, s (a purse walk at 50 Hz with
/// jittered timestamps has 6.3 s gaps); also the longest interval across dropped
/// samples counted at the cadence.
const FILL_MAX_GAP_S: f64 = 10.0;
/// Most steps filled into one gap (10 s at 2.4 steps/s).
const FILL_MAX_STEPS: usize = 24;

/// A step peak this share of a period from a gap's edge may be lost with it (its rise
/// or fall is cut, and the grid bridges the gap with a straight line).
const HIDDEN_PEAK_EDGE: f64 = 0.25;
/// Inside a confirmed bout, one step of an interval across a gap may also have been
/// too weak to see, as in an interval without a gap (a missed step, see `bout`); the
/// candidates before a bout is confirmed chain back across a gap only by the steps
/// the gap can hide.
pub(super) const WEAK_STEPS_IN_BOUT: f64 = 1.0;
pub(super) const WEAK_STEPS_BEFORE_BOUT: f64 = 0.0;

/// Whether an `interval` between two candidates of a walk at `period`, of which gaps
/// in the data hid `missing_s`, went on through the gaps: what was seen of it is
/// short of a step-less stretch (2.5 periods, as inside a bout), it is within the
/// longest fill, and the steps it would fill are no more than the gaps can hide plus
/// `weak_steps` unseen ones (a 0.1 s gap in 1.4 s of handling bumps before a walk
/// hides at most one step, not two: Pixel_Jamie_Hard_BackPocket_1 with dropped
/// bursts).
pub(super) fn walks_across_gap(
    interval: f64,
    missing_s: f64,
    period: f64,
    weak_steps: f64,
) -> bool {
    let filled = (interval / period).round() - 1.0;
    missing_s > 0.0
        && interval - missing_s <= GAP_END_PERIODS * period
        && interval <= FILL_MAX_GAP_S
        && filled <= hidden_steps(missing_s, period) + weak_steps
}

/// Most step peaks, `period` apart, that gaps hiding `missing_s` can take with them:
/// the lattice points in the hidden time widened by [`HIDDEN_PEAK_EDGE`] on each side.
fn hidden_steps(missing_s: f64, period: f64) -> f64 {
    (missing_s / period + 2.0 * HIDDEN_PEAK_EDGE).floor() + 1.0
}

/// Emit the step `ev` at `t_s` after the `n` − 1 (at least 1, capped) steps missed
/// in its `interval` before it, evenly, flagged with `origin` (why they were not
/// seen; `ev` keeps its own); the filled step length, s.
pub(super) fn fill_missed(
    ev: StepEvent,
    t_s: f64,
    interval: f64,
    n: f64,
    origin: StepOrigin,
    emit: &mut impl FnMut(StepEvent),
) -> f64 {
    let n = n.clamp(2.0, FILL_MAX_STEPS as f64 + 1.0) as usize;
    let step = interval / n as f64;
    let t0 = t_s - interval;
    for i in 1..n {
        emit(StepEvent {
            t_s: t0 + i as f64 * step,
            duration_s: step,
            origin,
            ..ev
        });
    }
    emit(StepEvent {
        duration_s: step,
        ..ev
    });
    step
}

impl RobustDetector {
    /// A sample `dt` after the previous one: a spacing over [`DATA_GAP_S`] is a gap in
    /// the data (samples dropped).
    pub(super) fn note_data_gap(&mut self, t_s: f64, dt: f64) {
        if dt > DATA_GAP_S {
            self.data_gap_end_t_s = t_s;
            self.data_gap_s = dt;
            self.missing_s += dt;
        }
    }

    /// Whether the walk went on through dropped samples since the last step: a gap
    /// ended after it and what was seen of the `interval` is short of a step-less
    /// stretch (several gaps close together count by the time they hid).
    pub(super) fn across_gap(&self, interval: f64) -> bool {
        self.data_gap_end_t_s > self.last_t_s
            && walks_across_gap(interval, self.missing_s, self.period_s, WEAK_STEPS_IN_BOUT)
    }

    /// Whether no walk went on over the `interval` since the last candidate (NaN: there
    /// was none): more than `max_step_interval_s` of input seen without one (time the
    /// gaps in the data hid is no silence: samples dropped by a busy phone), or longer
    /// than the longest fill.
    pub(super) fn silent(&self, interval: f64) -> bool {
        !(interval - self.missing_s <= self.p.max_step_interval_s && interval <= FILL_MAX_GAP_S)
    }

    /// Time the input has been missing since `t_s`, a candidate's time (it is
    /// processed a little after its peak, when a gap may already have begun).
    pub(super) fn missing_after(&self, t_s: f64) -> f64 {
        let gap_start = self.data_gap_end_t_s - self.data_gap_s;
        if self.data_gap_end_t_s > t_s {
            self.data_gap_end_t_s - gap_start.max(t_s)
        } else {
            0.0
        }
    }

    /// A bout was just confirmed at `period`: if the previous bout lost its
    /// periodicity (not by silence) at most [`FILL_MAX_GAP_S`] before and at a cadence
    /// within ±30 %, the steps of the gap are filled at the cadence (a short walk kept
    /// in the gap is then counted by the fill). The previous bout's end is used once.
    pub(super) fn fill_gap_before_bout(&mut self, period: f64, out: &mut Sink<'_>) {
        if let Some(first) = self.pending.get(0) {
            let gap = first.event.t_s - self.bout_end_t_s; // NaN without a previous bout
            let same_cadence = (period - self.bout_end_period_s).abs()
                <= CADENCE_TOLERANCE * self.bout_end_period_s;
            if gap <= FILL_MAX_GAP_S && same_cadence {
                let m = ((gap / period).round() as usize)
                    .saturating_sub(1)
                    .min(FILL_MAX_STEPS);
                let step = gap / (m + 1) as f64;
                if m > 0 {
                    self.short_walk = Ring::new();
                }
                for i in 1..=m {
                    out.push(StepEvent {
                        t_s: self.bout_end_t_s + i as f64 * step,
                        duration_s: step,
                        origin: StepOrigin::FilledBetweenBouts,
                        ..first.event
                    });
                }
            }
        }
        self.bout_end_t_s = f64::NAN;
        self.bout_end_period_s = f64::NAN;
    }
}

#[cfg(test)]
mod tests {
    use super::super::RobustStepParams;
    use super::*;

    #[test]
    fn a_gap_fills_only_the_steps_it_can_hide() {
        // 1.36 s at 0.53 s steps would fill two; a 0.11 s gap hides at most one (one
        // more may be weak inside a bout), a 0.47 s gap two.
        assert_eq!(hidden_steps(0.11, 0.53), 1.0);
        assert_eq!(hidden_steps(0.47, 0.53), 2.0);
        assert!(!walks_across_gap(1.36, 0.11, 0.53, WEAK_STEPS_BEFORE_BOUT));
        assert!(walks_across_gap(1.36, 0.11, 0.53, WEAK_STEPS_IN_BOUT));
        assert!(walks_across_gap(1.36, 0.47, 0.53, WEAK_STEPS_BEFORE_BOUT));
        // What was seen is longer than a step-less stretch: no walk across the gap.
        assert!(!walks_across_gap(2.0, 0.2, 0.53, WEAK_STEPS_IN_BOUT));
    }

    #[test]
    fn filled_steps_carry_their_origin_and_the_seen_step_keeps_its_own() {
        let ev = StepEvent {
            t_s: 12.0,
            duration_s: 1.5,
            ..StepEvent::default()
        };
        let mut out = Vec::new();
        let step = fill_missed(ev, 12.0, 1.5, 3.0, StepOrigin::FilledMissed, &mut |e| {
            out.push(e)
        });
        assert!((step - 0.5).abs() < 1e-12);
        let origins: Vec<StepOrigin> = out.iter().map(|e| e.origin).collect();
        let filled = StepOrigin::FilledMissed;
        assert_eq!(origins, [filled, filled, StepOrigin::Detected]);
        assert!((out[0].t_s - 11.0).abs() < 1e-12 && out[2].t_s == 12.0);
    }

    #[test]
    fn missing_time_counts_only_the_part_of_a_gap_after_the_candidate() {
        let mut d = RobustDetector::new(RobustStepParams::default());
        assert_eq!(d.missing_after(1.0), 0.0);
        d.note_data_gap(5.0, 0.5);
        assert!((d.missing_after(4.7) - 0.3).abs() < 1e-12);
        assert_eq!(d.missing_after(4.0), 0.5);
        assert_eq!(d.missing_after(5.0), 0.0);
        d.note_data_gap(5.05, 0.05);
        assert_eq!(d.data_gap_end_t_s, 5.0, "a spacing of 0.05 s is no gap");
    }
}
