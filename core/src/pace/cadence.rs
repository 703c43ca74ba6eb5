//! Cadence from step data: a two-state Kalman filter on [cumulative steps, cadence].
//!
//! Platform step counters deliver integers, often once a second: a cadence from a
//! short window carries ±1 step of quantisation (8 % over 4 s at 170 steps/min), a
//! long window lags behind pace changes. Cadence itself changes slowly (runners speed
//! up mostly by longer steps), so a filter with a slowly wandering cadence averages
//! the quantisation away and still follows interval changes within seconds.
//!
//! Count and event samples measure the step total (events exactly, counts to ±0.5
//! step); cadence reports measure the cadence directly.

use crate::snapshot::{Reader, SnapshotError, Writer};

/// Random walk of cadence, steps/s per √s.
const CADENCE_RW: f64 = 0.06;
/// Quantisation of an integer step count (uniform ±0.5 step), steps.
const COUNT_SIGMA: f64 = 0.35;
/// Timing uncertainty of a step event expressed in steps.
const EVENT_SIGMA: f64 = 0.15;
/// Noise of a reported cadence, steps/s (watches report whole steps per minute).
const REPORT_SIGMA: f64 = 1.5 / 60.0;
/// Highest cadence the filter holds, steps/s: the input layer's cadence limit
/// (300 steps/min). Sparse counts after a pause could otherwise drive the estimate to
/// tens of steps/s, an estimate no runner has and a state `restore` refuses.
/// Largest variances the filter keeps: (10⁵ steps)², (100 steps/s)².
const MAX_STEPS_VARIANCE: f64 = 1e10;
const MAX_CADENCE_VARIANCE: f64 = 1e4;
const MAX_CADENCE_HZ: f64 = crate::input::limits::MAX_CADENCE_SPM / 60.0;

/// Kalman filter on [n (steps), c (steps/s)].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CadenceFilter {
    active: bool,
    t_s: f64,
    n: f64,
    c: f64,
    p: [[f64; 2]; 2],
}

impl Default for CadenceFilter {
    fn default() -> Self {
        Self::IDLE
    }
}

impl CadenceFilter {
    pub const IDLE: Self = Self {
        active: false,
        t_s: 0.0,
        n: 0.0,
        c: 0.0,
        p: [[0.0; 2]; 2],
    };

    /// Start a bout at `t` with step total `n` and a first cadence guess.
    pub fn start(t_s: f64, n: f64, c: f64) -> Self {
        Self {
            active: true,
            t_s,
            n,
            c,
            p: [[COUNT_SIGMA * COUNT_SIGMA, 0.0], [0.0, 1.0]],
        }
    }

    pub fn is_active(&self) -> bool {
        self.active
    }

    fn predict(&mut self, t: f64) {
        let dt = t - self.t_s;
        if dt.is_nan() || dt <= 0.0 {
            return;
        }
        self.t_s = t;
        self.n += self.c * dt;
        let q = CADENCE_RW * CADENCE_RW;
        let p = self.p;
        // F = [[1, dt], [0, 1]], Q for a random-walk rate: q·[[dt³/3, dt²/2], [dt²/2, dt]].
        let p00 = p[0][0] + dt * (p[0][1] + p[1][0]) + dt * dt * p[1][1] + q * dt * dt * dt / 3.0;
        let p01 = p[0][1] + dt * p[1][1] + q * dt * dt / 2.0;
        let p11 = p[1][1] + q * dt;
        // Across a gap of months P would grow as dt³ past what a snapshot holds: cap
        // the variances (D·P·D scaling keeps the correlation), a no-op normally.
        let d0 = (MAX_STEPS_VARIANCE / p00).sqrt().min(1.0);
        let d1 = (MAX_CADENCE_VARIANCE / p11).sqrt().min(1.0);
        self.p = [
            [p00 * d0 * d0, p01 * d0 * d1],
            [p01 * d0 * d1, p11 * d1 * d1],
        ];
    }

