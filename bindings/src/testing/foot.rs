//! Foot test helper: a simulated foot-mounted walk with Rust's reference estimates.

use stridekit_core::foot as core;

use crate::foot::*;

/// Most laps `simulate_foot_walk` accepts.
pub const MAX_SIM_FOOT_LAPS: u32 = 20;

/// A simulated foot-mounted IMU walk (core `sim::foot`: laps of a 20 m × 10 m
/// rectangle at 200 Hz, 2 s rest at both ends, body axes = sensor axes, z up) and
/// what Rust computes from it, so host tests can check the FFI path.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct SimulatedFootWalk {
    pub seed: u64,
    pub laps: u32,
    /// The samples as 56-byte (6-axis) records (layout in `crate::packed`).
    pub samples_packed: Vec<u8>,
    pub sample_count: i32,
    /// True path length (sum of stride lengths), m, and true number of strides.
    pub true_distance_m: f64,
    pub true_strides: i32,
    /// True position at the last sample (the walk ends where it started), ENU, m.
    pub true_end_m: EnuVector,
    /// `estimate()` of a default-configuration navigator fed every sample in Rust.
    pub reference_final: Option<FootEstimate>,
    /// Estimates that navigator produced and samples it rejected (0).
    pub reference_produced: i32,
    pub reference_rejected: i32,
}

/// Simulate `laps` (1..=20) laps of walking from `seed`. Deterministic: the same
/// seed gives the same samples on every platform.
#[uniffi::export]
pub fn simulate_foot_walk(seed: u64, laps: u32) -> Result<SimulatedFootWalk, FootError> {
    if !(1..=MAX_SIM_FOOT_LAPS).contains(&laps) {
        return Err(FootError::InvalidConfig {
            field: "laps".into(),
            reason: format!("must be 1..={MAX_SIM_FOOT_LAPS}"),
        });
    }
    guard(|| {
        let sim = stridekit_sim::simulate_foot(&stridekit_sim::FootScenario::walk(seed, laps));
        let mut nav = core::FootNavigator::new(core::FootConfig::default())?;
        let outcome = nav.push_batch_with(&sim.samples, |_| {});
        let packed = crate::packed::pack_imu6(sim.samples.iter().copied());
        let count = |n: usize| i32::try_from(n).unwrap_or(i32::MAX);
        Ok(SimulatedFootWalk {
            seed,
            laps,
            samples_packed: packed,
            sample_count: count(sim.samples.len()),
            true_distance_m: sim.distance_m,
            true_strides: count(sim.strides.len()),
            true_end_m: sim.truth.last().map_or([0.0; 3], |t| t.position_m).into(),
            reference_final: nav.estimate().map(Into::into),
            reference_produced: count(outcome.estimates),
            reference_rejected: count(outcome.rejected.len()),
        })
    })
}

/// A simulated running foot whose accelerometer clips, and the ceiling Rust finds.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct ClippedFootRun {
    pub seed: u64,
    pub laps: u32,
    /// The samples as 56-byte (6-axis) records (layout in `crate::packed`).
    pub samples_packed: Vec<u8>,
    pub sample_count: i32,
    /// Where every accelerometer axis was clipped, m/s² (`clip_share` × the run's
    /// largest magnitude), and how many axis values were clipped.
    pub clip_mps2: f64,
    pub clipped_values: i32,
    /// `accel_ceiling_mps2()` of a default-configuration navigator fed every sample in
    /// Rust.
    pub reference_ceiling_mps2: Option<f64>,
}

/// Simulate `laps` (1..=20) laps of running from `seed` (core `sim::foot`, 200 Hz, the
/// same loop as `simulate_foot_walk`, 26 m × 13 m) with every accelerometer axis
/// clipped at `clip_share` (0 < share ≤ 1) of the run's largest magnitude, as an
/// IMU of a narrow range records it. Deterministic.
#[uniffi::export]
pub fn simulate_clipped_foot_run(
    seed: u64,
    laps: u32,
    clip_share: f64,
) -> Result<ClippedFootRun, FootError> {
    if !(1..=MAX_SIM_FOOT_LAPS).contains(&laps) {
        return Err(FootError::InvalidConfig {
            field: "laps".into(),
            reason: format!("must be 1..={MAX_SIM_FOOT_LAPS}"),
        });
    }
    if !(clip_share > 0.0 && clip_share <= 1.0) {
        return Err(FootError::InvalidConfig {
            field: "clip_share".into(),
            reason: "must be in (0, 1]".into(),
        });
    }
    guard(|| {
        let mut sim = stridekit_sim::simulate_foot(&stridekit_sim::FootScenario::run(seed, laps));
        let (clip, clipped) = sim.clip_accel(clip_share);
        let mut nav = core::FootNavigator::new(core::FootConfig::default())?;
        nav.push_batch_with(&sim.samples, |_| {});
        let count = |n: usize| i32::try_from(n).unwrap_or(i32::MAX);
        Ok(ClippedFootRun {
            seed,
            laps,
            samples_packed: crate::packed::pack_imu6(sim.samples.iter().copied()),
            sample_count: count(sim.samples.len()),
            clip_mps2: clip,
            clipped_values: count(clipped),
            reference_ceiling_mps2: nav.accel_ceiling_mps2(),
        })
    })
}
