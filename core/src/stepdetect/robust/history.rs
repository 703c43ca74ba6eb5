//! The last grid samples of the de-meaned magnitude, stored twice so the newest n are
//! always one contiguous slice, and their normalised autocorrelation at a lag (the
//! periodicity checks of bouts).

use super::{RobustDetector, GRID_DT_S};

/// Grid samples kept (5.12 s).
pub(super) const HISTORY: usize = 256;
/// The autocorrelation spans at least this long, s, and at least this many lags.
const ACF_MIN_WINDOW_S: f64 = 3.0;
const ACF_WINDOW_LAGS: f64 = 2.5;
/// It needs an overlap of twice the lag, at most twice this many grid samples (1 s).
const ACF_MIN_OVERLAP: usize = 25;

/// The ring of grid samples.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct History {
    pub(super) buf: [f64; 2 * HISTORY],
    /// Where the next value goes, 0..HISTORY.
    pub(super) pos: usize,
    pub(super) len: usize,
}

impl History {
    pub(super) fn new() -> Self {
        Self {
            buf: [0.0; 2 * HISTORY],
            pos: 0,
            len: 0,
        }
    }

    pub(super) fn push(&mut self, v: f64) {
        self.buf[self.pos] = v;
        self.buf[self.pos + HISTORY] = v;
        self.pos = (self.pos + 1) % HISTORY;
        self.len = (self.len + 1).min(HISTORY);
    }

    /// The newest `n` values (n ≤ len), oldest first.
    pub(super) fn last(&self, n: usize) -> &[f64] {
        let end = self.pos + HISTORY;
        &self.buf[end - n..end]
    }
}

impl RobustDetector {
    /// Normalised autocorrelation of the last grid samples at `lag_s`.
    pub(super) fn acf(&self, lag_s: f64) -> f64 {
        let lag = (lag_s / GRID_DT_S).round() as usize;
        if lag == 0 {
            return 1.0;
        }
        let want = (ACF_MIN_WINDOW_S.max(ACF_WINDOW_LAGS * lag_s) / GRID_DT_S) as usize;
        let n = want.min(self.xs.len.saturating_sub(lag));
        if n < 2 * lag.min(ACF_MIN_OVERLAP) {
            return f64::NAN;
        }
        let (mut sa, mut sb, mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let recent = self.xs.last(n + lag);
        for (&a, &b) in recent[lag..].iter().zip(&recent[..n]) {
            sa += a;
            sb += b;
            sab += a * b;
            saa += a * a;
            sbb += b * b;
        }
        let nf = n as f64;
        let cov = sab - sa * sb / nf;
        let va = saa - sa * sa / nf;
        let vb = sbb - sb * sb / nf;
        if va <= 0.0 || vb <= 0.0 {
            return 0.0;
        }
        cov / (va * vb).sqrt()
    }

    /// The autocorrelation at `lag_s` over its whole window ([`ACF_MIN_WINDOW_S`] at
    /// least); NaN while less signal has been seen.
    pub(super) fn acf_full_window(&self, lag_s: f64) -> f64 {
        let span_s = ACF_MIN_WINDOW_S.max(ACF_WINDOW_LAGS * lag_s) + lag_s;
        if (self.xs.len as f64) * GRID_DT_S < span_s {
            return f64::NAN;
        }
        self.acf(lag_s)
    }

    /// Whether the autocorrelation at the step or at the stride period reaches `min`
    /// (the stride lag is only computed when the step lag fails; NaN never passes).
    pub(super) fn periodic(&self, period_s: f64, min: f64) -> bool {
        self.acf(period_s) >= min || self.acf(2.0 * period_s) >= min
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_newest_values_are_one_slice_oldest_first() {
        let mut h = History::new();
        for i in 0..(HISTORY + 10) {
            h.push(i as f64);
        }
        assert_eq!(h.len, HISTORY);
        let last = h.last(3);
        assert_eq!(
            last,
            &[
                (HISTORY + 7) as f64,
                (HISTORY + 8) as f64,
                (HISTORY + 9) as f64
            ]
        );
    }
}
