//! The step detector of method 3 (docs/architecture.md) as published: variance of the acceleration magnitude
//! over a sliding window of `w` samples, two thresholds, a physiological rate gate.
//!
//! Per sample i: σ²ᵢ = variance of a over the last w samples (mean and variance of the
//! window, w = 15). The sample is "swing" (high) when σ²ᵢ > T1 and "stance" (low) when
//! σ²ᵢ < T2. The paper's two conditions — (1) the swing turns from high to low
//! acceleration, (2) at least one low sample within a window of w samples — are read as
//! in the detector this method comes from (Jiménez et al. 2009): a step is counted at
//! the first low sample that comes within w samples after the end of a swing phase
//! (σ² falling from above T1), provided the time since the previous step lies inside the
//! rate gate. (Read literally as "a low sample among the w samples *before* the
//! transition", the swing would have to be shorter than w samples, which a 15-sample
//! window at 100 Hz or more practically never sees.)
//!
//! Choices the paper leaves open (documented, chosen once, not fitted to any data):
//! - T1, T2 are not given. The defaults T1 = 2 (m/s²)², T2 = 1 (m/s²)² are of the order
//!   used with this detector in the literature (swing: σ above ≈ 1.4 m/s², stance: below
//!   1 m/s²); they were set once and not fitted to the evaluation data.
//! - The gate is written both as "1–5 Hz" and "0.2–2 s per step", which disagree below
//!   1 Hz. The 0.2–2 s form is used: a step closer than 0.2 s to the previous one is
//!   rejected; a step more than 2 s after the previous one starts a new bout and is
//!   counted (the first step of a bout has no rate to test).
//! - w stays 15 *samples* whatever the sample rate, as published; the method is
//!   therefore rate-dependent (0.3 s at 50 Hz, 0.04 s at 400 Hz).

use crate::snapshot::{Reader, SnapshotError, Writer};

use super::event::StepEvent;
use super::Moments;

/// Largest window the published detector supports, samples.
pub const MAX_WINDOW: usize = 64;

/// Parameters of the published detector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PublishedStepParams {
    /// Window length w, samples (paper: 15).
    pub window_n: usize,
    /// T1: variance above which a sample is "swing", (m/s²)².
    pub swing_variance_m2ps4: f64,
    /// T2: variance below which a sample is "stance", (m/s²)².
    pub stance_variance_m2ps4: f64,
    /// Steps closer than this to the previous step are rejected, s (paper: 0.2).
    pub min_step_interval_s: f64,
    /// A step later than this after the previous one starts a new bout, s (paper: 2).
    pub max_step_interval_s: f64,
}

impl Default for PublishedStepParams {
    fn default() -> Self {
        Self {
            window_n: 15,
            swing_variance_m2ps4: 2.0,
            stance_variance_m2ps4: 1.0,
            min_step_interval_s: 0.2,
            max_step_interval_s: 2.0,
        }
    }
}

impl PublishedStepParams {
    pub(crate) fn validate(&self) -> Result<(), String> {
        if !(2..=MAX_WINDOW).contains(&self.window_n) {
            return Err(format!("window_n must be 2..={MAX_WINDOW}"));
        }
        let (t1, t2) = (self.swing_variance_m2ps4, self.stance_variance_m2ps4);
        if !(t1.is_finite() && t2.is_finite() && t2 > 0.0 && t1 >= t2) {
            return Err("need finite thresholds with T1 ≥ T2 > 0".into());
        }
        let (lo, hi) = (self.min_step_interval_s, self.max_step_interval_s);
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
            return Err("need 0 < min_step_interval_s < max_step_interval_s".into());
        }
        Ok(())
    }
    pub(crate) fn write(&self, w: &mut Writer) {
        // Exhaustive on purpose: a new setting must be added to the snapshot.
        let Self {
            window_n,
            swing_variance_m2ps4,
            stance_variance_m2ps4,
            min_step_interval_s,
            max_step_interval_s,
        } = *self;
        w.u64(window_n as u64);
        w.f64s(&[
            swing_variance_m2ps4,
            stance_variance_m2ps4,
            min_step_interval_s,
            max_step_interval_s,
        ]);
    }
    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let window_n = r.len(MAX_WINDOW)?;
        let mut v = [0.0; 4];
        r.f64s(&mut v)?;
        Ok(Self {
            window_n,
            swing_variance_m2ps4: v[0],
            stance_variance_m2ps4: v[1],
            min_step_interval_s: v[2],
            max_step_interval_s: v[3],
        })
    }
}

