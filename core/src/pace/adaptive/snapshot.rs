//! The adaptive filter's snapshot: every field written (each writer destructures its
//! struct, so a field left out is a compile error), read back and checked to be a
//! state the filter can reach.

use super::settings::*;
use super::state::{Direction, FixPoint, PathWindow, SessionLine};
use super::AdaptiveFilter;
use crate::pace::published::{read_estimate, write_estimate};
use crate::pace::share::GnssChord;
use crate::pace::PaceConfig;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Bounds a running filter stays within even on garbage (fixes teleporting across
/// the globe, gaps of months): state magnitude; times, s; positions, m; statistics.
const MAX_STATE_MAGNITUDE: f64 = 1e12;
const MAX_TIME_S: f64 = 1e11 + 1.0;
const MAX_POSITION_M: f64 = 1e12;
const MAX_REFERENCE_CADENCE: f64 = 10.0;
const MAX_NIS_AVG: f64 = 1e6;
const MAX_INFORMATION: f64 = 1e12;
const MAX_STEPS: f64 = 1e12;
const MAX_DISTANCE_M: f64 = 1e13;
/// Tolerances of a restored variance against the cap, relative, and of a restored
/// direction's length.
const VARIANCE_CAP_TOLERANCE: f64 = 1e-9;
const UNIT_TOLERANCE: f64 = 1e-6;

impl FixPoint {
    /// Written as east, north, t.
    fn write(&self, w: &mut Writer) {
        let Self {
            east_m,
            north_m,
            t_s,
        } = *self;
        w.f64s(&[east_m, north_m, t_s]);
    }
}

impl PathWindow {
    fn write(&self, w: &mut Writer) {
        let Self {
            active,
            start_t_s,
            start_steps,
            anchor,
            path_m,
        } = *self;
        w.bool(active);
        w.f64s(&[start_t_s, start_steps]);
        anchor.write(w);
        w.f64(path_m);
    }

    fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let active = r.bool()?;
        let mut pw = [0.0; 6];
        r.f64s(&mut pw)?;
        let [start_t_s, start_steps, east_m, north_m, t_s, path_m] = pw;
        Ok(Self {
            active,
            start_t_s,
            start_steps,
            anchor: FixPoint {
                east_m,
                north_m,
                t_s,
            },
            path_m,
        })
    }
}

impl SessionLine {
    fn write(&self, w: &mut Writer) {
        let Self {
            steps,
            steps_x_cadence,
            steps_x_length,
        } = *self;
        w.f64s(&[steps, steps_x_cadence, steps_x_length]);
    }

    fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut s = [0.0; 3];
        r.f64s(&mut s)?;
        let [steps, steps_x_cadence, steps_x_length] = s;
        Ok(Self {
            steps,
            steps_x_cadence,
            steps_x_length,
        })
    }
}

impl AdaptiveFilter {
    pub fn write(&self, w: &mut Writer) {
        let Self {
            params: _, // part of the configuration, stored by the tracker
            x,
            p,
            initialized,
            t_s,
            last_fix_t_s,
            last_ped_t_s,
            last_trusted_t_s,
            reset_t_s,
            nis_avg,
            cadence_ref,
            distance_m,
            stationary,
            contradictions,
            steps_distrusted,
            window,
            recent_fixes,
            gnss_still,
            prev_fix,
            gated_run,
            gated_since_t_s,
            last_dir,
            slope_observable,
            info_gnss,
            info_ped,
            chord,
            epoch_gnss_weight,
            ped_speed,
            session,
            walking_gait,
            out,
        } = self;
        w.f64s(x.as_slice());
        w.f64s(p.as_slice());
        w.bool(*initialized);
        w.f64s(&[
            *t_s,
            *last_fix_t_s,
            *last_ped_t_s,
            *last_trusted_t_s,
            *reset_t_s,
            *nis_avg,
            *cadence_ref,
            *distance_m,
            *info_gnss,
            *info_ped,
            *ped_speed,
            *epoch_gnss_weight,
        ]);
        chord.write(w);
        session.write(w);
        w.bool(*walking_gait);
        w.bool(*stationary);
        w.u64(*contradictions as u64);
        w.bool(*steps_distrusted);
        w.bool(*slope_observable);
        let Direction { east, north } = *last_dir;
        w.f64s(&[east, north]);
        w.u64(recent_fixes.len() as u64);
        // Stored as t, east, north.
        for f in recent_fixes.iter() {
            w.f64s(&[f.t_s, f.east_m, f.north_m]);
        }
        w.bool(*gnss_still);
        window.write(w);
        prev_fix.write(w);
        w.u64(*gated_run as u64);
        w.f64(*gated_since_t_s);
        write_estimate(w, out);
    }

