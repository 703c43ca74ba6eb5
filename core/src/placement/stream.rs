//! [`FeatureStream`]: samples in (`t_s`, acceleration with gravity in m/s², any rate,
//! any axes) → checked at the door → 20-ms bin means ([`resample`](super::resample))
//! → a ring of the last [`WINDOW`] bins (5.12 s) → every [`HOP`] bins (1.28 s) with a
//! full window, the window's [features](super::features). Training and the
//! classifier share this path.
//!
//! At the door: non-finite values, a time not after the previous sample and a
//! magnitude above 50 g are rejected; samples in g are recognised like the step
//! detector does (a first sample with magnitude 0.3..=3, or a 1-s mean magnitude that
//! would fall below 3 m/s²): [`PlacementError::LooksLikeG`]. A rejected sample leaves
//! the stream exactly as it was. A gap over 0.25 s empties the window.
//!
//! No heap allocation: fixed-size ring and stack arrays only.

use super::error::PlacementError;
use super::features::{window_features, FeatureTables, Features, WINDOW};
use super::resample::BinAverager;
use crate::signal::Ring;
use crate::snapshot::SnapshotError;

/// Bins between two feature windows (1.28 s).
pub const HOP: usize = 64;
/// Magnitudes above this are not an accelerometer reading, m/s² (50 g).
pub const MAX_ACCEL_MPS2: f64 = 50.0 * 9.80665;
const UNITS_TAU_S: f64 = 1.0;
const UNITS_MIN_MEAN_MPS2: f64 = 3.0;

/// Streaming window features.
#[derive(Clone, Debug, Default)]
pub struct FeatureStream {
    tables: FeatureTables,
    bins: BinAverager,
    window: Ring<[f64; 3], WINDOW>,
    since_window: usize,
    last_t_s: Option<f64>,
    units_mean_mps2: f64,
}

impl FeatureStream {
    pub fn new() -> Self {
        Self::default()
    }

    /// Time of the last accepted sample.
    pub fn last_t_s(&self) -> Option<f64> {
        self.last_t_s
    }

    fn check(&self, t_s: f64, a: [f64; 3]) -> Result<f64, PlacementError> {
        if !t_s.is_finite() {
            return Err(PlacementError::NonFinite { field: "t_s" });
        }
        for (v, field) in a
            .iter()
            .zip(["accel_x_mps2", "accel_y_mps2", "accel_z_mps2"])
        {
            if !v.is_finite() {
                return Err(PlacementError::NonFinite { field });
            }
        }
        if let Some(last) = self.last_t_s {
            if t_s <= last {
                return Err(PlacementError::TimeNotIncreasing {
                    t_s,
                    last_t_s: last,
                });
            }
        }
        let mag = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if mag > MAX_ACCEL_MPS2 {
            return Err(PlacementError::OutOfRange {
                field: "acceleration magnitude",
                value: mag,
                expected: "≤ 50 g (490 m/s²)",
            });
        }
        match self.last_t_s {
            None if (0.3..=3.0).contains(&mag) => Err(PlacementError::LooksLikeG {
                mean_magnitude: mag,
            }),
            None => Ok(mag),
            Some(last) => {
                let g = 1.0 - (-(t_s - last) / UNITS_TAU_S).exp();
                let mean = self.units_mean_mps2 + g * (mag - self.units_mean_mps2);
                if mean < UNITS_MIN_MEAN_MPS2 {
                    Err(PlacementError::LooksLikeG {
                        mean_magnitude: mean,
                    })
                } else {
                    Ok(mean)
                }
            }
        }
    }

    /// Adds one sample; returns the features of a window when one is due.
    pub fn push(
        &mut self,
        t_s: f64,
        accel_mps2: [f64; 3],
    ) -> Result<Option<Features>, PlacementError> {
        let mean = self.check(t_s, accel_mps2)?;
        self.last_t_s = Some(t_s);
        self.units_mean_mps2 = mean;
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
        w.opt_f64(self.last_t_s);
        w.f64(self.units_mean_mps2);
    }

    pub(crate) fn read(r: &mut crate::snapshot::Reader<'_>) -> Result<Self, SnapshotError> {
        let bins = BinAverager::read(r)?;
        let mut window = Ring::new();
        for _ in 0..r.len(WINDOW)? {
            let mut v = [0.0; 3];
            r.f64s(&mut v)?;
            window.push(v);
        }
        let since_window = r.len(u32::MAX as usize)?;
        let last_t_s = r.opt_f64()?;
        let units_mean_mps2 = r.f64()?;
        Ok(Self {
            tables: FeatureTables::default(),
            bins,
            window,
            since_window,
            last_t_s,
            units_mean_mps2,
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
