//! A step candidate: the amplitude gates (absolute, and relative to the typical
//! amplitude of recent steps, which fades after a silence), then either the next step
//! of the running bout or a candidate buffered until a bout is confirmed.

use super::pending::Pending;
use super::{Moments, RobustDetector, Sink};
use crate::vec3;

/// Weight of a new candidate in the typical step amplitude.
pub(super) const AMPLITUDE_GAIN: f64 = 0.2;
/// Time constant with which the typical amplitude fades once no candidate has been
/// accepted for longer than `max_step_interval_s`, s.
const AMPLITUDE_MEMORY_S: f64 = 8.0;

impl RobustDetector {
    /// A peak at `t_s` (delay-corrected) of `amplitude` over its valley, m/s².
    pub(super) fn candidate(&mut self, t_s: f64, amplitude: f64, out: &mut Sink<'_>) {
        let p = self.p;
        let impact = self.impact_ratio(t_s, amplitude);
        if amplitude > p.max_amplitude_mps2 || amplitude.is_nan() {
            return;
        }
        let reference = self.amplitude_reference(t_s);
        if amplitude < p.min_amplitude_mps2 && !self.weak_step_admitted(t_s, amplitude, reference) {
            return;
        }
        let interval = t_s - self.last_t_s; // NaN without a previous candidate
        if amplitude < p.relative_amplitude * reference {
            // A secondary bump of the previous step (or of the swing), or, on cadence
            // inside a bout, perhaps the walk's last step.
            self.hold_tail(t_s, interval);
            return;
        }
        // A step-strength candidate: the walk went on (or this one decides), the held
        // weak one is not a last step.
        self.tail = None;
        self.amplitude_ref_mps2 = reference;
        if interval < p.min_step_interval_s {
            return;
        }
        if self.silent(interval) {
            // Silence (or the first candidate): no walk continues across it.
            self.bout_end_t_s = f64::NAN;
        }
        if self.in_bout {
            if self.continue_bout(t_s, amplitude, interval, out) {
                return;
            }
            self.end_bout(interval, out);
        }
        self.buffer(t_s, amplitude, impact, interval);
        self.try_confirm(out);
    }

    /// The typical amplitude of the steps of *now*: after a silence longer than a step
    /// interval (no candidate accepted) it fades, so that a gentler gait after a harder
    /// one (a walk after a run, the phone then in a bag) is not measured against steps
    /// that have stopped. (From the last accepted candidate's time: rejected ones
    /// change nothing.)
    fn amplitude_reference(&self, t_s: f64) -> f64 {
        let silent = t_s - self.last_t_s - self.p.max_step_interval_s; // NaN without a previous
        if silent > 0.0 {
            self.amplitude_ref_mps2 * (-silent / AMPLITUDE_MEMORY_S).exp()
        } else {
            self.amplitude_ref_mps2
        }
    }

    /// Buffer a candidate outside a bout, `interval` after the previous one; a silence
    /// before it drops the buffer (kept as a short walk if it looks like one).
    fn buffer(&mut self, t_s: f64, amplitude: f64, impact: f64, interval: f64) {
        let duration = if !self.silent(interval) {
            interval
        } else {
            self.keep_short_walk();
            self.pending.clear();
            f64::NAN
        };
        let ev = self.moments.event(t_s, duration);
        // A weak one may be left out of a bout of strong steps (`slow_walk::over_floor`):
        // the next candidate's features then span its samples too, as without it.
        if amplitude >= self.p.min_amplitude_mps2 {
            self.moments = Moments::EMPTY;
        }
        self.pending.push(Pending {
            event: ev,
            impact,
            amplitude_mps2: amplitude,
            carry: vec3::unit(self.carry, 0.0).unwrap_or([0.0; 3]),
            missing_before_s: if duration.is_nan() {
                0.0
            } else {
                self.missing_s
            },
        });
        self.amplitude_ref_mps2 = if self.amplitude_ref_mps2 > 0.0 {
            self.amplitude_ref_mps2 + AMPLITUDE_GAIN * (amplitude - self.amplitude_ref_mps2)
        } else {
            amplitude
        };
        self.last_t_s = t_s;
        self.missing_s = self.missing_after(t_s);
    }
}
