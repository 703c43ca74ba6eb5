//! Learned phone inertial odometry (method 4 of docs/architecture.md, a RIDI-style pipeline:
//! Yan, Shan, Furukawa, "RIDI: Robust IMU Double Integration", ECCV 2018).
//!
//! Data flows one way, one small stage per file:
//! - [`sample`]: the IMU sample and the checks at the door;
//! - [`stabilise`]: AHRS attitude → angular rate and linear acceleration in ENU,
//!   and the yaw of the stabilised frame S;
//! - [`resample`]: onto the model's rate; [`smooth`]: Gaussian FIR (documented delay);
//! - [`features`]: fixed-capacity window ring and the engineered features in S;
//! - [`model`]: one velocity regressor per placement class (+ general), the model file;
//! - [`bias`]: the low-frequency acceleration-bias correction over a sliding block;
//! - [`engine`]: [`PhoneOdometry`], which chains them, picks the regressor from the
//!   [`PlacementSource`] (default: the embedded placement classifier) and integrates
//!   the position;
//! - [`baseline`]: naive double integration (fixed or AHRS orientation);
//! - [`metrics`]: ATE / RTE (RoNIN's definitions); [`train`]: fitting on the simulator.
//!
//! No allocation per sample after construction; snapshot engine kind 8.

// Small fixed-size numeric loops read better with indices.
#![allow(clippy::needless_range_loop)]

pub mod bias;
pub mod engine;
pub mod error;
pub mod features;
pub mod model;
pub mod resample;
pub mod sample;
pub mod smooth;
pub mod stabilise;

pub use engine::{
    OdometryConfig, OdometryEstimate, OdometryRejection, PhoneOdometry, PlacementSource,
    AUTO_MIN_CONFIDENCE,
};
pub use error::OdometryError;
pub use features::WindowFeatures;
pub use model::{OdometryModel, PipelineParams, Regressor};
pub use sample::ImuSample;
