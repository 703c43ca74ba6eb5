//! The last step of a walk: the foot that stops is set down gently, often under the
//! relative amplitude bar. Inside a bout such a weak candidate on cadence is held; if
//! the walk goes on, the next step fills it as a missed one; if no step comes, the walk
//! ended with it and it is released as the bout's last step.

use super::{RobustDetector, Sink};

/// A weak candidate is held when it comes within this share of the period of one
/// period after the previous step (1.3 m/s² against the walk's typical 6.4 at the end
/// of Samsung_Dario_Hard_InHand_1) ...
const TAIL_CADENCE: f64 = 0.2;
/// ... and released when no step has come this many periods after it.
pub(super) const TAIL_WAIT_PERIODS: f64 = 1.2;

impl RobustDetector {
    /// A weak candidate at `t_s`, `interval_s` after the last step: held as the
    /// possible last step when it is on cadence inside a bout.
    pub(super) fn hold_tail(&mut self, t_s: f64, interval_s: f64) {
        if self.in_bout
            && self.tail.is_none()
            && self.held.is_empty()
            && self.moments.n > 0.0
            && (interval_s - self.period_s).abs() <= TAIL_CADENCE * self.period_s
        {
            self.tail = Some(self.moments.event(t_s, interval_s));
        }
    }

    /// At grid time `t_s`: no step followed the held one for long enough, so the walk
    /// ended with it.
    pub(super) fn release_tail_if_due(&mut self, t_s: f64, out: &mut Sink<'_>) {
        let Some(ev) = self.tail else {
            return;
        };
        if t_s - ev.t_s > TAIL_WAIT_PERIODS * self.period_s {
            self.tail = None;
            if self.in_bout {
                // The statistics since the previous step are kept for the next one
                // (as after a rejected candidate): it always has samples.
                out.push(ev);
                self.last_t_s = ev.t_s;
            }
        }
    }
}
