//! A walk through the map engine: the engine itself ([`replay_map`], what `stridekit
//! pdr --map` runs), or the navigator once ([`nav_cache`]) and then its steps through
//! the particles as the engine hands them over ([`run_cached`], what the evaluation
//! runs for each configuration; a test checks that both agree).

use std::sync::Arc;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::map::{FloorPlan, MapConfig, MapFix, MapMatcher, MapNavigator, SmoothedPoint};
use stridekit_core::pdr::{NavStep, PhoneNavigator};
use stridekit_formats::InertialRecording;

use crate::pdr::metrics::TrackPoint;

/// What one walk through the map engine gave.
pub struct MapReplay {
    /// The estimate after every accepted sample, at that sample's time.
    pub live: Vec<TrackPoint>,
    /// σ of the live estimate per sample, m.
    pub live_std_m: Vec<f64>,
    /// The smoothed path (fixed points, then the open window at the end).
    pub smoothed: Vec<TrackPoint>,
    /// First sample time at which the estimate was converged (None: never).
    pub converged_at_s: Option<f64>,
    pub recoveries: u64,
    pub fixes_used: u64,
    pub fixes_rejected: u64,
    pub rejected: u64,
    /// The particles' mean after each step, at the step's own time (what the live
    /// estimate would be without the step detector's release delay; cached runs only).
    pub at_steps: Vec<TrackPoint>,
    /// The estimate whenever it changed (replays through the engine only).
    pub rows: Vec<stridekit_core::map::MapEstimate>,
}

/// Replay `rec` through a [`MapNavigator`] on `plan` (None: no plan), started at
/// `start` `(x, y, σ)` when given, with `fixes` pushed at their times.
pub fn replay_map(
    rec: &InertialRecording,
    plan: Option<Arc<FloorPlan>>,
    config: &MapConfig,
    start: Option<(f64, f64, f64)>,
    fixes: &[MapFix],
) -> Result<MapReplay, String> {
    let mut m =
        MapNavigator::new(*config, plan.into_iter().collect()).map_err(|e| e.to_string())?;
    if let Some((x, y, s)) = start {
        m.start_at(x, y, Some(s), None).map_err(|e| e.to_string())?;
    }
    let mut out = MapReplay {
        live: Vec::with_capacity(rec.samples.len()),
        live_std_m: Vec::with_capacity(rec.samples.len()),
        smoothed: Vec::new(),
        converged_at_s: None,
        recoveries: 0,
        fixes_used: 0,
        fixes_rejected: 0,
        rejected: 0,
        at_steps: Vec::new(),
        rows: Vec::new(),
    };
    let (mut fi, mut fixed) = (0, 0u64);
    for s in &rec.samples {
        while fi < fixes.len() && fixes[fi].t_s <= s.t_s {
            if m.push_fix(&fixes[fi]).is_err() {
                out.rejected += 1;
            }
            fi += 1;
        }
        let imu = ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: s.mag_ut,
        };
        if m.push_imu(&imu).is_err() {
            out.rejected += 1;
            continue;
        }
        let Some(e) = m.estimate() else { continue };
        if e.flags.converged && out.converged_at_s.is_none() {
            out.converged_at_s = Some(s.t_s);
        }
        let changed = out
            .rows
            .last()
            .is_none_or(|r| (r.x_m, r.y_m, r.flags, r.floor) != (e.x_m, e.y_m, e.flags, e.floor));
        if changed {
            out.rows.push(e);
        }
        out.live.push(TrackPoint {
            t_s: s.t_s,
            x_m: e.x_m,
            y_m: e.y_m,
            distance_m: e.distance_m,
        });
        out.live_std_m.push(e.position_std_m);
        out.smoothed
            .extend(m.smoothed_since(fixed).map(smoothed_point));
        fixed = m.smoothed_fixed();
    }
    m.smoothed_window(|p| out.smoothed.push(smoothed_point(p)));
    if let Some(e) = m.estimate() {
        out.recoveries = e.recoveries;
        out.fixes_used = e.fixes_used;
        out.fixes_rejected = e.fixes_rejected;
    }
    // The smoothed path starts where the walk started.
    if let (Some(s), Some(first)) = (start, rec.samples.first()) {
        out.smoothed.insert(
            0,
            TrackPoint {
                t_s: first.t_s,
                x_m: s.0,
                y_m: s.1,
                distance_m: 0.0,
            },
        );
    }
    Ok(out)
}

/// The navigator's output for one walk, kept to run the particles again without
/// the navigator (what [`MapNavigator`] hands its [`MapMatcher`], in the same order).
pub struct NavCache {
    /// Per accepted sample: time, distance walked after it, whether it had a
    /// magnetometer reading, and the range of `steps` the navigator placed with it.
    pub samples: Vec<(f64, f64, bool, std::ops::Range<usize>)>,
    pub steps: Vec<NavStep>,
}

/// Run the navigator over a walk once.
pub fn nav_cache(rec: &InertialRecording, config: &MapConfig) -> Result<NavCache, String> {
    let mut nav = PhoneNavigator::new(config.navigator).map_err(|e| e.to_string())?;
    let mut out = NavCache {
        samples: Vec::with_capacity(rec.samples.len()),
        steps: Vec::new(),
    };
    let mut placed = 0u64;
    for s in &rec.samples {
        let imu = ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: s.mag_ut,
        };
        if nav.push_imu(&imu).is_err() {
            continue;
        }
        let first = out.steps.len();
        out.steps.extend(nav.steps_since(placed));
        placed = nav.recent_steps().1;
        let e = nav
            .estimate()
            .expect("an estimate after an accepted sample");
        out.samples.push((
            e.t_s,
            e.distance_m,
            s.mag_ut.is_some(),
            first..out.steps.len(),
        ));
    }
    Ok(out)
}

