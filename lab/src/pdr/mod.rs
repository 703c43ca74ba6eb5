//! Phone dead reckoning in the lab: the real indoor walks (reading, the four measures,
//! leave-one-floor-out calibration, diagnosis, the odometry trained on them), the
//! simulator evaluation and the calibration learner behind `stridekit calibrate pdr`.

pub mod calibrate;
pub mod diagnose;
pub mod legs;
pub mod maps;
pub mod mapsvg;
pub mod metrics;
pub mod odometry;
pub mod real;
pub mod shared;
pub mod sim;
pub mod walks;
