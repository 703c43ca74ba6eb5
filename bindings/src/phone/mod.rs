//! The phone engines at the FFI: dead reckoning (`PhoneNavigator`), learned odometry
//! (`PhoneOdometry`), orientation (`OrientationFilter`) and placement
//! (`PlacementClassifier`). They share the packed 80-byte IMU record of
//! [`navigator`].

pub mod navigator;
pub mod odometry;
pub mod orientation;
pub mod placement;
