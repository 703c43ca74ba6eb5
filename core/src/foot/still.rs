//! The stillness floor: the quietest detector windows of the last few seconds, per
//! sensor. A walking foot stands still at least once per stride, so the floor is what
//! a stance looks like on this shoe now (sensor noise, or a vibration on top of it).

use super::detect::{WindowStats, STILL_WINDOW_S};
use crate::signal::Ring;

/// Capacity of each sliding-minimum queue (a queue holds only rising values; at more
/// than ~340 Hz a steady rise over [`STILL_WINDOW_S`] drops its oldest entry).
pub(crate) const STILL_CAP: usize = 1024;

/// Sliding minima of the SHOE terms per sample over [`STILL_WINDOW_S`].
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct StillFloor {
    /// `(t, shoe_acc_ss / n)`, rising from the front (the front is the minimum).
    pub acc: Ring<(f64, f64), STILL_CAP>,
    /// `(t, shoe_gyro_ss / n)`, likewise.
    pub gyro: Ring<(f64, f64), STILL_CAP>,
}

/// Push `(t, v)` into a sliding-minimum queue and drop what is older than `horizon`.
fn push_min(q: &mut Ring<(f64, f64), STILL_CAP>, t: f64, v: f64, horizon: f64) {
    while q.newest().is_some_and(|(_, x)| x >= v) {
        q.pop_back();
    }
    if q.len() == STILL_CAP {
        q.pop_front();
    }
    q.push((t, v));
    while q.len() > 1 && q.get(0).is_some_and(|(t0, _)| t0 < horizon) {
        q.pop_front();
    }
}

impl StillFloor {
    /// Take the window around the sample at `t_s` into the floor.
    pub fn push(&mut self, t_s: f64, s: &WindowStats) {
        let inv = 1.0 / s.n.max(1) as f64;
        let horizon = t_s - STILL_WINDOW_S;
        push_min(&mut self.acc, t_s, s.shoe_acc_ss * inv, horizon);
        push_min(&mut self.gyro, t_s, s.shoe_gyro_ss * inv, horizon);
    }

    /// `s` with the floor filled in.
    pub fn apply(&self, s: WindowStats) -> WindowStats {
        WindowStats {
            still_acc_ms2_sq: self.acc.get(0).map_or(0.0, |(_, v)| v),
            still_gyro_rads_sq: self.gyro.get(0).map_or(0.0, |(_, v)| v),
            ..s
        }
    }
}
