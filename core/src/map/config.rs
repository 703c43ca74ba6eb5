//! Settings of the map engine ([`MapConfig`]): how many particles, how the heading
//! offset and the step scale of each may wander, how sure a start is, where the
//! magnetic declination comes from. One configuration for every walk and building.

use crate::pdr::NavigatorConfig;

use super::error::MapError;

/// Particles at the default cost (about 0.1 µs each per step on a phone core).
pub const DEFAULT_PARTICLES: usize = 1000;
/// Fewest and most particles a configuration may ask for.
pub const MIN_PARTICLES: usize = 16;
pub const MAX_PARTICLES: usize = 20_000;
/// Seed of the engine's random numbers (any value; the same seed, the same track).
pub const DEFAULT_SEED: u64 = 0x5354_5249_4445;
/// σ of a start position given without one, m (an entrance or a check-in point).
pub const DEFAULT_START_SIGMA_M: f64 = 1.0;
/// Prior spread of the heading offset, rad: a phone's magnetic heading indoors is off
/// by about ±10° (interquartile) from walk to walk (docs/phone.md), σ ≈ 15°.
pub const DEFAULT_HEADING_SIGMA_RAD: f64 = 15.0 * std::f64::consts::PI / 180.0;
/// Random walk of the heading offset, rad per √m walked: a calibrated gyroscope's
/// residual drift and the slow magnetic loop's wander.
pub const DEFAULT_HEADING_WALK_RAD_PER_SQRT_M: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// Direction noise of one step, rad (the sway of a single step's azimuth).
pub const DEFAULT_STEP_HEADING_SIGMA_RAD: f64 = 4.0 * std::f64::consts::PI / 180.0;
/// Prior spread of the step-length scale. A walk's distance is off by 8.6 % robust sd
/// (docs/phone.md), but the walls see the scale only at corridor ends: a prior that
/// wide lets particles take scales that fit the walls by chance (0.10 → 0.05: live
/// map-frame RMSE 2.10 / 4.83 → 2.06 / 4.74 m, leave one floor out 2.09 / 4.83 →
/// 2.08 / 4.64 m; docs/lab/2026-12-06-map.md).
pub const DEFAULT_SCALE_SIGMA: f64 = 0.05;
/// Random walk of the step-length scale, per √m walked.
pub const DEFAULT_SCALE_WALK_PER_SQRT_M: f64 = 0.003;
/// Length noise of one step, relative.
pub const DEFAULT_STEP_LENGTH_SIGMA: f64 = 0.08;
/// Jitter of the heading offset and the scale of resampled particles (rad, relative):
/// copies of one particle become hypotheses of their own.
pub const DEFAULT_ROUGHEN_HEADING_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;
pub const DEFAULT_ROUGHEN_SCALE: f64 = 0.005;
/// Weight a particle keeps when its step crosses a wall (0: ruled out). Above 0 it
/// allows doors and gaps the plan does not draw, at that much less belief.
pub const DEFAULT_WALL_CROSSING_WEIGHT: f64 = 0.0;
/// Steps behind the newest that the smoothed path may still correct.
pub const DEFAULT_SMOOTHING_LAG_STEPS: usize = 64;
/// Most steps of smoothing lag a configuration may ask for.
pub const MAX_SMOOTHING_LAG_STEPS: usize = 256;

/// Where the magnetic declination (true north minus magnetic north) comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Declination {
    /// From the plan's position on the globe (or a latitude/longitude fix), by the
    /// built-in geomagnetic model; none without either.
    Auto,
    /// The app's own value, rad, east positive (Android `GeomagneticField`, iOS
    /// `CLHeading` true minus magnetic).
    Fixed(f64),
    /// Headings are used as they come (a plan drawn to magnetic north, or tests).
    Off,
}

