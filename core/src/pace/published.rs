//! The complementary filter of Skrzypczyk, "Running speed estimation using
//! complementary filter based fusion of satellite navigation and pedometer data"
//! (method 1 of docs/architecture.md), as published, with only the fixes needed to make it physically right.
//!
//! Per GNSS epoch n, over the window of the last N fixes:
//! 1. fit a 2nd-order polynomial in time to east and to north (eq. 2) and replace the
//!    raw positions by the fitted ones;
//! 2. per-interval distances d_k = |p̄_k − p̄_{k−1}| (eq. 3), smoothed by an EMA run
//!    from the oldest to the newest interval of the window (eq. 4);
//! 3. v_GPS from the smoothed distance (eq. 5), cadence over H epochs (eq. 6),
//!    step length over the window (eq. 8), v_PED = c·L (eq. 7);
//! 4. variance σ_d² of the window's distances (eq. 10), GNSS weight by a sigmoid
//!    (eq. 12), v_FUS = w v_GPS + (1 − w) v_PED (eq. 9, 13);
//! 5. step length learned only while σ_d² ≤ σ²_THR, else rolled back to the value of
//!    N − 1 epochs earlier (eq. 14).
//!
//! Deviations from the text, each because the text is dimensionally wrong or silent:
//! - eq. 5 divides the per-interval smoothed distance by NΔt: that under-reads speed by
//!   N. We use v_GPS = d̄/Δt.
//! - eq. 8 divides one interval's distance by the steps of N intervals: we divide the
//!   window's summed distance by the window's steps.
//! - Real receivers do not deliver exactly every Δt: distances are normalised to
//!   per-second speeds (d_k/Δt_k), so σ_d² is in (m/s)²·(1 s)², equal to the paper's m²
//!   at Δt = 1 s.
//! - N fixes give N − 1 intervals; the variance uses those N − 1 (sample variance).
//! - β of the sigmoid and α of the EMA are not given; see [`PublishedParams`].
//! - Nothing is said about GNSS outages: without fixes for more than 2 s the speed is
//!   v_PED from the step stream; after a gap of more than 10 s the window restarts.
//! - No stationary handling (the paper has none): GNSS jitter at rest shows as speed.
//!
//! Distance is the integral of v_FUS over time.

use super::config::PublishedParams;
use super::{Context, LocalFix, PaceConfig, PaceEstimate, PaceSource};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Largest window N or H supported (fixed-size buffers).
pub const MAX_WINDOW: usize = 32;
/// Without a fix for this long, speed comes from the pedometer alone, seconds.
const PEDOMETER_ONLY_AFTER_S: f64 = 2.0;
/// A GNSS gap longer than this restarts the fitting window, seconds.
const WINDOW_RESET_GAP_S: f64 = 10.0;
/// Fewer steps than this in the window teach no step length.
const MIN_LEARN_STEPS: f64 = 3.0;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Epoch {
    t_s: f64,
    /// Cumulative steps at the epoch (NaN without step data).
    steps: f64,
    /// Step length valid at this epoch (NaN when unknown).
    step_length_m: f64,
}

/// State of the as-published filter.
#[derive(Clone, Debug, PartialEq)]
pub struct PublishedFilter {
    params: PublishedParams,
    /// When true, the GNSS weight is forced to 1: the paper's "EMA" GNSS-only baseline.
    gnss_only: bool,
    window: Ring<[f64; 3], MAX_WINDOW>,
    epochs: Ring<Epoch, { MAX_WINDOW + 1 }>,
    step_length_m: Option<f64>,
    last_fix_t_s: Option<f64>,
    last_update_t_s: Option<f64>,
    distance_m: f64,
    out: PaceEstimate,
}

