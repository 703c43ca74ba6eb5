//! [`FeatureStream`]: samples in (`t_s`, acceleration with gravity in m/s², any rate,
//! any axes) → checked at the door → 20-ms bin means ([`resample`](super::resample))
//! → a ring of the last [`WINDOW`] bins (5.12 s) → every [`HOP`] bins (1.28 s) with a
//! full window, the window's [features](super::features). Training and the
//! classifier share this path.
//!
//! At the door: the checks and limits of [`crate::input`] (finite, per axis
//! ≤ 2 000 m/s², time after the previous sample and in seconds, the g-units check).
//! A rejected sample leaves the stream exactly as it was. A gap over 0.25 s empties
//! the window.
//!
//! No heap allocation: fixed-size ring and stack arrays only.

use super::error::PlacementError;
use super::features::{window_features, FeatureTables, Features, WINDOW};
use super::resample::BinAverager;
use crate::input::{self, AccelUnits, Stream, TimeGuard};
use crate::signal::Ring;
use crate::snapshot::SnapshotError;

/// Bins between two feature windows (1.28 s).
pub const HOP: usize = 64;

/// Streaming window features.
#[derive(Clone, Debug)]
pub struct FeatureStream {
    tables: FeatureTables,
    bins: BinAverager,
    window: Ring<[f64; 3], WINDOW>,
    since_window: usize,
    time: TimeGuard,
    units: AccelUnits,
}

impl Default for FeatureStream {
    fn default() -> Self {
        Self::new()
    }
}

impl FeatureStream {
    pub fn new() -> Self {
        Self {
            tables: FeatureTables::default(),
            bins: BinAverager::default(),
            window: Ring::new(),
            since_window: 0,
            time: TimeGuard::new(Stream::Accelerometer),
            units: AccelUnits::new(),
        }
    }

    /// Time of the last accepted sample.
    pub fn last_t_s(&self) -> Option<f64> {
        self.time.last_t_s()
    }

    fn check(&self, t_s: f64, a: [f64; 3]) -> Result<f64, PlacementError> {
        let dt = self.time.check(t_s)?;
        input::accel(&a)?;
        let mag = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        Ok(self.units.check(dt, mag)?)
    }

    /// Adds one sample; returns the features of a window when one is due.
    pub fn push(
        &mut self,
        t_s: f64,
        accel_mps2: [f64; 3],
    ) -> Result<Option<Features>, PlacementError> {
        let mean = self.check(t_s, accel_mps2)?;
        self.time.accept(t_s);
        self.units.accept(mean);
        let bins = self.bins.push(t_s, accel_mps2);
        if bins.restarted {
            self.window.clear();
            self.since_window = 0;
        }
        let mut due = false;
        for m in &bins.means[..bins.len] {
            self.window.push(*m);
            self.since_window += 1;
            if self.window.len() == WINDOW && self.since_window >= HOP {
                self.since_window = 0;
                due = true;
            }
        }
        Ok(if due { self.current_features() } else { None })
    }

    pub(crate) fn write(&self, w: &mut crate::snapshot::Writer) {
        self.bins.write(w);
        w.u64(self.window.len() as u64);
        for v in self.window.iter() {
            w.f64s(&v);
        }
        w.u64(self.since_window as u64);
        self.time.write(w);
        self.units.write(w);
    }

    pub(crate) fn read(r: &mut crate::snapshot::Reader<'_>) -> Result<Self, SnapshotError> {
        let bins = BinAverager::read(r)?;
        let mut window = Ring::new();
        for _ in 0..r.len(WINDOW)? {
            let mut v = [0.0; 3];
            r.f64s(&mut v)?;
            // Bin means of samples within the door's limits.
            if v.iter()
                .any(|x| x.abs() > crate::input::limits::MAX_ACCEL_MPS2)
            {
                return Err(SnapshotError::Invalid("window bin"));
            }
            window.push(v);
        }
        // Counts bins up to a full window at most (then restarts at the hop).
        let since_window = r.len(WINDOW.max(HOP))?;
        let time = TimeGuard::read(r, Stream::Accelerometer)?;
        let units = AccelUnits::read(r)?;
        Ok(Self {
            tables: FeatureTables::default(),
            bins,
            window,
            since_window,
            time,
            units,
        })
    }

    /// Features of the current window (`None` until the window is full).
    pub fn current_features(&self) -> Option<Features> {
        (self.window.len() == WINDOW).then(|| {
            let mut w = [[0.0; 3]; WINDOW];
            for (i, v) in w.iter_mut().enumerate() {
                *v = self.window.get(i).unwrap_or_default();
            }
            window_features(&self.tables, &w)
        })
    }
}

/// Features of every window of a recording (samples the stream rejects are skipped).
pub fn trace_features(samples: impl IntoIterator<Item = (f64, [f64; 3])>) -> Vec<Features> {
    let mut s = FeatureStream::new();
    samples
        .into_iter()
        .filter_map(|(t, a)| s.push(t, a).ok().flatten())
        .collect()
}