/// Per-sample class.
const LOW: u8 = 0;
const MID: u8 = 1;
const HIGH: u8 = 2;

/// State of the published detector.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PublishedDetector {
    p: PublishedStepParams,
    /// The last `window_n` magnitudes; slot `next` is overwritten next (the order does
    /// not matter for a mean and a variance).
    window: [f64; MAX_WINDOW],
    next: usize,
    filled: usize,
    /// Class of the previous sample (LOW/MID/HIGH; MID before any).
    prev_class: u8,
    last_step_t_s: Option<f64>,
    moments: Moments,
    /// Samples since the swing phase last ended (u64::MAX: no swing pending).
    since_swing_end: u64,
}

impl PublishedDetector {
    pub(crate) fn new(p: PublishedStepParams) -> Self {
        Self {
            p,
            window: [0.0; MAX_WINDOW],
            next: 0,
            filled: 0,
            prev_class: MID,
            last_step_t_s: None,
            moments: Moments::EMPTY,
            since_swing_end: u64::MAX,
        }
    }

    /// Process one validated sample; returns a step.
    pub(crate) fn push(&mut self, t_s: f64, mag: f64) -> Option<StepEvent> {
        let w = self.p.window_n;
        self.window[self.next] = mag;
        self.next = (self.next + 1) % w;
        self.filled = (self.filled + 1).min(w);
        self.moments.add(mag);
        if self.filled < w {
            return None;
        }
        let win = &self.window[..w];
        let n = w as f64;
        let mean = win.iter().sum::<f64>() / n;
        let var = win.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
        let class = if var > self.p.swing_variance_m2ps4 {
            HIGH
        } else if var < self.p.stance_variance_m2ps4 {
            LOW
        } else {
            MID
        };
        self.since_swing_end = self.since_swing_end.saturating_add(1);
        if self.prev_class == HIGH && class != HIGH {
            // The swing phase ends here.
            self.since_swing_end = 0;
        }
        self.prev_class = class;
        if class != LOW || self.since_swing_end > w as u64 {
            return None;
        }
        // High → low with a low sample within w samples of the end of the swing.
        self.since_swing_end = u64::MAX;
        let duration = self.last_step_t_s.map(|l| t_s - l);
        if matches!(duration, Some(d) if d < self.p.min_step_interval_s) {
            return None;
        }
        let duration_s = match duration {
            Some(d) if d <= self.p.max_step_interval_s => d,
            _ => f64::NAN,
        };
        let out = self.moments.event(t_s, duration_s);
        self.moments = Moments::EMPTY;
        self.last_step_t_s = Some(t_s);
        Some(out)
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        let PublishedDetector {
            p, // written by the step detector; its window length bounds the window
            window,
            next,
            filled,
            prev_class,
            last_step_t_s,
            moments,
            since_swing_end,
        } = self;
        w.u64(*next as u64);
        w.u64(*filled as u64);
        w.f64s(&window[..p.window_n]);
        w.u8(*prev_class);
        w.opt_f64(*last_step_t_s);
        moments.write(w);
        w.u64(*since_swing_end);
    }

    pub(crate) fn read(r: &mut Reader, p: PublishedStepParams) -> Result<Self, SnapshotError> {
        let mut d = Self::new(p);
        d.next = r.len(p.window_n - 1)?;
        d.filled = r.len(p.window_n)?;
        r.f64s(&mut d.window[..p.window_n])?;
        d.prev_class = r.u8()?;
        if d.prev_class > HIGH {
            return Err(SnapshotError::Invalid("sample class"));
        }
        d.last_step_t_s = r.opt_f64()?;
        d.moments = Moments::read(r)?;
        d.since_swing_end = r.u64()?;
        Ok(d)
    }
}
