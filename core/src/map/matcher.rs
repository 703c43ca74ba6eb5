//! `MapMatcher`: steps on floor plans, as particles — the map engine without the
//! navigator, for any source of steps (time, length, azimuth).
//!
//! Each particle is a hypothesis of where the walker is, how far the phone's heading
//! is off the plan's north and how much the step lengths are off. Per step every
//! particle moves by it, turned by its offset and scaled by its scale with a little
//! noise of its own; a particle whose step crosses a wall is ruled out (or, with a
//! crossing weight above 0, made that much less likely: doors the plan does not
//! draw); the survivors are resampled when too few carry the weight. A fix weighs the
//! particles by its likelihood. When every particle is ruled out the cloud is spread
//! anew around where it was (then over the whole floor) and the flags say so.

use std::sync::Arc;

use crate::pdr::NavStep;
use crate::signal::Ring;

use super::config::{Declination, MapConfig};
use super::error::MapError;
use super::fix::{
    FixPosition, MapFix, PendingFix, FIX_EXPLAINED_LIKELIHOOD, FIX_OUTLIER_FLOOR, MAX_FIX_WAIT_S,
};
use super::particles::{Cloud, OffsetPrior, Summary};
use super::plan::FloorPlan;
use super::smoother::{History, SmoothedPoint};
use crate::angle::wrap;
use crate::rng::Rng;

/// A start off the walkable area is moved onto it when it is this close, m.
pub const MAX_START_SNAP_M: f64 = 5.0;
/// The cloud has converged when its per-axis σ is under this, m.
pub const CONVERGED_STD_M: f64 = 2.0;
/// The cloud is ambiguous when less than `AMBIGUOUS_SHARE` of its weight lies within
/// `AMBIGUOUS_RADIUS_M` of its mean (several places fit).
pub const AMBIGUOUS_RADIUS_M: f64 = 3.0;
pub const AMBIGUOUS_SHARE: f64 = 0.6;
/// After every particle was ruled out, the cloud is spread anew around where it was
/// with at least this σ, m (its heading offsets drawn from the prior again).
const RECOVERY_SIGMA_M: f64 = 3.0;
/// Step scales stay within this band.
const SCALE_RANGE: (f64, f64) = (0.6, 1.5);
/// Largest |plan coordinate| of a start or a fix, m.
pub(crate) const MAX_PLAN_COORD_M: f64 = 1.0e5;
/// Largest σ of a start, m.
pub(crate) const MAX_START_SIGMA_M: f64 = 1_000.0;
/// The `recovered` flag stays set for at least this many steps.
pub const RECOVERED_MIN_STEPS: u64 = 5;
/// Fixes waiting for their steps.
pub(crate) const PENDING_FIXES: usize = 8;
/// Two fixes that no particle explains agree when they are this many σ apart or
/// closer (beyond the distance walked between them).
const CONFLICT_AGREE_SIGMAS: f64 = 3.0;

/// Flags of a map estimate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MapFlags {
    /// The particles agree on one place (σ under [`CONVERGED_STD_M`], not ambiguous).
    pub converged: bool,
    /// Several places fit (see [`AMBIGUOUS_SHARE`]).
    pub ambiguous: bool,
    /// Every particle was ruled out (or two fixes moved the walker) and the cloud was
    /// spread anew; stays set until it has converged again.
    pub recovered: bool,
    /// The start was off the walkable area and was moved onto it.
    pub start_snapped: bool,
    /// No start was given (or a recovery failed): the particles began over the whole
    /// floor; stays set until they have converged.
    pub global: bool,
}

/// What the particles say.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MatchState {
    pub floor: i32,
    pub x_m: f64,
    pub y_m: f64,
    /// Per-axis 1-σ, m.
    pub position_std_m: f64,
    /// Mean heading offset (plan north minus the steps' north, declination
    /// included: add it to a step's azimuth) and its spread, rad.
    pub heading_offset_rad: f64,
    pub heading_std_rad: f64,
    pub step_scale: f64,
    pub declination_rad: f64,
    pub flags: MapFlags,
    pub recoveries: u64,
    pub fixes_used: u64,
    pub fixes_rejected: u64,
}