/// Least-squares polynomial of degree 2 through (t, y); returns fitted values at each t.
/// Falls back to the raw values when the system is singular.
fn fit_quadratic(ts: &[f64], ys: &[f64], out: &mut [f64]) {
    let n = ts.len();
    // Normal equations on centred time for conditioning.
    let tm = ts.iter().sum::<f64>() / n as f64;
    let mut s = [0.0f64; 5];
    let mut b = [0.0f64; 3];
    for (&t, &y) in ts.iter().zip(ys) {
        let x = t - tm;
        let mut p = 1.0;
        for (k, sk) in s.iter_mut().enumerate() {
            *sk += p;
            if k < 3 {
                b[k] += p * y;
            }
            p *= x;
        }
    }
    let m = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    let scale = s[0] * s[2] * s[4];
    let singular = d.is_nan() || d.abs() <= 1e-12 * scale.max(1e-300);
    if n < 3 || singular {
        out[..n].copy_from_slice(&ys[..n]);
        return;
    }
    let mut coef = [0.0; 3];
    for (i, c) in coef.iter_mut().enumerate() {
        let mut mi = m;
        for r in 0..3 {
            mi[r][i] = b[r];
        }
        *c = det(&mi) / d;
    }
    for (o, &t) in out.iter_mut().zip(ts) {
        let x = t - tm;
        *o = coef[0] + coef[1] * x + coef[2] * x * x;
    }
}

/// The window's times and fitted positions (the first `m` entries).
struct FittedWindow {
    m: usize,
    ts: [f64; MAX_WINDOW],
    fx: [f64; MAX_WINDOW],
    fy: [f64; MAX_WINDOW],
}

/// What the window's intervals say about speed.
#[derive(Clone, Copy)]
struct WindowSpeeds {
    /// EMA of the per-interval speeds, oldest to newest (eq. 4, 5), m/s (NaN: < 2 fixes).
    v_gps: f64,
    /// Sample variance σ_d² of the per-interval speeds (eq. 10) (∞: < 3 fixes).
    variance: f64,
    /// Summed fitted distance over the window, m.
    window_dist: f64,
}

impl FittedWindow {
    /// Per-interval speeds d_k/Δt_k, their EMA and variance, and the window's distance.
    fn speeds(&self, ema_alpha: f64) -> WindowSpeeds {
        let Self { m, ts, fx, fy } = self;
        let m = *m;
        let mut out = WindowSpeeds {
            v_gps: f64::NAN,
            variance: f64::INFINITY,
            window_dist: 0.0,
        };
        if m >= 2 {
            let mut ema = f64::NAN;
            let (mut sum, mut sum2) = (0.0, 0.0);
            for k in 1..m {
                let d = (fx[k] - fx[k - 1]).hypot(fy[k] - fy[k - 1]);
                out.window_dist += d;
                let u = d / (ts[k] - ts[k - 1]);
                ema = if ema.is_nan() {
                    u
                } else {
                    ema_alpha * u + (1.0 - ema_alpha) * ema
                };
                sum += u;
                sum2 += u * u;
            }
            out.v_gps = ema;
            let q = (m - 1) as f64;
            if m >= 3 {
                out.variance = ((sum2 - sum * sum / q) / (q - 1.0)).max(0.0);
            }
        }
        out
    }
}

impl PublishedFilter {
    pub fn new(config: &PaceConfig) -> Self {
        Self {
            params: config.published,
            gnss_only: false,
            window: Ring::new(),
            epochs: Ring::new(),
            step_length_m: config
                .calibration
                .map(|c| c.step_length_m)
                .or(config.initial_step_length_m),
            last_fix_t_s: None,
            last_update_t_s: None,
            distance_m: 0.0,
            out: PaceEstimate::initial(config.initial_step_length_m),
        }
    }

    /// The paper's GNSS-only smoothing (polynomial fit + EMA, weight 1): a baseline.
    pub fn gnss_ema(config: &PaceConfig) -> Self {
        Self {
            gnss_only: true,
            ..Self::new(config)
        }
    }

    fn integrate(&mut self, t_s: f64, speed_mps: f64) {
        if let Some(t0) = self.last_update_t_s {
            let dt = t_s - t0;
            if dt > 0.0 && dt <= super::MAX_INTEGRATION_GAP_S {
                self.distance_m += speed_mps * dt;
            }
        }
        self.last_update_t_s = Some(t_s);
    }

