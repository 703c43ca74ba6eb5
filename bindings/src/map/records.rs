//! The map engine's records at the FFI, field by field the core's (units in the
//! names, plan metres x east / y north); the literal defaults are the core's, pinned
//! by a test.

use stridekit_core::map as core;

use super::error::MapError;
use crate::phone::navigator::NavigatorConfig;

/// Where the magnetic declination (true north minus magnetic north) comes from.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Enum)]
pub enum MapDeclination {
    /// From the plan's place on the globe by the built-in geomagnetic model (WMM2025).
    Auto,
    /// The app's own value, radians, east positive (Android `GeomagneticField`).
    Fixed { rad: f64 },
    /// Headings used as they come.
    Off,
}

/// Configuration of a `MapNavigator`: `mapConfigDefault()` gives
/// the default; see the core's `MapConfig` for what each setting does.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct MapConfig {
    /// The dead reckoning under the particles (default: `navigatorConfigDefault()`).
    pub navigator: NavigatorConfig,
    /// Hypotheses (16..=20 000).
    #[uniffi(default = 1000)]
    pub particles: i32,
    /// Seed of the random numbers (the same seed, the same track).
    #[uniffi(default = 91_621_622_891_589)]
    pub seed: u64,
    /// σ of a start given without one, m.
    #[uniffi(default = 1.0)]
    pub start_sigma_m: f64,
    /// Prior spread of the heading offset, rad (15°).
    #[uniffi(default = 0.2617993877991494)]
    pub heading_sigma_rad: f64,
    /// Random walk of the heading offset, rad per √m (0.5°).
    #[uniffi(default = 0.008726646259971648)]
    pub heading_walk_rad_per_sqrt_m: f64,
    /// Direction noise of one step, rad (4°).
    #[uniffi(default = 0.06981317007977318)]
    pub step_heading_sigma_rad: f64,
    /// Prior spread of the step-length scale.
    #[uniffi(default = 0.05)]
    pub scale_sigma: f64,
    /// Random walk of the step-length scale, per √m.
    #[uniffi(default = 0.003)]
    pub scale_walk_per_sqrt_m: f64,
    /// Length noise of one step, relative.
    #[uniffi(default = 0.08)]
    pub step_length_sigma: f64,
    /// Weight a particle keeps when its step crosses a wall (0: ruled out).
    #[uniffi(default = 0.0)]
    pub wall_crossing_weight: f64,
    /// Jitter of resampled heading offsets, rad (3°), and scales.
    #[uniffi(default = 0.05235987755982988)]
    pub roughen_heading_rad: f64,
    #[uniffi(default = 0.005)]
    pub roughen_scale: f64,
    /// Steps the smoothed path may still correct behind the newest.
    #[uniffi(default = 64)]
    pub smoothing_lag_steps: i32,
    /// Where the declination comes from (default `Auto`).
    pub declination: MapDeclination,
}

impl From<&core::MapConfig> for MapConfig {
    fn from(c: &core::MapConfig) -> Self {
        let core::MapConfig {
            navigator,
            particles,
            seed,
            start_sigma_m,
            heading_sigma_rad,
            heading_walk_rad_per_sqrt_m,
            step_heading_sigma_rad,
            scale_sigma,
            scale_walk_per_sqrt_m,
            step_length_sigma,
            wall_crossing_weight,
            roughen_heading_rad,
            roughen_scale,
            smoothing_lag_steps,
            declination,
        } = *c;
        Self {
            navigator: (&navigator).into(),
            particles: i32::try_from(particles).unwrap_or(i32::MAX),
            seed,
            start_sigma_m,
            heading_sigma_rad,
            heading_walk_rad_per_sqrt_m,
            step_heading_sigma_rad,
            scale_sigma,
            scale_walk_per_sqrt_m,
            step_length_sigma,
            wall_crossing_weight,
            roughen_heading_rad,
            roughen_scale,
            smoothing_lag_steps: i32::try_from(smoothing_lag_steps).unwrap_or(i32::MAX),
            declination: match declination {
                core::Declination::Auto => MapDeclination::Auto,
                core::Declination::Fixed(rad) => MapDeclination::Fixed { rad },
                core::Declination::Off => MapDeclination::Off,
            },
        }
    }
}

