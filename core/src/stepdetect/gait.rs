//! The step period from the signal's own periodicity, independent of peak picking.
//!
//! Gait repeats every stride (two steps). A running autocorrelation of the de-meaned,
//! low-passed magnitude over the human stride range tells the stride without looking
//! at individual peaks, so secondary bumps, noise from jittered timestamps or a missed
//! peak do not change it. The step period is half the stride when the signal is also
//! positively correlated at half the stride (both steps look alike, or at least do not
//! look like the opposite phase); if it is anti-correlated there, the lag found was a
//! single step (a symmetric slow walk whose step period falls in the stride range).
//!
//! Cost: the grid signal is decimated to 25 Hz and the products for every lag are
//! updated with an exponential window (time constant [`ACF_TAU_S`]): 50 multiply-adds
//! per 25 Hz tick, no search over the history, no allocation.

use crate::snapshot::{Reader, SnapshotError, Writer};

/// Decimated rate of the autocorrelation, Hz (lag resolution 0.04 s).
const ACF_HZ: f64 = 25.0;
const ACF_DT_S: f64 = 1.0 / ACF_HZ;
/// Grid samples averaged into one decimated sample (the grid runs at 50 Hz).
pub(crate) const DECIMATION: usize = 2;
/// Shortest lag kept, decimated samples (0.24 s: half of the shortest stride).
const MIN_LAG: usize = 6;
/// Longest lag kept, decimated samples (2.2 s: the slowest stride, ~55 steps/min).
const MAX_LAG: usize = 55;
/// Shortest stride searched, decimated samples (0.52 s: 230 steps/min).
const MIN_STRIDE_LAG: usize = 13;
/// Time constant of the exponential window, s (about three strides of a walk).
pub(crate) const ACF_TAU_S: f64 = 3.0;
/// A correlation at half the stride lag below this is anti-correlation: the lag was
/// one step (half a step apart, a peak meets a valley). Measured on the Oxford traces:
/// at half a true stride the correlation is above −0.1 in 95 % of candidates of every
/// placement (it measures how alike left and right steps look); at half a true step
/// it is below −0.25 in 95 % of them.
pub(crate) const HALF_LAG_ANTI: f64 = -0.25;
/// Decimated samples needed before the estimate is used: one window time constant
/// (shorter windows hold too few strides; their correlations are noisy).
const MIN_SEEN: usize = (ACF_TAU_S * ACF_HZ) as usize;
/// Samples after which the period overrides a bout's own (two time constants).
const SETTLED_SEEN: usize = 2 * MIN_SEEN;
/// Half a lag that correlates at least this fraction as well is the period (the lag
/// was two strides, or a stride of two look-alike steps). Left and right steps of a
/// phone on one side correlate at less than half the stride's correlation.
const MULTIPLE: f64 = 0.6;
/// Among local maxima at least this fraction of the best, the shortest lag is the
/// stride (the correlation at two strides is about as high as at one).
const NEAR_BEST: f64 = 0.85;

/// Running autocorrelation of the decimated signal at lags 0 and
/// `MIN_LAG..=MAX_LAG`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GaitPeriod {
    gain: f64,
    /// Decimation accumulator.
    acc: f64,
    acc_n: usize,
    /// Decimated samples, circular; `pos` is where the next one goes.
    z: [f64; MAX_LAG + 1],
    pos: usize,
    len: usize,
    /// Windowed mean products, index = lag (0 = power; 1..MIN_LAG unused).
    r: [f64; MAX_LAG + 1],
    /// Decimated samples seen (saturating at [`SETTLED_SEEN`]).
    seen: usize,
}

impl GaitPeriod {
    pub(crate) fn new() -> Self {
        Self {
            gain: 1.0 - (-ACF_DT_S / ACF_TAU_S).exp(),
            acc: 0.0,
            acc_n: 0,
            z: [0.0; MAX_LAG + 1],
            pos: 0,
            len: 0,
            r: [0.0; MAX_LAG + 1],
            seen: 0,
        }
    }

    /// Add one grid sample (50 Hz) of the de-meaned signal; NaN: no measurement (a gap
    /// in the data bridged by interpolation). A decimated sample with a missing part is
    /// missing; the windowed products leave out every pair with a missing sample, so
    /// each lag averages the pairs that were measured.
    pub(crate) fn push(&mut self, x: f64) {
        self.acc += x;
        self.acc_n += 1;
        if self.acc_n < DECIMATION {
            return;
        }
        let z = self.acc / DECIMATION as f64;
        self.acc = 0.0;
        self.acc_n = 0;
        self.z[self.pos] = z;
        let n = MAX_LAG + 1;
        if !z.is_nan() {
            let g = self.gain;
            self.r[0] += g * (z * z - self.r[0]);
            let avail = self.len.min(MAX_LAG);
            for lag in MIN_LAG..=avail {
                let past = self.z[(self.pos + n - lag) % n];
                if !past.is_nan() {
                    self.r[lag] += g * (z * past - self.r[lag]);
                }
            }
            self.seen = (self.seen + 1).min(SETTLED_SEEN);
        }
        self.pos = (self.pos + 1) % n;
        self.len = (self.len + 1).min(n);
    }

    /// Whether enough signal was seen for [`Self::step_period`] to answer.
    pub(crate) fn ready(&self) -> bool {
        self.seen >= MIN_SEEN
    }

    /// Whether two time constants were seen: from then on the period is trusted over
    /// a bout's own (before, a window of about three strides can still lock on half a
    /// step).
    pub(crate) fn settled(&self) -> bool {
        self.seen >= SETTLED_SEEN
    }