/// Configuration of a [`super::MapNavigator`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapConfig {
    /// The dead reckoning under the particles.
    pub navigator: NavigatorConfig,
    pub particles: usize,
    pub seed: u64,
    pub start_sigma_m: f64,
    pub heading_sigma_rad: f64,
    pub heading_walk_rad_per_sqrt_m: f64,
    pub step_heading_sigma_rad: f64,
    pub scale_sigma: f64,
    pub scale_walk_per_sqrt_m: f64,
    pub step_length_sigma: f64,
    pub wall_crossing_weight: f64,
    pub roughen_heading_rad: f64,
    pub roughen_scale: f64,
    pub smoothing_lag_steps: usize,
    pub declination: Declination,
}

impl Default for MapConfig {
    fn default() -> Self {
        Self {
            navigator: NavigatorConfig::default(),
            particles: DEFAULT_PARTICLES,
            seed: DEFAULT_SEED,
            start_sigma_m: DEFAULT_START_SIGMA_M,
            heading_sigma_rad: DEFAULT_HEADING_SIGMA_RAD,
            heading_walk_rad_per_sqrt_m: DEFAULT_HEADING_WALK_RAD_PER_SQRT_M,
            step_heading_sigma_rad: DEFAULT_STEP_HEADING_SIGMA_RAD,
            scale_sigma: DEFAULT_SCALE_SIGMA,
            scale_walk_per_sqrt_m: DEFAULT_SCALE_WALK_PER_SQRT_M,
            step_length_sigma: DEFAULT_STEP_LENGTH_SIGMA,
            wall_crossing_weight: DEFAULT_WALL_CROSSING_WEIGHT,
            roughen_heading_rad: DEFAULT_ROUGHEN_HEADING_RAD,
            roughen_scale: DEFAULT_ROUGHEN_SCALE,
            smoothing_lag_steps: DEFAULT_SMOOTHING_LAG_STEPS,
            declination: Declination::Auto,
        }
    }
}

impl MapConfig {
    /// Refuse settings no walk could use.
    pub fn validate(&self) -> Result<(), MapError> {
        if !(MIN_PARTICLES..=MAX_PARTICLES).contains(&self.particles) {
            return Err(MapError::config(format!(
                "particles = {}: must be {MIN_PARTICLES}..={MAX_PARTICLES}",
                self.particles
            )));
        }
        if !(1..=MAX_SMOOTHING_LAG_STEPS).contains(&self.smoothing_lag_steps) {
            return Err(MapError::config(format!(
                "smoothing_lag_steps = {}: must be 1..={MAX_SMOOTHING_LAG_STEPS}",
                self.smoothing_lag_steps
            )));
        }
        let pi = std::f64::consts::PI;
        let checks = [
            ("start_sigma_m", self.start_sigma_m, 0.0, 1_000.0),
            ("heading_sigma_rad", self.heading_sigma_rad, 0.0, pi),
            (
                "heading_walk_rad_per_sqrt_m",
                self.heading_walk_rad_per_sqrt_m,
                0.0,
                1.0,
            ),
            (
                "step_heading_sigma_rad",
                self.step_heading_sigma_rad,
                0.0,
                1.0,
            ),
            ("scale_sigma", self.scale_sigma, 0.0, 0.5),
            (
                "scale_walk_per_sqrt_m",
                self.scale_walk_per_sqrt_m,
                0.0,
                0.1,
            ),
            ("step_length_sigma", self.step_length_sigma, 0.0, 0.5),
            ("wall_crossing_weight", self.wall_crossing_weight, 0.0, 1.0),
            ("roughen_heading_rad", self.roughen_heading_rad, 0.0, 0.5),
            ("roughen_scale", self.roughen_scale, 0.0, 0.1),
        ];
        for (name, v, lo, hi) in checks {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(MapError::config(format!(
                    "{name} = {v}: must be {lo}..={hi}"
                )));
            }
        }
        if let Declination::Fixed(d) = self.declination {
            if !(d.is_finite() && d.abs() <= pi) {
                return Err(MapError::config(format!(
                    "declination = {d} rad: must be within ±π"
                )));
            }
        }
        Ok(())
    }
}
