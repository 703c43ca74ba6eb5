//! Absolute fixes from any source (GNSS, the app's WiFi/BLE positions, a manual
//! check-in), in latitude/longitude or plan metres, with their accuracy and
//! optionally a floor: checked at the door, held until the steps up to their time are
//! placed, then weighed against every particle. A fix no particle explains is held
//! back; a second one that agrees with it moves the walker there.

use crate::input::{self, InputError, Stream};
use crate::stats::RADIUS68_TO_SIGMA;

/// Smallest per-axis σ of a fix, m (no source places a walker closer).
pub(crate) const MIN_FIX_SIGMA_M: f64 = 0.5;
/// A fix waits at most this long for the steps up to its time to be placed, s (the
/// step detector releases steps up to about 2 s late).
pub(crate) const MAX_FIX_WAIT_S: f64 = 2.5;
/// A fix is explained when the weighted mean of its likelihood over the particles
/// reaches that of a particle 3.5 σ away (exp(−3.5²/2)).
pub(crate) const FIX_EXPLAINED_LIKELIHOOD: f64 = 2.187e-3;
/// Likelihood floor of a particle against an explained fix (a fix is wrong now and
/// then: it lowers weights, it never rules a particle out).
pub(crate) const FIX_OUTLIER_FLOOR: f64 = 1e-3;
/// Largest |plan coordinate| of a fix, m.
const MAX_PLAN_FIX_M: f64 = 1.0e5;

/// Where a fix says the walker is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FixPosition {
    /// WGS84 degrees (the plan's geographic reference places it).
    LatLon { lat_deg: f64, lon_deg: f64 },
    /// Plan metres.
    Plan { x_m: f64, y_m: f64 },
}

/// An absolute position fix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapFix {
    /// Time on the IMU samples' clock, s.
    pub t_s: f64,
    pub position: FixPosition,
    /// Horizontal accuracy, m: the 68 % radius, as Android's `Location.getAccuracy()`
    /// and iOS's `horizontalAccuracy` report it.
    pub accuracy_m: f64,
    /// The floor the fix is on, when its source knows.
    pub floor: Option<i32>,
}

impl MapFix {
    /// A fix in plan metres.
    pub fn plan(t_s: f64, x_m: f64, y_m: f64, accuracy_m: f64) -> Self {
        Self {
            t_s,
            position: FixPosition::Plan { x_m, y_m },
            accuracy_m,
            floor: None,
        }
    }

    /// A fix in WGS84 degrees.
    pub fn lat_lon(t_s: f64, lat_deg: f64, lon_deg: f64, accuracy_m: f64) -> Self {
        Self {
            t_s,
            position: FixPosition::LatLon { lat_deg, lon_deg },
            accuracy_m,
            floor: None,
        }
    }

    /// The input layer's checks: time (finite, seconds, after `last_t_s`), position
    /// and accuracy in range.
    pub(crate) fn check(&self, last_t_s: Option<f64>) -> Result<(), InputError> {
        // Fixes may come minutes apart (a check-in): the stream's order and units are
        // checked, not its rate.
        input::time_after(Stream::Gnss, self.t_s, last_t_s)?;
        match self.position {
            FixPosition::LatLon { lat_deg, lon_deg } => {
                input::gnss(lat_deg, lon_deg, None, Some(self.accuracy_m), None, None)?
            }
            FixPosition::Plan { x_m, y_m } => {
                input::in_range("x_m", x_m, -MAX_PLAN_FIX_M, MAX_PLAN_FIX_M, "m")?;
                input::in_range("y_m", y_m, -MAX_PLAN_FIX_M, MAX_PLAN_FIX_M, "m")?;
                input::in_range(
                    "horizontal_accuracy_m",
                    self.accuracy_m,
                    0.0,
                    input::limits::MAX_ACCURACY_M,
                    "m",
                )?;
            }
        }
        Ok(())
    }

    /// Per-axis σ, m.
    pub(crate) fn sigma_m(&self) -> f64 {
        (self.accuracy_m * RADIUS68_TO_SIGMA).max(MIN_FIX_SIGMA_M)
    }
}

/// A fix placed on a plan, waiting for its steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct PendingFix {
    pub(crate) t_s: f64,
    pub(crate) x_m: f64,
    pub(crate) y_m: f64,
    pub(crate) sigma_m: f64,
}