/// Particles on floor plans, moved by steps.
#[derive(Clone, Debug)]
pub struct MapMatcher {
    pub(crate) config: MapConfig,
    pub(crate) plans: Vec<Arc<FloorPlan>>,
    /// Index of the plan in use.
    pub(crate) floor: usize,
    pub(crate) cloud: Cloud,
    pub(crate) history: History,
    pub(crate) rng: Rng,
    pub(crate) declination_rad: f64,
    /// The steps' azimuths are absolute (a magnetometer): offsets start near 0.
    pub(crate) absolute_heading: bool,
    /// The heading offsets are drawn at the first step (when it is known whether
    /// headings are absolute).
    pub(crate) offsets_pending: bool,
    pub(crate) pending: Ring<PendingFix, PENDING_FIXES>,
    /// Time of the last accepted fix, s.
    pub(crate) last_fix_t_s: Option<f64>,
    /// The last fix no particle explained, and the distance walked then.
    pub(crate) conflict: Option<(PendingFix, f64)>,
    pub(crate) flags: MapFlags,
    /// Steps since the cloud was last spread anew (the `recovered` flag stays set for
    /// at least [`RECOVERED_MIN_STEPS`] of them).
    pub(crate) steps_since_recovery: u64,
    pub(crate) recoveries: u64,
    pub(crate) fixes_used: u64,
    pub(crate) fixes_rejected: u64,
    pub(crate) summary: Summary,
}

impl MapMatcher {
    /// Particles over `plans` (at least one, one per floor), spread over the whole of
    /// the first plan's floor until a start, a fix or a floor says otherwise.
    pub fn new(config: MapConfig, plans: Vec<Arc<FloorPlan>>) -> Result<Self, MapError> {
        config.validate()?;
        if plans.is_empty() {
            return Err(MapError::config("a map matcher needs at least one plan"));
        }
        for (i, p) in plans.iter().enumerate() {
            if plans[..i].iter().any(|q| q.floor() == p.floor()) {
                return Err(MapError::DuplicateFloor { floor: p.floor() });
            }
        }
        let n = config.particles;
        let declination_rad = match config.declination {
            Declination::Fixed(d) => d,
            Declination::Off => 0.0,
            Declination::Auto => plans[0].geo_reference().map_or(0.0, |g| {
                let (lat, lon) = g.location_deg();
                super::declination::declination_rad(lat, lon)
            }),
        };
        let mut m = Self {
            floor: 0,
            plans,
            cloud: Cloud::new(n),
            history: History::new(config.smoothing_lag_steps, n),
            rng: Rng::new(config.seed),
            declination_rad,
            absolute_heading: false,
            offsets_pending: true,
            pending: Ring::new(),
            last_fix_t_s: None,
            conflict: None,
            flags: MapFlags::default(),
            steps_since_recovery: 0,
            recoveries: 0,
            fixes_used: 0,
            fixes_rejected: 0,
            summary: Summary::default(),
            config,
        };
        let plan = m.plan();
        m.cloud.spread_global(&plan, &mut m.rng);
        m.flags.global = true;
        m.refresh();
        Ok(m)
    }

    pub fn config(&self) -> &MapConfig {
        &self.config
    }

    pub fn plans(&self) -> &[Arc<FloorPlan>] {
        &self.plans
    }

    /// The plan in use.
    pub fn plan(&self) -> Arc<FloorPlan> {
        Arc::clone(&self.plans[self.floor])
    }

    pub(crate) fn plan_index(&self, floor: i32) -> Result<usize, MapError> {
        self.plans
            .iter()
            .position(|p| p.floor() == floor)
            .ok_or(MapError::UnknownFloor { floor })
    }

