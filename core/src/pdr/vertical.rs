//! How far the phone rises and falls over a step, for the inverted-pendulum step
//! length (`StepLengthModel::Pendulum`, Zijlstra & Hof 2003: the body vaults over
//! the stance leg, so a longer step lifts and drops it more, L ≈ 2·√(2·l·h)).
//!
//! The navigator pushes the vertical specific force (earth frame, from its attitude)
//! of every sample; [`VerticalHistory`] averages it into [`SLOT_S`] slots and keeps
//! the newest [`SLOTS`] non-empty ones (8 s at 50 Hz or faster), so a step the
//! detector releases seconds late still finds its own span. Over a step's span
//! ([`VerticalHistory::displacement_range_m`]): the mean is removed (gravity, and
//! any tilt error's constant share), the rest is integrated to a vertical velocity
//! whose mean is removed (a step ends at the vertical speed it started with),
//! integrated again to a displacement whose straight-line trend is removed; h is its
//! peak-to-peak. Everything is in time, not samples: irregular, jittered or dropped
//! samples integrate over their own spacing. No allocation: the span's slots are
//! copied to the stack and integrated in three passes.

use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Width of one slot, s.
pub const SLOT_S: f64 = 0.02;
const SLOTS_PER_S: f64 = 50.0;
/// Non-empty slots kept (8 s at one sample per slot or more).
pub const SLOTS: usize = 400;
/// Most slots one span may hold (2.56 s; the navigator's spans are at most 2 s).
pub const MAX_SPAN_SLOTS: usize = 128;
/// Fewest slots a step's span needs, and the share of the span they must cover.
const MIN_SLOTS: usize = 4;
const MIN_COVER: f64 = 0.5;
/// Largest specific force a slot may hold, m/s² (the input layer's limit is lower).
const MAX_FORCE_MPS2: f64 = 4_000.0;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Slot {
    /// ⌊t / SLOT_S⌋ of the samples in it.
    id: i64,
    /// Sum of their vertical specific force, m/s², and how many.
    sum_mps2: f64,
    n: u32,
}

impl Slot {
    fn t_s(&self) -> f64 {
        (self.id as f64 + 0.5) * SLOT_S
    }
    fn mean_mps2(&self) -> f64 {
        self.sum_mps2 / f64::from(self.n)
    }
}

/// The recent vertical specific force, in slots (see the module docs). Equal when
/// they hold the same slots.
#[derive(Clone, Debug, Default)]
pub struct VerticalHistory {
    slots: Ring<Slot, SLOTS>,
}

impl PartialEq for VerticalHistory {
    fn eq(&self, other: &Self) -> bool {
        self.slots.iter().eq(other.slots.iter())
    }
}

impl VerticalHistory {
    pub fn new() -> Self {
        Self::default()
    }

    /// One sample's vertical specific force (earth frame, up positive, gravity
    /// included), m/s², at `t_s`. Samples must come in time order; an earlier one
    /// than the newest slot is ignored, as is a non-finite one.
    pub fn push(&mut self, t_s: f64, up_mps2: f64) {
        if !(t_s.is_finite() && up_mps2.is_finite() && up_mps2.abs() <= MAX_FORCE_MPS2) {
            return;
        }
        let id = (t_s * SLOTS_PER_S).floor() as i64;
        match self.slots.newest_mut() {
            Some(s) if s.id == id => {
                s.sum_mps2 += up_mps2;
                s.n = s.n.saturating_add(1);
            }
            Some(s) if s.id > id => {}
            _ => self.slots.push(Slot {
                id,
                sum_mps2: up_mps2,
                n: 1,
            }),
        }
    }