/// The particles over a cached walk, exactly as [`MapNavigator`] runs them (a test
/// checks it): the live estimate after every sample, and the smoothed path.
pub fn run_cached(
    cache: &NavCache,
    plan: Arc<FloorPlan>,
    config: &MapConfig,
    start: Option<(f64, f64, f64)>,
    fixes: &[MapFix],
) -> Result<MapReplay, String> {
    let mut m = MapMatcher::new(*config, vec![plan]).map_err(|e| e.to_string())?;
    if let Some(start) = start {
        m.start_at(start.0, start.1, start.2, None)
            .map_err(|e| e.to_string())?;
    }
    let mut out = MapReplay {
        live: Vec::with_capacity(cache.samples.len()),
        live_std_m: Vec::with_capacity(cache.samples.len()),
        smoothed: Vec::new(),
        converged_at_s: None,
        recoveries: 0,
        fixes_used: 0,
        fixes_rejected: 0,
        rejected: 0,
        at_steps: Vec::new(),
        rows: Vec::new(),
    };
    let (mut fi, mut fixed) = (0, 0u64);
    let (mut last_t, mut last_d) = (f64::NAN, 0.0);
    for (t, d, mag, range) in &cache.samples {
        while fi < fixes.len() && fixes[fi].t_s <= *t {
            m.push_fix(&fixes[fi], last_t, last_d)
                .map_err(|e| e.to_string())?;
            fi += 1;
        }
        if *mag {
            m.set_absolute_heading(true);
        }
        for st in &cache.steps[range.clone()] {
            m.step(st, *d);
            let s = m.state();
            out.at_steps.push(TrackPoint {
                t_s: st.t_s,
                x_m: s.x_m,
                y_m: s.y_m,
                distance_m: *d,
            });
        }
        m.tick(*t, *d);
        (last_t, last_d) = (*t, *d);
        let s = m.state();
        if s.flags.converged && out.converged_at_s.is_none() {
            out.converged_at_s = Some(*t);
        }
        out.live.push(TrackPoint {
            t_s: *t,
            x_m: s.x_m,
            y_m: s.y_m,
            distance_m: *d,
        });
        out.live_std_m.push(s.position_std_m);
        out.smoothed
            .extend(m.smoothed_since(fixed).map(smoothed_point));
        fixed = m.smoothed_fixed();
    }
    m.smoothed_window(|p| out.smoothed.push(smoothed_point(p)));
    let s = m.state();
    out.recoveries = s.recoveries;
    out.fixes_used = s.fixes_used;
    out.fixes_rejected = s.fixes_rejected;
    if let (Some(&(t0, ..)), Some(start)) = (cache.samples.first(), start) {
        let p = TrackPoint {
            t_s: t0,
            x_m: start.0,
            y_m: start.1,
            distance_m: 0.0,
        };
        out.smoothed.insert(0, p);
        out.at_steps.insert(0, p);
    }
    Ok(out)
}

/// A point of the smoothed path as a track point (the smoothed path carries no distance).
fn smoothed_point(p: SmoothedPoint) -> TrackPoint {
    TrackPoint {
        t_s: p.t_s,
        x_m: p.x_m,
        y_m: p.y_m,
        distance_m: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The evaluation's cached runs are the engine's, bit for bit: one real walk on
    /// its plan with two made fixes (skipped when the shared data is absent).
    #[test]
    fn cached_runs_are_the_engine() {
        let Some(dir) = stridekit_formats::data_dir().map(|d| d.join("phone-indoor/site1/F2"))
        else {
            eprintln!("skipping: the shared data folder is absent (set STRIDEKIT_DATA)");
            return;
        };
        let log = dir.join("5dda52519191710006b573c7.txt.gz");
        if !log.is_file() {
            eprintln!("skipping: {} is absent", log.display());
            return;
        }
        let walk = crate::pdr::walks::load_walk(&log).unwrap();
        let plan = Arc::new(
            stridekit_formats::read_floor_plan(&dir)
                .unwrap()
                .build()
                .unwrap(),
        );
        let config = MapConfig {
            particles: 300,
            ..MapConfig::default()
        };
        let t = &walk.rec.truth;
        let fixes = [
            MapFix::plan(t[3].0, t[3].1 + 2.0, t[3].2, 4.5),
            MapFix::plan(t[8].0 + 0.3, t[8].1, t[8].2 - 3.0, 4.5),
        ];
        let start = (t[0].1, t[0].2, 1.0);
        let engine = replay_map(
            &walk.rec,
            Some(Arc::clone(&plan)),
            &config,
            Some(start),
            &fixes,
        )
        .unwrap();
        let cache = nav_cache(&walk.rec, &config).unwrap();
        let cached = run_cached(&cache, plan, &config, Some(start), &fixes).unwrap();
        assert_eq!(engine.live, cached.live);
        assert_eq!(engine.smoothed, cached.smoothed);
        assert_eq!(
            (engine.fixes_used, engine.fixes_rejected, engine.recoveries),
            (cached.fixes_used, cached.fixes_rejected, cached.recoveries)
        );
        assert!(engine.live.len() > 1000 && engine.fixes_used + engine.fixes_rejected == 2);
    }
}