    /// The steps' azimuths are absolute (from a magnetometer): the heading offsets
    /// start near 0 (else anywhere). Call before the first step.
    pub fn set_absolute_heading(&mut self, absolute: bool) {
        self.absolute_heading = absolute;
    }

    /// Start at `(x_m, y_m)` in plan metres with `sigma_m` per axis on `floor` (None:
    /// the floor in use): see [`super::MapNavigator::start_at`].
    pub fn start_at(
        &mut self,
        x_m: f64,
        y_m: f64,
        sigma_m: f64,
        floor: Option<i32>,
    ) -> Result<(), MapError> {
        crate::input::in_range("x_m", x_m, -MAX_PLAN_COORD_M, MAX_PLAN_COORD_M, "m")?;
        crate::input::in_range("y_m", y_m, -MAX_PLAN_COORD_M, MAX_PLAN_COORD_M, "m")?;
        crate::input::in_range("sigma_m", sigma_m, 0.0, MAX_START_SIGMA_M, "m")?;
        let index = match floor {
            Some(f) => self.plan_index(f)?,
            None => self.floor,
        };
        let p = [x_m, y_m];
        let plan = Arc::clone(&self.plans[index]);
        let (c, snapped) = snap(&plan, p)?;
        self.floor = index;
        self.history.fix_all(&self.cloud);
        self.cloud.spread_around(&plan, &mut self.rng, c, sigma_m);
        let prior = self.offset_prior();
        self.cloud
            .draw_states(&mut self.rng, prior, self.config.scale_sigma);
        self.flags = MapFlags {
            start_snapped: snapped,
            ..MapFlags::default()
        };
        self.pending.clear();
        self.conflict = None;
        self.refresh();
        Ok(())
    }

    /// Switch to the plan `index`: particles keep their places where walkable there,
    /// else the cloud is spread around where it was.
    pub(crate) fn switch_floor(&mut self, index: usize) {
        if self.floor == index {
            return;
        }
        self.floor = index;
        let plan = self.plan();
        self.history.fix_all(&self.cloud);
        for i in 0..self.cloud.len() {
            if !plan.is_walkable([self.cloud.x[i], self.cloud.y[i]]) {
                self.cloud.w[i] = 0.0;
            }
        }
        if self.cloud.normalise() > 0.0 {
            self.resample_if_needed();
        } else {
            self.respread_near(&plan, [self.summary.x, self.summary.y]);
        }
        self.pending.clear();
        self.refresh();
    }

    fn offset_prior(&self) -> OffsetPrior {
        if self.absolute_heading || self.offsets_pending {
            OffsetPrior::Normal {
                mean: 0.0,
                sigma: self.config.heading_sigma_rad,
            }
        } else {
            OffsetPrior::Uniform
        }
    }

    fn front_fix(&self) -> Option<PendingFix> {
        self.pending.iter().next()
    }

    /// Time passed (the newest input's time, s; `walked_m` the distance walked so
    /// far): fixes that waited long enough for their steps are weighed.
    pub fn tick(&mut self, t_s: f64, walked_m: f64) {
        while let Some(f) = self.front_fix() {
            if t_s - f.t_s < MAX_FIX_WAIT_S {
                break;
            }
            self.pending.pop_front();
            self.weigh_fix(f, walked_m);
        }
    }

    /// Move every particle by one step (`walked_m`: the distance walked so far,
    /// this step included).
    pub fn step(&mut self, step: &NavStep, walked_m: f64) {
        if self.offsets_pending {
            self.offsets_pending = false;
            let prior = self.offset_prior();
            self.cloud
                .draw_states(&mut self.rng, prior, self.config.scale_sigma);
        }
        while let Some(f) = self.front_fix() {
            if f.t_s > step.t_s {
                break;
            }
            self.pending.pop_front();
            self.weigh_fix(f, walked_m);
        }
        let plan = self.plan();
        let az = step.azimuth_rad + self.declination_rad;
        if self.move_all(&plan, az, step.length_m) == 0 {
            self.recover(&plan, az, step.length_m);
        }
        self.steps_since_recovery = self.steps_since_recovery.saturating_add(1);
        self.history.push(step.t_s, &self.cloud);
        self.cloud.normalise();
        self.resample_if_needed();
        self.refresh();
    }

