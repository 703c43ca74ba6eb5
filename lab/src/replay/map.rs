//! `stridekit pdr FILE --map FLOORDIR|FILE`: a phone recording on a floor plan through
//! the map engine (`MapNavigator`), one row each time the estimate changed (plan
//! metres: live estimate, σ, the smoothed path at that time, flags), then rendered as
//! the CSV, both tracks on the plan's image (SVG) and the summary.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use stridekit_core::map::{FloorPlan, MapConfig};
use stridekit_formats::{read_floor_plan, PlanFile, PlanFileError};

use super::basis::PDR_PRIOR;
use super::ReplayError;
use crate::pdr::maps::{map_score, replay_map, MapReplay, START_SIGMA_M};
use crate::pdr::mapsvg::{map_svg, Layer};
use crate::pdr::metrics::{track_at, TrackPoint};
use crate::pdr::walks::Walk;

/// The CSV header.
const HEADER: &str = "t_s,x_m,y_m,position_std_m,smoothed_x_m,smoothed_y_m,floor,converged,ambiguous,recovered,steps";

/// A walk replayed on a plan.
pub struct MapWalk {
    pub walk: Walk,
    /// The floor folder or GeoJSON file given.
    pub map: PathBuf,
    pub plan_file: PlanFile,
    pub plan: Arc<FloorPlan>,
    /// Where the start came from, for the summary.
    pub start_said: String,
    pub replay: MapReplay,
}

/// Replays `walk` on the plan at `map` (a floor folder: `geojson_map.json`,
/// `floor_info.json`, `floor_image.png`; or one GeoJSON file), started at `start`
/// (x, y, σ in plan metres; σ defaults to [`START_SIGMA_M`]), else at the log's first
/// waypoint, else nowhere (global localisation).
pub fn replay(
    walk: Walk,
    map: &Path,
    start: Option<(f64, f64, Option<f64>)>,
) -> Result<MapWalk, ReplayError> {
    let plan_file = read_floor_plan(map).map_err(|e| match e {
        PlanFileError::Io { .. } => e.to_string(), // names the file it could not read
        e => format!("{}: {e}", map.display()),
    })?;
    let plan = Arc::new(
        plan_file
            .build()
            .map_err(|e| format!("{}: {e}", map.display()))?,
    );
    let (start, start_said) = start_of(&walk, start);
    let replay = replay_map(
        &walk.rec,
        Some(Arc::clone(&plan)),
        &MapConfig::default(),
        start,
        &[],
    )?;
    Ok(MapWalk {
        walk,
        map: map.to_path_buf(),
        plan_file,
        plan,
        start_said,
        replay,
    })
}

/// The start `(x, y, σ)` and where it came from.
fn start_of(
    walk: &Walk,
    given: Option<(f64, f64, Option<f64>)>,
) -> (Option<(f64, f64, f64)>, String) {
    match (given, walk.rec.truth.first()) {
        (Some((x, y, s)), _) => (
            Some((x, y, s.unwrap_or(START_SIGMA_M))),
            "from --start".to_string(),
        ),
        (None, Some(w)) => (
            Some((w.1, w.2, START_SIGMA_M)),
            "at the log's first waypoint".to_string(),
        ),
        (None, None) => (
            None,
            "none given and no waypoint in the log: global localisation over the floor".to_string(),
        ),
    }
}

impl MapWalk {
    /// The CSV, one row per change of the estimate.
    pub fn write_csv(&self, f: &mut dyn Write) -> std::io::Result<()> {
        writeln!(f, "{HEADER}")?;
        let r = &self.replay;
        for e in &r.rows {
            let (sx, sy, _) = track_at(&r.smoothed, e.t_s);
            writeln!(
                f,
                "{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{},{},{},{},{}",
                e.t_s,
                e.x_m,
                e.y_m,
                e.position_std_m,
                sx,
                sy,
                e.floor.map_or(String::new(), |f| f.to_string()),
                u8::from(e.flags.converged),
                u8::from(e.flags.ambiguous),
                u8::from(e.flags.recovered),
                e.steps
            )?;
        }
        Ok(())
    }

