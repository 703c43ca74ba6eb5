//! The walks that have a plan: each walk's floor plan (its folder's
//! `geojson_map.json` + `floor_info.json`, built once per folder, with what it cost),
//! its navigator run, and the fixes made from its waypoints.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use stridekit_core::map::{FloorPlan, MapConfig, MapFix};
use stridekit_core::stats::SIGMA_TO_RADIUS68;
use stridekit_formats::{list_android_logs, read_floor_plan};

use super::replay::{nav_cache, NavCache};
use super::{FIX_EVERY_S, FIX_NOISE_M};
use crate::pdr::walks::Walk;

/// The plan of every walk (None: its folder has none) and the plans by folder.
pub type WalkPlans = (Vec<Option<Arc<FloorPlan>>>, BTreeMap<PathBuf, PlanInfo>);

/// Fixes made from a walk's waypoints: the first waypoint at least [`FIX_EVERY_S`]
/// after the start, then the first at least that long after it, and so on; each moved
/// by Gaussian noise of [`FIX_NOISE_M`] per axis (seeded by `seed`). Returns the fixes
/// and which waypoints they came from (not scored).
pub fn made_fixes(waypoints: &[(f64, f64, f64)], seed: u64) -> (Vec<MapFix>, Vec<bool>) {
    let mut rng = stridekit_sim::rng::Rng::new(seed);
    let mut used = vec![false; waypoints.len()];
    let mut fixes = Vec::new();
    let Some(&(t0, _, _)) = waypoints.first() else {
        return (fixes, used);
    };
    let mut next = t0 + FIX_EVERY_S;
    for (i, w) in waypoints.iter().enumerate().skip(1) {
        if w.0 >= next {
            used[i] = true;
            fixes.push(MapFix::plan(
                w.0,
                w.1 + FIX_NOISE_M * rng.normal(),
                w.2 + FIX_NOISE_M * rng.normal(),
                SIGMA_TO_RADIUS68 * FIX_NOISE_M,
            ));
            next = w.0 + FIX_EVERY_S;
        }
    }
    (fixes, used)
}

/// The plans of the walks: walk name → its folder's plan (built once per folder).
pub fn plans_of_walks(dir: &Path, walks: &[Walk]) -> Result<WalkPlans, String> {
    let paths = list_android_logs(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let by_name: BTreeMap<String, PathBuf> = paths
        .iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_string_lossy().to_string();
            let stem = name
                .strip_suffix(".gz")
                .unwrap_or(&name)
                .strip_suffix(".txt")
                .unwrap_or(&name)
                .to_string();
            Some((stem, p.parent()?.to_path_buf()))
        })
        .collect();
    let mut built: BTreeMap<PathBuf, PlanInfo> = BTreeMap::new();
    let mut out = Vec::with_capacity(walks.len());
    for w in walks {
        let Some(folder) = by_name.get(&w.rec.name) else {
            out.push(None);
            continue;
        };
        if !folder.join("geojson_map.json").is_file() {
            out.push(None);
            continue;
        }
        if !built.contains_key(folder) {
            let t = std::time::Instant::now();
            let file = read_floor_plan(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
            let read_ms = t.elapsed().as_secs_f64() * 1e3;
            let t = std::time::Instant::now();
            let plan = file
                .build()
                .map_err(|e| format!("{}: {e}", folder.display()))?;
            let build_ms = t.elapsed().as_secs_f64() * 1e3;
            built.insert(
                folder.clone(),
                PlanInfo {
                    plan: Arc::new(plan),
                    read_ms,
                    build_ms,
                    walks: 0,
                    waypoints: 0,
                    walkable: 0,
                },
            );
        }
        let info = built.get_mut(folder).expect("inserted above");
        info.walks += 1;
        for wp in &w.rec.truth {
            info.waypoints += 1;
            info.walkable += usize::from(info.plan.is_walkable([wp.1, wp.2]));
        }
        out.push(Some(Arc::clone(&info.plan)));
    }
    Ok((out, built))
}

/// A plan and what it cost.
pub struct PlanInfo {
    pub plan: Arc<FloorPlan>,
    pub read_ms: f64,
    pub build_ms: f64,
    pub walks: usize,
    pub waypoints: usize,
    pub walkable: usize,
}

/// The walks that have a plan, with it.
pub struct Planned<'a> {
    pub walk: &'a Walk,
    pub plan: Arc<FloorPlan>,
    pub cache: NavCache,
    /// A seed of its own (for the made fixes).
    pub seed: u64,
}

/// Seed of a walk for its made fixes: FNV-1a of its name.
pub fn seed_of(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The walks with a plan, each with its navigator run (progress while it runs).
pub fn planned<'a>(
    walks: &'a [Walk],
    plans: &[Option<Arc<FloorPlan>>],
    config: &MapConfig,
) -> Result<Vec<Planned<'a>>, String> {
    let pb = crate::progress::bar(walks.len(), "dead reckoning");
    let mut out = Vec::new();
    for (w, p) in walks.iter().zip(plans) {
        pb.inc(1);
        if let Some(p) = p {
            out.push(Planned {
                walk: w,
                plan: Arc::clone(p),
                cache: nav_cache(&w.rec, config)?,
                seed: seed_of(&w.rec.name),
            });
        }
    }
    pb.finish_and_clear();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixes_come_at_most_every_30_s_from_waypoints_and_are_seeded() {
        let wp: Vec<(f64, f64, f64)> = (0..20)
            .map(|i| (10.0 * f64::from(i), f64::from(i), 0.0))
            .collect();
        let (f, used) = made_fixes(&wp, 7);
        // Waypoints at 30, 60, ... 180 s.
        assert_eq!(f.len(), 6);
        assert_eq!(used.iter().filter(|u| **u).count(), 6);
        assert!(used[3] && used[6] && !used[0] && !used[4]);
        assert_eq!(made_fixes(&wp, 7).0, f);
        assert_ne!(made_fixes(&wp, 8).0, f);
        assert_ne!(seed_of("a"), seed_of("b"));
    }
}
