//! Sliding median pre-filter (paper): each of the six channels is replaced by the
//! median of a centred window of `M` samples (odd), which removes impact spikes while
//! keeping the edges of the stance phases. `M = 1` passes samples through.

use super::types::BodySample;
use crate::signal::Ring;

/// Largest supported median window, samples.
pub const MAX_MEDIAN_WINDOW: usize = 15;

#[derive(Clone, Debug, PartialEq)]
pub struct MedianFilter {
    window: usize,
    ring: Ring<BodySample, MAX_MEDIAN_WINDOW>,
}

impl MedianFilter {
    /// `window` must be odd and 1..=15 (checked by the configuration).
    pub fn new(window: usize) -> Self {
        Self {
            window,
            ring: Ring::new(),
        }
    }

    /// Samples of delay between input and output.
    pub fn delay(&self) -> usize {
        self.window / 2
    }

    /// Push a sample; once the window is full, the filtered centre sample comes out
    /// (its timestamp is the centre sample's).
    #[inline]
    pub fn push(&mut self, s: BodySample) -> Option<BodySample> {
        if self.window <= 1 {
            return Some(s);
        }
        // Keep exactly `window` samples.
        while self.ring.len() >= self.window {
            self.ring.pop_front();
        }
        self.ring.push(s);
        if self.ring.len() < self.window {
            return None;
        }
        let centre = self.ring.back(self.window / 2).unwrap_or(s);
        let mut out = centre;
        // One pass over the window (one copy of each sample), then a short sort per
        // channel.
        let mut buf = [[0.0_f64; MAX_MEDIAN_WINDOW]; 6];
        let mut saturated = false;
        for (k, v) in self.ring.iter().enumerate() {
            for ch in 0..3 {
                buf[ch][k] = v.f[ch];
                buf[ch + 3][k] = v.w[ch];
            }
            saturated |= v.saturated;
        }
        for (ch, b) in buf.iter_mut().enumerate() {
            let w = &mut b[..self.window];
            insertion_sort(w);
            out.set_channel(ch, w[self.window / 2]);
        }
        // A saturated sample anywhere in the window taints the output.
        out.saturated = saturated;
        Some(out)
    }

    pub(crate) fn samples(&self) -> impl Iterator<Item = BodySample> + '_ {
        self.ring.iter()
    }

    pub(crate) fn restore_push(&mut self, s: BodySample) {
        self.ring.push(s);
    }
}

/// Sorts a short slice by `f64::total_cmp` (faster than the general sort for the
/// ≤ 15 values of a median window; same order).
#[inline]
fn insertion_sort(w: &mut [f64]) {
    for i in 1..w.len() {
        let x = w[i];
        let mut j = i;
        while j > 0 && w[j - 1].total_cmp(&x).is_gt() {
            w[j] = w[j - 1];
            j -= 1;
        }
        w[j] = x;
    }
}
