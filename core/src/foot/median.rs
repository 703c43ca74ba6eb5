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
        // One pass over the window (one copy of each sample, its six channels side by
        // side), then a branch-free sorting network on all six channels at once.
        let n = self.window;
        let mut rows = [[0.0_f64; 6]; MAX_MEDIAN_WINDOW];
        let mut saturated = false;
        for (row, v) in rows.iter_mut().zip(self.ring.iter()) {
            *row = [v.f[0], v.f[1], v.f[2], v.w[0], v.w[1], v.w[2]];
            saturated |= v.saturated;
        }
        sort_rows(&mut rows[..n]);
        let mid = rows[n / 2];
        out.f = [mid[0], mid[1], mid[2]];
        out.w = [mid[3], mid[4], mid[5]];
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

/// Sorts each of the six columns of `rows` ascending: odd-even transposition (`n`
/// rounds of compare-exchanges between neighbouring rows), without branches, so the
/// six channels go through the vector unit together and noisy data costs no branch
/// mispredictions (an insertion sort per channel cost ≈ 0.25 µs per sample at 5).
/// The values are finite (checked at the door).
#[inline]
fn sort_rows(rows: &mut [[f64; 6]]) {
    let n = rows.len();
    for round in 0..n {
        let mut i = round & 1;
        while i + 1 < n {
            let (a, b) = rows.split_at_mut(i + 1);
            let (lo, hi) = (&mut a[i], &mut b[0]);
            for c in 0..6 {
                let (x, y) = (lo[c], hi[c]);
                lo[c] = x.min(y);
                hi[c] = x.max(y);
            }
            i += 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_network_sorts_every_column_like_a_sort() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            // Few distinct values, so ties are common.
            (seed % 7) as f64 - 3.0
        };
        for n in 1..=MAX_MEDIAN_WINDOW {
            for _ in 0..200 {
                let mut rows = vec![[0.0; 6]; n];
                for r in rows.iter_mut() {
                    for v in r.iter_mut() {
                        *v = next();
                    }
                }
                let mut want: Vec<Vec<f64>> = (0..6)
                    .map(|c| {
                        let mut col: Vec<f64> = rows.iter().map(|r| r[c]).collect();
                        col.sort_by(f64::total_cmp);
                        col
                    })
                    .collect();
                sort_rows(&mut rows);
                for (c, col) in want.iter_mut().enumerate() {
                    let got: Vec<f64> = rows.iter().map(|r| r[c]).collect();
                    assert_eq!(&got, col, "window {n}, channel {c}");
                }
            }
        }
    }
}
