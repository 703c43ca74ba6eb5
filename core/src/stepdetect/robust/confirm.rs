//! Bout confirmation: the newest `confirm_steps` candidates, double peaks merged at the
//! autocorrelation's step period, must look like gait (regular strides, running
//! strength at a running cadence, heel impacts, the phone held one way); older buffered
//! candidates join only while they chain back like steps held the same way.

use super::bout::MISSED_STEP_MAX_PERIODS;
use super::gaps::{fill_missed, walks_across_gap, WEAK_STEPS_BEFORE_BOUT};
use super::pending::{merge, Pending};
use super::slow_walk::SLOW_WALK_MAX_PERIOD_S;
use super::{RobustDetector, Sink, PENDING};
use crate::signal::Ring;
use crate::stepdetect::gait::HALF_LAG_ANTI;
use crate::stepdetect::StepOrigin;
use crate::vec3::dot;

/// The shortest step period of a walk, s (2.86 steps/s; a faster cadence is a run,
/// which must show running strength).
const FAST_WALK_MIN_PERIOD_S: f64 = 0.35;
/// Consecutive steps of a walk are alike in strength: the weaker of two at least this
/// share of the stronger (a slow walk's secondary bump is 45–70 % of its heel strike,
/// Pixel_Jamie_Carpet_InHand_2; the fast in-hand walks' steps are within 10 % of each
/// other at the median).
const STEPS_ALIKE_AMPLITUDE: f64 = 0.75;
/// Largest deviation of one step interval from the period when confirming (left/right
/// asymmetry of a phone carried on one side: 0.45 s / 0.65 s in a front pocket).
pub(super) const ASYMMETRY: f64 = 0.5;
/// The phone held the same way: within 45° (cosine) of how it is held at the newest
/// checked candidate. Putting the phone into a pocket or bag turns it further; a
/// stride's ±30° thigh or arm swing, averaged over the stride, does not.
pub(super) const CARRY_MIN_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// An older candidate still turned more than 30° (cosine) from how the phone is held in
/// the bout ...
const SETTLED_MIN_COS: f64 = 0.866;
/// ... and a jolt (impact ratio over this factor times the bout's median) is the phone
/// being put away (into a pocket: 34–41° and 2–6 times the walk's), not a first step.
const HANDLING_IMPACT_FACTOR: f64 = 2.0;

impl RobustDetector {
    /// Confirm a bout from the newest `confirm_steps` pending candidates and release
    /// its steps: those of a gap before it, of a short walk before it, then its own.
    pub(super) fn try_confirm(&mut self, out: &mut Sink<'_>) {
        let k = self.p.confirm_steps;
        if self.pending.len() < k {
            return;
        }
        let Some(period) = self.bout_period(k) else {
            return;
        };
        let kept = merge_double_peaks(&self.pending, self.p.refractory * period);
        if kept.len() < k || !self.looks_like_gait(&kept, k, period) {
            return;
        }
        // A bout of steps over the floor: the weak candidates among them are bumps.
        self.pending = if self.has_weak_steps(&kept, k) {
            kept
        } else {
            self.over_floor(&kept)
        };
        self.in_bout = true;
        self.period_s = period;
        self.prev_interval_s = f64::NAN;
        let bout_carry = self.pending.newest().map_or([0.0; 3], |c| c.carry);
        let dropped = self.drop_unchained(k, period, bout_carry);
        self.keep_parted_short_walk(dropped, bout_carry);
        self.fill_gap_before_bout(period, out);
        self.release_short_walk(period, out);
        self.release_pending(period, out);
    }

    /// Release the bout's candidates, oldest first, with the steps that gaps in the
    /// data hid between two of them (chained back across the gap) filled at the
    /// cadence.
    fn release_pending(&mut self, period: f64, out: &mut Sink<'_>) {
        let mut prev_t_s = f64::NAN;
        while let Some(c) = self.pending.pop_front() {
            let interval = c.event.t_s - prev_t_s; // NaN for the first
            prev_t_s = c.event.t_s;
            let n = (interval / period).round();
            if n >= 2.0
                && walks_across_gap(interval, c.missing_before_s, period, WEAK_STEPS_BEFORE_BOUT)
            {
                let origin = StepOrigin::FilledAcrossGap;
                fill_missed(c.event, c.event.t_s, interval, n, origin, &mut |e| {
                    out.push(e)
                });
            } else {
                out.push(c.event);
            }
        }
    }

    /// The step period of a bout: the autocorrelation's (not the candidates': bumps
    /// between steps cannot change it), or before it has seen enough signal, the
    /// candidates' own; inside the bout interval range.
    fn bout_period(&self, k: usize) -> Option<f64> {
        let p = self.p;
        let period = match self.gait.step_period(p.min_periodicity) {
            Some((period, _, _)) => period,
            None if !self.gait.ready() => self.candidate_period(k)?,
            None => return None,
        };
        (p.min_bout_interval_s..=p.max_step_interval_s)
            .contains(&period)
            .then_some(period)
    }

