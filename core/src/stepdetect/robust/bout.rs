//! Inside a bout: each candidate is a step unless it comes sooner than `refractory` ×
//! the period (a double peak); an interval of 1.6–2.4 periods holds a missed step; a
//! longer stretch or lost periodicity ends the bout. The period follows half the stride
//! and is reset when it drifts to about half or twice the autocorrelation's.

use super::candidate::AMPLITUDE_GAIN;
use super::gaps::fill_missed;
use super::{Moments, RobustDetector, Sink};
use crate::stepdetect::gait::ACF_TAU_S;
use crate::stepdetect::StepOrigin;

/// "±30 % of the period": intervals within this share of the step period are on
/// cadence (they move the period; a walk on after a pause keeps within it).
pub(super) const CADENCE_TOLERANCE: f64 = 0.3;
/// Weight of a new interval in the step period on cadence, and otherwise (a secondary
/// bump that passed, a missed step barely move it).
const PERIOD_GAIN_ON_CADENCE: f64 = 0.25;
const PERIOD_GAIN_OFF_CADENCE: f64 = 0.03;
/// A bout period outside this ratio to the autocorrelation's step period has lost the
/// cadence (about half or double it) and is reset.
const PERIOD_LOCK_MIN: f64 = 0.7;
const PERIOD_LOCK_MAX: f64 = 1.45;
/// ... but not to about three times it: a bout follows steps or, having lost every
/// other one, strides, never three steps; a lag of three steps is the
/// autocorrelation's own mistake (an odd multiple of the step is anti-correlated at
/// its half, which reads as one slow step; a purse swinging at its own pendulum
/// period, Samsung_Dario_Hard_Purse_2 at 131 s with dropped samples).
const PERIOD_LOCK_MAX_MULTIPLE: f64 = 2.5;
/// A stretch without a step this many periods long ends the bout (or
/// `max_step_interval_s` if longer).
pub(super) const GAP_END_PERIODS: f64 = 2.5;
/// An interval between these many periods holds one missed step (filled at its middle).
const MISSED_STEP_MIN_PERIODS: f64 = 1.6;
pub(super) const MISSED_STEP_MAX_PERIODS: f64 = 2.4;
/// Inside a bout the periodicity needs only this share of `min_periodicity`.
const BOUT_PERIODICITY_SHARE: f64 = 0.5;

/// Weight of a new interval in the step period: intervals on cadence follow it; others
/// (a secondary bump that passed, a missed step) barely move it.
fn period_gain(interval_s: f64, period_s: f64) -> f64 {
    if (interval_s - period_s).abs() <= CADENCE_TOLERANCE * period_s {
        PERIOD_GAIN_ON_CADENCE
    } else {
        PERIOD_GAIN_OFF_CADENCE
    }
}

impl RobustDetector {
    /// A step-strength candidate at `t_s` inside the bout, `interval` after its last
    /// step: `true` when it belongs to the bout (a step, released, or a double peak of
    /// one), `false` when the bout ended before it.
    pub(super) fn continue_bout(
        &mut self,
        t_s: f64,
        amplitude: f64,
        interval: f64,
        out: &mut Sink<'_>,
    ) -> bool {
        let p = self.p;
        self.relock_period(t_s);
        if interval < p.refractory * self.period_s {
            self.replace_bump(t_s, out);
            return true;
        }
        let gap_end = p.max_step_interval_s.max(GAP_END_PERIODS * self.period_s);
        let across_gap = self.across_gap(interval);
        // While a bridged gap is inside the correlation window (the interpolated
        // stretch is not periodic, the walk may well be), steps that keep coming at the
        // cadence continue the bout.
        let on_cadence = (interval - self.period_s).abs() <= CADENCE_TOLERANCE * self.period_s;
        let periodic = self.periodic(self.period_s, p.min_periodicity * BOUT_PERIODICITY_SHARE)
            || across_gap
            || (on_cadence && t_s - self.data_gap_end_t_s < ACF_TAU_S);
        if !((interval <= gap_end || across_gap) && periodic) {
            return false;
        }
        self.release_step(t_s, interval, across_gap, out);
        self.last_t_s = t_s;
        self.missing_s = self.missing_after(t_s);
        self.amplitude_ref_mps2 += AMPLITUDE_GAIN * (amplitude - self.amplitude_ref_mps2);
        true
    }

