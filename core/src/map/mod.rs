//! Positioning on a floor plan: the plan ([`FloorPlan`], built from polygons in
//! metres with a wall grid and a walkability raster) and the map-aware engine that
//! runs particles over the phone navigator's steps (see `docs/map.md`).

mod config;
mod declination;
mod error;
mod fix;
mod geometry;
mod georef;
mod grid;
mod matcher;
mod navigator;
mod particles;
mod plan;
mod raster;
mod smoother;
mod snapshot;

pub use config::{
    Declination, MapConfig, DEFAULT_HEADING_SIGMA_RAD, DEFAULT_HEADING_WALK_RAD_PER_SQRT_M,
    DEFAULT_PARTICLES, DEFAULT_SCALE_SIGMA, DEFAULT_SCALE_WALK_PER_SQRT_M, DEFAULT_SEED,
    DEFAULT_SMOOTHING_LAG_STEPS, DEFAULT_START_SIGMA_M, DEFAULT_STEP_HEADING_SIGMA_RAD,
    DEFAULT_STEP_LENGTH_SIGMA, DEFAULT_WALL_CROSSING_WEIGHT, MAX_PARTICLES,
    MAX_SMOOTHING_LAG_STEPS, MIN_PARTICLES,
};
pub use declination::declination_rad;
pub use error::{MapError, PlanError};
pub use fix::{FixPosition, MapFix};
pub use geometry::{PlanGeometry, Polygon, Ring, MAX_PLAN_EXTENT_M, MAX_PLAN_POINTS};
pub use georef::GeoReference;
pub use grid::{Wall, DEFAULT_WALL_CELL_M};
pub use matcher::{
    MapFlags, MapMatcher, MatchState, AMBIGUOUS_RADIUS_M, AMBIGUOUS_SHARE, CONVERGED_STD_M,
    MAX_START_SNAP_M,
};
pub use navigator::{MapEstimate, MapNavigator};
pub use plan::FloorPlan;
pub use raster::DEFAULT_RASTER_CELL_M;
pub use smoother::SmoothedPoint;
