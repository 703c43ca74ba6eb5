//! `PlacementClassifier` at the FFI: where the phone is carried, from the
//! accelerometer alone (core: `stridekit_core::placement`; accuracy and limits in
//! `docs/odometry.md`).
//!
//! Samples cross the FFI as `AccelSample` records or packed, 32-byte little-endian
//! records of four f64 (`t_s, ax, ay, az`, m/s² with gravity, device axes: the same
//! layout as the pace tracker's packed accelerometer input, [`crate::packed`]).
//! Any sampling rate from about 50 Hz, any phone orientation. The first estimate
//! comes after one 5.12 s window, then one every 1.28 s.

use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::placement as core;

use crate::pace::types::AccelSample;
use crate::phone::navigator::{push_each, RejectedImuSample};

/// Where a phone is carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum PhonePlacement {
    /// Held in front of the body (reading the screen).
    InHand,
    /// In a trouser pocket (front or back).
    Pocket,
    /// In a bag or purse.
    Bag,
    /// In a pouch hanging from the neck, on the chest.
    NeckPouch,
    /// Strapped to the upper arm.
    Armband,
    /// In the hand of a swinging arm.
    SwingingArm,
}

impl From<core::Placement> for PhonePlacement {
    fn from(p: core::Placement) -> Self {
        match p {
            core::Placement::InHand => Self::InHand,
            core::Placement::Pocket => Self::Pocket,
            core::Placement::Bag => Self::Bag,
            core::Placement::NeckPouch => Self::NeckPouch,
            core::Placement::Armband => Self::Armband,
            core::Placement::SwingingArm => Self::SwingingArm,
        }
    }
}

impl From<PhonePlacement> for core::Placement {
    fn from(p: PhonePlacement) -> Self {
        match p {
            PhonePlacement::InHand => Self::InHand,
            PhonePlacement::Pocket => Self::Pocket,
            PhonePlacement::Bag => Self::Bag,
            PhonePlacement::NeckPouch => Self::NeckPouch,
            PhonePlacement::Armband => Self::Armband,
            PhonePlacement::SwingingArm => Self::SwingingArm,
        }
    }
}

/// All placements, in the order of [`PlacementEstimate::probabilities`].
#[uniffi::export]
pub fn phone_placements() -> Vec<PhonePlacement> {
    core::Placement::ALL.iter().map(|&p| p.into()).collect()
}

/// The classifier's current belief.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct PlacementEstimate {
    /// Time of the sample that completed the latest window, s.
    pub t_s: f64,
    /// The most probable placement.
    pub placement: PhonePlacement,
    /// Its probability (0..1), smoothed over the recent windows.
    pub confidence: f64,
    /// Every placement's probability, in the order of `phonePlacements()`.
    pub probabilities: Vec<f64>,
    /// Windows classified so far.
    pub windows: i64,
}

impl From<core::PlacementEstimate> for PlacementEstimate {
    fn from(e: core::PlacementEstimate) -> Self {
        Self {
            t_s: e.t_s,
            placement: e.placement.into(),
            confidence: e.confidence,
            probabilities: e.probabilities.to_vec(),
            windows: i64::try_from(e.windows).unwrap_or(i64::MAX),
        }
    }
}

crate::error::engine_error! {
    /// Why the classifier rejected an input, a model, a buffer or a snapshot (Kotlin
    /// `PlacementException`, Swift `PlacementError`): the typed input causes every
    /// engine shares, then its own. A rejected sample changes nothing.
    pub enum PlacementError {
        /// A sample was refused for a reason other than the input checks.
        #[error("accelerometer sample rejected: {reason}")]
        InvalidSample { reason: String },
        /// A model text could not be loaded (wrong version, wrong feature count, corrupt).
        #[error("invalid placement model: {reason}")]
        InvalidModel { reason: String },
        /// Snapshot bytes could not be restored.
        #[error("cannot restore snapshot: {reason}")]
        InvalidSnapshot { reason: String },
        /// A packed buffer is not a whole number of 32-byte records.
        #[error("invalid packed buffer: {reason}")]
        InvalidBuffer { reason: String },
        /// A bug inside stridekit (a caught panic). The classifier stays usable.
        #[error("internal error in stridekit: {reason}")]
        Internal { reason: String },
    }
}

fn guard<T>(f: impl FnOnce() -> Result<T, PlacementError>) -> Result<T, PlacementError> {
    crate::error::guard_with(f, |reason| PlacementError::Internal { reason })
}

/// What a batch push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct PlacementBatchResult {
    /// Samples accepted (the batch minus the rejected ones).
    pub accepted: i32,
    /// Windows classified during the batch.
    pub produced: i32,
    pub rejected: Vec<RejectedImuSample>,
    /// The estimate after the batch (null until the first window is full).
    pub latest: Option<PlacementEstimate>,
}

/// Streaming phone-placement classifier. Safe to call from several threads.
#[derive(Debug, uniffi::Object)]
pub struct PlacementClassifier {
    inner: Mutex<core::PlacementClassifier>,
}

