//! The named parts of the adaptive filter's state: the indices of its state vector,
//! a fix's position and time, a direction, the path window and the session's line.
//! See `super::snapshot` for how they are stored.

use nalgebra::{SMatrix, SVector};

use super::super::LocalFix;

pub(super) type V8 = SVector<f64, 8>;
pub(super) type M8 = SMatrix<f64, 8, 8>;

/// Indices of the state vector: position, velocity, correlated GNSS error (east,
/// north), level and slope of the step-length line.
pub(super) const PE: usize = 0;
pub(super) const PN: usize = 1;
pub(super) const VE: usize = 2;
pub(super) const VN: usize = 3;
pub(super) const BE: usize = 4;
pub(super) const BN: usize = 5;
pub(super) const LA: usize = 6;
pub(super) const LB: usize = 7;

/// What an update may teach the step-length line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Learn {
    Nothing,
    Level,
    LevelAndSlope,
}

impl Learn {
    pub(super) fn level_if(trusted: bool) -> Self {
        if trusted {
            Learn::Level
        } else {
            Learn::Nothing
        }
    }
}

/// A fix's position in the local ENU frame, metres, and its time, seconds (NaN: none).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct FixPoint {
    pub(super) east_m: f64,
    pub(super) north_m: f64,
    pub(super) t_s: f64,
}

impl FixPoint {
    pub(super) const NONE: Self = Self {
        east_m: f64::NAN,
        north_m: f64::NAN,
        t_s: f64::NAN,
    };

    pub(super) fn of(fix: &LocalFix) -> Self {
        Self {
            east_m: fix.east_m,
            north_m: fix.north_m,
            t_s: fix.t_s,
        }
    }
}

/// A unit vector in the horizontal ENU plane (NaN: none yet).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Direction {
    pub(super) east: f64,
    pub(super) north: f64,
}

impl Direction {
    pub(super) const NONE: Self = Self {
        east: f64::NAN,
        north: f64::NAN,
    };
}

/// GNSS path length and steps accumulated over a window, to observe step length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PathWindow {
    pub(super) active: bool,
    pub(super) start_t_s: f64,
    pub(super) start_steps: f64,
    /// Last fix used as a chord end.
    pub(super) anchor: FixPoint,
    pub(super) path_m: f64,
}

impl PathWindow {
    pub(super) const IDLE: Self = Self {
        active: false,
        start_t_s: 0.0,
        start_steps: 0.0,
        anchor: FixPoint {
            east_m: 0.0,
            north_m: 0.0,
            t_s: 0.0,
        },
        path_m: 0.0,
    };

    pub(super) fn start(fix: &LocalFix, steps: f64) -> Self {
        Self {
            active: true,
            start_t_s: fix.t_s,
            start_steps: steps,
            anchor: FixPoint::of(fix),
            path_m: 0.0,
        }
    }
}

/// Step-weighted sums over the accepted path windows of a session: the calibration's
/// level and cadence.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct SessionLine {
    /// Steps.
    pub(super) steps: f64,
    /// Steps × cadence (steps/s).
    pub(super) steps_x_cadence: f64,
    /// Steps × step length (m).
    pub(super) steps_x_length: f64,
}

/// Variance of the velocity along the unit vector (ue, un).
pub(super) fn along(p: &M8, ue: f64, un: f64) -> f64 {
    ue * ue * p[(VE, VE)] + 2.0 * ue * un * p[(VE, VN)] + un * un * p[(VN, VN)]
}
