//! Resampling onto the model's rate: linear interpolation of the stabilised
//! channels between consecutive input samples at the grid times `t0 + k / rate`.
//! Input faster than the model is decimated by interpolation *without* an
//! anti-alias filter (the Gaussian smoothing comes after the resampling): content
//! above the model's Nyquist frequency (50 Hz at 100 Hz) folds back. Gait content
//! is far below it; sensor noise aliases. Slower input is interpolated.

/// Gyro (ENU, rad/s) then linear acceleration (ENU, m/s²).
pub type Channels = [f64; 6];

/// Longest span one push interpolates, s (the AHRS's largest `max_gap_s`).
const MAX_GAP_S: f64 = crate::ahrs::MAX_GAP_LIMIT_S;

/// Interpolates a stream of `(t, channels)` onto a uniform grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resampler {
    pub(crate) dt_s: f64,
    /// Previous input sample.
    pub(crate) prev: Option<(f64, Channels)>,
    /// Index of the next grid time and the grid origin.
    pub(crate) t0_s: f64,
    pub(crate) k: u64,
}

impl Resampler {
    pub fn new(rate_hz: f64) -> Self {
        Self {
            dt_s: 1.0 / rate_hz,
            prev: None,
            t0_s: 0.0,
            k: 0,
        }
    }

    /// Whether a restored state is consistent: the next grid time lies within one
    /// grid step of the previous input sample (so a push advances a bounded number
    /// of grid points).
    pub(crate) fn is_consistent(&self) -> bool {
        match self.prev {
            None => true,
            Some((tp, _)) => {
                let next = self.t0_s + self.k as f64 * self.dt_s;
                next > tp - 1e-9 && next <= tp + self.dt_s + 1e-9
            }
        }
    }

    /// Forget the history (after a gap); the next sample starts a new grid.
    pub fn reset(&mut self) {
        self.prev = None;
        self.k = 0;
    }

    /// Feed one input sample; `emit` is called for every grid time in
    /// `(previous input, t]` with the interpolated channels.
    #[inline]
    pub fn push(&mut self, t: f64, x: Channels, mut emit: impl FnMut(f64, &Channels)) {
        let Some((tp, xp)) = self.prev else {
            self.prev = Some((t, x));
            self.t0_s = t;
            self.k = 1;
            emit(t, &x);
            return;
        };
        // Bounded by construction: the engine restarts the grid after a gap longer
        // than its AHRS's `max_gap_s` (at most 10 s), so no push covers more than
        // MAX_GAP_S of grid; the cap also ends the loop on a corrupt grid state.
        let cap = (MAX_GAP_S / self.dt_s) as u64 + 2;
        for _ in 0..cap {
            let tg = self.t0_s + self.k as f64 * self.dt_s;
            if tg > t {
                break;
            }
            let f = ((tg - tp) / (t - tp)).clamp(0.0, 1.0);
            let mut y = [0.0; 6];
            for i in 0..6 {
                y[i] = xp[i] + f * (x[i] - xp[i]);
            }
            emit(tg, &y);
            self.k = self.k.saturating_add(1);
        }
        if self.t0_s + self.k as f64 * self.dt_s <= t {
            // Cap reached: skip the rest of the span and continue after `t`.
            self.t0_s = t;
            self.k = 1;
        }
        self.prev = Some((t, x));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_signal_is_reproduced_on_the_grid() {
        let mut r = Resampler::new(100.0);
        let mut out = Vec::new();
        let mut t = 0.0;
        while t < 1.0 {
            r.push(t, [t; 6], |tg, y| out.push((tg, y[0])));
            t += 0.0137;
        }
        assert!(out.len() > 90);
        for (tg, y) in out {
            assert!((tg - y).abs() < 1e-12);
        }
    }
}
