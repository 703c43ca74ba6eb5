//! Pedestrian dead reckoning with a phone: steps × step length × walking direction
//! ([`PhoneNavigator`]), built from the AHRS, the step detector, the step-length
//! estimator and the walking-direction estimator ([`WalkingDirection`]); the phone's
//! vertical motion over each step ([`VerticalHistory`]) gives the step length; GNSS
//! stretches cross-check it (`scale`).

mod calibration;
mod heading;
mod navigator;
mod scale;
mod vertical;

pub use calibration::{CalibrationError, PdrCalibration};
pub use heading::wrap;
pub use heading::WalkingDirection;
pub use navigator::{
    NavError, NavEstimate, NavStep, NavigatorConfig, PhoneNavigator, RECENT_STEPS,
};
pub use vertical::VerticalHistory;