    /// The step period from the newest `k` candidates themselves (half their median
    /// stride), when the signal's own autocorrelation is periodic at it: used only
    /// while the autocorrelation has not yet seen `gait::ACF_TAU_S` of signal (a
    /// recording that starts in mid-walk), so the first steps are not lost waiting
    /// for it.
    fn candidate_period(&self, k: usize) -> Option<f64> {
        let mut strides = [0.0f64; PENDING];
        let mut ns = 0;
        for j in 0..k.saturating_sub(2) {
            let (Some(a), Some(c)) = (self.pending.back(j + 2), self.pending.back(j)) else {
                break;
            };
            strides[ns] = c.event.t_s - a.event.t_s;
            ns += 1;
        }
        if ns == 0 {
            return None;
        }
        let st = &mut strides[..ns];
        st.sort_by(f64::total_cmp);
        let period = 0.5 * st[ns / 2];
        // Anti-correlated at the claimed step: the candidates were half steps (a
        // secondary bump between heel strikes), not steps.
        let half_steps = self.acf(period) < HALF_LAG_ANTI;
        (period > 0.0 && !half_steps && self.periodic(period, self.p.min_periodicity))
            .then_some(period)
    }

    /// Whether the newest `k` of `kept` are spaced like steps of `period` (regular
    /// strides: left and right steps of a phone on one side differ, strides do not;
    /// each interval within ±[`ASYMMETRY`]), strong enough for a running cadence, with
    /// heel impacts, and held one way.
    fn looks_like_gait(&self, kept: &Ring<Pending, PENDING>, k: usize, period: f64) -> bool {
        let p = self.p;
        let iv = newest_intervals(kept, k);
        let ivs = &iv[..k - 1];
        let stride = 2.0 * period;
        let irregular = ivs
            .windows(2)
            .any(|w| (w[0] + w[1] - stride).abs() > p.regularity * stride)
            || ivs.iter().any(|&i| (i - period).abs() > ASYMMETRY * period);
        if irregular {
            return false;
        }
        // Running cadence without running impacts: secondary bumps of a slow walk,
        // unless it is a walking cadence and one step looks like the next (a fast walk).
        if period < p.running_interval_s
            && newest_median(kept, k, |c| c.amplitude_mps2) < p.running_min_amplitude_mps2
            && !(period >= FAST_WALK_MIN_PERIOD_S && self.steps_alike(kept, k, period))
        {
            return false;
        }
        // Steps under the absolute floor: a slow walk, at a walking cadence, whose steps
        // all look alike.
        if self.has_weak_steps(kept, k)
            && !(period <= SLOW_WALK_MAX_PERIOD_S && self.steps_alike(kept, k, period))
        {
            return false;
        }
        if newest_median(kept, k, |c| c.impact) < p.min_impact_ratio {
            return false;
        }
        let bout_carry = kept.newest().map_or([0.0; 3], |c| c.carry);
        !(0..k).any(|j| {
            kept.back(j)
                .is_some_and(|c| dot(c.carry, bout_carry) < CARRY_MIN_COS)
        })
    }

    /// Whether consecutive steps of the newest `k` of `kept` look alike, as those of
    /// a fast walk do: the signal repeats at one step `period_s` over the
    /// autocorrelation's whole window (correlation at least `min_periodicity`; 0.72–0.75
    /// at 0.42–0.44 s on the Oxford in-hand walks time-stretched × 1.4), and each
    /// candidate is about as strong as the one before (median ratio of the smaller to
    /// the larger at least [`STEPS_ALIKE_AMPLITUDE`]). A slow walk's secondary bump is
    /// no copy of its heel strike: at the bump's interval the signal is uncorrelated
    /// (−0.32 to −0.05 at 0.38–0.39 s on the slow carpet walks in hand) and the bump is
    /// 45–70 % of the strike. A whole window (3 s): a second of handling the phone can
    /// repeat too; a walk keeps its cadence for seconds.
    fn steps_alike(&self, kept: &Ring<Pending, PENDING>, k: usize, period_s: f64) -> bool {
        let alike = |j: usize| {
            let (Some(a), Some(b)) = (kept.back(j), kept.back(j + 1)) else {
                return 0.0;
            };
            let (lo, hi) = (
                a.amplitude_mps2.min(b.amplitude_mps2),
                a.amplitude_mps2.max(b.amplitude_mps2),
            );
            lo / hi
        };
        median_of(k - 1, alike) >= STEPS_ALIKE_AMPLITUDE
            && self.acf_full_window(period_s) >= self.p.min_periodicity
    }

