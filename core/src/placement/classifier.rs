//! [`PlacementClassifier`]: the streaming engine. A [`FeatureStream`] turns samples
//! into window features every 1.28 s once 5.12 s are buffered; the model gives class
//! probabilities per window; the estimate is the softmax of the mean log-probability
//! over the last `smoothing_windows` windows (default 8, about 10 s of walking).
//! Errors and door checks are those of [`FeatureStream`]: a rejected sample leaves
//! the classifier exactly as it was. No heap allocation per sample.
//! `snapshot()` / `restore()` (engine kind byte 7) continue bit-exactly.

use super::class::{Placement, CLASSES};
use super::error::PlacementError;
use super::model::PlacementModel;
use super::stream::FeatureStream;
use crate::batch::{self, Batch};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stepdetect::AccelSample;

/// Snapshot engine kind byte of the placement classifier.
const SNAPSHOT_KIND: u8 = 7;
/// Snapshot format version written by this build.
/// Version 2: the input layer's time and g-units state.
const SNAPSHOT_VERSION: u16 = 2;

/// Largest smoothing length, windows.
pub const MAX_SMOOTHING: usize = 32;
/// Default smoothing length, windows.
pub const DEFAULT_SMOOTHING: usize = 8;
/// Floor of a probability before its logarithm is averaged.
const P_FLOOR: f64 = 1e-6;

/// The current placement with its class probabilities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacementEstimate {
    /// Time of the sample that completed the newest classified window, s.
    pub t_s: f64,
    /// Most probable class of the smoothed probabilities.
    pub placement: Placement,
    /// Its smoothed probability.
    pub confidence: f64,
    /// Smoothed probabilities, in [`Placement::ALL`] order (sum 1).
    pub probabilities: [f64; CLASSES],
    /// Probabilities of the newest window alone.
    pub window_probabilities: [f64; CLASSES],
    /// Windows classified since construction.
    pub windows: u64,
}

/// A sample a batch push rejected, with its index in the batch.
pub type PlacementRejection = crate::batch::Rejected<PlacementError>;

/// Streaming phone-placement classifier.
#[derive(Clone, Debug)]
pub struct PlacementClassifier {
    model: PlacementModel,
    smoothing: usize,
    stream: FeatureStream,
    recent_log_p: Ring<[f64; CLASSES], MAX_SMOOTHING>,
    latest: Option<PlacementEstimate>,
    windows: u64,
}

impl PlacementClassifier {
    /// A classifier with the shipped model and the default smoothing.
    pub fn shipped() -> Self {
        Self::new(PlacementModel::shipped(), DEFAULT_SMOOTHING)
    }

    /// A classifier with `model`, smoothing over the last `smoothing_windows` windows
    /// (clamped to 1..=32).
    pub fn new(model: PlacementModel, smoothing_windows: usize) -> Self {
        Self {
            model,
            smoothing: smoothing_windows.clamp(1, MAX_SMOOTHING),
            stream: FeatureStream::new(),
            recent_log_p: Ring::new(),
            latest: None,
            windows: 0,
        }
    }

    pub fn model(&self) -> &PlacementModel {
        &self.model
    }

    /// The current estimate, once a window was classified.
    pub fn estimate(&self) -> Option<PlacementEstimate> {
        self.latest
    }

    /// Forget all samples (keeps the model and the smoothing).
    pub fn reset(&mut self) {
        self.stream = FeatureStream::new();
        self.recent_log_p.clear();
        self.latest = None;
        self.windows = 0;
    }

    /// Adds one sample (acceleration with gravity, m/s², any axes). Returns the new
    /// estimate when this sample completed a classified window.
    pub fn push(&mut self, s: &AccelSample) -> Result<Option<PlacementEstimate>, PlacementError> {
        Ok(self
            .stream
            .push(s.t_s, s.accel_mps2)?
            .map(|f| self.classify(s.t_s, &f)))
    }

