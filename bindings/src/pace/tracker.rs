//! `PaceTracker` at the FFI: the core tracker behind a mutex, single and batch pushes.

use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::pace as core;

use crate::error::{guard, PaceError};
use crate::pace::types::{
    AccelSample, GnssFix, PaceCalibration, PaceConfig, PaceEstimate, PaceSample, StepSample,
};
use crate::packed;

/// A sample a batch push rejected; the rest of the batch was still processed.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct RejectedSample {
    /// Position of the sample in the batch (or record in a packed buffer), from 0.
    pub index: i32,
    /// Why it was rejected.
    pub error: PaceError,
    /// The same as a sentence, for logs (the field every engine's rejected sample
    /// has: `reason`).
    pub reason: String,
}

/// What a batch push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct BatchResult {
    /// Samples accepted (the batch minus the rejected ones).
    pub accepted: i32,
    /// Estimates the engine produced during the batch (returned or not).
    pub produced: i32,
    /// One estimate per accepted GNSS fix, in batch order (empty for step-only batches).
    pub estimates: Vec<PaceEstimate>,
    /// Samples that were rejected, in batch order.
    pub rejected: Vec<RejectedSample>,
    /// The tracker's estimate after the whole batch (what `estimate()` would return:
    /// null while nothing was accepted yet).
    pub latest: Option<PaceEstimate>,
}

/// Running-pace tracker. Feed it GNSS fixes and step data, each stream in time order
/// (the two streams may interleave freely); read a [`PaceEstimate`] at every fix or
/// at any time. Safe to call from several threads: calls are serialised, and a batch
/// is applied as a whole before any other call sees the tracker.
#[derive(Debug, uniffi::Object)]
pub struct PaceTracker {
    inner: Mutex<core::PaceTracker>,
}

impl PaceTracker {
    fn wrap(tracker: core::PaceTracker) -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(tracker),
        })
    }

    /// The core tracker; a mutex poisoned by an earlier panic is recovered (the
    /// panic was already reported as an error) instead of panicking again.
    fn lock(&self) -> MutexGuard<'_, core::PaceTracker> {
        crate::error::lock(&self.inner)
    }

    /// Push every item with `push` under one lock, collecting estimates and rejections.
    fn batch<T>(
        &self,
        items: impl Iterator<Item = T>,
        capacity: usize,
        mut push: impl FnMut(
            &mut core::PaceTracker,
            T,
        ) -> Result<Option<core::PaceEstimate>, core::PaceError>,
    ) -> BatchResult {
        let mut tracker = self.lock();
        let mut estimates = Vec::with_capacity(capacity);
        let mut rejected = Vec::new();
        // The core's batch loop; a panic in one sample (a core bug) refuses that
        // sample and the batch goes on.
        let accepted = stridekit_core::batch::each(
            items,
            |e: core::PaceEstimate| estimates.push(e.into()),
            |r: stridekit_core::batch::Rejected<PaceError>| {
                rejected.push(RejectedSample {
                    index: i32::try_from(r.index).unwrap_or(i32::MAX),
                    reason: r.error.to_string(),
                    error: r.error,
                })
            },
            |item| guard(|| Ok(push(&mut tracker, item)?)),
        );
        let accepted = i32::try_from(accepted).unwrap_or(i32::MAX);
        // A panic here (a core bug) is caught by uniffi's scaffolding.
        let latest = tracker.estimate().map(Into::into);
        BatchResult {
            accepted,
            produced: i32::try_from(estimates.len()).unwrap_or(i32::MAX),
            estimates,
            rejected,
            latest,
        }
    }
}

#[uniffi::export]
impl PaceTracker {
    /// A tracker with the given configuration (other parameters at their defaults).
    #[uniffi::constructor]
    pub fn new(config: PaceConfig) -> Result<Arc<Self>, PaceError> {
        guard(|| Ok(Self::wrap(core::PaceTracker::new(config.into())?)))
    }

