//! `MapNavigator`: the phone navigator's steps on floor plans — the map engine.
//!
//! Per IMU sample the [`PhoneNavigator`] dead-reckons as it always does; every step it
//! places goes to the [`MapMatcher`]'s particles, every fix (latitude/longitude or plan
//! metres, with its accuracy and floor) to their weights. The estimate is the
//! particles' mean with its spread, the heading on the plan and the flags; the
//! smoothed path is read beside it. Without a plan the engine is the navigator,
//! unchanged (moved to a start, turned by a fixed declination when asked).

use std::sync::Arc;

use crate::ahrs::ImuSample;
use crate::batch::{self, Batch};
use crate::pace::GnssFix;
use crate::pdr::{NavEstimate, PhoneNavigator};

use super::config::{Declination, MapConfig};
use super::error::MapError;
use super::fix::{FixPosition, MapFix};
use super::matcher::{MapFlags, MapMatcher};
use super::plan::FloorPlan;
use super::smoother::SmoothedPoint;
use crate::angle::wrap;

/// Where the walker is on the plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapEstimate {
    /// Time of the newest input, s.
    pub t_s: f64,
    /// The floor of the plan in use (None without a plan).
    pub floor: Option<i32>,
    /// Position in the plan's metres (x east, y north); without a plan the
    /// navigator's east/north from the start.
    pub x_m: f64,
    pub y_m: f64,
    /// 1-σ of the position per axis, m.
    pub position_std_m: f64,
    /// WGS84 position when the plan has a geographic reference (without a plan: once
    /// a fix anchored the navigator).
    pub lat_deg: Option<f64>,
    pub lon_deg: Option<f64>,
    /// Walking direction on the plan, radians clockwise from its north, once known.
    pub walking_azimuth_rad: Option<f64>,
    /// Spread of the heading offset over the particles, rad (NaN without a plan).
    pub heading_std_rad: f64,
    /// The particles' mean step-length scale (1 without a plan).
    pub step_scale: f64,
    /// The magnetic declination applied, rad (east positive).
    pub declination_rad: f64,
    pub flags: MapFlags,
    /// Times the cloud was spread anew.
    pub recoveries: u64,
    /// Fixes used and held back.
    pub fixes_used: u64,
    pub fixes_rejected: u64,
    /// Steps detected, and the distance walked by the navigator's step lengths, m.
    pub steps: u64,
    pub distance_m: f64,
}

/// The phone navigator on floor plans.
#[derive(Clone, Debug)]
pub struct MapNavigator {
    pub(crate) nav: PhoneNavigator,
    /// The particles (None: no plan).
    pub(crate) matcher: Option<MapMatcher>,
    pub(crate) config: MapConfig,
    /// Steps of the navigator handed to the particles.
    pub(crate) placed: u64,
    pub(crate) last_fix_t_s: Option<f64>,
    /// Where a start put the navigator's origin (no plan), m.
    pub(crate) origin: [f64; 2],
    /// Fixes used and refused without a plan.
    pub(crate) fixes_used: u64,
}

impl MapNavigator {
    /// An engine over `plans` (one per floor, any order; none: the navigator alone).
    /// With plans, the particles start over the whole of the first plan's floor until
    /// a start, a fix or [`set_floor`](Self::set_floor) says otherwise.
    pub fn new(config: MapConfig, plans: Vec<Arc<FloorPlan>>) -> Result<Self, MapError> {
        config.validate()?;
        Ok(Self {
            nav: PhoneNavigator::new(config.navigator)?,
            matcher: if plans.is_empty() {
                None
            } else {
                Some(MapMatcher::new(config, plans)?)
            },
            config,
            placed: 0,
            last_fix_t_s: None,
            origin: [0.0; 2],
            fixes_used: 0,
        })
    }

    pub fn config(&self) -> &MapConfig {
        &self.config
    }

    /// The navigator under the particles (its estimate is the plain dead reckoning).
    pub fn navigator(&self) -> &PhoneNavigator {
        &self.nav
    }

    /// The particles (None without a plan).
    pub fn matcher(&self) -> Option<&MapMatcher> {
        self.matcher.as_ref()
    }

