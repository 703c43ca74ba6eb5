//! Foot-mounted inertial navigation (method 2 of docs/architecture.md; OpenShoe / pyshoe lineage):
//! [`FootNavigator`] runs a sliding median pre-filter, a zero-velocity detector
//! ([`ZeroVelocityDetector`]: fixed thresholds, gait-adaptive thresholds, SVM, SVM
//! while walking + adaptive thresholds when running, SHOE),
//! strapdown mechanisation in a local level ENU frame and a 15-state error-state
//! Kalman filter with zero-velocity updates. See `docs/foot.md`.

pub mod config;
pub mod detect;
mod ekf;
pub mod error;
mod median;
pub mod navigator;
pub mod svm;
pub mod types;

pub use config::{Correction, FootConfig, GyroTiming};
pub use detect::{
    AdaptiveShoe, AdaptiveThresholds, FixedThresholds, Gait, ShoeDetector, SvmAdaptive,
    WindowStats, ZeroVelocityDetector,
};
pub use error::FootError;
pub use navigator::{FootNavigator, FootRejection};
pub use svm::SvmModel;
pub use types::{FootEstimate, FootSample, Stride};
