//! stridekit-core: sensor-fusion engines for running pace and pedestrian navigation.
//!
//! Pure Rust, no FFI types, no I/O. Conventions used everywhere:
//! - time: f64 seconds on the app's monotonic clock (`t_s`);
//! - SI units, named in fields (`_m`, `_mps`, `_rad`, `_deg` where degrees are the norm);
//! - local frames are East-North-Up (ENU) unless a type says otherwise.
//!
//! Every engine checks its inputs at the door and returns typed errors; none panics
//! on bad input. Every engine can be snapshotted to bytes and restored.

pub mod ahrs;
pub mod angle;
pub mod batch;
pub mod calibration;
pub mod foot;
pub mod geo;
pub mod imu;
pub mod input;
pub mod map;
mod model_text;
pub mod odometry;
pub mod pace;
pub mod pdr;
pub mod placement;
pub mod rng;
pub mod signal;
pub mod snapshot;
pub mod stats;
pub mod stepdetect;
pub mod steplength;
pub mod vec3;

// What apps use, at the crate root: each engine with its configuration, sample,
// estimate and error (the domain modules hold the rest of their surface).
pub use ahrs::{Ahrs, AhrsError, AhrsOutput, AhrsSettings, ImuSample};
pub use batch::{Batch, Rejected};
pub use foot::{FootConfig, FootError, FootEstimate, FootNavigator, FootSample};
pub use input::InputError;
pub use odometry::{OdometryConfig, OdometryError, OdometryEstimate, PhoneOdometry};
pub use pace::{
    AccelStepModel, GnssFix, PaceCalibration, PaceConfig, PaceError, PaceEstimate, PaceFlags,
    PaceMode, PaceSample, PaceSource, PaceTracker, Rejection, StepSample,
};
pub use pdr::{NavError, NavEstimate, NavigatorConfig, PdrCalibration, PhoneNavigator};
pub use placement::{PlacementClassifier, PlacementError, PlacementEstimate};
pub use stepdetect::{
    AccelSample, StepDetectError, StepDetector, StepDetectorConfig, StepEvent, StepOrigin,
};
pub use steplength::{StepLengthConfig, StepLengthError, StepLengthEstimator, StepLengthModel};
