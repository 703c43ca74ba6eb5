//! Why a floor plan or the map engine refused something: bad geometry (the plan is
//! not built), a start off the plan, a fix the plan cannot place, a snapshot that does
//! not belong to the plans given. Every refusal leaves the engine's state unchanged.

use crate::input::InputError;
use crate::pdr::NavError;
use crate::snapshot::SnapshotError;

/// Why a floor plan could not be built from its polygons.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// A coordinate is NaN or infinite.
    #[error("{what}: a coordinate is not a finite number")]
    NonFinite { what: String },
    /// A ring has fewer than 4 points (3 corners and the closing point).
    #[error("{what}: a ring needs at least 3 corners and its closing point, has {points} points")]
    TooFewPoints { what: String, points: usize },
    /// A ring's last point is not its first.
    #[error("{what}: the ring is not closed (its last point is not its first)")]
    OpenRing { what: String },
    /// A ring encloses no area (all its points on a line).
    #[error("{what}: the ring encloses no area")]
    NoArea { what: String },
    /// No walkable outline, or the outlines minus holes and obstacles leave nothing.
    #[error("the plan has no walkable area{}", if reason.is_empty() { String::new() } else { format!(": {reason}") })]
    NoWalkableArea { reason: String },
    /// The plan is larger than any building (or its numbers are not metres).
    #[error("the plan spans {extent_m:.0} m, more than the {max_m:.0} m a floor plan may (are the coordinates metres?)")]
    TooLarge { extent_m: f64, max_m: f64 },
    /// More corners than a floor plan holds.
    #[error("the plan has {points} points, more than the {max} a floor plan may")]
    TooManyPoints { points: usize, max: usize },
    /// The geographic reference is not usable (a latitude off the globe, an empty
    /// bounding box...).
    #[error("geographic reference: {reason}")]
    GeoReference { reason: String },
}

/// Why the map engine refused an input, a configuration, a start or a snapshot (its
/// state is unchanged).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MapError {
    /// The navigator under the engine refused the input or its configuration.
    #[error(transparent)]
    Nav(#[from] NavError),
    /// A fix or a start was refused at the door (see [`crate::input`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A setting of the map engine is not usable (the sentence names it).
    #[error("invalid map configuration: {reason}")]
    Config { reason: String },
    /// A start or a fix lies farther from the walkable area than it can be snapped.
    #[error("position ({x_m:.1}, {y_m:.1}) m is {distance_m:.1} m or more from the walkable area of floor {floor}")]
    OffPlan {
        x_m: f64,
        y_m: f64,
        distance_m: f64,
        floor: i32,
    },
    /// A fix names a floor no plan was given for.
    #[error("no plan for floor {floor}")]
    UnknownFloor { floor: i32 },
    /// A fix in latitude/longitude, but the plan has no geographic reference.
    #[error("floor {floor}'s plan has no geographic reference: give fixes in plan metres")]
    NoGeoReference { floor: i32 },
    /// Two plans were given for one floor.
    #[error("two plans for floor {floor}")]
    DuplicateFloor { floor: i32 },
    /// A snapshot could not be restored, or belongs to other plans.
    #[error("cannot restore map engine snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

impl MapError {
    pub(crate) fn config(reason: impl Into<String>) -> Self {
        MapError::Config {
            reason: reason.into(),
        }
    }
}