    /// Pushes many samples in order; invalid ones are skipped and reported. One
    /// estimate per classified window.
    pub fn push_batch(
        &mut self,
        samples: &[AccelSample],
    ) -> Batch<PlacementEstimate, PlacementError> {
        batch::run(samples, |s| self.push(s))
    }

    /// The whole state as bytes (versioned, checksummed; the model is included as
    /// its text file, so a snapshot restores on its own).
    pub fn snapshot(&self) -> Vec<u8> {
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.bytes(self.model.to_text().as_bytes());
        w.u64(self.smoothing as u64);
        self.stream.write(&mut w);
        w.u64(self.recent_log_p.len() as u64);
        for v in self.recent_log_p.iter() {
            w.f64s(&v);
        }
        w.bool(self.latest.is_some());
        if let Some(e) = &self.latest {
            w.f64(e.t_s);
            w.u8(e.placement.index() as u8);
            w.f64(e.confidence);
            w.f64s(&e.probabilities);
            w.f64s(&e.window_probabilities);
            w.u64(e.windows);
        }
        w.u64(self.windows);
        w.finish()
    }

    /// A classifier continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, PlacementError> {
        let (mut r, _version) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let text = std::str::from_utf8(r.bytes()?).map_err(|_| SnapshotError::Invalid("model"))?;
        let model = PlacementModel::parse(text)?;
        let smoothing = r.len(MAX_SMOOTHING)?.max(1);
        let stream = FeatureStream::read(&mut r)?;
        let mut recent_log_p = Ring::new();
        for _ in 0..r.len(MAX_SMOOTHING)? {
            let mut v = [0.0; CLASSES];
            r.f64s(&mut v)?;
            if v.iter().any(|&l| l > 1e-9) {
                return Err(SnapshotError::Invalid("log-probabilities").into());
            }
            recent_log_p.push(v);
        }
        let latest = if r.bool()? {
            let t_s = r.f64()?;
            let placement = *Placement::ALL
                .get(r.u8()? as usize)
                .ok_or(SnapshotError::Invalid("placement"))?;
            let confidence = r.f64()?;
            let mut probabilities = [0.0; CLASSES];
            r.f64s(&mut probabilities)?;
            let mut window_probabilities = [0.0; CLASSES];
            r.f64s(&mut window_probabilities)?;
            let windows = r.u64()?;
            let unit = |p: &[f64]| p.iter().all(|v| (0.0..=1.0).contains(v));
            if !((0.0..=1.0).contains(&confidence)
                && unit(&probabilities)
                && unit(&window_probabilities))
            {
                return Err(SnapshotError::Invalid("probabilities").into());
            }
            Some(PlacementEstimate {
                t_s,
                placement,
                confidence,
                probabilities,
                window_probabilities,
                windows,
            })
        } else {
            None
        };
        let windows = r.u64()?;
        r.end()?;
        Ok(Self {
            model,
            smoothing,
            stream,
            recent_log_p,
            latest,
            windows,
        })
    }

    fn classify(&mut self, t_s: f64, f: &super::features::Features) -> PlacementEstimate {
        let p = self.model.probabilities(f);
        let mut lp = [0.0; CLASSES];
        for c in 0..CLASSES {
            lp[c] = p[c].max(P_FLOOR).ln();
        }
        self.recent_log_p.push(lp);
        let n = self.recent_log_p.len().min(self.smoothing);
        let mut s = [0.0; CLASSES];
        for k in 0..n {
            let v = self.recent_log_p.back(k).unwrap_or_default();
            for c in 0..CLASSES {
                s[c] += v[c] / n as f64;
            }
        }
        let max = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut sum = 0.0;
        for v in &mut s {
            *v = (*v - max).exp();
            sum += *v;
        }
        let mut best = 0;
        for c in 0..CLASSES {
            s[c] /= sum;
            if s[c] > s[best] {
                best = c;
            }
        }
        self.windows = self.windows.saturating_add(1);
        let e = PlacementEstimate {
            t_s,
            placement: Placement::ALL[best],
            confidence: s[best],
            probabilities: s,
            window_probabilities: p,
            windows: self.windows,
        };
        self.latest = Some(e);
        e
    }
}