    pub fn on_fix(&mut self, fix: &LocalFix, ctx: &Context) -> PaceEstimate {
        self.admit(fix);
        // 1. Polynomial fit over the window.
        let fitted = self.fitted_window();
        // 2. Per-interval speeds, EMA, variance.
        let speeds = fitted.speeds(self.params.ema_alpha);
        // 3. Cadence over H epochs and step length over the window.
        let steps_now = ctx.steps.total_at(fix.t_s).unwrap_or(f64::NAN);
        let cadence = self.push_epoch(fix.t_s, steps_now);
        self.learn_step_length(steps_now, fitted.m, &speeds);
        // 4. Fusion.
        let v_ped = cadence.zip(self.step_length_m).map(|(c, l)| c * l);
        let (speed, w) = self.fuse(&speeds, v_ped);
        self.integrate(fix.t_s, speed);
        let source = if !speeds.v_gps.is_finite() && v_ped.is_none() {
            PaceSource::Initializing
        } else {
            PaceSource::from_gnss_weight(w)
        };
        self.out = PaceEstimate {
            t_s: fix.t_s,
            speed_mps: speed,
            pace_s_per_km: PaceEstimate::pace_for(speed),
            speed_std_mps: None,
            cadence_spm: cadence.map(|c| c * 60.0),
            step_length_m: self.step_length_m,
            gnss_weight: w,
            distance_m: self.distance_m,
            source,
            flags: super::PaceFlags::default(),
        };
        self.out
    }

    /// The fix joins the window (restarted after a long gap), which keeps N fixes.
    fn admit(&mut self, fix: &LocalFix) {
        if let Some(t0) = self.last_fix_t_s {
            if fix.t_s - t0 > WINDOW_RESET_GAP_S {
                self.window.clear();
            }
        }
        self.last_fix_t_s = Some(fix.t_s);
        self.window.push([fix.t_s, fix.east_m, fix.north_m]);
        while self.window.len() > self.params.window_n {
            self.window.pop_front();
        }
    }

    /// The window's positions replaced by the fitted polynomials (eq. 2).
    fn fitted_window(&self) -> FittedWindow {
        let m = self.window.len();
        let mut ts = [0.0; MAX_WINDOW];
        let mut xs = [0.0; MAX_WINDOW];
        let mut ys = [0.0; MAX_WINDOW];
        for (i, v) in self.window.iter().enumerate() {
            ts[i] = v[0];
            xs[i] = v[1];
            ys[i] = v[2];
        }
        let mut fx = [0.0; MAX_WINDOW];
        let mut fy = [0.0; MAX_WINDOW];
        fit_quadratic(&ts[..m], &xs[..m], &mut fx);
        fit_quadratic(&ts[..m], &ys[..m], &mut fy);
        FittedWindow { m, ts, fx, fy }
    }

    /// Records this epoch's step count; returns the cadence over H epochs (eq. 6).
    fn push_epoch(&mut self, t_s: f64, steps_now: f64) -> Option<f64> {
        self.epochs.push(Epoch {
            t_s,
            steps: steps_now,
            step_length_m: f64::NAN,
        });
        self.epoch_back(self.params.cadence_h)
            .filter(|e| t_s > e.t_s && e.steps.is_finite() && steps_now.is_finite())
            .map(|e| ((steps_now - e.steps) / (t_s - e.t_s)).max(0.0))
    }

    /// The epoch `k` back (the oldest when fewer are kept).
    fn epoch_back(&self, k: usize) -> Option<Epoch> {
        self.epochs.back(k.min(self.epochs.len() - 1))
    }

