//! A short walk: a run of regular candidates that ended before a bout could be
//! confirmed (a few steps, then a stop at a door, a shop window, a surveyed point) is
//! kept, and released as steps when a bout at the same cadence and strength is
//! confirmed soon after it.

use super::confirm::{ASYMMETRY, CARRY_MIN_COS};
use super::pending::Pending;
use super::{RobustDetector, Sink, PENDING};
use crate::signal::Ring;
use crate::vec3::dot;

/// Least candidates of a short walk.
const SHORT_WALK_MIN: usize = 3;
/// Longest stop between a short walk and the bout that confirms it, s.
const SHORT_WALK_MAX_GAP_S: f64 = 6.0;
/// A short walk's step intervals must be within this share of the confirming bout's
/// period, and its median amplitude within this factor of the bout's.
const SHORT_WALK_CADENCE: f64 = 0.3;
const SHORT_WALK_AMPLITUDE: f64 = 2.0;

impl RobustDetector {
    /// The pending candidates are about to be dropped by a silence: keep them as a
    /// short walk if they look like one (at least [`SHORT_WALK_MIN`], spaced like
    /// steps: every interval within ±[`ASYMMETRY`] of their median, inside the bout
    /// interval range).
    pub(super) fn keep_short_walk(&mut self) {
        let strong = self.over_floor(&self.pending);
        if self.is_short_walk(&strong) {
            self.short_walk = strong;
        }
    }

    /// Whether the candidates of `ring` look like a short walk (at least
    /// [`SHORT_WALK_MIN`], every interval within ±[`ASYMMETRY`] of their median, the
    /// median inside the bout interval range).
    fn is_short_walk(&self, ring: &Ring<Pending, PENDING>) -> bool {
        let n = ring.len();
        if n < SHORT_WALK_MIN {
            return false;
        }
        let mut iv = [0.0f64; PENDING];
        for (j, slot) in iv.iter_mut().enumerate().take(n - 1) {
            let (Some(a), Some(b)) = (ring.get(j), ring.get(j + 1)) else {
                return false;
            };
            *slot = b.event.t_s - a.event.t_s;
        }
        let mut sorted = iv;
        let ivs = &mut sorted[..n - 1];
        ivs.sort_by(f64::total_cmp);
        let median = ivs[(n - 1) / 2];
        let p = self.p;
        (p.min_bout_interval_s..=p.max_step_interval_s).contains(&median)
            && iv[..n - 1]
                .iter()
                .all(|&i| (i - median).abs() <= ASYMMETRY * median)
    }

    /// A bout was just confirmed at `period` with the candidates in `pending`: release
    /// the kept short walk first if it ended at most [`SHORT_WALK_MAX_GAP_S`] before
    /// the bout, at its cadence and strength, with heel impacts (the same walker
    /// walking before a stop); drop it either way.
    pub(super) fn release_short_walk(&mut self, period: f64, out: &mut Sink<'_>) {
        let short = std::mem::replace(&mut self.short_walk, Ring::new());
        let (Some(first), Some(last)) = (self.pending.get(0), short.newest()) else {
            return;
        };
        let gap = first.event.t_s - last.event.t_s;
        if !(gap > 0.0 && gap <= SHORT_WALK_MAX_GAP_S) {
            return;
        }
        let n = short.len();
        let mut prev = f64::NAN;
        let (mut amp, mut imp) = ([0.0f64; PENDING], [0.0f64; PENDING]);
        for (j, c) in short.iter().enumerate() {
            let iv = c.event.t_s - prev;
            if (iv - period).abs() > SHORT_WALK_CADENCE * period {
                return;
            }
            prev = c.event.t_s;
            amp[j] = c.amplitude_mps2;
            imp[j] = c.impact;
        }
        let mut bout = [0.0f64; PENDING];
        let m = self.pending.len();
        for (j, c) in self.pending.iter().enumerate() {
            bout[j] = c.amplitude_mps2;
        }
        let med = |v: &mut [f64]| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let (a_short, a_bout) = (med(&mut amp[..n]), med(&mut bout[..m]));
        if !(a_short * SHORT_WALK_AMPLITUDE >= a_bout && a_short <= SHORT_WALK_AMPLITUDE * a_bout)
            || med(&mut imp[..n]) < self.p.min_impact_ratio
        {
            return;
        }
        for c in short.iter() {
            out.push(c.event);
        }
    }

    /// The candidates a confirmation `dropped` may be a short walk that a brief stop
    /// (under the silence that keeps one, `max_step_interval_s`) parted from the bout:
    /// a surveyor pausing at a waypoint, a walker at a door. They are kept as a short
    /// walk when all of them form one with the phone held as in the bout
    /// (`bout_carry`), and released on the same terms.
    pub(super) fn keep_parted_short_walk(
        &mut self,
        dropped: Ring<Pending, PENDING>,
        bout_carry: [f64; 3],
    ) {
        if self.short_walk.is_empty()
            && self.is_short_walk(&dropped)
            && dropped
                .iter()
                .all(|c| dot(c.carry, bout_carry) >= CARRY_MIN_COS)
        {
            self.short_walk = dropped;
        }
    }
}
