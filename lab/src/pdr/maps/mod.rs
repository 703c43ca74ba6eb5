//! `stridekit eval pdr --data DIR --maps`: the error a user sees on the floor plan.
//!
//! Every walk starts at its first waypoint (the app knows where the walk began) on
//! its floor's plan (`geojson_map.json` + `floor_info.json` in the walk's folder), and
//! is scored in the plan's frame with nothing forgiven: no rotation, no translation.
//! Per walk: the RMSE over its waypoints after the first (the track interpolated at
//! their times) and the error at the last one; per floor and overall, the median and
//! 90th percentile of the RMSE and the median end error, for:
//!
//! - no plan: the dead-reckoned track moved to the first waypoint, magnetic north as
//!   the plan's north (the steps at their own times, and the live estimate);
//! - with the plan: the live estimate of [`MapNavigator`] (what it said at each
//!   sample's time, from the samples up to then) and its smoothed path;
//! - with the plan and fixes every 30 s, made from waypoints plus noise (seeded) and
//!   scored on the other waypoints only;
//! - the configuration chosen leave one floor out from a small grid (heading σ,
//!   roughening, step-scale σ), beside it.

mod replay;
mod rows;
mod score;
mod walks;

use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::map::MapConfig;
use stridekit_core::stats::SIGMA_TO_RADIUS68;

pub use replay::{nav_cache, replay_map, run_cached, MapReplay, NavCache};
pub use rows::{
    global_localisation, lofo_row, no_plan_rows, oracle_rows, score_map_rows, Chosen, Global,
    LOFO_GRID,
};
pub use score::{best_rotation, map_score, quantile, MapScore, Row};
pub use walks::{made_fixes, planned, plans_of_walks, PlanInfo, Planned};

use crate::pdr::real::{floors, load_walks_with_progress};

/// σ of the start at the first waypoint, m.
pub const START_SIGMA_M: f64 = 1.0;
/// Fixes made from the waypoints: one every this many seconds at most...
pub const FIX_EVERY_S: f64 = 30.0;
/// ... with this much Gaussian noise per axis, m, reported as a 68 % radius of
/// `SIGMA_TO_RADIUS68` (1.515) × that.
pub const FIX_NOISE_M: f64 = 3.0;

/// Apply `NAME=VALUE` settings to a configuration.
pub fn apply_sets(mut c: MapConfig, sets: &[(String, f64)]) -> Result<MapConfig, String> {
    for (k, v) in sets {
        match k.as_str() {
            "particles" => c.particles = *v as usize,
            "seed" => c.seed = *v as u64,
            "start_sigma_m" => c.start_sigma_m = *v,
            "heading_sigma_deg" => c.heading_sigma_rad = v.to_radians(),
            "heading_walk_deg_per_sqrt_m" => c.heading_walk_rad_per_sqrt_m = v.to_radians(),
            "step_heading_sigma_deg" => c.step_heading_sigma_rad = v.to_radians(),
            "scale_sigma" => c.scale_sigma = *v,
            "scale_walk_per_sqrt_m" => c.scale_walk_per_sqrt_m = *v,
            "step_length_sigma" => c.step_length_sigma = *v,
            "wall_crossing_weight" => c.wall_crossing_weight = *v,
            "roughen_heading_deg" => c.roughen_heading_rad = v.to_radians(),
            "roughen_scale" => c.roughen_scale = *v,
            "smoothing_lag_steps" => c.smoothing_lag_steps = *v as usize,
            "declination_deg" => {
                c.declination = stridekit_core::map::Declination::Fixed(v.to_radians())
            }
            _ => return Err(format!("unknown map setting {k:?}")),
        }
    }
    c.validate().map_err(|e| e.to_string())?;
    Ok(c)
}

/// Every combination of the settings: a name given several values is swept.
pub fn combinations(sets: &[(String, f64)]) -> Vec<Vec<(String, f64)>> {
    let mut names: Vec<&String> = sets.iter().map(|s| &s.0).collect();
    names.dedup();
    let mut seen = Vec::new();
    names.retain(|n| {
        let new = !seen.contains(n);
        seen.push(*n);
        new
    });
    let mut out: Vec<Vec<(String, f64)>> = vec![Vec::new()];
    for n in names {
        let values: Vec<f64> = sets.iter().filter(|s| &s.0 == n).map(|s| s.1).collect();
        out = out
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((n.clone(), *v));
                    c
                })
            })
            .collect();
    }
    out
}

