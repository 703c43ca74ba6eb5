//! Learned phone inertial odometry (method 4 of docs/architecture.md, a RIDI-style pipeline:
//! Yan, Shan, Furukawa, "RIDI: Robust IMU Double Integration", ECCV 2018). Experimental:
//! on real indoor walks the PDR (`pdr::PhoneNavigator`) is more accurate (docs/odometry.md).
//!
//! Data flows one way, one small stage per file:
//! - `sample`: the IMU sample and the checks at the door;
//! - `stabilise`: AHRS attitude → angular rate and linear acceleration in ENU,
//!   and the yaw of the stabilised frame S;
//! - `resample`: onto the model's rate; `smooth`: Gaussian FIR (documented delay);
//! - `features`: fixed-capacity window ring and the engineered features in S;
//! - `model`: one velocity regressor per placement class (+ general), the model file;
//! - `bias`: the low-frequency acceleration-bias correction over a sliding block;
//! - `engine`: [`PhoneOdometry`], which chains them, picks the regressor from the
//!   [`PlacementSource`] (default: the embedded placement classifier) and integrates
//!   the position;
//! - `baseline`: naive double integration (fixed or AHRS orientation);
//! - `metrics`: ATE / RTE (RoNIN's definitions); `train`: fitting on the simulator.
//!
//! No allocation per sample after construction; snapshot engine kind 8.

// Small fixed-size numeric loops read better with indices.
#![allow(clippy::needless_range_loop)]

mod bias;
mod engine;
mod error;
mod features;
mod model;
mod resample;
mod sample;
mod smooth;
mod stabilise;

pub use bias::BiasCorrector;
pub use engine::{
    OdometryConfig, OdometryEstimate, OdometryRejection, PhoneOdometry, PlacementSource,
    AUTO_MIN_CONFIDENCE,
};
pub use error::OdometryError;
pub use features::WindowFeatures;
/// Pieces the odometry trainer and baselines (`stridekit-lab`) build on.
pub use features::{FeatureWindow, N_SCALAR, N_VECTOR};
pub use model::{placement_from_name, slot};
pub use model::{OdometryModel, PipelineParams, Regressor};
pub use sample::ImuSample;
pub use stabilise::rotate;
