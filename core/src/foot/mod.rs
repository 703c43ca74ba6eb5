//! Foot-mounted inertial navigation (method 2 of docs/architecture.md; OpenShoe / pyshoe lineage):
//! [`FootNavigator`] runs a sliding median pre-filter, a zero-velocity detector
//! ([`ZeroVelocityDetector`]: fixed thresholds, gait-adaptive thresholds, SVM, SVM
//! while walking + adaptive thresholds when running, SHOE),
//! strapdown mechanisation in a local level ENU frame and a 15-state error-state
//! Kalman filter with zero-velocity updates. See `docs/foot.md`.

mod accel_clip;
mod ceiling;
mod clip;
mod config;
mod detect;
mod ekf;
mod error;
mod hole;
mod median;
mod navigator;
mod still;
mod svm;
mod types;
mod unresolved;
mod zaru;

pub use accel_clip::{
    AccelCeilingDetector, LEVEL_SHARE as ACCEL_LEVEL_SHARE, MAX_PEAK_SHARE, MIN_ACCEL_CEILING_MPS2,
    MIN_CLIP_HITS, UNKNOWN_SHARE,
};
pub use ceiling::{
    GyroCeiling, GyroCeilingDetector, ABOVE_SHARE, FLAT_SHARE, LEVEL_SHARE, MIN_CEILING_RADS,
    MIN_FLAT_SAMPLES, MIN_FLAT_TOPS, SHARPNESS,
};
pub use clip::AT_RANGE;
pub use config::{
    Correction, FootConfig, GyroTiming, LEVEL_STRIDE_MAX_GRADE, MAX_ACCEL_ALIGNMENT_RAD,
    MAX_LEVEL_STRIDE_GRADE, ZUPT_GATE_NIS,
};
pub use detect::{
    AdaptiveShoe, AdaptiveThresholds, FixedThresholds, Gait, ShoeDetector, SvmAdaptive,
    WindowStats, ZeroVelocityDetector, STILL_FLOOR_MARGIN, STILL_WINDOW_S,
};
pub use error::FootError;
pub use navigator::{FootNavigator, FootRejection};
pub use svm::SvmModel;
/// The SVM pieces the zero-velocity trainer (`stridekit-lab`) builds a model from.
pub use svm::{PairSvm, SIGMA_EPS};
pub use types::{FootEstimate, FootSample, Stride};