    /// The live and smoothed tracks and the waypoints on the plan's image (when the
    /// folder has `floor_image.png`), as SVG.
    pub fn chart(&self, svg: &Path) -> Result<(), String> {
        let image = if self.map.is_dir() {
            self.map.join("floor_image.png")
        } else {
            self.map.with_file_name("floor_image.png")
        };
        let pts =
            |t: &[TrackPoint]| -> Vec<(f64, f64)> { t.iter().map(|p| (p.x_m, p.y_m)).collect() };
        let (live, smoothed) = (pts(&self.replay.live), pts(&self.replay.smoothed));
        let truth: Vec<(f64, f64)> = self.walk.rec.truth.iter().map(|w| (w.1, w.2)).collect();
        let layer = |name, color, points, dots| Layer {
            name,
            color,
            points,
            dots,
        };
        map_svg(
            svg,
            &self.walk.rec.name,
            &self.plan,
            image.is_file().then_some(image.as_path()),
            &[
                layer("live", "#1f77b4", &live, false),
                layer("smoothed", "#2ca02c", &smoothed, false),
                layer("waypoints", "#d62728", &truth, false),
                layer("", "#d62728", &truth, true),
            ],
        )
    }

    /// A step was detected.
    pub fn walked(&self) -> bool {
        self.replay.rows.last().is_some_and(|e| e.steps > 0)
    }

    /// The summary; `written_to` names where the CSV went, `svg` the plot if any.
    pub fn summary(&self, written_to: &str, svg: Option<&Path>) -> String {
        let mut summary = self.headline(written_to, svg);
        let (r, wp) = (&self.replay, &self.walk.rec.truth);
        if r.rejected > 0 {
            summary += &format!("rejected samples: {}\n", r.rejected);
        }
        if wp.len() >= 2 {
            let none = vec![false; wp.len()];
            for (name, track) in [("live", &r.live), ("smoothed", &r.smoothed)] {
                if let Some(m) = map_score(track, wp, &none) {
                    summary += &format!(
                        "{name}: map-frame RMSE {:.2} m over {} waypoints after the first, {:.2} m at the last\n",
                        m.rmse_m,
                        wp.len() - 1,
                        m.end_m
                    );
                }
            }
        }
        if self.walked() {
            summary += &format!(
                "rests on: the floor plan's walls and the start; step length: {PDR_PRIOR}, \
                 its scale learned per particle; heading: the magnetometer (north) and the \
                 gyroscope, its offset learned per particle\n"
            );
        }
        summary.trim_end().to_string()
    }

    /// The first three lines: the plan, the output, the walk.
    fn headline(&self, written_to: &str, svg: Option<&Path>) -> String {
        let (r, plan, plan_file) = (&self.replay, &self.plan, &self.plan_file);
        let last = r.rows.last();
        format!(
            "{}: {} samples on floor {} of {} ({} walls, built from {} features{}); start {}\n\
             trajectory {} ({} rows){}\n\
             {} steps, {:.1} m walked; {} recoveries{}\n",
            self.walk.rec.name,
            self.walk.rec.samples.len(),
            plan.floor(),
            self.map.display(),
            plan.walls().len(),
            plan_file.geometry.walkable.len() + plan_file.geometry.obstacles.len(),
            if plan_file.skipped_features > 0 {
                format!(
                    ", {} features that are not polygons skipped",
                    plan_file.skipped_features
                )
            } else {
                String::new()
            },
            self.start_said,
            written_to,
            r.rows.len(),
            svg.map(|s| format!(", plot {}", s.display()))
                .unwrap_or_default(),
            last.map_or(0, |e| e.steps),
            last.map_or(0.0, |e| e.distance_m),
            r.recoveries,
            match r.converged_at_s {
                Some(t) => format!(", converged {:.1} s after the start", t - r.live[0].t_s),
                None => ", never converged".into(),
            }
        )
    }
}
