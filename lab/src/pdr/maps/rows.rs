//! The rows of `eval pdr --maps`: the dead reckoning without a plan (magnetic and
//! true north, and a heading offset learned leave one floor out), the map engine
//! (live, smoothed, with made fixes), its heading settings chosen leave one floor
//! out, and bounds that take the heading and the scale from the walk's own waypoints.

use std::sync::Arc;

use stridekit_core::map::MapConfig;

use super::replay::{run_cached, NavCache};
use super::score::{best_rotation, map_score, pinned, quantile, Row};
use super::walks::{made_fixes, Planned};
use super::{apply_sets, MapReplay, START_SIGMA_M};
use crate::pdr::metrics::TrackPoint;
use crate::pdr::walks::{replay, ReplayOptions};

/// Score every planned walk with the map engine.
pub fn score_map_rows(
    walks: &[Planned],
    config: &MapConfig,
    with_fixes: bool,
    label: &str,
) -> Result<(Row, Row, Vec<MapReplay>), String> {
    let mut live = Row {
        name: format!("{label}, live"),
        by_walk: Vec::new(),
    };
    let mut smooth = Row {
        name: format!("{label}, smoothed"),
        by_walk: Vec::new(),
    };
    let mut runs = Vec::new();
    let pb = crate::progress::bar(walks.len(), label);
    for p in walks {
        pb.inc(1);
        let truth = &p.walk.rec.truth;
        let (fixes, excluded) = if with_fixes {
            made_fixes(truth, p.seed)
        } else {
            (Vec::new(), vec![false; truth.len()])
        };
        let start = (truth[0].1, truth[0].2, START_SIGMA_M);
        let r = run_cached(&p.cache, Arc::clone(&p.plan), config, Some(start), &fixes)?;
        if let Some(s) = map_score(&r.live, truth, &excluded) {
            live.by_walk.push((p.walk.floor.clone(), s));
        }
        if let Some(s) = map_score(&r.smoothed, truth, &excluded) {
            smooth.by_walk.push((p.walk.floor.clone(), s));
        }
        runs.push(r);
    }
    pb.finish_and_clear();
    Ok((live, smooth, runs))
}

/// The dead-reckoned tracks moved to the first waypoint (no plan): rows and, per
/// walk, the best rotation of its track after the declination (floor, rad).
pub struct NoPlan {
    pub rows: Vec<Row>,
    pub rotation: Vec<(String, f64)>,
    pub declination_rad: f64,
}

pub fn no_plan_rows(walks: &[Planned]) -> Result<NoPlan, String> {
    let names = [
        "no plan, start pinned, magnetic north up (steps at their times)",
        "no plan, start pinned, magnetic north up, live",
        "no plan, start pinned, true north up (declination of the plan's place), steps",
        "no plan, start pinned, true north up, live",
        "no plan, start pinned, true north + heading offset learned leave one floor out, steps",
    ];
    let mut rows: Vec<Row> = names
        .iter()
        .map(|n| Row {
            name: n.to_string(),
            by_walk: Vec::new(),
        })
        .collect();
    let mut rotation = Vec::new();
    let mut tracks = Vec::new();
    let mut declination_rad = 0.0;
    let pb = crate::progress::bar(walks.len(), "no plan");
    for p in walks {
        pb.inc(1);
        let truth = &p.walk.rec.truth;
        let r = replay(&p.walk.rec, &ReplayOptions::default())?;
        let d = p.plan.geo_reference().map_or(0.0, |g| {
            let (lat, lon) = g.location_deg();
            stridekit_core::map::declination_rad(lat, lon)
        });
        declination_rad = d;
        let none = vec![false; truth.len()];
        let floor = p.walk.floor.clone();
        for (i, (track, theta)) in [
            (&r.track, 0.0),
            (&r.live, 0.0),
            (&r.track, -d),
            (&r.live, -d),
        ]
        .into_iter()
        .enumerate()
        {
            if let Some(s) = map_score(&pinned(track, truth, theta), truth, &none) {
                rows[i].by_walk.push((floor.clone(), s));
            }
        }
        if let Some(th) = best_rotation(&pinned(&r.track, truth, -d), truth) {
            rotation.push((floor.clone(), th));
        }
        tracks.push((floor, r.track, d));
    }
    pb.finish_and_clear();
    // The heading offset learned on the other floors: the median best rotation there.
    for (p, (floor, track, d)) in walks.iter().zip(&tracks) {
        let truth = &p.walk.rec.truth;
        let learned = quantile(rotation.iter().filter(|r| &r.0 != floor).map(|r| r.1), 0.5);
        if learned.is_finite() {
            let none = vec![false; truth.len()];
            if let Some(s) = map_score(&pinned(track, truth, learned - d), truth, &none) {
                rows[4].by_walk.push((floor.clone(), s));
            }
        }
    }
    Ok(NoPlan {
        rows,
        rotation,
        declination_rad,
    })
}

