//! Gyroscope clipping repair: the rotation a saturated gyroscope did not report.
//!
//! A foot's pitch rate peaks in every swing, and a gyroscope whose range is below that
//! peak reports its ceiling for as long as the true rate is above it. The attitude then
//! misses the rotation above the ceiling (a few degrees per stride on the UofT
//! MicroStrain, whose pitch rate clips at about 9.15 rad/s), which tips gravity into
//! the rest of the swing; the next stance's zero-velocity updates put the attitude back,
//! but the velocity and position integrated in between keep the error.
//!
//! Over a clipped run the true rate is modelled as the parabola that leaves the ceiling
//! at the slope it had when it reached it and comes back symmetrically: crossing the
//! ceiling `c` at `t_a` with slope `s` and again at `t_b`, it is
//! `c + s·τ − (s/D)·τ²` (`τ = t − t_a`, `D = t_b − t_a`), and the rotation above the
//! ceiling is `s·D²/6`. Causal: the entry slope comes from the last two samples before
//! the run, the crossing times from linear extrapolation at that slope (the exit one
//! from the first sample after the run), and the missing rotation is added to the rate
//! of the samples after the run (spread over `spread` samples, so that a median
//! pre-filter of that window keeps it). Only with a configured range
//! ([`FootConfig::gyro_range_rads`](super::FootConfig::gyro_range_rads)): a sample at
//! 99 % of it or more is clipped.

use crate::input::limits::MAX_GYRO_RADS;

/// A sample at this share of a configured sensor range or more is at the range
/// (saturated; on a gyroscope axis, clipped).
pub const AT_RANGE: f64 = 0.99;

/// Longest clipped run repaired, s: a parabolic swing peak above the ceiling lasts a
/// few tens of milliseconds; longer saturation (the sensor spun) is left as it is.
pub const MAX_CLIP_S: f64 = 0.2;
/// Largest rotation restored per run, rad (≈ 17°).
pub const MAX_RESTORED_RAD: f64 = 0.3;

/// One axis of the repair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct AxisClip {
    /// The previous two samples' magnitudes and times (`t` NaN before them).
    pub prev: [(f64, f64); 2],
    /// Inside a clipped run: its sign, ceiling, entry slope (rad/s², NaN: unknown)
    /// and entry crossing time.
    pub active: bool,
    pub sign: f64,
    pub ceiling: f64,
    pub slope: f64,
    pub t_entry: f64,
    /// Rotation still to add, rad, and over how many more samples.
    pub pending_rad: f64,
    pub pending_n: u32,
}

impl AxisClip {
    pub(crate) fn new() -> Self {
        Self {
            prev: [(f64::NAN, f64::NAN); 2],
            ..Self::default()
        }
    }

    /// One sample's rate on this axis at `t_s` (after the previous one; `dt` > 0 is
    /// its interval), with the clip threshold `limit`; returns the rate to use.
    pub(crate) fn push(&mut self, t_s: f64, w: f64, dt: f64, limit: f64, spread: u32) -> f64 {
        let mag = w.abs();
        let clipped = mag >= limit;
        let [(t1, m1), (t2, m2)] = self.prev; // newest first
        if clipped && !self.active {
            self.active = true;
            self.sign = w.signum();
            self.ceiling = mag;
            let slope = (m1 - m2) / (t1 - t2);
            if slope.is_finite() && slope > 0.0 && m1 < mag {
                self.slope = slope;
                self.t_entry = (t1 + (mag - m1) / slope).clamp(t1, t_s);
            } else {
                self.slope = f64::NAN;
                self.t_entry = t_s;
            }
        } else if !clipped && self.active {
            self.active = false;
            let s = self.slope;
            if s.is_finite() {
                let t_exit = (t_s - (self.ceiling - mag).max(0.0) / s).clamp(t1, t_s);
                let d = t_exit - self.t_entry;
                if d > 0.0 && d <= MAX_CLIP_S {
                    let restored = (s * d * d / 6.0).min(MAX_RESTORED_RAD);
                    self.pending_rad += self.sign * restored;
                    self.pending_n = spread.max(1);
                }
            }
        }
        self.prev = [(t_s, mag), (t1, m1)];
        let mut out = w;
        if self.pending_n > 0 && dt > 0.0 {
            let add = self.pending_rad / self.pending_n as f64;
            // Within the door's limit (a very short interval would need a rate no
            // sensor gives; the excess is dropped).
            out = (w + add / dt).clamp(-MAX_GYRO_RADS, MAX_GYRO_RADS);
            self.pending_rad -= add;
            self.pending_n -= 1;
            if self.pending_n == 0 {
                self.pending_rad = 0.0;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rate pulse `peak·sin(π t / T)` sampled at 200 Hz, clipped at `c`: the repair
    /// restores the rotation above the ceiling to within 15 %.
    #[test]
    fn a_clipped_parabolic_peak_gets_its_rotation_back() {
        let (peak, period, c, dt) = (11.0_f64, 0.4_f64, 9.15_f64, 0.005_f64);
        let mut a = AxisClip::new();
        let (mut truth, mut clipped, mut repaired) = (0.0, 0.0, 0.0);
        for k in 0..200 {
            let t = k as f64 * dt;
            let w = if t < period {
                peak * (std::f64::consts::PI * t / period).sin()
            } else {
                0.0
            };
            let wc = w.clamp(-c, c);
            truth += w * dt;
            clipped += wc * dt;
            repaired += a.push(t, wc, dt, 0.99 * c, 1) * dt;
        }
        let lost = truth - clipped;
        assert!(lost > 0.02, "the test clips something: {lost}");
        let err = (truth - repaired).abs();
        assert!(err < 0.15 * lost, "lost {lost}, left {err}");
    }

    /// A run that ends on a very short interval: the restored rotation would need a
    /// rate beyond the door's limit, and the rate stays within it (found by fuzzing:
    /// such a rate in the buffered samples made the navigator refuse its own snapshot).
    #[test]
    fn the_restored_rate_stays_within_the_door_limit() {
        let mut a = AxisClip::new();
        let (c, dt) = (9.15_f64, 0.005_f64);
        let mut t = 0.0;
        for w in [5.0, 7.0, c, c, c] {
            a.push(t, w, dt, 0.99 * c, 1);
            t += dt;
        }
        let tiny = 1e-6;
        let out = a.push(t - dt + tiny, 8.0, tiny, 0.99 * c, 1);
        assert!(out.abs() <= MAX_GYRO_RADS, "{out}");
        assert!(out > 8.0, "some rotation is still restored: {out}");
    }

    #[test]
    fn unclipped_rates_pass_unchanged() {
        let mut a = AxisClip::new();
        for k in 0..400 {
            let t = k as f64 * 0.005;
            let w = 8.0 * (t * 7.0).sin();
            assert_eq!(a.push(t, w, 0.005, 9.0, 1), w);
        }
    }
}
