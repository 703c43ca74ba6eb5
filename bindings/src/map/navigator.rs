//! `MapNavigator` at the FFI: the phone navigator's steps on floor plans, with fixes
//! from any source; IMU samples packed as the `PhoneNavigator`'s (80-byte records).

use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::map as core;

use super::error::{guard, MapError};
use super::plan::FloorPlan;
use super::records::{MapConfig, MapEstimate, MapFix, SmoothedPoint};
use crate::packed::imu_samples;
use crate::phone::navigator::{push_each, RejectedImuSample};

/// What a packed IMU push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct MapBatchResult {
    /// Samples accepted.
    pub accepted: i32,
    /// Estimates produced: one per accepted sample.
    pub produced: i32,
    pub rejected: Vec<RejectedImuSample>,
    /// Points of the smoothed path fixed during the batch, in order: append them to
    /// the path drawn so far (its open end is `smoothedWindow()`).
    pub smoothed_fixed: Vec<SmoothedPoint>,
    /// The estimate after the batch (null while nothing was accepted yet).
    pub latest: Option<MapEstimate>,
}

fn plans_of(plans: &[Arc<FloorPlan>]) -> Vec<Arc<core::FloorPlan>> {
    plans.iter().map(|p| Arc::clone(&p.inner)).collect()
}

/// The phone navigator on floor plans. Safe to call from several threads.
#[derive(Debug, uniffi::Object)]
pub struct MapNavigator {
    inner: Mutex<core::MapNavigator>,
}

impl MapNavigator {
    fn lock(&self) -> MutexGuard<'_, core::MapNavigator> {
        crate::error::lock(&self.inner)
    }

    fn wrap(n: core::MapNavigator) -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(n),
        })
    }
}

#[uniffi::export]
impl MapNavigator {
    /// An engine over `plans` (one per floor; none: the phone navigator alone).
    #[uniffi::constructor]
    pub fn new(config: MapConfig, plans: Vec<Arc<FloorPlan>>) -> Result<Arc<Self>, MapError> {
        guard(|| {
            let n = core::MapNavigator::new(config.try_into()?, plans_of(&plans))?;
            Ok(Self::wrap(n))
        })
    }

    /// An engine with the default configuration over `plans`.
    #[uniffi::constructor]
    pub fn with_defaults(plans: Vec<Arc<FloorPlan>>) -> Result<Arc<Self>, MapError> {
        guard(|| {
            let n = core::MapNavigator::new(core::MapConfig::default(), plans_of(&plans))?;
            Ok(Self::wrap(n))
        })
    }

    /// An engine continuing exactly where `snapshot()` was taken, over the same plans
    /// (the same floors in the same order; others are refused).
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>, plans: Vec<Arc<FloorPlan>>) -> Result<Arc<Self>, MapError> {
        guard(|| {
            let n = core::MapNavigator::restore(&snapshot, plans_of(&plans))?;
            Ok(Self::wrap(n))
        })
    }

    /// The configuration the engine runs with.
    pub fn config(&self) -> MapConfig {
        (self.lock().config()).into()
    }

    /// Start at plan metres with `sigma_m` per axis (null: the configured σ) on
    /// `floor` (null: the floor in use). A start up to 5 m off the walkable area is
    /// moved onto it (`flags.startSnapped`); farther is `OffPlan` and nothing changes.
    #[uniffi::method(default(sigma_m = None, floor = None))]
    pub fn start_at(
        &self,
        x_m: f64,
        y_m: f64,
        sigma_m: Option<f64>,
        floor: Option<i32>,
    ) -> Result<(), MapError> {
        guard(|| Ok(self.lock().start_at(x_m, y_m, sigma_m, floor)?))
    }

    /// Start at a WGS84 position (the plan needs a geographic reference).
    #[uniffi::method(default(sigma_m = None, floor = None))]
    pub fn start_at_lat_lon(
        &self,
        lat_deg: f64,
        lon_deg: f64,
        sigma_m: Option<f64>,
        floor: Option<i32>,
    ) -> Result<(), MapError> {
        guard(|| {
            Ok(self
                .lock()
                .start_at_lat_lon(lat_deg, lon_deg, sigma_m, floor)?)
        })
    }

    /// The walker is on `floor` now (an elevator, the app's floor selector).
    pub fn set_floor(&self, floor: i32) -> Result<(), MapError> {
        guard(|| Ok(self.lock().set_floor(floor)?))
    }

    /// Push IMU samples packed as 80-byte little-endian records of ten f64 `t_s,
    /// accel_x, accel_y, accel_z (m/s²), gyro_x, gyro_y, gyro_z (rad/s), mag_x, mag_y,
    /// mag_z (µT, NaN: none)` (`packImuSamples` builds them). Refused samples are
    /// reported and skipped.
    pub fn push_imu_packed(&self, data: Vec<u8>) -> Result<MapBatchResult, MapError> {
        guard(|| {
            let samples =
                imu_samples(&data).map_err(|reason| MapError::InvalidBuffer { reason })?;
            let mut m = self.lock();
            let mut fixed = m.smoothed_fixed();
            let mut smoothed_fixed = Vec::new();
            let b = push_each(samples, |s| {
                let pushed = m.push_imu(&s).map(|()| true);
                smoothed_fixed.extend(m.smoothed_since(fixed).map(SmoothedPoint::from));
                fixed = m.smoothed_fixed();
                pushed
            });
            Ok(MapBatchResult {
                accepted: b.accepted,
                produced: b.produced,
                rejected: b.rejected,
                smoothed_fixed,
                latest: m.estimate().map(Into::into),
            })
        })
    }

    /// One absolute fix (latitude/longitude or plan metres, with its accuracy and
    /// optionally its floor): held until the steps up to its time are placed (at most
    /// 2.5 s), then weighs the particles; a fix on another floor switches to it.
    pub fn push_fix(&self, fix: MapFix) -> Result<Option<MapEstimate>, MapError> {
        guard(|| Ok(self.lock().push_fix(&fix.into())?.map(Into::into)))
    }

    /// Where the walker is now: null before the first accepted sample.
    pub fn estimate(&self) -> Option<MapEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// The open end of the smoothed path (the last steps, still being corrected),
    /// oldest first.
    pub fn smoothed_window(&self) -> Vec<SmoothedPoint> {
        let mut out = Vec::new();
        self.lock()
            .smoothed_window(|p| out.push(SmoothedPoint::from(p)));
        out
    }

    /// The whole state as bytes (the plans are identified in it, not stored).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}