    /// Move the particles; returns how many carry weight after.
    fn move_all(&mut self, plan: &FloorPlan, az: f64, length_m: f64) -> usize {
        let c = &self.config;
        let walk_h = c.heading_walk_rad_per_sqrt_m * length_m.sqrt();
        let walk_s = c.scale_walk_per_sqrt_m * length_m.sqrt();
        let crossing = c.wall_crossing_weight;
        let cloud = &mut self.cloud;
        let rng = &mut self.rng;
        let mut alive = 0;
        for i in 0..cloud.len() {
            if cloud.w[i] == 0.0 {
                continue;
            }
            let a = az + cloud.off[i] + c.step_heading_sigma_rad * rng.normal();
            let l = length_m * cloud.scale[i] * (1.0 + c.step_length_sigma * rng.normal());
            let (s, co) = a.sin_cos();
            let from = [cloud.x[i], cloud.y[i]];
            let to = [from[0] + l * s, from[1] + l * co];
            if plan.crosses_wall(from, to) {
                cloud.w[i] *= crossing;
                if cloud.w[i] == 0.0 {
                    continue;
                }
            }
            cloud.x[i] = to[0];
            cloud.y[i] = to[1];
            cloud.off[i] = wrap(cloud.off[i] + walk_h * rng.normal());
            cloud.scale[i] =
                (cloud.scale[i] + walk_s * rng.normal()).clamp(SCALE_RANGE.0, SCALE_RANGE.1);
            alive += 1;
        }
        alive
    }

    /// Every particle was ruled out by the step: spread anew around where the cloud
    /// was and take the step again; if no particle can take it there either, the plan
    /// has no way for it (a door or an opening it does not draw): take it through.
    fn recover(&mut self, plan: &FloorPlan, az: f64, length_m: f64) {
        self.respread_near(plan, [self.summary.x, self.summary.y]);
        if self.move_all(plan, az, length_m) > 0 {
            return;
        }
        let n = self.cloud.len() as f64;
        self.cloud.w.iter_mut().for_each(|w| *w = 1.0 / n);
        self.move_through(az, length_m);
    }

    /// Move every particle by the step, walls or not.
    fn move_through(&mut self, az: f64, length_m: f64) {
        let c = &self.config;
        let cloud = &mut self.cloud;
        for i in 0..cloud.len() {
            let a = az + cloud.off[i] + c.step_heading_sigma_rad * self.rng.normal();
            let l = length_m * cloud.scale[i] * (1.0 + c.step_length_sigma * self.rng.normal());
            let (s, co) = a.sin_cos();
            cloud.x[i] += l * s;
            cloud.y[i] += l * co;
        }
    }

    /// Spread the cloud around `c` after a failure.
    fn respread_near(&mut self, plan: &FloorPlan, c: [f64; 2]) {
        let s = self.summary;
        let sigma = s.std_m.max(RECOVERY_SIGMA_M);
        let c = plan
            .nearest_walkable(c, sigma * 3.0)
            .unwrap_or_else(|| plan.walkable_point(0.5, 0.5, 0.5));
        self.history.fix_all(&self.cloud);
        self.cloud.spread_around(plan, &mut self.rng, c, sigma);
        // The cloud that failed may have failed for its headings: start them again
        // from the prior.
        let prior = if self.absolute_heading {
            OffsetPrior::Normal {
                mean: 0.0,
                sigma: self.config.heading_sigma_rad,
            }
        } else {
            OffsetPrior::Uniform
        };
        self.cloud
            .draw_states(&mut self.rng, prior, self.config.scale_sigma);
        self.recovered();
    }

