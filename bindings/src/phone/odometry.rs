//! `PhoneOdometry` at the FFI: learned phone inertial odometry, RIDI-style (core:
//! `stridekit_core::odometry`; method, measured accuracy and limits in
//! `docs/odometry-pipeline.md`). **Experimental**: on 287 real indoor walks
//! `PhoneNavigator` is more accurate (median ATE 1.18 m against 1.47 m leave one floor
//! out); the shipped model is trained on those hand-held walks (docs/odometry.md).
//!
//! IMU samples cross the FFI packed, in the same 80-byte little-endian layout as
//! `PhoneNavigator` ([`crate::phone::navigator`]): ten f64 `t_s, gyro_x, gyro_y, gyro_z
//! (rad/s), accel_x, accel_y, accel_z (m/s², gravity included), mag_x, mag_y, mag_z
//! (µT; NaN when there is no magnetometer)`, device axes as the platform reports them.
//! Positions and velocities are horizontal, in the local East-North frame of the
//! AHRS (north from the magnetometer when there is one; otherwise relative to the
//! initial heading), origin where the engine started.

use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::odometry as core;

use crate::packed::imu_samples;
use crate::phone::navigator::{push_each, RejectedImuSample};
use crate::phone::placement::{PhonePlacement, PlacementEstimate};

/// Where the placement that picks the velocity regressor comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Enum)]
pub enum OdometryPlacementSource {
    /// The embedded placement classifier decides (its regressor when confident).
    Auto,
    /// The app knows where the phone is.
    Fixed { placement: PhonePlacement },
    /// The general regressor (the default; see docs/odometry-pipeline.md for why).
    Unknown,
}

impl From<OdometryPlacementSource> for core::PlacementSource {
    fn from(s: OdometryPlacementSource) -> Self {
        match s {
            OdometryPlacementSource::Auto => Self::Auto,
            OdometryPlacementSource::Fixed { placement } => Self::Fixed(placement.into()),
            OdometryPlacementSource::Unknown => Self::Unknown,
        }
    }
}

impl From<core::PlacementSource> for OdometryPlacementSource {
    fn from(s: core::PlacementSource) -> Self {
        match s {
            core::PlacementSource::Auto => Self::Auto,
            core::PlacementSource::Fixed(p) => Self::Fixed {
                placement: p.into(),
            },
            core::PlacementSource::Unknown => Self::Unknown,
        }
    }
}

/// Settings of a [`PhoneOdometry`] (the orientation filter uses the core AHRS
/// defaults; the model file carries the pipeline's own parameters).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct OdometryConfig {
    /// Where the placement comes from (default `Unknown`).
    pub placement: OdometryPlacementSource,
    /// Use the magnetometer when a sample has one (absolute heading). Default true.
    #[uniffi(default = true)]
    pub use_magnetometer: bool,
    /// Apply the paper's low-frequency acceleration-bias correction. Default true.
    #[uniffi(default = true)]
    pub bias_correction: bool,
}

/// The core's default configuration.
#[uniffi::export]
pub fn odometry_config_default() -> OdometryConfig {
    let c = core::OdometryConfig::default();
    OdometryConfig {
        placement: c.placement.into(),
        use_magnetometer: c.use_magnetometer,
        bias_correction: c.bias_correction,
    }
}

impl From<OdometryConfig> for core::OdometryConfig {
    fn from(c: OdometryConfig) -> Self {
        Self {
            placement: c.placement.into(),
            use_magnetometer: c.use_magnetometer,
            bias_correction: c.bias_correction,
            ..Self::default()
        }
    }
}

/// The latest window's estimate. It refers to the centre of the newest feature
/// window, about 1 s behind the newest sample.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct OdometryEstimate {
    pub t_s: f64,
    /// Horizontal velocity after the bias correction, m/s (east, north).
    pub velocity_east_mps: f64,
    pub velocity_north_mps: f64,
    /// The regressor's velocity before the bias correction, m/s.
    pub regressed_east_mps: f64,
    pub regressed_north_mps: f64,
    /// Position, metres from the start (east, north).
    pub east_m: f64,
    pub north_m: f64,
    /// Whose regressor produced this window (null: the general one).
    pub regressor_placement: Option<PhonePlacement>,
    /// The embedded classifier's current placement (`Auto` only).
    pub detected_placement: Option<PhonePlacement>,
    /// Its smoothed probability (0 when there is none).
    pub placement_confidence: f64,
}