/// The whole evaluation as markdown (a sweep when a setting is given several values).
pub fn run(dir: &Path, sets: &[(String, f64)]) -> Result<String, String> {
    let combos = combinations(sets);
    if combos.len() > 1 {
        return sweep(dir, &combos);
    }
    Ok(evaluate(dir, sets)?.render())
}

/// The map-frame evaluation of one configuration, rendered by [`MapsReport::render`].
pub struct MapsReport {
    /// The folder of the walks, as displayed.
    dir: String,
    /// Walks read, and those with a floor plan.
    walks: usize,
    planned: usize,
    floors: Vec<String>,
    /// No plan, with the plan (live, smoothed; without and with fixes), leave one
    /// floor out, and the oracle bounds, in table order.
    rows: Vec<Row>,
    /// The declination applied to the no-plan tracks, rad.
    declination_rad: f64,
    /// Per floor: p10, median and p90 of the no-plan tracks' best rotation, degrees.
    heading: Vec<(String, [f64; 3])>,
    chosen: Chosen,
    config: MapConfig,
    /// The 10 walks of the largest live RMSE with the plan.
    worst: Vec<WorstWalk>,
    global: Global,
    /// Recoveries with the plan over all walks, and the walks replayed.
    recoveries: u64,
    runs: usize,
    infos: std::collections::BTreeMap<std::path::PathBuf, PlanInfo>,
}

/// One of the worst walks with the plan (live), beside its no-plan figure.
struct WorstWalk {
    floor: String,
    name: String,
    live_rmse_m: f64,
    no_plan_rmse_m: f64,
    recoveries: u64,
}

/// Every walk under `dir` with a plan, scored without the plan, with it (with and
/// without fixes), leave one floor out, against the oracle bounds and started nowhere.
pub fn evaluate(dir: &Path, sets: &[(String, f64)]) -> Result<MapsReport, String> {
    let walks = load_walks_with_progress(dir)?;
    let (plans, infos) = plans_of_walks(dir, &walks)?;
    let config = apply_sets(MapConfig::default(), sets)?;
    let planned = planned(&walks, &plans, &config)?;
    if planned.is_empty() {
        return Err(format!(
            "no walk under {} has a floor plan beside it (geojson_map.json and floor_info.json in its folder)",
            dir.display()
        ));
    }
    let no_plan = no_plan_rows(&planned)?;
    let (live, smooth, runs) = score_map_rows(&planned, &config, false, "with the plan")?;
    let (flive, fsmooth, _) = score_map_rows(
        &planned,
        &config,
        true,
        "with the plan and fixes every 30 s",
    )?;
    let (lofo, chosen) = lofo_row(&planned, &config)?;
    let bounds = oracle_rows(&planned, &config, &at_steps(&planned, &runs))?;
    let global = global_localisation(&planned, &config)?;
    let floors = floors(&walks);
    let worst = worst_walks(&planned, &live, &no_plan.rows[0], &runs);
    let heading = floors
        .iter()
        .map(|f| (f.clone(), heading_quantiles(&no_plan.rotation, f)))
        .collect();
    let mut rows = no_plan.rows;
    rows.extend([live, smooth, flive, fsmooth, lofo]);
    rows.extend(bounds);
    Ok(MapsReport {
        dir: dir.display().to_string(),
        walks: walks.len(),
        planned: planned.len(),
        floors,
        rows,
        declination_rad: no_plan.declination_rad,
        heading,
        chosen,
        config,
        worst,
        global,
        recoveries: runs.iter().map(|r| r.recoveries).sum(),
        runs: runs.len(),
        infos,
    })
}

/// The live estimate's score at the step times of each walk with the plan.
fn at_steps(planned: &[Planned], runs: &[MapReplay]) -> Row {
    let mut at_steps = Row {
        name: String::new(),
        by_walk: Vec::new(),
    };
    for (p, r) in planned.iter().zip(runs) {
        let none = vec![false; p.walk.rec.truth.len()];
        if let Some(s) = map_score(&r.at_steps, &p.walk.rec.truth, &none) {
            at_steps.by_walk.push((p.walk.floor.clone(), s));
        }
    }
    at_steps
}