/// The candidates leave-one-floor-out chooses from: the prior spread of the heading
/// offset (°), the roughening of resampled headings (°) and the prior spread of the
/// step-length scale.
pub const LOFO_GRID: [(f64, f64, f64); 12] = [
    (10.0, 1.0, 0.05),
    (10.0, 3.0, 0.05),
    (15.0, 1.0, 0.05),
    (15.0, 3.0, 0.05),
    (20.0, 1.0, 0.05),
    (20.0, 3.0, 0.05),
    (10.0, 1.0, 0.10),
    (10.0, 3.0, 0.10),
    (15.0, 1.0, 0.10),
    (15.0, 3.0, 0.10),
    (20.0, 1.0, 0.10),
    (20.0, 3.0, 0.10),
];

/// What leave-one-floor-out chose for each floor: (floor, heading σ °, roughening °,
/// step-scale σ).
pub type Chosen = Vec<(String, f64, f64, f64)>;

/// The live estimate with the configuration chosen leave one floor out: for each
/// floor, the candidate of [`LOFO_GRID`] with the lowest median live RMSE on the other
/// floors; and what was chosen (floor, heading σ °, roughening °, step-scale σ).
pub fn lofo_row(planned: &[Planned], base: &MapConfig) -> Result<(Row, Chosen), String> {
    let mut per_candidate = Vec::new();
    for (h, r, k) in LOFO_GRID {
        let c = apply_sets(
            *base,
            &[
                ("heading_sigma_deg".into(), h),
                ("roughen_heading_deg".into(), r),
                ("scale_sigma".into(), k),
            ],
        )?;
        let (live, _, _) = score_map_rows(
            planned,
            &c,
            false,
            &format!("candidate heading σ {h}°, roughening {r}°, step-scale σ {k}"),
        )?;
        per_candidate.push(live);
    }
    let mut fl: Vec<String> = planned.iter().map(|p| p.walk.floor.clone()).collect();
    fl.sort();
    fl.dedup();
    let mut row = Row {
        name: "with the plan, live, settings chosen leave one floor out".into(),
        by_walk: Vec::new(),
    };
    let mut chosen = Vec::new();
    for f in &fl {
        let best = (0..LOFO_GRID.len())
            .min_by(|&a, &b| {
                let m = |i: usize| per_candidate[i].median_where(|g| g != f);
                m(a).total_cmp(&m(b))
            })
            .unwrap_or(0);
        let (h, r, k) = LOFO_GRID[best];
        chosen.push((f.clone(), h, r, k));
        row.by_walk.extend(
            per_candidate[best]
                .by_walk
                .iter()
                .filter(|s| &s.0 == f)
                .cloned(),
        );
    }
    Ok((row, chosen))
}

