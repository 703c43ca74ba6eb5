//! The attitude history: steps reach the walking direction seconds late (the detector
//! confirms a bout before it releases its steps), so the attitude is kept in short
//! slots (Σ of the east and north rows of the body → ENU rotation, and μ), and a step
//! gets the walking azimuth of its own time span.

use nalgebra::UnitQuaternion;

use crate::signal::Ring;

/// Slot length, s.
pub(super) const SLOT_S: f64 = 0.2;
/// Slots kept (16 s: longer than the step detector's longest release delay, a bout
/// confirmed after its buffered candidates).
pub(super) const HISTORY_SLOTS: usize = 80;
/// A body vector whose horizontal ENU part is shorter than this share (per sample)
/// points too near the vertical to have an azimuth.
pub(super) const MIN_HORIZONTAL_SHARE: f64 = 0.2;
/// Smallest slot span and weight in the averages (a slot of one sample), s and share.
const MIN_SLOT_SPAN_S: f64 = 1e-9;
const MIN_SLOT_WEIGHT: f64 = 1e-6;

/// The east and north rows of R(q), body → ENU.
pub(super) fn enu_rows(q: &UnitQuaternion<f64>) -> [f64; 6] {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
    ]
}

/// East and north components of body vector `f` through the rows `rows` of R.
pub(super) fn project(rows: &[f64; 6], f: [f64; 3]) -> (f64, f64) {
    let e = rows[0] * f[0] + rows[1] * f[1] + rows[2] * f[2];
    let n = rows[3] * f[0] + rows[4] * f[1] + rows[5] * f[2];
    (e, n)
}

/// One slot: Σ over its samples of the east and north rows of `R(q)` (body → ENU)
/// and the yaw correction μ at its end, so that the azimuth of any body-frame vector
/// averaged over a time span can be computed later.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Slot {
    pub(super) t0_s: f64,
    pub(super) t1_s: f64,
    pub(super) rows: [f64; 6],
    pub(super) n: f64,
    pub(super) mu_rad: f64,
}

impl Slot {
    /// Σ over the slot of the horizontal ENU direction of body vector `f`, with the
    /// yaw correction applied (azimuth − μ).
    fn horizontal(&self, f: [f64; 3]) -> (f64, f64) {
        let (e, n) = project(&self.rows, f);
        let (s, c) = self.mu_rad.sin_cos();
        (c * e - s * n, s * e + c * n)
    }
}

/// The slots, oldest first.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct AttitudeHistory {
    pub(super) slots: Ring<Slot, HISTORY_SLOTS>,
}

impl AttitudeHistory {
    /// One sample at `t_s`: its rows of R and the current μ (which moves over tens of
    /// seconds, not within a slot).
    pub(super) fn push(&mut self, t_s: f64, rows: [f64; 6], mu_rad: f64) {
        match self.slots.newest_mut() {
            Some(slot) if t_s - slot.t0_s < SLOT_S && t_s >= slot.t0_s => {
                for (a, b) in slot.rows.iter_mut().zip(rows) {
                    *a += b;
                }
                slot.n += 1.0;
                slot.t1_s = t_s;
                slot.mu_rad = mu_rad;
            }
            _ => self.slots.push(Slot {
                t0_s: t_s,
                t1_s: t_s,
                rows,
                n: 1.0,
                mu_rad,
            }),
        }
    }

    /// Move μ by `step_rad` in the slots holding samples from `t_s` on (a correction
    /// found after them: the heading across a gap, see `super::gap`).
    pub(super) fn shift_mu_since(&mut self, t_s: f64, step_rad: f64) {
        let mut i = 0;
        while let Some(slot) = self.slots.back_mut(i) {
            if slot.t1_s < t_s {
                break;
            }
            slot.mu_rad = crate::angle::wrap(slot.mu_rad + step_rad);
            i += 1;
        }
    }