/// The 10 walks of the largest live RMSE (`live`), beside their no-plan RMSE.
fn worst_walks(
    planned: &[Planned],
    live: &Row,
    no_plan: &Row,
    runs: &[MapReplay],
) -> Vec<WorstWalk> {
    let mut worst: Vec<(f64, usize)> = live
        .by_walk
        .iter()
        .enumerate()
        .map(|(i, s)| (s.1.rmse_m, i))
        .collect();
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    worst
        .iter()
        .take(10)
        .map(|&(e, i)| WorstWalk {
            floor: planned[i].walk.floor.clone(),
            name: planned[i].walk.rec.name.clone(),
            live_rmse_m: e,
            no_plan_rmse_m: no_plan.by_walk.get(i).map_or(f64::NAN, |s| s.1.rmse_m),
            recoveries: runs[i].recoveries,
        })
        .collect()
}

/// p10, median and p90 of the best rotations on floor `f`, degrees.
fn heading_quantiles(rotation: &[(String, f64)], f: &str) -> [f64; 3] {
    let v: Vec<f64> = rotation
        .iter()
        .filter(|r| r.0 == f)
        .map(|r| r.1.to_degrees())
        .collect();
    [0.1, 0.5, 0.9].map(|q| quantile(v.iter().copied(), q))
}

impl MapsReport {
    /// The tables overall and per floor, then the heading, leave-one-floor-out,
    /// worst-walk, global-localisation and plan sections.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Map frame ({} walks with a floor plan under {}; {} without): each walk starts at its first waypoint (σ {START_SIGMA_M} m with the plan), scored in the plan's metres with nothing forgiven. Cells: walks | median RMSE over the waypoints after the first | p90 RMSE | median error at the last waypoint. Fixes: made from the waypoints, one at most every {FIX_EVERY_S} s, moved by {FIX_NOISE_M} m Gaussian noise per axis (seeded per walk), reported with a 68 % radius of {:.1} m; those waypoints are not scored.\n",
            self.planned,
            self.dir,
            self.walks - self.planned,
            SIGMA_TO_RADIUS68 * FIX_NOISE_M
        );
        self.render_tables(&mut out);
        self.render_heading(&mut out);
        self.render_lofo(&mut out);
        self.render_worst(&mut out);
        self.render_global(&mut out);
        self.render_plans(&mut out);
        out
    }

    fn render_tables(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "| method | walks | RMSE median | RMSE p90 | end median |\n|---|---|---|---|---|"
        );
        for r in &self.rows {
            let _ = writeln!(out, "| {} | {} |", r.name, r.overall());
        }
        for f in &self.floors {
            let _ = writeln!(out, "\nFloor {f}:\n\n| method | walks | RMSE median | RMSE p90 | end median |\n|---|---|---|---|---|");
            for r in &self.rows {
                let _ = writeln!(out, "| {} | {} |", r.name, r.floor(f));
            }
        }
    }

    fn render_heading(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "\nHeading without a plan: the rotation that best turns each start-pinned track (true north: declination {:+.1}° applied) onto its waypoints, degrees anticlockwise; p10 / median / p90 per floor:\n",
            self.declination_rad.to_degrees()
        );
        for (f, q) in &self.heading {
            let _ = writeln!(out, "- {f}: {:+.1} / {:+.1} / {:+.1}", q[0], q[1], q[2]);
        }
    }

    fn render_lofo(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "\nLeave one floor out (from {} candidates: heading σ, roughening, step-scale σ):\n",
            LOFO_GRID.len()
        );
        for (f, h, r, k) in &self.chosen {
            let _ = writeln!(
                out,
                "- without {f}: heading σ {h}°, roughening {r}°, step-scale σ {k}"
            );
        }
        let c = &self.config;
        let _ = writeln!(
            out,
            "\nThe default: heading σ {:.0}°, roughening {:.0}°, step-scale σ {}, {} particles.",
            c.heading_sigma_rad.to_degrees(),
            c.roughen_heading_rad.to_degrees(),
            c.scale_sigma,
            c.particles
        );
    }

    fn render_worst(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "\nWorst walks with the plan (live RMSE; no plan, magnetic north; recoveries):\n"
        );
        for w in &self.worst {
            let _ = writeln!(
                out,
                "- {}/{}: {:.2} m (no plan {:.2} m; {} recoveries)",
                w.floor, w.name, w.live_rmse_m, w.no_plan_rmse_m, w.recoveries
            );
        }
    }

    fn render_global(&self, out: &mut String) {
        let g = &self.global;
        let _ = writeln!(
            out,
            "\nGlobal localisation (no start: the particles over the walk's whole floor): {} of {} walks converged (σ < 2 m, not ambiguous) before they ended, a median {:.1} s after the start, then {:.1} m from the truth (median); {} of them more than {:.0} m off (converged to the wrong place).",
            g.converged,
            g.walks,
            g.median_time_s,
            g.median_error_m,
            g.wrong_place,
            rows::WRONG_PLACE_M
        );
        let _ = writeln!(
            out,
            "\nWith the plan: {} recoveries (every particle ruled out) over {} walks.",
            self.recoveries, self.runs
        );
    }

    fn render_plans(&self, out: &mut String) {
        let _ = writeln!(out, "\nPlans:\n\n| folder | walks | waypoints walkable | read | build | memory | walkable area |\n|---|---|---|---|---|---|---|");
        for (folder, i) in &self.infos {
            let _ = writeln!(
                out,
                "| {} | {} | {:.1} % | {:.1} ms | {:.1} ms | {:.2} MB | {:.0} m² |",
                folder.display(),
                i.walks,
                100.0 * i.walkable as f64 / i.waypoints.max(1) as f64,
                i.read_ms,
                i.build_ms,
                i.plan.heap_bytes() as f64 / 1e6,
                i.plan.walkable_area_m2()
            );
        }
    }
}