    /// Measure the step total at `t`: exact for events, ±0.5 for counts.
    pub fn observe_total(&mut self, t: f64, total: f64, exact: bool) {
        self.predict(t);
        let r = if exact { EVENT_SIGMA } else { COUNT_SIGMA }.powi(2);
        let s = self.p[0][0] + r;
        let (k0, k1) = (self.p[0][0] / s, self.p[1][0] / s);
        let y = total - self.n;
        self.n += k0 * y;
        self.c = (self.c + k1 * y).clamp(0.0, MAX_CADENCE_HZ);
        let p = self.p;
        let p00 = (1.0 - k0) * p[0][0];
        let p01 = (1.0 - k0) * p[0][1];
        let p11 = p[1][1] - k1 * p[0][1];
        self.p = [[p00, p01], [p01, p11.max(1e-9)]];
    }

    /// Measure the cadence directly (a device's cadence report), steps/s.
    pub fn observe_cadence(&mut self, t: f64, c: f64) {
        self.predict(t);
        let r = REPORT_SIGMA * REPORT_SIGMA;
        let s = self.p[1][1] + r;
        let (k0, k1) = (self.p[0][1] / s, self.p[1][1] / s);
        let y = c - self.c;
        self.n += k0 * y;
        self.c = (self.c + k1 * y).clamp(0.0, MAX_CADENCE_HZ);
        let p = self.p;
        let p00 = p[0][0] - k0 * p[1][0];
        let p01 = (1.0 - k1) * p[0][1];
        let p11 = (1.0 - k1) * p[1][1];
        self.p = [[p00.max(1e-9), p01], [p01, p11.max(1e-12)]];
    }

    /// Multiply the step total and the cadence by `k` (the stream counted strides:
    /// `super::steps::StepStream::rescale`), the covariance by k².
    pub fn rescale(&mut self, k: f64) {
        self.n *= k;
        self.c = (self.c * k).clamp(0.0, MAX_CADENCE_HZ);
        for row in &mut self.p {
            for v in row {
                *v *= k * k;
            }
        }
    }

    /// Cadence estimate, steps/s, and its 1-σ.
    pub fn cadence(&self) -> (f64, f64) {
        (self.c, self.p[1][1].max(0.0).sqrt())
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.bool(self.active);
        w.f64s(&[
            self.t_s,
            self.n,
            self.c,
            self.p[0][0],
            self.p[0][1],
            self.p[1][1],
        ]);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let active = r.bool()?;
        let mut v = [0.0; 6];
        r.f64s(&mut v)?;
        // A covariance: non-negative variances, |correlation| ≤ 1; a step total and a
        // cadence (steps/s) of human size.
        if !(0.0..=1e12).contains(&v[3])
            || !(0.0..=1e6).contains(&v[5])
            || v[4] * v[4] > v[3] * v[5] * (1.0 + 1e-9) + 1e-300
        {
            return Err(SnapshotError::Invalid("cadence covariance"));
        }
        if v[0].abs() > crate::input::limits::MAX_ABS_T_S + 1.0
            || v[1].abs() > 1e12
            || v[2].abs() > 100.0
        {
            return Err(SnapshotError::Invalid("cadence state"));
        }
        Ok(Self {
            active,
            t_s: v[0],
            n: v[1],
            c: v[2],
            p: [[v[3], v[4]], [v[4], v[5]]],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::CadenceFilter;

    #[test]
    fn smooths_integer_counts() {
        // 2.85 steps/s reported as an integer count once a second.
        let mut f = CadenceFilter::start(0.0, 0.0, 2.0);
        let mut worst = 0.0f64;
        for i in 1..=120 {
            let t = i as f64;
            f.observe_total(t, (2.85 * t).floor(), false);
            if i > 30 {
                worst = worst.max((f.cadence().0 - 2.85).abs());
            }
        }
        // Within 3.5 % of 2.85 steps/s from integer counts once a second.
        assert!(worst < 0.1, "worst cadence error {worst}");
    }

    #[test]
    fn follows_a_cadence_change() {
        let mut f = CadenceFilter::start(0.0, 0.0, 2.8);
        let mut n = 0.0f64;
        for i in 1..=60 {
            let c = if i <= 30 { 2.8 } else { 3.4 };
            n += c;
            f.observe_total(i as f64, n.floor(), false);
        }
        assert!((f.cadence().0 - 3.4).abs() < 0.08, "{:?}", f.cadence());
    }
}