    /// Whether any of the newest `k` of `kept` is under the absolute amplitude floor (a
    /// slow walk's weak step, see `slow_walk`).
    fn has_weak_steps(&self, kept: &Ring<Pending, PENDING>, k: usize) -> bool {
        (0..k).any(|j| {
            kept.back(j)
                .is_some_and(|c| c.amplitude_mps2 < self.p.min_amplitude_mps2)
        })
    }

    /// Only the newest k candidates were checked. Older ones waiting in the buffer
    /// (handling the phone before walking, a stumble) are steps only while they chain
    /// back from the bout with step-like intervals (a step, a step and a missed one,
    /// or a walk through dropped samples) and the phone held as in the bout, not
    /// being put away ([`SETTLED_MIN_COS`]); the first that does not and all before it
    /// are dropped (returned).
    fn drop_unchained(
        &mut self,
        k: usize,
        period: f64,
        bout_carry: [f64; 3],
    ) -> Ring<Pending, PENDING> {
        let n = self.pending.len();
        let jolt = HANDLING_IMPACT_FACTOR * newest_median(&self.pending, k, |c| c.impact);
        let mut keep = k;
        while keep < n {
            let (Some(older), Some(newer)) = (self.pending.back(keep), self.pending.back(keep - 1))
            else {
                break;
            };
            let iv = newer.event.t_s - older.event.t_s;
            let step_like =
                ((1.0 - ASYMMETRY) * period..MISSED_STEP_MAX_PERIODS * period).contains(&iv);
            if !(step_like
                || walks_across_gap(iv, newer.missing_before_s, period, WEAK_STEPS_BEFORE_BOUT))
            {
                break;
            }
            let cos = dot(older.carry, bout_carry);
            if cos < CARRY_MIN_COS || (cos < SETTLED_MIN_COS && older.impact > jolt) {
                break;
            }
            keep += 1;
        }
        let mut dropped: Ring<Pending, PENDING> = Ring::new();
        for _ in keep..n {
            if let Some(c) = self.pending.pop_front() {
                dropped.push(c);
            }
        }
        dropped
    }
}

/// Candidates closer than `refractory_s` are one step (the larger peak is kept).
fn merge_double_peaks(
    pending: &Ring<Pending, PENDING>,
    refractory_s: f64,
) -> Ring<Pending, PENDING> {
    let mut kept: Ring<Pending, PENDING> = Ring::new();
    for c in pending.iter() {
        match kept.newest_mut() {
            Some(last) if c.event.t_s - last.event.t_s < refractory_s => {
                *last = merge(last, &c);
            }
            _ => kept.push(c),
        }
    }
    kept
}

/// Intervals between the newest `k` of `kept`, oldest first (the first k − 1 values).
fn newest_intervals(kept: &Ring<Pending, PENDING>, k: usize) -> [f64; PENDING] {
    let mut iv = [0.0f64; PENDING];
    for (j, slot) in iv.iter_mut().enumerate().take(k - 1) {
        let a = kept.back(k - 1 - j).map(|c| c.event.t_s).unwrap_or(0.0);
        let b = kept.back(k - 2 - j).map(|c| c.event.t_s).unwrap_or(0.0);
        *slot = b - a;
    }
    iv
}

/// The median (upper, for an even `k`) of `f` over the newest `k` of `kept`.
fn newest_median(kept: &Ring<Pending, PENDING>, k: usize, f: impl Fn(Pending) -> f64) -> f64 {
    median_of(k, |j| kept.back(j).map(&f).unwrap_or(0.0))
}

/// The (upper) median of `f(0) … f(n − 1)`, n ≤ [`PENDING`], without allocating.
fn median_of(n: usize, f: impl Fn(usize) -> f64) -> f64 {
    let mut v = [0.0f64; PENDING];
    for (j, slot) in v.iter_mut().enumerate().take(n) {
        *slot = f(j);
    }
    let v = &mut v[..n];
    v.sort_by(f64::total_cmp);
    v[n / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t_s: f64, amplitude_mps2: f64) -> Pending {
        let mut c = Pending {
            amplitude_mps2,
            ..Pending::default()
        };
        c.event.t_s = t_s;
        c
    }

    #[test]
    fn double_peaks_merge_and_the_medians_and_intervals_are_of_the_newest() {
        let mut ring: Ring<Pending, PENDING> = Ring::new();
        for (t, a) in [(0.0, 3.0), (0.5, 4.0), (0.6, 6.0), (1.0, 5.0), (1.5, 2.0)] {
            ring.push(at(t, a));
        }
        let kept = merge_double_peaks(&ring, 0.3);
        let times: Vec<f64> = kept.iter().map(|c| c.event.t_s).collect();
        assert_eq!(times, [0.0, 0.6, 1.0, 1.5]);
        let iv = newest_intervals(&kept, 3);
        assert!((iv[0] - 0.4).abs() < 1e-12 && (iv[1] - 0.5).abs() < 1e-12);
        assert_eq!(newest_median(&kept, 3, |c| c.amplitude_mps2), 5.0);
    }
}
