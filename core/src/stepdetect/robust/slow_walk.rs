//! A slow walk's weak steps: a candidate under the absolute amplitude floor is a step when
//! it is about as strong as the walk's recent steps (a slow walk's steps are all weak, a
//! bump is weak beside strikes): in a bout on its cadence, or confirming a walk-paced bout.

use super::bout::CADENCE_TOLERANCE;
use super::pending::Pending;
use super::{RobustDetector, PENDING};
use crate::signal::Ring;

/// A weak candidate may be a step when it is at least this share of the typical
/// amplitude of the recent steps (a slow walk in hand time-stretched × 0.7,
/// Samsung_Jamie_Hard_InHand_2: 0.6–1.0 m/s² steps against a typical 1.2) ...
const WEAK_STEP_ALIKE: f64 = 0.6;
/// ... and at least this strong, m/s² (that copy's weakest steps are 0.45 m/s²; the
/// peak detector's smallest hysteresis is 0.3).
const WEAK_STEP_MIN_MPS2: f64 = 0.4;
/// A bout with weak steps must have a walking cadence: a step period of at most this, s
/// (0.8 steps/s; a body swaying while standing is slower, and has no steps).
pub(super) const SLOW_WALK_MAX_PERIOD_S: f64 = 1.25;

impl RobustDetector {
    /// Whether a candidate under `min_amplitude_mps2` at `t_s` may be a step of a slow
    /// walk: within a step interval of the last candidate (after a silence there is no
    /// walk to be alike to: a first weak bump does not hold back the strike after it),
    /// alike in strength to the recent ones (`reference`), and inside a bout on its
    /// cadence.
    pub(super) fn weak_step_admitted(&self, t_s: f64, amplitude: f64, reference: f64) -> bool {
        let interval = t_s - self.last_t_s;
        let on_cadence = (interval - self.period_s).abs() <= CADENCE_TOLERANCE * self.period_s;
        amplitude >= WEAK_STEP_MIN_MPS2
            && !self.silent(interval)
            && amplitude >= WEAK_STEP_ALIKE * reference
            && (!self.in_bout || (self.held.is_empty() && on_cadence))
    }

    /// The candidates of `ring` over the absolute floor: outside a bout of weak steps
    /// the weak candidates are bumps, left out of the steps chained back and of short
    /// walks; the interval and hidden time before a weak one go to the next kept one
    /// (whose features already span its samples), as if it had not been a candidate.
    pub(super) fn over_floor(&self, ring: &Ring<Pending, PENDING>) -> Ring<Pending, PENDING> {
        let mut out = Ring::new();
        let (mut duration_s, mut missing_s) = (0.0, 0.0);
        for mut c in ring.iter() {
            if c.amplitude_mps2 >= self.p.min_amplitude_mps2 {
                c.event.duration_s += duration_s;
                c.missing_before_s += missing_s;
                out.push(c);
                (duration_s, missing_s) = (0.0, 0.0);
            } else {
                duration_s += c.event.duration_s;
                missing_s += c.missing_before_s;
            }
        }
        out
    }
}
