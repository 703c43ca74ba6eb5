//! The phone engines at the FFI: dead reckoning (`PhoneNavigator`), learned odometry
//! (`PhoneOdometry`), orientation (`OrientationFilter`) and placement
//! (`PlacementClassifier`). The first three take the SDK's one `ImuSample` record
//! packed in the 80-byte (9-axis) layout of [`crate::packed`].

pub mod navigator;
pub mod odometry;
pub mod orientation;
pub mod placement;