impl PlacementClassifier {
    fn lock(&self) -> MutexGuard<'_, core::PlacementClassifier> {
        crate::error::lock(&self.inner)
    }

    fn push_all(
        &self,
        samples: impl Iterator<Item = (f64, [f64; 3])>,
    ) -> Result<PlacementBatchResult, PlacementError> {
        let mut c = self.lock();
        let b = push_each(samples, |(t_s, accel_mps2)| {
            c.push(&core::AccelSample { t_s, accel_mps2 })
                .map(|e| e.is_some())
        });
        Ok(PlacementBatchResult {
            accepted: b.accepted,
            produced: b.produced,
            rejected: b.rejected,
            latest: c.estimate().map(Into::into),
        })
    }
}

#[uniffi::export]
impl PlacementClassifier {
    /// A classifier with the model that ships with the SDK.
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(core::PlacementClassifier::shipped()),
        })
    }

    /// A classifier with a model file written by `stridekit train placement`,
    /// smoothing its output over the last `smoothing_windows` windows (1..=32).
    #[uniffi::constructor]
    pub fn with_model(
        model_text: String,
        smoothing_windows: i32,
    ) -> Result<Arc<Self>, PlacementError> {
        guard(|| {
            let model = core::PlacementModel::parse(&model_text).map_err(|e| {
                PlacementError::InvalidModel {
                    reason: e.to_string(),
                }
            })?;
            Ok(Arc::new(Self {
                inner: Mutex::new(core::PlacementClassifier::new(
                    model,
                    usize::try_from(smoothing_windows).unwrap_or(1),
                )),
            }))
        })
    }

    /// A classifier continuing exactly where `snapshot()` was taken.
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, PlacementError> {
        guard(|| {
            let c = core::PlacementClassifier::restore(&snapshot).map_err(|e| {
                PlacementError::InvalidSnapshot {
                    reason: match e {
                        core::PlacementError::Snapshot(s) => s.to_string(),
                        e => e.to_string(),
                    },
                }
            })?;
            Ok(Arc::new(Self {
                inner: Mutex::new(c),
            }))
        })
    }

    /// Push accelerometer samples; bad ones are skipped and reported by index.
    pub fn push_accel_samples(
        &self,
        samples: Vec<AccelSample>,
    ) -> Result<PlacementBatchResult, PlacementError> {
        guard(|| {
            self.push_all(
                samples
                    .iter()
                    .map(|s| (s.t_s, [s.x_mps2, s.y_mps2, s.z_mps2])),
            )
        })
    }

    /// Push accelerometer samples packed as 32-byte little-endian records of four f64 `t_s, x, y, z` (m/s², gravity included; `packAccelSamples` builds them).
    pub fn push_accel_packed(&self, data: Vec<u8>) -> Result<PlacementBatchResult, PlacementError> {
        guard(|| {
            let samples =
                crate::packed::accel(&data).map_err(|e| PlacementError::InvalidBuffer {
                    reason: e.to_string(),
                })?;
            self.push_all(samples)
        })
    }

    /// The current estimate (null until the first 5.12 s window is full).
    pub fn estimate(&self) -> Option<PlacementEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// Forget all samples (after the phone was put somewhere else); keeps the model.
    pub fn reset(&self) {
        self.lock().reset()
    }

    /// The whole state as bytes (the model included).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

/// The text of the placement model that ships with the SDK (its comment lines say
/// how it was trained).
#[uniffi::export]
pub fn placement_shipped_model() -> String {
    core::PlacementModel::shipped().to_text()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk(seconds: f64) -> Vec<u8> {
        // A synthetic 2 Hz step pattern at 100 Hz, phone upright.
        let mut out = Vec::new();
        let n = (seconds * 100.0) as usize;
        for i in 0..n {
            let t = i as f64 / 100.0;
            let a = (2.0 * std::f64::consts::PI * 2.0 * t).sin();
            for v in [t, 0.5 * a, 9.81 + 2.0 * a, 0.3 * a] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }

    #[test]
    fn packed_push_classifies_and_snapshot_resumes() {
        let c = PlacementClassifier::with_defaults();
        assert!(c.estimate().is_none());
        let r = c.push_accel_packed(walk(12.0)).unwrap();
        assert!(r.rejected.is_empty());
        assert!(r.produced >= 2, "{r:?}");
        let e = r.latest.unwrap();
        assert_eq!(e.probabilities.len(), phone_placements().len());
        assert!((e.probabilities.iter().sum::<f64>() - 1.0).abs() < 1e-9);
        assert!(e.confidence > 0.0 && e.confidence <= 1.0);
        let restored = PlacementClassifier::restore(c.snapshot()).unwrap();
        assert_eq!(restored.estimate(), c.estimate());
    }

    #[test]
    fn bad_input_is_typed() {
        let c = PlacementClassifier::with_defaults();
        assert!(matches!(
            c.push_accel_packed(vec![0; 31]),
            Err(PlacementError::InvalidBuffer { .. })
        ));
        let r = c
            .push_accel_samples(vec![AccelSample {
                t_s: f64::NAN,
                x_mps2: 0.0,
                y_mps2: 0.0,
                z_mps2: 9.8,
            }])
            .unwrap();
        assert_eq!(r.rejected.len(), 1);
        assert!(matches!(
            PlacementClassifier::with_model("garbage".into(), 8),
            Err(PlacementError::InvalidModel { .. })
        ));
        assert!(matches!(
            PlacementClassifier::restore(vec![1, 2, 3]),
            Err(PlacementError::InvalidSnapshot { .. })
        ));
        let text = placement_shipped_model();
        assert!(PlacementClassifier::with_model(text, 8).is_ok());
    }
}