/// Bounds, not product paths: the particles at each step's own time (no release
/// delay), and with the heading (and the step scale) taken from the walk's own
/// waypoints: the rotation that best fits its start-pinned track, and its polyline
/// against its step lengths.
pub fn oracle_rows(
    planned: &[Planned],
    base: &MapConfig,
    at_steps: &Row,
) -> Result<Vec<Row>, String> {
    let mut heading = Row {
        name: "bound: heading from the walk's own waypoints, live".into(),
        by_walk: Vec::new(),
    };
    let mut both = Row {
        name: "bound: heading and step scale from the walk's own waypoints, at step times".into(),
        by_walk: Vec::new(),
    };
    let pb = crate::progress::bar(planned.len(), "bounds from the waypoints");
    for p in planned {
        pb.inc(1);
        let t = &p.walk.rec.truth;
        let none = vec![false; t.len()];
        let d = p.plan.geo_reference().map_or(0.0, |g| {
            let (lat, lon) = g.location_deg();
            stridekit_core::map::declination_rad(lat, lon)
        });
        let mut dr = vec![TrackPoint {
            t_s: p.cache.samples.first().map_or(t[0].0, |s| s.0),
            ..Default::default()
        }];
        dr.extend(p.cache.steps.iter().map(|st| TrackPoint {
            t_s: st.t_s,
            x_m: st.east_m,
            y_m: st.north_m,
            distance_m: 0.0,
        }));
        let theta = best_rotation(&pinned(&dr, t, -d), t).unwrap_or(0.0);
        let poly: f64 = t
            .windows(2)
            .map(|w| (w[1].1 - w[0].1).hypot(w[1].2 - w[0].2))
            .sum();
        let walked: f64 = p
            .cache
            .steps
            .iter()
            .filter(|s| s.t_s >= t[0].0 && s.t_s <= t[t.len() - 1].0)
            .map(|s| s.length_m)
            .sum();
        let scale = if walked > 1.0 {
            (poly / walked).clamp(0.6, 1.5)
        } else {
            1.0
        };
        let c = MapConfig {
            declination: stridekit_core::map::Declination::Fixed(d - theta),
            heading_sigma_rad: ORACLE_HEADING_SIGMA_RAD,
            ..*base
        };
        let start = (t[0].1, t[0].2, START_SIGMA_M);
        let r = run_cached(&p.cache, Arc::clone(&p.plan), &c, Some(start), &[])?;
        if let Some(s) = map_score(&r.live, t, &none) {
            heading.by_walk.push((p.walk.floor.clone(), s));
        }
        let mut scaled = NavCache {
            samples: p.cache.samples.clone(),
            steps: p.cache.steps.clone(),
        };
        scaled.steps.iter_mut().for_each(|s| s.length_m *= scale);
        let c = MapConfig {
            scale_sigma: ORACLE_SCALE_SIGMA,
            ..c
        };
        let r = run_cached(&scaled, Arc::clone(&p.plan), &c, Some(start), &[])?;
        if let Some(s) = map_score(&r.at_steps, t, &none) {
            both.by_walk.push((p.walk.floor.clone(), s));
        }
    }
    pb.finish_and_clear();
    let steps = Row {
        name: "with the plan, at each step's own time (no release delay; a bound)".into(),
        by_walk: at_steps.by_walk.clone(),
    };
    Ok(vec![steps, heading, both])
}

/// Spreads of the heading and the scale when the bounds take them from the truth.
const ORACLE_HEADING_SIGMA_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;
const ORACLE_SCALE_SIGMA: f64 = 0.02;

/// Global localisation: every walk without a start (the particles over its whole
/// floor). How many walks converged (`converged` at some time), when (seconds after the
/// start, median), how far the estimate was from the truth when they did (median), and
/// how many of those were more than [`WRONG_PLACE_M`] off (converged to the wrong place).
pub struct Global {
    pub walks: usize,
    pub converged: usize,
    pub median_time_s: f64,
    pub median_error_m: f64,
    pub wrong_place: usize,
}

/// Converged this far from the truth is converged to the wrong place, m.
pub const WRONG_PLACE_M: f64 = 5.0;

pub fn global_localisation(planned: &[Planned], config: &MapConfig) -> Result<Global, String> {
    let pb = crate::progress::bar(planned.len(), "global localisation (no start)");
    let (mut times, mut errors, mut wrong) = (Vec::new(), Vec::new(), 0);
    for p in planned {
        pb.inc(1);
        let r = run_cached(&p.cache, Arc::clone(&p.plan), config, None, &[])?;
        let Some(t) = r.converged_at_s else { continue };
        let t0 = r.live.first().map_or(t, |q| q.t_s);
        let (x, y, _) = crate::pdr::metrics::track_at(&r.live, t);
        let (tx, ty) = p.walk.rec.position_at(t);
        let e = (x - tx).hypot(y - ty);
        wrong += usize::from(e > WRONG_PLACE_M);
        times.push(t - t0);
        errors.push(e);
    }
    pb.finish_and_clear();
    Ok(Global {
        walks: planned.len(),
        converged: times.len(),
        median_time_s: quantile(times.iter().copied(), 0.5),
        median_error_m: quantile(errors.iter().copied(), 0.5),
        wrong_place: wrong,
    })
}
