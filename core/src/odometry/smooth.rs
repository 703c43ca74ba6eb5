//! Gaussian smoothing of the resampled channels: a symmetric FIR of `2K + 1` taps,
//! `K = ceil(3σ)`, so each output is the smoothed value of the sample `K` grid steps
//! back (a documented delay of `K / rate` seconds, 60 ms at σ = 2 samples, 100 Hz).
//! Fixed capacity: σ ≤ [`MAX_SIGMA_SAMPLES`].

use super::resample::Channels;
use crate::signal::Ring;

/// Largest smoothing σ, grid samples.
pub const MAX_SIGMA_SAMPLES: f64 = 10.0;
/// Largest number of taps (`2·ceil(3·MAX_SIGMA) + 1`).
pub const MAX_TAPS: usize = 61;

/// Causal Gaussian smoother with delay `half_width()` samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaussian {
    taps: [f64; MAX_TAPS],
    n_taps: usize,
    pub(crate) hist: Ring<(f64, Channels), MAX_TAPS>,
}

impl Gaussian {
    /// σ in grid samples, 0 < σ ≤ [`MAX_SIGMA_SAMPLES`] (0 = no smoothing).
    pub fn new(sigma_samples: f64) -> Self {
        let k = if sigma_samples > 0.0 {
            (3.0 * sigma_samples.min(MAX_SIGMA_SAMPLES)).ceil() as usize
        } else {
            0
        };
        let n_taps = 2 * k + 1;
        let mut taps = [0.0; MAX_TAPS];
        let mut sum = 0.0;
        for (i, w) in taps.iter_mut().take(n_taps).enumerate() {
            let x = i as f64 - k as f64;
            *w = if k == 0 {
                1.0
            } else {
                (-0.5 * x * x / (sigma_samples * sigma_samples)).exp()
            };
            sum += *w;
        }
        for w in taps.iter_mut().take(n_taps) {
            *w /= sum;
        }
        Self {
            taps,
            n_taps,
            hist: Ring::new(),
        }
    }

    /// Delay of the output, grid samples.
    pub fn half_width(&self) -> usize {
        self.n_taps / 2
    }

    pub fn reset(&mut self) {
        self.hist.clear();
    }

    /// Push a grid sample; once `2K + 1` are held, returns the smoothed sample `K`
    /// steps back (its time and channels).
    #[inline]
    pub fn push(&mut self, t: f64, x: &Channels) -> Option<(f64, Channels)> {
        self.hist.push((t, *x));
        if self.hist.len() < self.n_taps {
            return None;
        }
        let base = self.hist.len() - self.n_taps;
        let mut y = [0.0; 6];
        for (i, &w) in self.taps.iter().take(self.n_taps).enumerate() {
            let (_, v) = self.hist.get(base + i).unwrap_or_default();
            for c in 0..6 {
                y[c] += w * v[c];
            }
        }
        let (tc, _) = self.hist.get(base + self.half_width()).unwrap_or_default();
        Some((tc, y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_passes_and_delay_is_k() {
        let mut g = Gaussian::new(2.0);
        assert_eq!(g.half_width(), 6);
        let mut out = None;
        for i in 0..20 {
            out = g.push(i as f64, &[3.0; 6]).or(out);
        }
        let (t, y) = out.unwrap();
        assert_eq!(t, 13.0);
        assert!((y[0] - 3.0).abs() < 1e-12);
    }
}