    /// Start at `(x_m, y_m)` in plan metres with `sigma_m` per axis (None: the
    /// configured start σ) on `floor` (None: the floor in use). A start off the
    /// walkable area is moved to the nearest walkable point within
    /// [`super::MAX_START_SNAP_M`] (the flag `start_snapped` says so); farther is
    /// [`MapError::OffPlan`] and nothing changes. Without a plan the navigator's
    /// track is moved to start there.
    pub fn start_at(
        &mut self,
        x_m: f64,
        y_m: f64,
        sigma_m: Option<f64>,
        floor: Option<i32>,
    ) -> Result<(), MapError> {
        let sigma = sigma_m.unwrap_or(self.config.start_sigma_m);
        match self.matcher.as_mut() {
            Some(m) => m.start_at(x_m, y_m, sigma, floor),
            None => {
                crate::input::in_range("x_m", x_m, -1e5, 1e5, "m")?;
                crate::input::in_range("y_m", y_m, -1e5, 1e5, "m")?;
                self.origin = [x_m, y_m];
                Ok(())
            }
        }
    }

    /// Start at a WGS84 position (the plan must have a geographic reference).
    pub fn start_at_lat_lon(
        &mut self,
        lat_deg: f64,
        lon_deg: f64,
        sigma_m: Option<f64>,
        floor: Option<i32>,
    ) -> Result<(), MapError> {
        crate::input::gnss(lat_deg, lon_deg, None, None, None, None)?;
        let Some(m) = self.matcher.as_ref() else {
            return Err(MapError::config(
                "a start in latitude/longitude needs a plan",
            ));
        };
        let index = match floor {
            Some(f) => m.plan_index(f)?,
            None => m.floor,
        };
        let plan = &m.plans[index];
        let geo = plan.geo_reference().ok_or(MapError::NoGeoReference {
            floor: plan.floor(),
        })?;
        let (x, y) = geo.to_plan(lat_deg, lon_deg);
        let floor = plan.floor();
        self.start_at(x, y, sigma_m, Some(floor))
    }

    /// The walker is on `floor` now (an elevator, the app's floor selector): the
    /// particles keep their places where walkable on the new plan, else the cloud is
    /// spread around where it was.
    pub fn set_floor(&mut self, floor: i32) -> Result<(), MapError> {
        let Some(m) = self.matcher.as_mut() else {
            return Err(MapError::UnknownFloor { floor });
        };
        let index = m.plan_index(floor)?;
        m.switch_floor(index);
        Ok(())
    }

    /// One IMU sample.
    pub fn push_imu(&mut self, s: &ImuSample) -> Result<(), MapError> {
        self.nav.push_imu(s)?;
        if let Some(m) = self.matcher.as_mut() {
            if s.mag_ut.is_some() && !m.absolute_heading {
                m.set_absolute_heading(true);
            }
        }
        self.after_input();
        Ok(())
    }

    /// One IMU sample (the engine contract's form): the estimate after it.
    pub fn push(&mut self, s: &ImuSample) -> Result<Option<MapEstimate>, MapError> {
        self.push_imu(s)?;
        Ok(self.estimate())
    }

    /// Many IMU samples in order, as if pushed one by one; bad ones are skipped and
    /// reported.
    pub fn push_batch(&mut self, samples: &[ImuSample]) -> Batch<MapEstimate, MapError> {
        batch::run(samples, |s| self.push(s))
    }

    /// Hand the steps placed since the last input to the particles, then let the
    /// fixes that waited long enough be weighed.
    fn after_input(&mut self) {
        let Some(m) = self.matcher.as_mut() else {
            return;
        };
        let Some(e) = self.nav.estimate() else { return };
        let (_, total) = self.nav.recent_steps();
        // The navigator keeps its last 32 steps and places a few per sample.
        for step in self.nav.steps_since(self.placed) {
            m.step(&step, e.distance_m);
        }
        self.placed = total;
        m.tick(e.t_s, e.distance_m);
    }