/// Each combination of settings on every walk (no fixes): the live and smoothed
/// figures overall and the live median per floor, one line each (sensitivity).
fn sweep(dir: &Path, combos: &[Vec<(String, f64)>]) -> Result<String, String> {
    let walks = load_walks_with_progress(dir)?;
    let (plans, _) = plans_of_walks(dir, &walks)?;
    let base = MapConfig::default();
    let planned = planned(&walks, &plans, &base)?;
    let fl = floors(&walks);
    let mut out = format!(
        "| settings | live median | live p90 | live end | smoothed median | smoothed p90 | {} |\n|---|---|---|---|---|---|{}\n",
        fl.join(" | "),
        "---|".repeat(fl.len())
    );
    for c in combos {
        let config = apply_sets(base, c)?;
        let label = c
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(" ");
        let (live, smooth, _) = score_map_rows(&planned, &config, false, &label)?;
        let q = |r: &Row, q: f64| quantile(r.by_walk.iter().map(|s| s.1.rmse_m), q);
        let per_floor: Vec<String> = fl
            .iter()
            .map(|f| format!("{:.2}", live.median_where(|g| g == f)))
            .collect();
        out += &format!(
            "| {label} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {} |\n",
            q(&live, 0.5),
            q(&live, 0.9),
            quantile(live.by_walk.iter().map(|s| s.1.end_m), 0.5),
            q(&smooth, 0.5),
            q(&smooth, 0.9),
            per_floor.join(" | ")
        );
        eprintln!("{}", out.lines().last().unwrap_or(""));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_apply_and_several_values_of_one_are_swept() {
        let c = apply_sets(
            MapConfig::default(),
            &[
                ("particles".into(), 300.0),
                ("heading_sigma_deg".into(), 20.0),
            ],
        )
        .unwrap();
        assert_eq!(c.particles, 300);
        assert!((c.heading_sigma_rad.to_degrees() - 20.0).abs() < 1e-9);
        assert!(apply_sets(MapConfig::default(), &[("nonsense".into(), 1.0)]).is_err());
        assert!(apply_sets(MapConfig::default(), &[("particles".into(), 1.0)]).is_err());
        let sets = [
            ("a".to_string(), 1.0),
            ("b".to_string(), 2.0),
            ("a".to_string(), 3.0),
        ];
        let c = combinations(&sets);
        assert_eq!(c.len(), 2);
        assert_eq!(c[1], vec![("a".to_string(), 3.0), ("b".to_string(), 2.0)]);
        assert_eq!(combinations(&[]), vec![Vec::new()]);
    }
}