    /// The bout ended (long gap or lost periodicity) before a candidate `interval`
    /// after its last step; a bout that lost its periodicity without a silence is
    /// remembered (the next may be the same walk, see `gaps`).
    pub(super) fn end_bout(&mut self, interval: f64, out: &mut Sink<'_>) {
        self.release_held(out);
        self.in_bout = false;
        self.prev_interval_s = f64::NAN;
        if interval <= self.p.max_step_interval_s {
            self.bout_end_t_s = self.last_t_s;
            self.bout_end_period_s = self.period_s;
        }
        self.pending.clear();
    }

    /// The bout's period follows the candidates; when it has drifted to twice or half
    /// the period of the signal itself (a run of missed or extra peaks), it is reset
    /// from the autocorrelation. Not right after dropped samples: the gap bridged by
    /// interpolation is in the correlation's window.
    fn relock_period(&mut self, t_s: f64) {
        let p = self.p;
        let clean = t_s - self.data_gap_end_t_s >= ACF_TAU_S || self.data_gap_end_t_s.is_nan();
        let clean = clean && self.gait.settled();
        let acf = self.gait.step_period(p.min_periodicity).filter(|_| clean);
        if let Some((acf_period, _, _)) = acf {
            let ratio = acf_period / self.period_s;
            let longer = ratio > PERIOD_LOCK_MAX && ratio < PERIOD_LOCK_MAX_MULTIPLE;
            let shorter = ratio < PERIOD_LOCK_MIN && self.shorter_period_is_a_step(acf_period);
            if longer || shorter {
                self.period_s = acf_period;
            }
        }
    }

    /// Whether the autocorrelation's `acf_period`, shorter than the bout's, is the walk's
    /// step: a correlated lag (half a slow step is anti-correlated, peak against
    /// valley), and either one at which the signal repeats as a bout's must (half
    /// `min_periodicity`), or at least as well as at the bout's own period (a bout that
    /// lost its cadence), or the steps have running strength (a walk turning into a
    /// run: the correlation window still holds the walk, whose steps repeat at the
    /// run's stride). A slow walk whose secondary bumps are as strong as its steps
    /// offers a half-step period that correlates at 0.0–0.13 while its step correlates
    /// at 0.22–0.65 (Pixel_Jamie_Carpet_InHand_1 time-stretched × 0.7–0.85, steps of
    /// 1.3–1.5 m/s²): taken, every bump was counted as a step.
    fn shorter_period_is_a_step(&self, acf_period: f64) -> bool {
        let p = self.p;
        let rho = self.gait.rho_at(acf_period);
        let rho_own = self.gait.rho_at(self.period_s);
        rho > 0.0
            && (rho >= p.min_periodicity * BOUT_PERIODICITY_SHARE
                || rho_own.is_nan()
                || rho >= rho_own
                || self.amplitude_ref_mps2 >= p.running_min_amplitude_mps2)
    }

    /// Release the step at `t_s`, and the steps missed before it (a weak one, or
    /// samples dropped) evenly in its interval; a step sooner than the cadence is held
    /// one step (see `held`).
    fn release_step(&mut self, t_s: f64, interval: f64, across_gap: bool, out: &mut Sink<'_>) {
        let ev = self.moments.event(t_s, interval);
        self.moments = Moments::EMPTY;
        if self.too_soon(interval) {
            self.hold(ev, out);
            self.follow_period(interval, true);
            return;
        }
        self.release_held(out);
        let period = self.period_s;
        let n = (interval / period).round();
        let missed = interval > MISSED_STEP_MIN_PERIODS * period
            && interval < MISSED_STEP_MAX_PERIODS * period;
        if missed || (across_gap && n >= 2.0) {
            // Dropped samples explain the unseen steps before a weak step does.
            let origin = if across_gap {
                StepOrigin::FilledAcrossGap
            } else {
                StepOrigin::FilledMissed
            };
            let step = fill_missed(ev, t_s, interval, n, origin, &mut |e| out.push(e));
            self.follow_period(step, false);
        } else {
            out.push(ev);
            self.follow_period(interval, true);
        }
    }