    /// The azimuth of body vector `f` averaged over `t0_s..=t1_s`. Spans older than
    /// the history use its oldest slot, spans in a gap the nearest slot; `None` with
    /// no history or a vector near the vertical.
    pub(super) fn azimuth_between(&self, f: [f64; 3], t0_s: f64, t1_s: f64) -> Option<f64> {
        if self.slots.is_empty() {
            return None;
        }
        let (mut e, mut n, mut w) = (0.0, 0.0, 0.0);
        let len = self.slots.len();
        for i in 0..len {
            let Some(s) = self.slots.get(i) else {
                continue;
            };
            // A slot spans from its start to the next slot's start (the newest: to
            // its last sample).
            let end = self
                .slots
                .get(i + 1)
                .map_or(s.t1_s, |next| next.t0_s.min(s.t0_s + SLOT_S));
            let span = (end - s.t0_s).max(MIN_SLOT_SPAN_S);
            let overlap = (end.min(t1_s) - s.t0_s.max(t0_s)).max(0.0);
            if overlap <= 0.0 && !(s.t0_s <= t1_s && t1_s <= end) {
                continue;
            }
            let k = (overlap / span).max(MIN_SLOT_WEIGHT) / s.n;
            let (se, sn) = s.horizontal(f);
            e += k * se;
            n += k * sn;
            w += k;
        }
        if w == 0.0 {
            // Outside the history: the nearest slot.
            let s = if self.slots.get(0).is_some_and(|s| t1_s < s.t0_s) {
                self.slots.get(0)
            } else {
                self.slots.newest()
            }?;
            (e, n) = s.horizontal(f);
            w = s.n;
        }
        (e.hypot(n) > MIN_HORIZONTAL_SHARE * w).then(|| e.atan2(n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// Body +x pointing at azimuth `az` (level), sampled at 100 Hz over `t0..t1`.
    fn history(t0: f64, t1: f64, az_of_t: impl Fn(f64) -> f64, mu_rad: f64) -> AttitudeHistory {
        let mut h = AttitudeHistory::default();
        let mut t = t0;
        while t < t1 {
            // Body x → ENU (sin az, cos az): a rotation about up by π/2 − az.
            let q = UnitQuaternion::from_axis_angle(
                &Vector3::z_axis(),
                0.5 * std::f64::consts::PI - az_of_t(t),
            );
            h.push(t, enu_rows(&q), mu_rad);
            t += 0.01;
        }
        h
    }

    #[test]
    fn a_span_gets_the_azimuth_of_its_own_time() {
        let h = history(0.0, 10.0, |t| if t < 5.0 { 0.2 } else { 1.2 }, 0.0);
        let x = [1.0, 0.0, 0.0];
        assert!((h.azimuth_between(x, 1.0, 2.0).unwrap() - 0.2).abs() < 1e-9);
        assert!((h.azimuth_between(x, 6.0, 7.0).unwrap() - 1.2).abs() < 1e-9);
        // Older than the history (16 s kept of it here: all), in the future: the
        // nearest slot.
        assert!((h.azimuth_between(x, -3.0, -2.0).unwrap() - 0.2).abs() < 1e-9);
        assert!((h.azimuth_between(x, 20.0, 21.0).unwrap() - 1.2).abs() < 1e-9);
        // A vertical body vector has no azimuth.
        assert!(h.azimuth_between([0.0, 0.0, 1.0], 1.0, 2.0).is_none());
        assert!(AttitudeHistory::default()
            .azimuth_between(x, 0.0, 1.0)
            .is_none());
    }

    #[test]
    fn the_yaw_correction_is_subtracted_and_old_slots_drop_out() {
        let h = history(0.0, 30.0, |_| 0.5, 0.1);
        let az = h.azimuth_between([1.0, 0.0, 0.0], 20.0, 21.0).unwrap();
        assert!((az - 0.4).abs() < 1e-9, "{az}");
        assert_eq!(h.slots.len(), HISTORY_SLOTS);
        assert!(h.slots.get(0).unwrap().t0_s > 30.0 - 16.0 - 0.5);
    }
}
