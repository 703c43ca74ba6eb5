//! Orientation (attitude and heading reference system, AHRS) from a phone's or
//! watch's gyroscope, accelerometer and optional magnetometer (method 4, seed 003:
//! Madgwick's filter, used to rotate accelerations into the earth frame and remove
//! gravity).
//!
//! [`Ahrs`] is Madgwick's gradient-descent filter ([`madgwick`]) with the robustness
//! of x-io Technologies' Fusion library: a settings struct with named defaults
//! ([`settings`]), a fast initialisation phase, acceleration and magnetic rejection
//! with recovery, angular-rate recovery, gyroscope bias learning at rest ([`bias`]),
//! and readable flags ([`flags`]) telling why the filter did what it did. The earth
//! frame (ENU or NED) and a sensor-axis remap are chosen in [`frame`].
//!
//! Inputs are checked at the door (finite numbers, increasing time, accelerations in
//! m/s² rather than g); a rejected sample returns an [`AhrsError`] and leaves the
//! state exactly as it was. An update allocates nothing; the state snapshots to
//! bytes and restores bit-exactly.

pub mod bias;
pub mod error;
pub mod flags;
pub mod frame;
pub mod madgwick;
pub mod output;
pub(crate) mod quat;
pub mod settings;

pub use error::AhrsError;
pub use flags::AhrsFlags;
pub use frame::{AxisRemap, EarthFrame};
pub use madgwick::Ahrs;
pub use output::{AhrsOutput, AhrsRejection, ImuSample};
pub use settings::{AhrsSettings, MAX_GAP_LIMIT_S};