    /// Normalised autocorrelation at a (fractional) lag in seconds, linearly
    /// interpolated; NaN outside the kept lags or before enough data.
    pub(crate) fn rho_at(&self, lag_s: f64) -> f64 {
        let l = lag_s / ACF_DT_S;
        let lo = l.floor() as usize;
        if !(MIN_LAG..MAX_LAG).contains(&lo) || self.len <= lo + 1 || self.r[0] <= 0.0 {
            return f64::NAN;
        }
        let f = l - lo as f64;
        (self.r[lo] + f * (self.r[lo + 1] - self.r[lo])) / self.r[0]
    }

    /// The step period, s, and the autocorrelation at the stride; `None` when the best
    /// correlation in the stride range is below `min_rho` or too little was seen.
    pub(crate) fn step_period(&self, min_rho: f64) -> Option<(f64, f64, f64)> {
        if self.r[0] <= 0.0 || self.seen < MIN_SEEN {
            return None;
        }
        let rho = |l: usize| self.r[l] / self.r[0];
        let mut best = f64::NEG_INFINITY;
        for l in MIN_STRIDE_LAG..=MAX_LAG {
            best = best.max(rho(l));
        }
        if best.is_nan() || best < min_rho {
            return None;
        }
        // The shortest local maximum near the best.
        let mut stride_lag = None;
        for l in MIN_STRIDE_LAG..MAX_LAG {
            let v = rho(l);
            if v >= NEAR_BEST * best && v >= rho(l - 1) && v >= rho(l + 1) {
                stride_lag = Some(l);
                break;
            }
        }
        let mut l = stride_lag.unwrap_or(MAX_LAG);
        // Two strides correlate about as well as one: while half the lag correlates
        // nearly as well, the lag was a multiple of the stride.
        while l / 2 >= MIN_STRIDE_LAG {
            let h = (l as f64 / 2.0).round() as usize;
            // The best of the three lags around the half.
            let m = (h - 1..=h + 1)
                .max_by(|&a, &b| rho(a).total_cmp(&rho(b)))
                .unwrap_or(h);
            if rho(m) >= MULTIPLE * rho(l) {
                l = m;
            } else {
                break;
            }
        }
        // Parabolic refinement of the peak between its neighbours.
        let (a, b, c) = (rho(l - 1), rho(l), rho((l + 1).min(MAX_LAG)));
        let den = a - 2.0 * b + c;
        let shift = if den < 0.0 {
            (0.5 * (a - c) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        let stride_s = (l as f64 + shift) * ACF_DT_S;
        let half = self.rho_at(0.5 * stride_s);
        let step_s = if half.is_nan() || half >= HALF_LAG_ANTI {
            0.5 * stride_s
        } else {
            stride_s
        };
        Some((step_s, rho(l), stride_s))
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        let GaitPeriod {
            gain: _, // a constant
            acc,
            acc_n,
            z,
            pos,
            len,
            r,
            seen,
        } = self;
        w.f64(*acc);
        w.u64(*acc_n as u64);
        w.u64(*pos as u64);
        w.u64(*len as u64);
        w.f64s(z);
        w.f64s(r);
        w.u64(*seen as u64);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut g = Self::new();
        // NaN: a missing (bridged) sample.
        g.acc = r.f64_or_nan()?;
        g.acc_n = r.len(DECIMATION - 1)?;
        g.pos = r.len(MAX_LAG)?;
        g.len = r.len(MAX_LAG + 1)?;
        for v in &mut g.z {
            *v = r.f64_or_nan()?;
        }
        r.f64s(&mut g.r)?;
        g.seen = r.len(SETTLED_SEEN)?;
        // De-meaned magnitudes within the door's limit, their sum over a decimation
        // block, and mean products within its square.
        const A: f64 = crate::input::limits::MAX_ACCEL_NORM_MPS2;
        if g.acc.abs() > DECIMATION as f64 * 2.0 * A
            || g.z.iter().any(|v| v.abs() > 2.0 * A)
            || g.r.iter().any(|v| v.abs() > 4.0 * A * A)
        {
            return Err(SnapshotError::Invalid("gait period state"));
        }
        Ok(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feed(mut f: impl FnMut(f64) -> f64, seconds: f64) -> GaitPeriod {
        let mut g = GaitPeriod::new();
        let n = (seconds * 50.0) as usize;
        for i in 0..n {
            g.push(f(i as f64 / 50.0));
        }
        g
    }

    #[test]
    fn symmetric_walk_gives_the_step() {
        // 0.55 s steps, both alike.
        let g = feed(|t| (std::f64::consts::TAU * t / 0.55).sin(), 10.0);
        let (step, rho, _) = g.step_period(0.4).unwrap();
        assert!((step - 0.55).abs() < 0.03, "{step}");
        assert!(rho > 0.8);
    }

    #[test]
    fn asymmetric_walk_gives_half_the_stride() {
        // Stride 1.1 s; the left step has a much smaller peak than the right one.
        let g = feed(
            |t| {
                let s = std::f64::consts::TAU * t / 1.1;
                (2.0 * s).sin() + 0.8 * s.sin()
            },
            10.0,
        );
        let (step, _, _) = g.step_period(0.4).unwrap();
        assert!((step - 0.55).abs() < 0.03, "{step}");
    }

    #[test]
    fn a_slow_symmetric_walk_is_not_halved() {
        // 0.9 s steps: the step lag lies in the stride range; half of it is
        // anti-correlated, so it is one step, not a stride.
        let g = feed(|t| (std::f64::consts::TAU * t / 0.9).sin(), 12.0);
        let (step, _, _) = g.step_period(0.4).unwrap();
        assert!((step - 0.9).abs() < 0.04, "{step}");
    }

    #[test]
    fn noise_is_not_periodic() {
        let mut s = 12345u64;
        let g = feed(
            |_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
                ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            },
            10.0,
        );
        assert!(g.step_period(0.4).is_none());
    }
}
