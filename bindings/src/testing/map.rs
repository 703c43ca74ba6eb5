//! Map test helper: the Rust reference replay of packed IMU records and fixes through
//! the core map engine, for the host tests to compare the FFI path with.

use std::sync::Arc;

use stridekit_core::map as core;

use crate::map::error::{guard, MapError};
use crate::map::plan::{FloorPlan, PlanPoint};
use crate::map::records::{MapEstimate, MapFix, SmoothedPoint};
use crate::packed::imu_samples;

/// What a Rust replay through the map engine produced (see [`map_reference_replay`]).
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct MapReplay {
    /// The estimate after every accepted sample, in order.
    pub estimates: Vec<MapEstimate>,
    /// The smoothed path: every point fixed, then the open window at the end.
    pub smoothed: Vec<SmoothedPoint>,
    pub rejected: i32,
    /// The engine's snapshot at the end.
    pub snapshot: Vec<u8>,
}

/// The reference for host tests: the core `MapNavigator` (default configuration,
/// `plans`, started at `start` with `start_sigma_m` when given) fed the packed 80-byte
/// IMU records one by one in Rust, each fix pushed just before the first sample at or
/// after its time. Pushing the same through a `MapNavigator` in batches cut at the
/// fixes must give exactly this.
#[uniffi::export]
pub fn map_reference_replay(
    imu_packed: Vec<u8>,
    plans: Vec<Arc<FloorPlan>>,
    start: Option<PlanPoint>,
    start_sigma_m: Option<f64>,
    fixes: Vec<MapFix>,
) -> Result<MapReplay, MapError> {
    guard(|| {
        let samples =
            imu_samples(&imu_packed).map_err(|reason| MapError::InvalidBuffer { reason })?;
        let plans = plans.iter().map(|p| Arc::clone(&p.inner)).collect();
        let mut m = core::MapNavigator::new(core::MapConfig::default(), plans)?;
        if let Some(s) = start {
            m.start_at(s.x_m, s.y_m, start_sigma_m, None)?;
        }
        let (mut estimates, mut smoothed, mut rejected) = (Vec::new(), Vec::new(), 0i32);
        let (mut fi, mut fixed) = (0, 0u64);
        for s in samples {
            while fi < fixes.len() && fixes[fi].t_s <= s.t_s {
                m.push_fix(&fixes[fi].into())?;
                fi += 1;
            }
            match m.push(&s) {
                Ok(e) => estimates.extend(e.map(MapEstimate::from)),
                Err(_) => rejected += 1,
            }
            smoothed.extend(m.smoothed_since(fixed).map(SmoothedPoint::from));
            fixed = m.smoothed_fixed();
        }
        m.smoothed_window(|p| smoothed.push(p.into()));
        Ok(MapReplay {
            estimates,
            smoothed,
            rejected,
            snapshot: m.snapshot(),
        })
    })
}