    /// Follow the bout's step period with a new step interval (`measured`: between
    /// two detected steps; otherwise one of the steps filled into a gap).
    ///
    /// The period is half the stride: the mean of the last two intervals. A phone
    /// carried on one side sees its left and right steps apart unequally (0.40 s /
    /// 0.62 s in a back pocket); followed one interval at a time, the short ones
    /// (on cadence) pull and the long ones barely do, and the period settles near the
    /// short interval, where the stride lag of the periodicity check misses the stride
    /// and the bout ends while the walk goes on (Samsung_Carmelo_Hard_BackPocket_2).
    pub(super) fn follow_period(&mut self, interval_s: f64, measured: bool) {
        let observed = if measured && self.prev_interval_s.is_finite() {
            0.5 * (interval_s + self.prev_interval_s)
        } else {
            interval_s
        };
        self.prev_interval_s = if measured { interval_s } else { f64::NAN };
        self.period_s += period_gain(observed, self.period_s) * (observed - self.period_s);
    }
}

#[cfg(test)]
mod tests {
    use super::super::RobustStepParams;
    use super::*;
    use crate::signal::Ring;

    /// In a bout at 0.68 s steps, the step at `t0` and the steps released after it.
    fn released(steps: &[(f64, bool)]) -> Vec<f64> {
        let mut d = RobustDetector::new(RobustStepParams::default());
        (d.in_bout, d.period_s, d.prev_interval_s, d.last_t_s) = (true, 0.68, 0.68, 10.0);
        let mut queue = Ring::new();
        let mut n = 0;
        let mut out = Sink {
            queue: &mut queue,
            released: &mut n,
        };
        for &(t_s, refractory) in steps {
            if refractory {
                d.replace_bump(t_s, &mut out);
            } else {
                d.release_step(t_s, t_s - d.last_t_s, false, &mut out);
                d.last_t_s = t_s;
            }
        }
        d.release_held(&mut out);
        queue.iter().map(|e| e.t_s).collect()
    }

    #[test]
    fn a_secondary_bump_gives_way_to_the_heel_strike_on_cadence_after_it() {
        // A bump 0.44 s after the step, the strike 0.26 s later (inside the refractory
        // time of the bump): the strike is the step.
        assert_eq!(released(&[(10.44, false), (10.70, true)]), [10.70]);
        // A step sooner than the cadence followed by a step: both count.
        assert_eq!(released(&[(10.44, false), (11.12, false)]), [10.44, 11.12]);
        // Short and long steps of a phone on one side (one stride) are not held.
        let mut d = RobustDetector::new(RobustStepParams::default());
        (d.period_s, d.prev_interval_s) = (0.54, 0.74);
        assert!(!d.too_soon(0.34) && d.too_soon(0.20));
    }

    #[test]
    fn the_period_follows_half_the_stride_of_unequal_steps() {
        let mut d = RobustDetector::new(RobustStepParams::default());
        d.period_s = 0.5;
        for i in 0..200 {
            d.follow_period(if i % 2 == 0 { 0.40 } else { 0.62 }, true);
        }
        assert!((d.period_s - 0.51).abs() < 0.01, "{}", d.period_s);
    }

    #[test]
    fn intervals_off_cadence_barely_move_the_period() {
        assert_eq!(period_gain(0.6, 0.5), PERIOD_GAIN_ON_CADENCE);
        assert_eq!(period_gain(0.66, 0.5), PERIOD_GAIN_OFF_CADENCE);
        assert_eq!(period_gain(0.34, 0.5), PERIOD_GAIN_OFF_CADENCE);
    }
}
