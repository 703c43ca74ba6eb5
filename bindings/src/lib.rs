//! stridekit: the uniffi (Kotlin, Swift) face of `stridekit-core`.
//!
//! This crate only adapts: records mirror the core types field by field, objects wrap
//! the core engines behind a [`std::sync::Mutex`], and every call that can fail
//! returns a [`PaceError`] (Kotlin `PaceException`, Swift `PaceError`). No panic
//! crosses the FFI: calls returning `Result` catch panics into
//! [`PaceError::Internal`]; batch pushes report a panicking sample as rejected; the
//! rest are caught by uniffi's own scaffolding (Kotlin `InternalException`).
//!
//! Kotlin, as an app writes it:
//!
//! ```kotlin
//! val tracker = PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE))
//! tracker.pushStepSamples(listOf(StepSample.Count(tS = 0.5, steps = 1200L)))
//! val result = tracker.pushFixes(listOf(GnssFix(tS = 1.0, latDeg = 50.29, lonDeg = 18.67)))
//! val pace = result.latest.paceSPerKm
//! val saved: ByteArray = tracker.snapshot()        // later: PaceTracker.restore(saved)
//! ```
//!
//! The other engines follow the same pattern with their own error type:
//! [`phone::navigator::PhoneNavigator`] (`NavError`), [`foot::FootNavigator`] (`FootError`,
//! Kotlin `FootException`; packed 56-byte IMU records, see the [`packed`] module docs),
//! [`phone::placement::PlacementClassifier`] (`PlacementError`), [`phone::odometry::PhoneOdometry`]
//! (`OdometryError`) and [`phone::orientation::OrientationFilter`] (`OrientationError`). On Android, `init_android_logging(level)` sends the SDK's `log`
//! records to logcat (a no-op elsewhere).

uniffi::setup_scaffolding!();

mod error;
pub mod foot;
mod logging;
pub mod map;
pub mod pace;
pub mod packed;
pub mod phone;
#[cfg(feature = "testing")]
pub mod testing;

pub use error::{PaceError, SensorStream};
pub use foot::{FootConfig, FootError, FootEstimate, FootNavigator};
pub use logging::{init_android_logging, LogLevel};
pub use pace::{
    default_pace_config, pace_calibration_from_text, pace_calibration_to_text, AccelSample,
    AccelStepModel, BatchResult, GnssFix, PaceCalibration, PaceConfig, PaceEstimate, PaceFlags,
    PaceMode, PaceSample, PaceSource, PaceTracker, RejectedSample, StepSample,
};
pub use packed::{ImuEvent, ImuSample};