    /// The cloud was spread anew: count it and say so.
    fn recovered(&mut self) {
        self.recoveries += 1;
        self.flags.recovered = true;
        self.steps_since_recovery = 0;
    }

    fn resample_if_needed(&mut self) {
        if self.cloud.needs_resampling() {
            self.cloud.resample(&mut self.rng);
            self.history.resampled(&self.cloud.pick);
            // Copies of one particle would stay one hypothesis: jitter their heading
            // offsets and scales (positions spread with the next steps' noise).
            let (rh, rs) = (self.config.roughen_heading_rad, self.config.roughen_scale);
            for i in 0..self.cloud.len() {
                self.cloud.off[i] = wrap(self.cloud.off[i] + rh * self.rng.normal());
                self.cloud.scale[i] = (self.cloud.scale[i] + rs * self.rng.normal())
                    .clamp(SCALE_RANGE.0, SCALE_RANGE.1);
            }
        }
    }

    /// Recompute the summary and the flags that follow from it.
    fn refresh(&mut self) {
        self.summary = self.cloud.summary(AMBIGUOUS_RADIUS_M, self.summary.off);
        let s = &self.summary;
        self.flags.ambiguous = s.near_share < AMBIGUOUS_SHARE;
        self.flags.converged = s.std_m < CONVERGED_STD_M && !self.flags.ambiguous;
        if self.flags.converged {
            if self.steps_since_recovery >= RECOVERED_MIN_STEPS {
                self.flags.recovered = false;
            }
            self.flags.global = false;
        }
    }

    /// One absolute fix, checked at the door (time after the previous fix, position
    /// and accuracy in range; `now_t_s` and `walked_m`: the newest input's time and
    /// the distance walked): held until the steps up to its time are in (at most
    /// [`MAX_FIX_WAIT_S`]), then weighed; a fix on another floor switches to it.
    pub fn push_fix(&mut self, fix: &MapFix, now_t_s: f64, walked_m: f64) -> Result<(), MapError> {
        fix.check(self.last_fix_t_s)?;
        let index = match fix.floor {
            Some(f) => self.plan_index(f)?,
            None => self.floor,
        };
        let plan = &self.plans[index];
        let (x_m, y_m) = match fix.position {
            FixPosition::Plan { x_m, y_m } => (x_m, y_m),
            FixPosition::LatLon { lat_deg, lon_deg } => plan
                .geo_reference()
                .ok_or(MapError::NoGeoReference {
                    floor: plan.floor(),
                })?
                .to_plan(lat_deg, lon_deg),
        };
        self.last_fix_t_s = Some(fix.t_s);
        self.add_fix(
            index,
            PendingFix {
                t_s: fix.t_s,
                x_m,
                y_m,
                sigma_m: fix.sigma_m(),
            },
        );
        let now = if now_t_s.is_nan() {
            fix.t_s
        } else {
            now_t_s.max(fix.t_s)
        };
        self.tick(now, walked_m);
        Ok(())
    }

    /// A fix on the plan `index`, placed in its metres: held until the steps up to
    /// its time are in, or weighed now when it is on another floor (which it
    /// switches to).
    fn add_fix(&mut self, index: usize, f: PendingFix) {
        if index != self.floor {
            // Another floor: the fix places the walker there now.
            self.floor = index;
            let plan = self.plan();
            let (c, _) = snap(&plan, [f.x_m, f.y_m]).unwrap_or(([f.x_m, f.y_m], false));
            self.history.fix_all(&self.cloud);
            self.cloud.spread_around(&plan, &mut self.rng, c, f.sigma_m);
            self.pending.clear();
            self.conflict = None;
            self.fixes_used += 1;
            self.refresh();
        } else if self.pending.len() == PENDING_FIXES {
            self.fixes_rejected += 1;
        } else {
            self.pending.push(f);
        }
    }

