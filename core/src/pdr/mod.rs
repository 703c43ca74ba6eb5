//! Pedestrian dead reckoning with a phone: steps × step length × walking direction
//! (issue 3, in progress: the walking-direction estimator is here; the navigator that
//! ties AHRS, step detection, step length and GNSS together comes next).

pub mod heading;

pub use heading::WalkingDirection;
