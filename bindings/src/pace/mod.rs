//! Pace at the FFI: `PaceTracker` (GNSS fixes, step counts or cadence, raw
//! accelerometer) with its records and configuration.

pub mod tracker;
pub mod types;

pub use tracker::{BatchResult, PaceTracker, RejectedSample};
pub use types::{
    default_pace_config, pace_calibration_from_text, pace_calibration_to_text, AccelSample,
    AccelStepModel, GnssFix, PaceCalibration, PaceConfig, PaceEstimate, PaceFlags, PaceMode,
    PaceSample, PaceSource, StepSample,
};