    /// Weigh the particles by a fix (or hold it back, or move the walker to it).
    fn weigh_fix(&mut self, f: PendingFix, walked_m: f64) {
        let inv = 1.0 / (2.0 * f.sigma_m * f.sigma_m);
        let lik = |x: f64, y: f64| {
            let (dx, dy) = (x - f.x_m, y - f.y_m);
            (-(dx * dx + dy * dy) * inv).exp()
        };
        let explained: f64 = (0..self.cloud.len())
            .map(|i| self.cloud.w[i] * lik(self.cloud.x[i], self.cloud.y[i]))
            .sum();
        let agrees = |(prev, w): &(PendingFix, f64)| {
            let gap = (prev.x_m - f.x_m).hypot(prev.y_m - f.y_m);
            gap <= CONFLICT_AGREE_SIGMAS * (prev.sigma_m + f.sigma_m) + (walked_m - w)
        };
        if explained >= FIX_EXPLAINED_LIKELIHOOD {
            for i in 0..self.cloud.len() {
                self.cloud.w[i] *= lik(self.cloud.x[i], self.cloud.y[i]) + FIX_OUTLIER_FLOOR;
            }
            self.cloud.normalise();
            self.resample_if_needed();
            self.fixes_used += 1;
            self.conflict = None;
        } else if self.conflict.as_ref().is_some_and(agrees) {
            // Two fixes agree and no particle explains either: the walker is there.
            let plan = self.plan();
            let (c, _) = snap(&plan, [f.x_m, f.y_m]).unwrap_or(([f.x_m, f.y_m], false));
            self.history.fix_all(&self.cloud);
            self.cloud.spread_around(&plan, &mut self.rng, c, f.sigma_m);
            self.recovered();
            self.fixes_used += 1;
            self.conflict = None;
        } else {
            self.conflict = Some((f, walked_m));
            self.fixes_rejected += 1;
        }
        self.refresh();
    }

    /// What the particles say now.
    pub fn state(&self) -> MatchState {
        let s = &self.summary;
        MatchState {
            floor: self.plans[self.floor].floor(),
            x_m: s.x,
            y_m: s.y,
            position_std_m: s.std_m,
            heading_offset_rad: wrap(s.off + self.declination_rad),
            heading_std_rad: s.off_std,
            step_scale: s.scale,
            declination_rad: self.declination_rad,
            flags: self.flags,
            recoveries: self.recoveries,
            fixes_used: self.fixes_used,
            fixes_rejected: self.fixes_rejected,
        }
    }

    /// The smoothed path's points fixed since the first `count` (a count
    /// [`smoothed_fixed`](Self::smoothed_fixed) gave earlier), as far as the latest
    /// trace holds them: read after each step and remember the new count.
    pub fn smoothed_since(&self, count: u64) -> impl Iterator<Item = SmoothedPoint> + '_ {
        let new =
            usize::try_from(self.history.fixed_total.saturating_sub(count)).unwrap_or(usize::MAX);
        let f = &self.history.fixed;
        f[f.len().saturating_sub(new)..].iter().copied()
    }

    /// How many points of the smoothed path are fixed.
    pub fn smoothed_fixed(&self) -> u64 {
        self.history.fixed_total
    }

    /// The open end of the smoothed path (the last steps, still being corrected),
    /// oldest first.
    pub fn smoothed_window(&self, f: impl FnMut(SmoothedPoint)) {
        self.history.window(&self.cloud, f);
    }
}

/// `p`, or the nearest walkable point within [`MAX_START_SNAP_M`] (and true).
pub(crate) fn snap(plan: &FloorPlan, p: [f64; 2]) -> Result<([f64; 2], bool), MapError> {
    if plan.is_walkable(p) {
        return Ok((p, false));
    }
    plan.nearest_walkable(p, MAX_START_SNAP_M)
        .map(|q| (q, true))
        .ok_or(MapError::OffPlan {
            x_m: p[0],
            y_m: p[1],
            distance_m: MAX_START_SNAP_M,
            floor: plan.floor(),
        })
}