    pub fn read(r: &mut Reader, config: &PaceConfig) -> Result<Self, SnapshotError> {
        let mut f = Self::new(config);
        r.f64s(f.x.as_mut_slice())?;
        r.f64s(f.p.as_mut_slice())?;
        f.initialized = r.bool()?;
        // Times start as NaN or −∞ ("none yet"); the cadence reference and the
        // pedometer speed are NaN until moving.
        f.t_s = r.f64_or_nan()?;
        f.last_fix_t_s = r.f64_or_nan()?;
        f.last_ped_t_s = r.time_or_marker()?;
        f.last_trusted_t_s = r.time_or_marker()?;
        f.reset_t_s = r.time_or_marker()?;
        f.nis_avg = r.f64()?;
        f.cadence_ref = r.f64_or_nan()?;
        f.distance_m = r.f64()?;
        f.info_gnss = r.f64()?;
        f.info_ped = r.f64()?;
        f.ped_speed = r.f64_or_nan()?;
        f.epoch_gnss_weight = r.f64()?;
        f.chord = GnssChord::read(r)?;
        f.session = SessionLine::read(r)?;
        f.walking_gait = r.bool()?;
        f.stationary = r.bool()?;
        f.contradictions = r.len(u32::MAX as usize)? as u32;
        f.steps_distrusted = r.bool()?;
        f.slope_observable = r.bool()?;
        // NaN until moving / before the first fix.
        f.last_dir = Direction {
            east: r.f64_or_nan()?,
            north: r.f64_or_nan()?,
        };
        for _ in 0..r.len(RECENT_FIXES)? {
            let mut p = [0.0; 3];
            r.f64s(&mut p)?;
            let [t_s, east_m, north_m] = p;
            f.recent_fixes.push(FixPoint {
                east_m,
                north_m,
                t_s,
            });
        }
        f.gnss_still = r.bool()?;
        f.window = PathWindow::read(r)?;
        f.prev_fix = FixPoint {
            east_m: r.f64_or_nan()?,
            north_m: r.f64_or_nan()?,
            t_s: r.f64_or_nan()?,
        };
        f.gated_run = r.len(u32::MAX as usize)? as u32;
        f.gated_since_t_s = r.f64_or_nan()?;
        f.out = read_estimate(r)?;
        f.check_state().map_err(SnapshotError::Invalid)?;
        Ok(f)
    }

    /// Whether a restored state is one the filter can reach: a covariance
    /// (symmetric, non-negative variances), the filter time set once initialised,
    /// non-negative statistics.
    fn check_state(&self) -> Result<(), &'static str> {
        let p = &self.p;
        crate::snapshot::check_covariance(p)?;
        if self.initialized && self.t_s.is_nan() {
            return Err("filter time");
        }
        // The variance cap of the prediction: a larger restored variance loses every
        // digit of a later update to rounding and drives a variance negative.
        if self.x.iter().any(|v| v.abs() > MAX_STATE_MAGNITUDE)
            || (0..p.nrows()).any(|i| p[(i, i)] > MAX_VARIANCE * (1.0 + VARIANCE_CAP_TOLERANCE))
        {
            return Err("filter state out of range");
        }
        if !(0.0..=1.0).contains(&self.epoch_gnss_weight) {
            return Err("GNSS weight");
        }
        let t_ok = |t: f64| t.is_nan() || t == f64::NEG_INFINITY || t.abs() <= MAX_TIME_S;
        if ![
            self.t_s,
            self.last_fix_t_s,
            self.last_ped_t_s,
            self.last_trusted_t_s,
            self.reset_t_s,
            self.gated_since_t_s,
            self.window.start_t_s,
        ]
        .into_iter()
        .all(t_ok)
        {
            return Err("filter times");
        }
        let pos_ok = |v: f64| v.is_nan() || v.abs() <= MAX_POSITION_M;
        let point_ok = |f: &FixPoint| pos_ok(f.east_m) && pos_ok(f.north_m) && t_ok(f.t_s);
        let positions_ok = point_ok(&self.prev_fix)
            && self.recent_fixes.iter().all(|f| {
                t_ok(f.t_s) && f.east_m.abs() <= MAX_POSITION_M && f.north_m.abs() <= MAX_POSITION_M
            })
            && point_ok(&self.window.anchor);
        if !positions_ok {
            return Err("filter positions");
        }
        let dir = self.last_dir.east.hypot(self.last_dir.north);
        if !(dir.is_nan() || (dir - 1.0).abs() < UNIT_TOLERANCE) {
            return Err("filter direction not a unit vector");
        }
        if !(self.cadence_ref.is_nan() || (0.0..=MAX_REFERENCE_CADENCE).contains(&self.cadence_ref))
        {
            return Err("filter reference cadence out of range");
        }
        if self.nis_avg > MAX_NIS_AVG
            || self.info_gnss > MAX_INFORMATION
            || self.info_ped > MAX_INFORMATION
        {
            return Err("filter statistics out of range");
        }
        if !(0.0..=MAX_STEPS).contains(&self.window.start_steps)
            || self.window.path_m > MAX_DISTANCE_M
            || self.distance_m > MAX_DISTANCE_M
        {
            return Err("filter distances out of range");
        }
        if self.nis_avg < 0.0
            || self.distance_m < 0.0
            || self.info_gnss < 0.0
            || self.info_ped < 0.0
            || self.window.path_m < 0.0
        {
            return Err("filter statistics");
        }
        Ok(())
    }
}
