//! A simulated run with Rust reference estimates, so host tests of the bindings can
//! prove that pushing through the FFI gives bit-identical results.

use stridekit_core::pace as core;
use stridekit_sim::{self as sim, RunScenario};

use crate::error::{guard, PaceError};
use crate::pace::types::{GnssFix, PaceEstimate, PaceSample, StepSample};

/// Longest run `simulate_run` accepts, seconds (6 h).
pub const MAX_SIM_DURATION_S: f64 = 6.0 * 3600.0;

/// A simulated run (the core's demo scenario: intervals, stops, GNSS disturbances and
/// outages, step counts once per second) and what Rust computes from it.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct SimulatedRun {
    pub seed: u64,
    pub duration_s: f64,
    /// GNSS fixes in time order.
    pub fixes: Vec<GnssFix>,
    /// Step samples in time order.
    pub steps: Vec<StepSample>,
    /// Fixes and steps merged in time order (steps first at equal times).
    pub samples: Vec<PaceSample>,
    /// Estimates of a default-configuration tracker fed `samples` one by one in Rust:
    /// one per accepted fix.
    pub reference_estimates: Vec<PaceEstimate>,
    /// That tracker's `estimate()` after the last sample.
    pub reference_final: Option<PaceEstimate>,
    /// Samples that tracker rejected (0 for a well-formed simulation).
    pub reference_rejected: i32,
}

/// Simulate a run of `duration_s` seconds (0 < duration ≤ 6 h) from `seed`.
/// Deterministic: the same seed gives the same run on every platform.
#[uniffi::export]
pub fn simulate_run(seed: u64, duration_s: f64) -> Result<SimulatedRun, PaceError> {
    if !duration_s.is_finite() {
        return Err(PaceError::NonFinite {
            field: "duration_s".into(),
        });
    }
    if !(duration_s > 0.0 && duration_s <= MAX_SIM_DURATION_S) {
        return Err(PaceError::OutOfRange {
            field: "duration_s".into(),
            value: duration_s,
            expected: "0 < duration_s <= 21600 s".into(),
        });
    }
    guard(|| {
        let scenario = RunScenario {
            duration_s,
            ..RunScenario::demo(seed)
        };
        let run = sim::simulate_run(&scenario);
        let samples = run.samples();
        let mut tracker = core::PaceTracker::new(core::PaceConfig::default())?;
        let mut reference_estimates = Vec::with_capacity(run.fixes.len());
        let mut reference_rejected = 0i32;
        for s in &samples {
            match tracker.push(s) {
                Ok(Some(e)) => reference_estimates.push(e.into()),
                Ok(None) => {}
                Err(_) => reference_rejected += 1,
            }
        }
        Ok(SimulatedRun {
            seed,
            duration_s,
            fixes: run.fixes.iter().map(|&f| f.into()).collect(),
            steps: run.steps.iter().map(|&s| s.into()).collect(),
            samples: samples.into_iter().map(Into::into).collect(),
            reference_estimates,
            reference_final: tracker.estimate().map(Into::into),
            reference_rejected,
        })
    })
}