    /// Step length learned over the window while σ_d² ≤ σ²_THR (eq. 8), else rolled
    /// back to the value of N − 1 epochs ago (eq. 14); recorded at this epoch.
    fn learn_step_length(&mut self, steps_now: f64, m: usize, speeds: &WindowSpeeds) {
        let good = speeds.variance <= self.params.variance_threshold_m2;
        if good && m >= 2 {
            if let Some(e) = self.epoch_back(m - 1) {
                let steps = steps_now - e.steps;
                if steps.is_finite() && steps >= MIN_LEARN_STEPS {
                    self.step_length_m = Some(speeds.window_dist / steps);
                }
            }
        } else if !good && m >= 3 {
            // Eq. 14: roll back to the value of N − 1 epochs ago.
            if let Some(e) = self.epoch_back(self.params.window_n - 1) {
                if e.step_length_m.is_finite() {
                    self.step_length_m = Some(e.step_length_m);
                }
            }
        }
        if let (Some(l), Some(e)) = (self.step_length_m, self.epochs.newest_mut()) {
            // Record the step length valid at this epoch (for the eq. 14 roll-back).
            e.step_length_m = l;
        }
    }

    /// v_FUS = w v_GPS + (1 − w) v_PED with the sigmoid weight (eq. 9, 12, 13):
    /// `(speed, w)`.
    fn fuse(&self, speeds: &WindowSpeeds, v_ped: Option<f64>) -> (f64, f64) {
        let p = self.params;
        let WindowSpeeds {
            v_gps, variance, ..
        } = *speeds;
        match (v_gps.is_finite(), v_ped) {
            (true, Some(vp)) if !self.gnss_only => {
                let w = if variance.is_finite() {
                    1.0 / (1.0
                        + (p.sigmoid_beta_per_m2 * (variance - p.variance_threshold_m2)).exp())
                } else {
                    1.0
                };
                ((w * v_gps + (1.0 - w) * vp).max(0.0), w)
            }
            (true, _) => (v_gps, 1.0),
            (false, Some(vp)) if !self.gnss_only => (vp, 0.0),
            _ => (0.0, 1.0),
        }
    }

    pub fn on_steps(&mut self, t_s: f64, ctx: &Context) {
        if self.gnss_only {
            return;
        }
        let outage = self
            .last_fix_t_s
            .is_none_or(|t0| t_s - t0 > PEDOMETER_ONLY_AFTER_S);
        if !outage || t_s <= self.out.t_s {
            return;
        }
        let window_s = self.params.cadence_h as f64;
        let cadence = ctx
            .steps
            .cadence_at(t_s, window_s, ctx.config.stationary_after_s);
        let Some(l) = self.step_length_m else {
            self.out.t_s = t_s;
            self.out.cadence_spm = cadence.map(|c| c * 60.0);
            return;
        };
        let speed = (cadence.unwrap_or(0.0) * l).max(0.0);
        self.integrate(t_s, speed);
        self.out = PaceEstimate {
            t_s,
            speed_mps: speed,
            pace_s_per_km: PaceEstimate::pace_for(speed),
            speed_std_mps: None,
            cadence_spm: cadence.map(|c| c * 60.0),
            step_length_m: Some(l),
            gnss_weight: 0.0,
            distance_m: self.distance_m,
            source: PaceSource::Pedometer,
            flags: super::PaceFlags::default(),
        };
    }

    /// Cadence × step length of the latest estimate, m/s (`None` before both).
    pub fn pedometer_speed_mps(&self) -> Option<f64> {
        let c = self.out.cadence_spm? / 60.0;
        Some(c * self.step_length_m?)
    }

    /// The step stream now counts every reported step as `k` steps (strides found,
    /// `super::crosscheck`): step totals ×k, step lengths /k.
    pub fn rescale_steps(&mut self, k: f64) {
        let old = self.epochs;
        self.epochs = Ring::new();
        for e in old.iter() {
            self.epochs.push(Epoch {
                steps: k * e.steps,
                step_length_m: e.step_length_m / k,
                ..e
            });
        }
        self.step_length_m = self.step_length_m.map(|l| l / k);
    }

    pub fn estimate(&self, _ctx: &Context) -> PaceEstimate {
        self.out
    }

    pub fn write(&self, w: &mut Writer) {
        w.bool(self.gnss_only);
        w.u64(self.window.len() as u64);
        for v in self.window.iter() {
            w.f64s(&v);
        }
        w.u64(self.epochs.len() as u64);
        for e in self.epochs.iter() {
            w.f64s(&[e.t_s, e.steps, e.step_length_m]);
        }
        w.opt_f64(self.step_length_m);
        w.opt_f64(self.last_fix_t_s);
        w.opt_f64(self.last_update_t_s);
        w.f64(self.distance_m);
        write_estimate(w, &self.out);
    }