    /// One absolute fix (any source), checked at the door like every input. With a
    /// plan it is held until the steps up to its time are placed (at most 2.5 s),
    /// then weighs the particles; a fix on another floor switches to it. Without a
    /// plan a latitude/longitude fix goes to the navigator (its GNSS correction); a
    /// fix in plan metres is refused.
    pub fn push_fix(&mut self, fix: &MapFix) -> Result<Option<MapEstimate>, MapError> {
        let (now, walked) = self
            .nav
            .estimate()
            .map_or((f64::NAN, 0.0), |e| (e.t_s, e.distance_m));
        if let Some(m) = self.matcher.as_mut() {
            m.push_fix(fix, now, walked)?;
            return Ok(self.estimate());
        }
        fix.check(self.last_fix_t_s)?;
        let FixPosition::LatLon { lat_deg, lon_deg } = fix.position else {
            return Err(MapError::config("a fix in plan metres needs a plan"));
        };
        let g = GnssFix::new(fix.t_s, lat_deg, lon_deg).with_accuracy(fix.accuracy_m);
        self.nav.push_fix(&g)?;
        self.last_fix_t_s = Some(fix.t_s);
        self.fixes_used += 1;
        Ok(self.estimate())
    }

    /// Where the walker is now: None before the first accepted IMU sample.
    pub fn estimate(&self) -> Option<MapEstimate> {
        let nav = self.nav.estimate()?;
        Some(match &self.matcher {
            Some(m) => on_plan(m, &nav),
            None => self.off_plan(&nav),
        })
    }

    /// Without a plan: the navigator's estimate, turned by a fixed declination and
    /// moved to the start.
    fn off_plan(&self, nav: &NavEstimate) -> MapEstimate {
        let d = match self.config.declination {
            Declination::Fixed(d) => d,
            Declination::Auto | Declination::Off => 0.0,
        };
        let (sd, cd) = d.sin_cos();
        let (e, n) = (nav.east_m, nav.north_m);
        MapEstimate {
            t_s: nav.t_s,
            floor: None,
            x_m: self.origin[0] + (e * cd + n * sd),
            y_m: self.origin[1] + (n * cd - e * sd),
            position_std_m: nav.position_std_m,
            lat_deg: nav.lat_deg,
            lon_deg: nav.lon_deg,
            walking_azimuth_rad: nav.walking_azimuth_rad.map(|a| wrap(a + d)),
            heading_std_rad: f64::NAN,
            step_scale: 1.0,
            declination_rad: d,
            flags: MapFlags::default(),
            recoveries: 0,
            fixes_used: self.fixes_used,
            fixes_rejected: 0,
            steps: nav.steps,
            distance_m: nav.distance_m,
        }
    }

    /// The smoothed path's points fixed since the first `count` (see
    /// [`MapMatcher::smoothed_since`]); none without a plan.
    pub fn smoothed_since(&self, count: u64) -> impl Iterator<Item = SmoothedPoint> + '_ {
        self.matcher
            .iter()
            .flat_map(move |m| m.smoothed_since(count))
    }

    /// How many points of the smoothed path are fixed.
    pub fn smoothed_fixed(&self) -> u64 {
        self.matcher.as_ref().map_or(0, |m| m.smoothed_fixed())
    }

    /// The open end of the smoothed path, oldest first; none without a plan.
    pub fn smoothed_window(&self, f: impl FnMut(SmoothedPoint)) {
        if let Some(m) = &self.matcher {
            m.smoothed_window(f);
        }
    }
}

/// The estimate on the plan: the particles' state with the navigator's counts.
fn on_plan(m: &MapMatcher, nav: &NavEstimate) -> MapEstimate {
    let s = m.state();
    let plan = &m.plans[m.floor];
    let geo = plan.geo_reference().map(|g| g.to_geodetic(s.x_m, s.y_m));
    MapEstimate {
        t_s: nav.t_s,
        floor: Some(s.floor),
        x_m: s.x_m,
        y_m: s.y_m,
        position_std_m: s.position_std_m,
        lat_deg: geo.map(|g| g.0),
        lon_deg: geo.map(|g| g.1),
        walking_azimuth_rad: nav
            .walking_azimuth_rad
            .map(|a| wrap(a + s.heading_offset_rad)),
        heading_std_rad: s.heading_std_rad,
        step_scale: s.step_scale,
        declination_rad: s.declination_rad,
        flags: s.flags,
        recoveries: s.recoveries,
        fixes_used: s.fixes_used,
        fixes_rejected: s.fixes_rejected,
        steps: nav.steps,
        distance_m: nav.distance_m,
    }
}