impl TryFrom<MapConfig> for core::MapConfig {
    type Error = MapError;
    fn try_from(c: MapConfig) -> Result<Self, MapError> {
        let MapConfig {
            navigator,
            particles,
            seed,
            start_sigma_m,
            heading_sigma_rad,
            heading_walk_rad_per_sqrt_m,
            step_heading_sigma_rad,
            scale_sigma,
            scale_walk_per_sqrt_m,
            step_length_sigma,
            wall_crossing_weight,
            roughen_heading_rad,
            roughen_scale,
            smoothing_lag_steps,
            declination,
        } = c;
        let count = |v: i32, what: &str| {
            usize::try_from(v).map_err(|_| MapError::InvalidConfig {
                reason: format!("{what} = {v}: must be positive"),
            })
        };
        let out =
            Self {
                navigator: navigator.try_into().map_err(
                    |e: crate::phone::navigator::NavError| MapError::InvalidConfig {
                        reason: e.to_string(),
                    },
                )?,
                particles: count(particles, "particles")?,
                seed,
                start_sigma_m,
                heading_sigma_rad,
                heading_walk_rad_per_sqrt_m,
                step_heading_sigma_rad,
                scale_sigma,
                scale_walk_per_sqrt_m,
                step_length_sigma,
                wall_crossing_weight,
                roughen_heading_rad,
                roughen_scale,
                smoothing_lag_steps: count(smoothing_lag_steps, "smoothing_lag_steps")?,
                declination: match declination {
                    MapDeclination::Auto => core::Declination::Auto,
                    MapDeclination::Fixed { rad } => core::Declination::Fixed(rad),
                    MapDeclination::Off => core::Declination::Off,
                },
            };
        out.validate()?;
        Ok(out)
    }
}

/// The core's default map configuration.
#[uniffi::export]
pub fn map_config_default() -> MapConfig {
    (&core::MapConfig::default()).into()
}

/// Flags of a [`MapEstimate`] (see the core's `MapFlags`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Record)]
pub struct MapFlags {
    /// The particles agree on one place.
    pub converged: bool,
    /// Several places fit.
    pub ambiguous: bool,
    /// Every particle was ruled out (or two fixes moved the walker) and the cloud was
    /// spread anew; set until it has converged again (at least 5 steps).
    pub recovered: bool,
    /// The start was off the walkable area and was moved onto it.
    pub start_snapped: bool,
    /// No start was given: the particles began over the whole floor.
    pub global: bool,
}

/// Where the walker is on the plan.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct MapEstimate {
    pub t_s: f64,
    /// The floor of the plan in use (null without a plan).
    pub floor: Option<i32>,
    /// Plan metres (x east, y north); without a plan the dead reckoning from the start.
    pub x_m: f64,
    pub y_m: f64,
    /// 1-σ per axis, metres.
    pub position_std_m: f64,
    /// WGS84 when the plan has a geographic reference.
    pub lat_deg: Option<f64>,
    pub lon_deg: Option<f64>,
    /// Walking direction on the plan, radians clockwise from its north.
    pub walking_azimuth_rad: Option<f64>,
    /// Spread of the heading offset over the particles, radians (NaN without a plan).
    pub heading_std_rad: f64,
    pub step_scale: f64,
    /// The declination applied, radians, east positive.
    pub declination_rad: f64,
    pub flags: MapFlags,
    pub recoveries: i64,
    pub fixes_used: i64,
    pub fixes_rejected: i64,
    pub steps: i64,
    pub distance_m: f64,
}

fn long(v: u64) -> i64 {
    i64::try_from(v).unwrap_or(i64::MAX)
}

