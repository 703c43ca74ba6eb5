//! Rate-independent front end: the accelerometer signal, taken as piecewise linear
//! between samples, is averaged over consecutive bins of [`BIN_S`] seconds (20 ms,
//! i.e. a 50 Hz grid). The bin mean is an exact time integral, so a 100 Hz and a
//! 400 Hz recording of the same motion give the same bins (up to the sensor's own
//! filtering), and the box average is the anti-alias filter. A gap longer than
//! [`MAX_GAP_S`] restarts the grid at the next sample (the caller drops its window).

/// Bin length, s (50 Hz grid).
pub const BIN_S: f64 = 0.02;
/// Longest interval between two samples that is interpolated, s.
pub const MAX_GAP_S: f64 = 0.25;
/// Bins a single interval can complete (MAX_GAP_S / BIN_S rounded up, plus margin).
const MAX_BINS_PER_STEP: usize = 16;

/// Streaming bin averager. Fixed size, no heap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BinAverager {
    /// Previous sample (time, value), `None` before the first.
    prev: Option<(f64, [f64; 3])>,
    /// End of the current bin, s.
    bin_end_s: f64,
    /// Integral of the signal over the covered part of the current bin, (m/s²)·s.
    acc: [f64; 3],
}

/// What one sample produced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Bins {
    /// The grid restarted (a gap): bins before this sample are unrelated to later ones.
    pub restarted: bool,
    /// Completed bin means, oldest first (`len` of them).
    pub means: [[f64; 3]; MAX_BINS_PER_STEP],
    pub len: usize,
}

impl BinAverager {
    pub fn new() -> Self {
        Self::default()
    }

    /// Start over (the next sample starts a new grid).
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// Adds a sample (time strictly after the previous one, checked by the caller);
    /// returns the bins it completed.
    pub fn push(&mut self, t_s: f64, a: [f64; 3]) -> Bins {
        let mut out = Bins::default();
        let Some((t0, a0)) = self.prev else {
            self.start(t_s, a);
            return out;
        };
        let dt = t_s - t0;
        if !(dt > 0.0 && dt <= MAX_GAP_S) {
            self.start(t_s, a);
            out.restarted = true;
            return out;
        }
        // Linear interpolation between (t0, a0) and (t_s, a).
        let at = |u: f64| -> [f64; 3] {
            let w = ((u - t0) / dt).clamp(0.0, 1.0);
            [
                a0[0] + (a[0] - a0[0]) * w,
                a0[1] + (a[1] - a0[1]) * w,
                a0[2] + (a[2] - a0[2]) * w,
            ]
        };
        let mut u = t0;
        let mut au = a0;
        while self.bin_end_s <= t_s && out.len < MAX_BINS_PER_STEP {
            let v = self.bin_end_s;
            let av = at(v);
            let span = v - u;
            for k in 0..3 {
                self.acc[k] += 0.5 * span * (au[k] + av[k]);
                out.means[out.len][k] = self.acc[k] / BIN_S;
            }
            out.len += 1;
            self.acc = [0.0; 3];
            u = v;
            au = av;
            let next = self.bin_end_s + BIN_S;
            if next <= self.bin_end_s {
                // Time too large for the grid's resolution: restart instead of looping.
                self.start(t_s, a);
                out.restarted = true;
                return out;
            }
            self.bin_end_s = next;
        }
        let span = t_s - u;
        for k in 0..3 {
            self.acc[k] += 0.5 * span * (au[k] + a[k]);
        }
        self.prev = Some((t_s, a));
        out
    }

    pub(crate) fn write(&self, w: &mut crate::snapshot::Writer) {
        w.bool(self.prev.is_some());
        let (t, a) = self.prev.unwrap_or_default();
        w.f64(t);
        w.f64s(&a);
        w.f64(self.bin_end_s);
        w.f64s(&self.acc);
    }

    pub(crate) fn read(
        r: &mut crate::snapshot::Reader<'_>,
    ) -> Result<Self, crate::snapshot::SnapshotError> {
        let some = r.bool()?;
        let t = r.f64()?;
        let mut a = [0.0; 3];
        r.f64s(&mut a)?;
        let bin_end_s = r.f64()?;
        let mut acc = [0.0; 3];
        r.f64s(&mut acc)?;
        // The current bin ends within one bin after the newest sample; the sample is
        // within the door's limits and the integral within a bin's worth of it.
        if some && !(bin_end_s > t - 1e-9 && bin_end_s <= t + BIN_S + 1e-9) {
            return Err(crate::snapshot::SnapshotError::Invalid("bin time"));
        }
        let amax = crate::input::limits::MAX_ACCEL_MPS2;
        if a.iter().any(|v| v.abs() > amax) || acc.iter().any(|v| v.abs() > amax * BIN_S) {
            return Err(crate::snapshot::SnapshotError::Invalid("bin state"));
        }
        Ok(Self {
            prev: some.then_some((t, a)),
            bin_end_s,
            acc,
        })
    }

    fn start(&mut self, t_s: f64, a: [f64; 3]) {
        self.prev = Some((t_s, a));
        self.bin_end_s = t_s + BIN_S;
        self.acc = [0.0; 3];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bins_of(rate_hz: f64, f: impl Fn(f64) -> f64) -> Vec<f64> {
        let mut b = BinAverager::new();
        let mut out = Vec::new();
        let n = (4.0 * rate_hz) as usize;
        for k in 0..=n {
            let t = 100.0 + k as f64 / rate_hz;
            let r = b.push(t, [f(t), 0.0, 9.81]);
            assert!(!r.restarted);
            out.extend(r.means[..r.len].iter().map(|m| m[0]));
        }
        out
    }

    #[test]
    fn bins_are_rate_independent() {
        let f = |t: f64| (std::f64::consts::TAU * 1.8 * t).sin();
        let a = bins_of(100.0, f);
        let b = bins_of(400.0, f);
        assert!((a.len() as i64 - 200).abs() <= 1, "{}", a.len());
        let n = a.len().min(b.len());
        let worst = (0..n).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
        assert!(worst < 2e-3, "{worst}");
        // A constant stays exactly constant.
        let c = bins_of(137.0, |_| 2.5);
        assert!(c.iter().all(|v| (v - 2.5).abs() < 1e-9));
    }

    #[test]
    fn gaps_restart_the_grid() {
        let mut b = BinAverager::new();
        b.push(0.0, [1.0; 3]);
        assert_eq!(b.push(0.01, [1.0; 3]).len, 0);
        assert_eq!(b.push(0.03, [1.0; 3]).len, 1);
        let r = b.push(5.0, [1.0; 3]);
        assert!(r.restarted && r.len == 0);
        // A huge clock value cannot make the grid loop forever.
        let r = b.push(1e300, [1.0; 3]);
        assert!(r.restarted);
        let r = b.push(1e300 * (1.0 + f64::EPSILON), [1.0; 3]);
        assert!(r.restarted);
    }
}