impl From<core::OdometryEstimate> for OdometryEstimate {
    fn from(e: core::OdometryEstimate) -> Self {
        Self {
            t_s: e.t_s,
            velocity_east_mps: e.velocity_mps[0],
            velocity_north_mps: e.velocity_mps[1],
            regressed_east_mps: e.regressed_mps[0],
            regressed_north_mps: e.regressed_mps[1],
            east_m: e.position_m[0],
            north_m: e.position_m[1],
            regressor_placement: e.regressor_placement.map(Into::into),
            detected_placement: e.detected_placement.map(Into::into),
            placement_confidence: e.placement_confidence,
        }
    }
}

crate::error::engine_error! {
    /// Why the odometry rejected an input, a model, a setting, a buffer or a snapshot
    /// (Kotlin `OdometryException`, Swift `OdometryError`): the typed input causes every
    /// engine shares, then its own. A rejected sample changes nothing.
    pub enum OdometryError {
        /// A model text could not be loaded (wrong version, corrupt, wrong dimensions).
        #[error("invalid odometry model: {reason}")]
        InvalidModel { reason: String },
        /// A setting is not usable.
        #[error("invalid odometry setting: {reason}")]
        InvalidConfig { reason: String },
        /// Snapshot bytes could not be restored.
        #[error("cannot restore snapshot: {reason}")]
        InvalidSnapshot { reason: String },
        /// A packed buffer is not a whole number of 80-byte records.
        #[error("invalid packed buffer: {reason}")]
        InvalidBuffer { reason: String },
        /// A bug inside stridekit (a caught panic). The engine stays usable.
        #[error("internal error in stridekit: {reason}")]
        Internal { reason: String },
    }
}

impl From<core::OdometryError> for OdometryError {
    fn from(e: core::OdometryError) -> Self {
        let reason = e.to_string();
        match e {
            core::OdometryError::Input(e) => e.into(),
            core::OdometryError::InvalidModel { .. } | core::OdometryError::ModelVersion { .. } => {
                Self::InvalidModel { reason }
            }
            core::OdometryError::InvalidConfig { .. } => Self::InvalidConfig { reason },
            core::OdometryError::Snapshot(s) => Self::InvalidSnapshot {
                reason: s.to_string(),
            },
        }
    }
}

pub(crate) fn guard<T>(f: impl FnOnce() -> Result<T, OdometryError>) -> Result<T, OdometryError> {
    crate::error::guard_with(f, |reason| OdometryError::Internal { reason })
}

/// What a packed IMU push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct OdometryBatchResult {
    /// Samples accepted (the batch minus the rejected ones).
    pub accepted: i32,
    /// Window estimates produced during the batch.
    pub produced: i32,
    pub rejected: Vec<RejectedImuSample>,
    /// The estimate after the batch (null until the first window, about 2 s in).
    pub latest: Option<OdometryEstimate>,
}

/// Learned phone inertial odometry. Safe to call from several threads.
/// Learned phone inertial odometry. Experimental: for positions from a phone use
/// `PhoneNavigator`, more accurate on real walks (docs/odometry.md). The shipped model
/// is trained on real hand-held walks; other placements use its general regressor.
#[derive(Debug, uniffi::Object)]
pub struct PhoneOdometry {
    inner: Mutex<core::PhoneOdometry>,
}

impl PhoneOdometry {
    fn lock(&self) -> MutexGuard<'_, core::PhoneOdometry> {
        crate::error::lock(&self.inner)
    }

    fn wrap(engine: core::PhoneOdometry) -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(engine),
        })
    }
}