impl From<core::MapEstimate> for MapEstimate {
    fn from(e: core::MapEstimate) -> Self {
        let f = e.flags;
        Self {
            t_s: e.t_s,
            floor: e.floor,
            x_m: e.x_m,
            y_m: e.y_m,
            position_std_m: e.position_std_m,
            lat_deg: e.lat_deg,
            lon_deg: e.lon_deg,
            walking_azimuth_rad: e.walking_azimuth_rad,
            heading_std_rad: e.heading_std_rad,
            step_scale: e.step_scale,
            declination_rad: e.declination_rad,
            flags: MapFlags {
                converged: f.converged,
                ambiguous: f.ambiguous,
                recovered: f.recovered,
                start_snapped: f.start_snapped,
                global: f.global,
            },
            recoveries: long(e.recoveries),
            fixes_used: long(e.fixes_used),
            fixes_rejected: long(e.fixes_rejected),
            steps: long(e.steps),
            distance_m: e.distance_m,
        }
    }
}

/// Where a fix says the walker is.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Enum)]
pub enum FixPosition {
    /// WGS84 degrees (the plan's geographic reference places it).
    LatLon { lat_deg: f64, lon_deg: f64 },
    /// Plan metres.
    Plan { x_m: f64, y_m: f64 },
}

/// An absolute fix from any source (GNSS, the app's WiFi/BLE position, a check-in).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct MapFix {
    /// Time on the IMU samples' clock, s.
    pub t_s: f64,
    pub position: FixPosition,
    /// Horizontal accuracy, 68 % radius, metres.
    pub accuracy_m: f64,
    /// The floor of the fix, when its source knows.
    #[uniffi(default = None)]
    pub floor: Option<i32>,
}

impl From<MapFix> for core::MapFix {
    fn from(f: MapFix) -> Self {
        Self {
            t_s: f.t_s,
            position: match f.position {
                FixPosition::LatLon { lat_deg, lon_deg } => {
                    core::FixPosition::LatLon { lat_deg, lon_deg }
                }
                FixPosition::Plan { x_m, y_m } => core::FixPosition::Plan { x_m, y_m },
            },
            accuracy_m: f.accuracy_m,
            floor: f.floor,
        }
    }
}

/// A point of the smoothed path: where the walker was after a step.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct SmoothedPoint {
    pub t_s: f64,
    pub x_m: f64,
    pub y_m: f64,
}

impl From<core::SmoothedPoint> for SmoothedPoint {
    fn from(p: core::SmoothedPoint) -> Self {
        Self {
            t_s: p.t_s,
            x_m: p.x_m,
            y_m: p.y_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_agree_with_the_core() {
        let d = map_config_default();
        let c = core::MapConfig::try_from(d.clone()).unwrap();
        assert_eq!(c, core::MapConfig::default());
        // The record's literal defaults (used by the Kotlin/Swift constructors).
        let literal = MapConfig {
            navigator: d.navigator.clone(),
            particles: 1000,
            seed: 91_621_622_891_589,
            start_sigma_m: 1.0,
            heading_sigma_rad: 0.2617993877991494,
            heading_walk_rad_per_sqrt_m: 0.008726646259971648,
            step_heading_sigma_rad: 0.06981317007977318,
            scale_sigma: 0.05,
            scale_walk_per_sqrt_m: 0.003,
            step_length_sigma: 0.08,
            wall_crossing_weight: 0.0,
            roughen_heading_rad: 0.05235987755982988,
            roughen_scale: 0.005,
            smoothing_lag_steps: 64,
            declination: MapDeclination::Auto,
        };
        assert_eq!(literal, d);
        let bad = MapConfig {
            particles: -5,
            ..d.clone()
        };
        assert!(matches!(
            core::MapConfig::try_from(bad),
            Err(MapError::InvalidConfig { .. })
        ));
        let bad = MapConfig { particles: 3, ..d };
        assert!(matches!(
            core::MapConfig::try_from(bad),
            Err(MapError::InvalidConfig { .. })
        ));
    }
}