    /// A tracker with the default configuration (adaptive filter).
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Self::wrap(
            core::PaceTracker::new(core::PaceConfig::default())
                .expect("the core default configuration is valid"),
        )
    }

    /// A tracker continuing exactly where `snapshot()` was taken (same configuration,
    /// same state: it produces bit-identical estimates from there on).
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, PaceError> {
        guard(|| Ok(Self::wrap(core::PaceTracker::restore(&snapshot)?)))
    }

    /// The configuration the tracker runs with.
    pub fn config(&self) -> PaceConfig {
        (*self.lock().config()).into()
    }

    /// The step-length line learned so far, to store with the user's profile and pass
    /// as `PaceConfig.calibration` next session; null until learned from good GNSS
    /// (or given), always null in `AS_PUBLISHED` mode.
    pub fn calibration(&self) -> Option<PaceCalibration> {
        self.lock().calibration().map(Into::into)
    }

    /// Push one GNSS fix; returns the estimate at this fix. A rejected fix leaves the
    /// tracker unchanged.
    pub fn push_fix(&self, fix: GnssFix) -> Result<PaceEstimate, PaceError> {
        guard(|| Ok(self.lock().push_fix(&fix.into())?.into()))
    }

    /// Push one step sample. A rejected sample leaves the tracker unchanged.
    pub fn push_steps(&self, sample: StepSample) -> Result<(), PaceError> {
        guard(|| Ok(self.lock().push_steps(&sample.try_into()?)?))
    }

    /// Push GNSS fixes in time order; one estimate per accepted fix. Rejected fixes
    /// are skipped and reported by index; the others are processed as if pushed one
    /// by one.
    pub fn push_fixes(&self, fixes: Vec<GnssFix>) -> BatchResult {
        let n = fixes.len();
        self.batch(fixes.into_iter(), n, |t, f| t.push_fix(&f.into()).map(Some))
    }

    /// Push step samples in time order (rejections reported by index).
    pub fn push_step_samples(&self, samples: Vec<StepSample>) -> BatchResult {
        self.batch(samples.into_iter(), 0, |t, s| {
            t.push_steps(&s.try_into()?).map(|_| None)
        })
    }

    /// Push samples of both streams, merged in time order; one estimate per accepted
    /// fix (rejections reported by index).
    pub fn push_samples(&self, samples: Vec<PaceSample>) -> BatchResult {
        let n = samples.len();
        self.batch(samples.into_iter(), n, |t, s| t.push(&s.try_into()?))
    }

    /// Fast path: push GNSS fixes packed as 56-byte little-endian records of seven
    /// f64 `t_s, lat_deg, lon_deg, alt_m, horizontal_accuracy_m, speed_mps,
    /// speed_accuracy_mps` (NaN: absent; `packFixes` builds them). Fails as a whole only if the length is not a
    /// multiple of 56; otherwise behaves like `push_fixes`.
    pub fn push_fixes_packed(&self, data: Vec<u8>) -> Result<BatchResult, PaceError> {
        guard(|| {
            let fixes = packed::fixes(&data)?;
            let n = data.len() / packed::FIX_RECORD_BYTES;
            Ok(self.batch(fixes, n, |t, f| t.push_fix(&f).map(Some)))
        })
    }

    /// Fast path: push cumulative step counts packed as 16-byte little-endian records
    /// `(t_s: f64, steps: i64)` (a negative count is rejected by index). Fails as a whole only if the length is not a multiple
    /// of 16; otherwise behaves like `push_step_samples`.
    pub fn push_step_counts_packed(&self, data: Vec<u8>) -> Result<BatchResult, PaceError> {
        guard(|| {
            let counts = packed::step_counts(&data)?;
            Ok(self.batch(counts, 0, |t, s| t.push_steps(&s?).map(|_| None)))
        })
    }

    /// Raw accelerometer samples (m/s², gravity included, any axes) instead of
    /// platform step counts: the tracker detects steps itself. Use one step source
    /// per tracker.
    pub fn push_accel_samples(&self, samples: Vec<AccelSample>) -> BatchResult {
        let n = samples.len();
        self.batch(samples.into_iter(), n, |t, s| {
            t.push_accel(s.t_s, [s.x_mps2, s.y_mps2, s.z_mps2])
                .map(|_| None)
        })
    }

    /// Fast path for accelerometer streams (100–400 Hz): 32-byte little-endian
    /// records `(t_s, ax, ay, az)` as f64. Fails as a whole only if the length is not a
    /// multiple of 32; otherwise behaves like `push_accel_samples`.
    pub fn push_accel_packed(&self, data: Vec<u8>) -> Result<BatchResult, PaceError> {
        guard(|| {
            let samples = packed::accel(&data)?;
            Ok(self.batch(samples, 0, |t, (ts, a)| t.push_accel(ts, a).map(|_| None)))
        })
    }

    /// Steps detected so far from accelerometer input.
    pub fn detected_steps(&self) -> i64 {
        i64::try_from(self.lock().detected_steps()).unwrap_or(i64::MAX)
    }

    /// The current estimate, at the time of the newest sample of either stream: null
    /// until a sample (fix, step sample or accelerometer sample) was accepted, as for
    /// every engine.
    pub fn estimate(&self) -> Option<PaceEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// The whole state as bytes (versioned, checksummed), to survive the app being
    /// killed; give them to `PaceTracker.restore`.
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(t_s: f64) -> core::GnssFix {
        core::GnssFix::new(t_s, 50.0 + t_s * 1e-5, 18.0)
    }

    #[test]
    fn a_poisoned_mutex_is_recovered() {
        let t = PaceTracker::with_defaults();
        t.push_fix(fix(1.0).into()).unwrap();
        let t2 = Arc::clone(&t);
        let poisoner = std::thread::spawn(move || {
            let _guard = t2.inner.lock().unwrap();
            panic!("poisoning the tracker's mutex on purpose");
        });
        assert!(poisoner.join().is_err());
        assert!(t.inner.is_poisoned());
        assert_eq!(t.estimate().unwrap().t_s, 1.0);
        assert!(!t.inner.is_poisoned());
        t.push_fix(fix(2.0).into()).unwrap();
    }

    #[test]
    fn panics_become_errors() {
        let err = guard::<()>(|| panic!("boom {}", 42)).unwrap_err();
        assert_eq!(
            err,
            PaceError::Internal {
                reason: "boom 42".into()
            }
        );
        let t = PaceTracker::with_defaults();
        let r = t.batch([1.0, 2.0, 3.0].into_iter(), 3, |tr, x| {
            if x == 2.0 {
                panic!("bug at sample {x}");
            }
            tr.push_fix(&fix(x)).map(Some)
        });
        assert_eq!(r.estimates.len(), 2);
        assert_eq!(r.rejected.len(), 1);
        assert_eq!(r.rejected[0].index, 1);
        assert!(matches!(r.rejected[0].error, PaceError::Internal { .. }));
        assert!(!t.inner.is_poisoned());
        assert_eq!(t.estimate().unwrap().t_s, 3.0);
    }
}