#[uniffi::export]
impl PhoneOdometry {
    /// An engine with the default configuration and the shipped model.
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Self::wrap(
            core::PhoneOdometry::shipped(core::OdometryConfig::default())
                .expect("the core default configuration and the shipped model are valid"),
        )
    }

    /// An engine with `config` and the shipped model.
    #[uniffi::constructor]
    pub fn new(config: OdometryConfig) -> Result<Arc<Self>, OdometryError> {
        guard(|| Ok(Self::wrap(core::PhoneOdometry::shipped(config.into())?)))
    }

    /// An engine with `config` and a model file written by `stridekit train odometry`.
    #[uniffi::constructor]
    pub fn with_model(
        config: OdometryConfig,
        model_text: String,
    ) -> Result<Arc<Self>, OdometryError> {
        guard(|| {
            let model = core::OdometryModel::parse(&model_text)?;
            Ok(Self::wrap(core::PhoneOdometry::new(config.into(), model)?))
        })
    }

    /// An engine continuing exactly where `snapshot()` was taken (the model travels
    /// inside the snapshot).
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, OdometryError> {
        guard(|| Ok(Self::wrap(core::PhoneOdometry::restore(&snapshot)?)))
    }

    /// Push IMU samples packed as 80-byte little-endian records of ten f64 `t_s,
    /// accel_x, accel_y, accel_z (m/s²), gyro_x, gyro_y, gyro_z (rad/s), mag_x, mag_y,
    /// mag_z (µT, NaN: none)` (`packImuSamples` builds them); bad samples are skipped
    /// and reported by index.
    pub fn push_imu_packed(&self, data: Vec<u8>) -> Result<OdometryBatchResult, OdometryError> {
        guard(|| {
            let samples =
                imu_samples(&data).map_err(|reason| OdometryError::InvalidBuffer { reason })?;
            let mut engine = self.lock();
            let b = push_each(samples, |s| engine.push(&s).map(|e| e.is_some()));
            Ok(OdometryBatchResult {
                accepted: b.accepted,
                produced: b.produced,
                rejected: b.rejected,
                latest: engine.estimate().map(Into::into),
            })
        })
    }

    /// The latest window's estimate (null before the first window).
    pub fn estimate(&self) -> Option<OdometryEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// Change where the placement comes from (takes effect at the next window).
    pub fn set_placement(&self, source: OdometryPlacementSource) {
        self.lock().set_placement(source.into())
    }

    /// The settings in use.
    pub fn config(&self) -> OdometryConfig {
        let c = *self.lock().config();
        OdometryConfig {
            placement: c.placement.into(),
            use_magnetometer: c.use_magnetometer,
            bias_correction: c.bias_correction,
        }
    }

    /// The embedded classifier's belief (`Auto` only; null before its first window).
    pub fn placement_estimate(&self) -> Option<PlacementEstimate> {
        self.lock().placement_estimate().map(Into::into)
    }

    /// The whole state as bytes (model and classifier included).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

/// The text of the odometry model that ships with the SDK (its comment lines say
/// how it was trained: on the simulator).
#[uniffi::export]
pub fn odometry_shipped_model() -> String {
    core::OdometryModel::shipped().to_text()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk() -> Vec<core::ImuSample> {
        use stridekit_sim::{simulate_phone, PhonePlacement as SimPlacement, PhoneScenario};
        let sim = simulate_phone(&PhoneScenario::walk(5, SimPlacement::InHand, 1.3, 30.0));
        sim.samples.iter().map(core::ImuSample::from).collect()
    }

    #[test]
    fn defaults_agree_with_the_core_and_a_walk_moves() {
        assert_eq!(
            core::OdometryConfig::from(odometry_config_default()),
            core::OdometryConfig::default()
        );
        let o = PhoneOdometry::with_defaults();
        assert!(o.estimate().is_none());
        let r = o
            .push_imu_packed(crate::packed::pack_imu(walk().into_iter()))
            .unwrap();
        assert!(r.rejected.is_empty());
        assert!(r.produced > 100, "{r:?}");
        let e = r.latest.unwrap();
        assert!(e.east_m.hypot(e.north_m) > 5.0, "{e:?}");
        let restored = PhoneOdometry::restore(o.snapshot()).unwrap();
        assert_eq!(restored.estimate(), o.estimate());
    }

    #[cfg(feature = "testing")]
    #[test]
    fn simulated_walk_reference_matches_a_packed_push() {
        use crate::testing::simulate_phone_walk;
        let w = simulate_phone_walk(3, PhonePlacement::Armband, 1.2, 20.0).unwrap();
        let o = PhoneOdometry::with_defaults();
        let r = o.push_imu_packed(w.imu_packed.clone()).unwrap();
        assert!(r.rejected.is_empty());
        assert_eq!(r.latest, w.reference_final);
        assert!(w.truth_distance_m > 15.0);
        assert!(simulate_phone_walk(3, PhonePlacement::Bag, f64::NAN, 20.0).is_err());
        assert!(simulate_phone_walk(3, PhonePlacement::Bag, 1.0, 1e9).is_err());
    }

    #[test]
    fn bad_input_is_typed() {
        let o = PhoneOdometry::with_defaults();
        assert!(matches!(
            o.push_imu_packed(vec![0; 79]),
            Err(OdometryError::InvalidBuffer { .. })
        ));
        let mut bad = walk()[..2].to_vec();
        bad[0].t_s = f64::NAN;
        let r = o
            .push_imu_packed(crate::packed::pack_imu(bad.into_iter()))
            .unwrap();
        assert_eq!(r.rejected.len(), 1);
        assert!(matches!(
            PhoneOdometry::with_model(odometry_config_default(), "nope".into()),
            Err(OdometryError::InvalidModel { .. })
        ));
        assert!(matches!(
            PhoneOdometry::restore(vec![0; 8]),
            Err(OdometryError::InvalidSnapshot { .. })
        ));
        assert!(
            PhoneOdometry::with_model(odometry_config_default(), odometry_shipped_model()).is_ok()
        );
    }
}
