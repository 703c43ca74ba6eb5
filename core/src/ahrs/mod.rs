//! Orientation (attitude and heading reference system, AHRS) from a phone's or
//! watch's gyroscope, accelerometer and optional magnetometer.
//!
//! [`Ahrs`] (`engine`) is the one orientation engine of stridekit: it checks every
//! sample at the door (`door`: finite numbers, increasing time, accelerations in
//! m/s² rather than g; a rejected sample returns an [`AhrsError`] and leaves the state
//! exactly as it was), runs the filter chosen by [`AhrsSettings::algorithm`], and
//! derives gravity, linear acceleration, Euler angles and heading (`output`):
//! - [`AhrsAlgorithm::Decoupled`], the default (`decoupled`): inclination from the
//!   accelerometer averaged in an almost-inertial frame, heading from the
//!   magnetometer on its own with disturbance rejection and recovery, gyroscope bias
//!   learned at rest and in motion. Measured against optical motion capture in
//!   `docs/orientation.md`.
//! - [`AhrsAlgorithm::Madgwick`] (`madgwick`): Madgwick's gradient-descent filter
//!   with the robustness of x-io's Fusion (initialisation, acceleration and magnetic
//!   rejection with recovery, gyroscope bias at rest, `bias`);
//!   [`AhrsSettings::plain`] is the filter of the paper.
//!
//! Settings are a plain struct with named defaults (`settings`); flags tell why the
//! filter did what it did (`flags`). The earth frame (ENU or NED) and a sensor-axis
//! remap are chosen in `frame`. An update allocates nothing; the state snapshots to
//! bytes and restores bit-exactly.

mod bias;
mod decoupled;
mod door;
mod engine;
mod error;
pub(crate) mod field;
mod flags;
mod frame;
mod madgwick;
mod output;
pub(crate) mod quat;
mod settings;

pub use decoupled::DecoupledSettings;
/// The named defaults of the decoupled filter's settings.
pub mod decoupled_defaults {
    pub use super::decoupled::{
        DEFAULT_ACCEL_TIME_CONSTANT_S, DEFAULT_BIAS_RANDOM_WALK,
        DEFAULT_HEADING_BIAS_TIME_CONSTANT_S, DEFAULT_MAG_DIP_THRESHOLD_RAD,
        DEFAULT_MAG_MAX_REJECTION_S, DEFAULT_MAG_MIN_UNDISTURBED_S, DEFAULT_MAG_NORM_THRESHOLD,
        DEFAULT_MAG_OFFSET_MAX_UT, DEFAULT_MAG_TIME_CONSTANT_S, DEFAULT_MAX_BIAS_RADS,
        DEFAULT_MOTION_BIAS_ACCURACY_RADS, DEFAULT_MOTION_BIAS_TIME_CONSTANT_S,
        DEFAULT_REST_ACCEL_MPS2, DEFAULT_REST_BIAS_TIME_CONSTANT_S, DEFAULT_REST_GYRO_RADS,
        DEFAULT_REST_TIME_S,
    };
}
pub use engine::Ahrs;
pub use error::AhrsError;
pub use flags::AhrsFlags;
pub use frame::{AxisRemap, EarthFrame};
pub use output::{AhrsOutput, AhrsRejection, ImuSample};
pub use settings::{AhrsAlgorithm, AhrsSettings, MAX_GAP_LIMIT_S};