    /// Peak-to-peak vertical displacement over `t0_s..=t1_s`, m; NaN when the
    /// history does not cover the span (fewer than 4 slots, or less than half of it)
    /// or the span is longer than `MAX_SPAN_SLOTS` slots (2.56 s).
    pub fn displacement_range_m(&self, t0_s: f64, t1_s: f64) -> f64 {
        if t1_s.partial_cmp(&t0_s) != Some(std::cmp::Ordering::Greater) {
            return f64::NAN;
        }
        // The span's slot times and mean forces, oldest first (walked back from the
        // newest, filled from the end of the buffer).
        let mut t = [0.0; MAX_SPAN_SLOTS];
        let mut a = [0.0; MAX_SPAN_SLOTS];
        let mut k = MAX_SPAN_SLOTS;
        for s in self.slots.iter().rev() {
            let ts = s.t_s();
            if ts < t0_s {
                break;
            }
            if ts <= t1_s {
                if k == 0 {
                    return f64::NAN;
                }
                k -= 1;
                t[k] = ts;
                a[k] = s.mean_mps2();
            }
        }
        let (t, a) = (&t[k..], &mut a[k..]);
        let len = t.len();
        if len < MIN_SLOTS || t[len - 1] - t[0] < MIN_COVER * (t1_s - t0_s) {
            return f64::NAN;
        }
        let n = len as f64;
        let first = t[0];
        let a_mean = a.iter().sum::<f64>() / n;
        // Velocity (mean removed), by the rectangle rule over each slot's spacing from
        // the previous one; `a` is overwritten with it.
        let mut v = 0.0;
        let mut v_sum = 0.0;
        for i in 0..len {
            let dt = t[i] - if i == 0 { first } else { t[i - 1] };
            v += (a[i] - a_mean) * dt;
            a[i] = v;
            v_sum += v;
        }
        let v_mean = v_sum / n;
        // Displacement (overwrites the velocity) and its least-squares line
        // x ≈ α + β·τ, τ = t − first.
        let (mut x, mut st, mut sx, mut stt, mut stx) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..len {
            let dt = t[i] - if i == 0 { first } else { t[i - 1] };
            x += (a[i] - v_mean) * dt;
            a[i] = x;
            let tau = t[i] - first;
            st += tau;
            sx += x;
            stt += tau * tau;
            stx += tau * x;
        }
        let den = n * stt - st * st;
        let beta = if den > 0.0 {
            (n * stx - st * sx) / den
        } else {
            0.0
        };
        let alpha = (sx - beta * st) / n;
        let (mut lo_x, mut hi_x) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..len {
            let r = a[i] - alpha - beta * (t[i] - first);
            lo_x = lo_x.min(r);
            hi_x = hi_x.max(r);
        }
        hi_x - lo_x
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        let VerticalHistory { slots } = self;
        w.u64(slots.len() as u64);
        for s in slots.iter() {
            let Slot { id, sum_mps2, n } = s;
            w.u64(id as u64);
            w.f64(sum_mps2);
            w.u64(u64::from(n));
        }
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut slots = Ring::new();
        let mut prev: Option<i64> = None;
        let max_id = (crate::input::limits::MAX_ABS_T_S / SLOT_S) as i64 + 1;
        for _ in 0..r.len(SLOTS)? {
            let id = r.u64()? as i64;
            let sum_mps2 = r.f64()?;
            let n = r.u64()?;
            // Slots in time order, within the time limits, each of 1..u32::MAX samples
            // whose mean is a plausible force.
            let ok = id.abs() <= max_id
                && prev.is_none_or(|p| id > p)
                && (1..=u64::from(u32::MAX)).contains(&n)
                && (sum_mps2 / n as f64).abs() <= MAX_FORCE_MPS2;
            if !ok {
                return Err(SnapshotError::Invalid("vertical history"));
            }
            prev = Some(id);
            slots.push(Slot {
                id,
                sum_mps2,
                n: n as u32,
            });
        }
        Ok(Self { slots })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A walker whose phone bobs by `h` peak to peak at `hz` steps per second, sampled
    /// at `rate_hz` with `jitter` (share of the spacing) on the timestamps.
    fn bobbing(h: f64, hz: f64, rate_hz: f64, jitter: f64, seconds: f64) -> VerticalHistory {
        let mut v = VerticalHistory::new();
        let w = 2.0 * std::f64::consts::PI * hz;
        let n = (seconds * rate_hz) as usize;
        for i in 0..n {
            // A deterministic jitter.
            let j = jitter * ((i * 7919 % 1000) as f64 / 1000.0 - 0.5);
            let t = 100.0 + (i as f64 + j) / rate_hz;
            // x = h/2·cos(ωt): a = −h/2·ω²·cos(ωt), plus gravity.
            v.push(t, 9.81 - 0.5 * h * w * w * (w * t).cos());
        }
        v
    }

    #[test]
    fn a_steps_rise_and_fall_is_recovered_at_any_rate_and_with_jitter() {
        for (rate, jitter) in [
            (50.0, 0.0),
            (100.0, 0.0),
            (400.0, 0.0),
            (50.0, 0.8),
            (30.0, 0.5),
        ] {
            let v = bobbing(0.06, 1.9, rate, jitter, 6.0);
            // One step: a full period ending at the newest samples.
            let t1 = 105.5;
            let h = v.displacement_range_m(t1 - 1.0 / 1.9, t1);
            assert!(
                (h - 0.06).abs() < 0.006,
                "{rate} Hz, jitter {jitter}: h = {h}"
            );
        }
    }

    #[test]
    fn a_span_the_history_does_not_cover_is_nan() {
        let v = bobbing(0.06, 1.9, 50.0, 0.0, 3.0);
        assert!(v.displacement_range_m(10.0, 10.5).is_nan());
        assert!(v.displacement_range_m(102.0, 102.0).is_nan());
        assert!(VerticalHistory::new()
            .displacement_range_m(0.0, 1.0)
            .is_nan());
        // A third of the span is covered.
        assert!(v.displacement_range_m(101.0, 107.0).is_nan());
        assert!(v.displacement_range_m(101.0, 104.0).is_finite());
        // Covered, but longer than a span may be (150 slots > 128).
        assert!(v.displacement_range_m(100.0, 103.0).is_nan());
        assert!(v.displacement_range_m(100.5, 103.0).is_finite());
    }

    #[test]
    fn the_snapshot_round_trips_and_refuses_disorder() {
        let v = bobbing(0.05, 2.0, 50.0, 0.3, 12.0);
        let mut w = Writer::new(0, 0);
        v.write(&mut w);
        let bytes = w.finish();
        let (mut r, _) = Reader::new(&bytes, 0, 0).unwrap();
        let back = VerticalHistory::read(&mut r).unwrap();
        assert_eq!(back, v);
        // Two slots swapped: refused.
        let mut bad = VerticalHistory::new();
        bad.slots.push(Slot {
            id: 5,
            sum_mps2: 9.8,
            n: 1,
        });
        bad.slots.push(Slot {
            id: 4,
            sum_mps2: 9.8,
            n: 1,
        });
        let mut w = Writer::new(0, 0);
        bad.write(&mut w);
        let bytes = w.finish();
        let (mut r, _) = Reader::new(&bytes, 0, 0).unwrap();
        assert!(VerticalHistory::read(&mut r).is_err());
    }
}
