//! Phone test helpers: a simulated phone walk for `PhoneOdometry` and the Rust
//! reference replay of packed IMU records through the navigator.

use stridekit_core::odometry as core_odometry;
use stridekit_core::pdr as core;

use crate::packed::{imu_samples, pack_imu};
use crate::phone::navigator::{collect_new_steps, NavError, NavEstimate, NavStep, PdrCalibration};
use crate::phone::odometry::{OdometryError, OdometryEstimate};
use crate::phone::placement::PhonePlacement;

/// What a Rust replay of packed IMU records produced (see [`pdr_reference_replay`]).
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct PdrReplay {
    pub steps: Vec<NavStep>,
    pub rejected: i32,
    pub latest: Option<NavEstimate>,
}

/// The reference for host tests of the bindings: the core navigator (default
/// configuration, `calibration` loaded) fed the packed 80-byte IMU records one by
/// one in Rust, no batching, no FFI object; every placed step and the final
/// estimate. Pushing the same records through a `PhoneNavigator` in batches must
/// give exactly this.
#[uniffi::export]
pub fn pdr_reference_replay(
    imu_packed: Vec<u8>,
    calibration: Option<PdrCalibration>,
) -> Result<PdrReplay, NavError> {
    crate::phone::navigator::guard(|| {
        let samples =
            imu_samples(&imu_packed).map_err(|reason| NavError::InvalidBuffer { reason })?;
        let mut nav = core::PhoneNavigator::new(core::NavigatorConfig::default())
            .expect("the core default configuration is valid");
        if let Some(c) = &calibration {
            nav.set_calibration(&c.try_into()?)
                .map_err(|e| NavError::InvalidCalibration {
                    reason: e.to_string(),
                })?;
        }
        let (mut steps, mut rejected, mut placed) = (Vec::new(), 0i32, 0u64);
        for s in samples {
            if nav.push_imu(&s).is_err() {
                rejected += 1;
            }
            collect_new_steps(&nav, &mut placed, &mut steps);
        }
        Ok(PdrReplay {
            steps,
            rejected,
            latest: nav.estimate().map(Into::into),
        })
    })
}

/// A simulated phone walk (the core's phone simulator) packed for
/// [`PhoneOdometry::push_imu_packed`], its truth, and what a default engine computes
/// from it in Rust, so host tests can prove that the FFI gives identical results.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct SimulatedPhoneWalk {
    /// IMU samples in the 80-byte layout (magnetometer included).
    pub imu_packed: Vec<u8>,
    pub samples: i32,
    /// Truth every 0.1 s: time, s; position east / north of the start, m.
    pub truth_t_s: Vec<f64>,
    pub truth_east_m: Vec<f64>,
    pub truth_north_m: Vec<f64>,
    /// Distance walked, m.
    pub truth_distance_m: f64,
    /// The final estimate of `PhoneOdometry.withDefaults()` fed the samples in Rust.
    pub reference_final: Option<OdometryEstimate>,
}

/// Simulate `duration_s` (1..=3600 s) of walking at `speed_mps` (0.3..=3 m/s) with
/// the phone at `placement` (a pocket is simulated as a front pocket).
/// Deterministic: the same arguments give the same walk on every platform.
#[uniffi::export]
pub fn simulate_phone_walk(
    seed: u64,
    placement: PhonePlacement,
    speed_mps: f64,
    duration_s: f64,
) -> Result<SimulatedPhoneWalk, OdometryError> {
    use stridekit_sim::{simulate_phone, PhonePlacement as Sim, PhoneScenario};
    if !(speed_mps.is_finite() && (0.3..=3.0).contains(&speed_mps)) {
        return Err(OdometryError::InvalidConfig {
            reason: format!("speed_mps = {speed_mps}: must be 0.3..=3 m/s"),
        });
    }
    if !(duration_s.is_finite() && (1.0..=3600.0).contains(&duration_s)) {
        return Err(OdometryError::InvalidConfig {
            reason: format!("duration_s = {duration_s}: must be 1..=3600 s"),
        });
    }
    crate::phone::odometry::guard(|| {
        let p = match placement {
            PhonePlacement::InHand => Sim::InHand,
            PhonePlacement::Pocket => Sim::FrontPocket,
            PhonePlacement::Bag => Sim::Bag,
            PhonePlacement::NeckPouch => Sim::NeckPouch,
            PhonePlacement::Armband => Sim::Armband,
            PhonePlacement::SwingingArm => Sim::SwingingArm,
        };
        let sim = simulate_phone(&PhoneScenario::walk(seed, p, speed_mps, duration_s));
        let samples: Vec<core_odometry::ImuSample> = sim
            .samples
            .iter()
            .map(core_odometry::ImuSample::from)
            .collect();
        let mut engine =
            core_odometry::PhoneOdometry::shipped(core_odometry::OdometryConfig::default())?;
        for s in &samples {
            // A well-formed simulation has no rejected sample; skip like a batch would.
            let _ = engine.push(s);
        }
        let last = sim.truth.last().copied().unwrap_or_default();
        Ok(SimulatedPhoneWalk {
            imu_packed: pack_imu(samples.iter().copied()),
            samples: i32::try_from(samples.len()).unwrap_or(i32::MAX),
            truth_t_s: sim.truth.iter().map(|t| t.t_s).collect(),
            truth_east_m: sim.truth.iter().map(|t| t.east_m).collect(),
            truth_north_m: sim.truth.iter().map(|t| t.north_m).collect(),
            truth_distance_m: last.distance_m,
            reference_final: engine.estimate().map(Into::into),
        })
    })
}
