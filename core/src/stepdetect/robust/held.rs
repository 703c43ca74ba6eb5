//! A step sooner than the cadence waits one step: it may be the secondary bump of a slow
//! walk's step (45–70 % of its amplitude, 0.3–0.5 s after it), and then the heel strike
//! that follows inside the refractory time, on cadence from the step before, replaces it.
//! Otherwise it is released with the next step, when the bout ends, or after a wait.

use super::bout::CADENCE_TOLERANCE;
use super::tail::TAIL_WAIT_PERIODS;
use super::{Moments, RobustDetector, Sink, StepEvent};

/// Steps held at most (consecutive steps sooner than the cadence); a full buffer releases
/// its oldest.
pub(super) const HELD: usize = 4;
/// A stride (two steps) within this share of two periods is on the walk's rhythm even
/// when each step is not (a front pocket's 0.34 s / 0.74 s steps at a 0.54 s period):
/// the stride time of steady walking varies by 2–3 %.
const STRIDE_TOLERANCE: f64 = 0.1;

impl RobustDetector {
    /// Whether an `interval` after the previous step is on the bout's cadence.
    fn on_cadence(&self, interval: f64) -> bool {
        (interval - self.period_s).abs() <= CADENCE_TOLERANCE * self.period_s
    }

    /// Whether a step `interval` after the previous one comes sooner than the cadence
    /// without completing a stride with the interval before it (a perhaps secondary bump).
    pub(super) fn too_soon(&self, interval: f64) -> bool {
        let stride = 2.0 * self.period_s;
        let on_stride =
            (interval + self.prev_interval_s - stride).abs() <= STRIDE_TOLERANCE * stride;
        interval < (1.0 - CADENCE_TOLERANCE) * self.period_s && !on_stride
    }

    /// Hold a step sooner than the cadence.
    pub(super) fn hold(&mut self, ev: StepEvent, out: &mut Sink<'_>) {
        if self.held.len() == HELD {
            if let Some(oldest) = self.held.pop_front() {
                out.push(oldest);
            }
        }
        self.held.push(ev);
    }

    /// The held steps are steps: the walk went on, the bout ended, or the input paused.
    pub(super) fn release_held(&mut self, out: &mut Sink<'_>) {
        while let Some(ev) = self.held.pop_front() {
            out.push(ev);
        }
    }

    /// At grid time `t_s`: no strike came to replace the newest held step (nor a step
    /// after it) for as long as a walk's last step is waited for.
    pub(super) fn release_held_if_due(&mut self, t_s: f64, out: &mut Sink<'_>) {
        if self
            .held
            .back(0)
            .is_some_and(|ev| t_s - ev.t_s > TAIL_WAIT_PERIODS * self.period_s)
        {
            self.release_held(out);
        }
    }

    /// A candidate at `t_s` inside the refractory time of the newest step: when that step
    /// is held alone and this one is on cadence from the step before it, the held one was
    /// a secondary bump and this strike replaces it (released at once).
    pub(super) fn replace_bump(&mut self, t_s: f64, out: &mut Sink<'_>) {
        let Some(bump) = self.held.back(0) else {
            return;
        };
        let interval = t_s - (bump.t_s - bump.duration_s);
        if !(self.held.len() == 1 && self.on_cadence(interval)) {
            return;
        }
        let ev = self.moments.event(t_s, interval);
        self.moments = Moments::EMPTY;
        self.held.clear();
        out.push(StepEvent {
            accel_max_mps2: ev.accel_max_mps2.max(bump.accel_max_mps2),
            accel_min_mps2: ev.accel_min_mps2.min(bump.accel_min_mps2),
            ..ev
        });
        self.last_t_s = t_s;
        self.prev_interval_s = interval;
    }
}

#[cfg(test)]
mod tests {
    use super::super::RobustStepParams;
    use super::*;
    use crate::snapshot::{Reader, SnapshotError, Writer};

    fn bytes(d: &RobustDetector) -> Vec<u8> {
        let mut w = Writer::new(3, 1);
        d.write(&mut w);
        w.finish()
    }

    /// The detector read back from its snapshot, as snapshot bytes.
    fn round_trip(d: &RobustDetector) -> Result<Vec<u8>, SnapshotError> {
        let b = bytes(d);
        let (mut r, _) = Reader::new(&b, 3, 1)?;
        RobustDetector::read(&mut r, d.p).map(|d| bytes(&d))
    }

    #[test]
    fn held_steps_round_trip_and_are_checked_against_the_bout() {
        let mut d = RobustDetector::new(RobustStepParams::default());
        (d.in_bout, d.period_s, d.last_t_s) = (true, 0.68, 10.44);
        let ev = StepEvent {
            t_s: 10.44,
            duration_s: 0.44,
            ..StepEvent::default()
        };
        d.held.push(ev);
        assert!(round_trip(&d).unwrap() == bytes(&d));
        // A held step after the bout's last step, or outside a bout, is refused.
        d.last_t_s = 10.0;
        assert!(round_trip(&d).is_err());
        (d.last_t_s, d.in_bout) = (10.44, false);
        assert!(round_trip(&d).is_err());
    }
}