    pub fn read(r: &mut Reader, config: &PaceConfig) -> Result<Self, SnapshotError> {
        let mut f = Self::new(config);
        f.gnss_only = r.bool()?;
        for _ in 0..r.len(MAX_WINDOW)? {
            let mut v = [0.0; 3];
            r.f64s(&mut v)?;
            f.window.push(v);
        }
        for _ in 0..r.len(MAX_WINDOW + 1)? {
            // Steps and step length are NaN for an epoch without step data.
            let v = [r.f64()?, r.f64_or_nan()?, r.f64_or_nan()?];
            f.epochs.push(Epoch {
                t_s: v[0],
                steps: v[1],
                step_length_m: v[2],
            });
        }
        f.step_length_m = r.opt_f64()?;
        f.last_fix_t_s = r.opt_f64()?;
        f.last_update_t_s = r.opt_f64()?;
        f.distance_m = r.f64()?;
        f.out = read_estimate(r)?;
        Ok(f)
    }
}

/// Serialise an estimate (shared by the filters).
pub(crate) fn write_estimate(w: &mut Writer, e: &PaceEstimate) {
    w.f64(e.t_s);
    w.f64(e.speed_mps);
    w.opt_f64(e.pace_s_per_km);
    w.opt_f64(e.speed_std_mps);
    w.opt_f64(e.cadence_spm);
    w.opt_f64(e.step_length_m);
    w.f64(e.gnss_weight);
    w.f64(e.distance_m);
    w.u8(match e.source {
        PaceSource::Initializing => 0,
        PaceSource::Stationary => 1,
        PaceSource::Gnss => 2,
        PaceSource::Fused => 3,
        PaceSource::Pedometer => 4,
    });
}

pub(crate) fn read_estimate(r: &mut Reader) -> Result<PaceEstimate, SnapshotError> {
    let e = PaceEstimate {
        t_s: r.f64()?,
        speed_mps: r.f64()?,
        pace_s_per_km: r.opt_f64()?,
        speed_std_mps: r.opt_f64()?,
        cadence_spm: r.opt_f64()?,
        step_length_m: r.opt_f64()?,
        gnss_weight: r.f64()?,
        distance_m: r.f64()?,
        source: match r.u8()? {
            0 => PaceSource::Initializing,
            1 => PaceSource::Stationary,
            2 => PaceSource::Gnss,
            3 => PaceSource::Fused,
            4 => PaceSource::Pedometer,
            _ => return Err(SnapshotError::Invalid("pace source")),
        },
        flags: super::PaceFlags::default(),
    };
    let non_negative = |v: Option<f64>| v.is_none_or(|v| (0.0..=1e13).contains(&v));
    if !(0.0..=1e8).contains(&e.speed_mps)
        || !(0.0..=1e13).contains(&e.distance_m)
        || e.t_s.abs() > 1e11 + 1.0
        || !(0.0..=1.0).contains(&e.gnss_weight)
        || !non_negative(e.pace_s_per_km)
        || !non_negative(e.speed_std_mps)
        || !non_negative(e.cadence_spm)
        || !non_negative(e.step_length_m)
    {
        return Err(SnapshotError::Invalid("stored estimate"));
    }
    Ok(e)
}

#[cfg(test)]
mod tests {
    use super::fit_quadratic;

    #[test]
    fn quadratic_fit_is_exact_on_a_parabola() {
        let ts = [0.0, 1.0, 2.0, 3.0, 4.0];
        let ys: Vec<f64> = ts.iter().map(|t| 1.0 + 2.0 * t - 0.5 * t * t).collect();
        let mut out = [0.0; 5];
        fit_quadratic(&ts, &ys, &mut out);
        for (a, b) in out.iter().zip(&ys) {
            assert!((a - b).abs() < 1e-9);
        }
    }
}
