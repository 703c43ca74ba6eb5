//! `stridekit pdr FILE --map FLOORDIR|FILE [--start X,Y[,SIGMA]]`: a phone recording
//! on a floor plan, through the map engine (`MapNavigator`).
//!
//! Writes the CSV, one row each time the estimate changed (a step, a fix), `t_s` on
//! the file's clock, positions in the plan's metres (x east, y north):
//!
//! ```text
//! t_s,x_m,y_m,position_std_m,smoothed_x_m,smoothed_y_m,floor,converged,ambiguous,recovered,steps
//! ```
//!
//! `x_m, y_m` are the live estimate, what the engine said at that time from the
//! samples up to it; `smoothed_x_m, smoothed_y_m` the smoothed path at that time (the
//! path as corrected by everything after it). Beside it (same name, `.svg`) both
//! tracks on the plan's image with the waypoints. The start is `--start`, else the
//! log's first waypoint (σ 1 m), else none: the particles then begin over the whole
//! floor (global localisation, said in the summary).

use std::io::Write;
use std::path::Path;
use std::sync::Arc;

use stridekit_core::map::MapConfig;
use stridekit_formats::{read_floor_plan, PlanFileError};
use stridekit_lab::pdr::maps::{map_score, replay_map, MapReplay, START_SIGMA_M};
use stridekit_lab::pdr::mapsvg::{map_svg, Layer};
use stridekit_lab::pdr::metrics::track_at;
use stridekit_lab::pdr::walks::load_walk;

use crate::basis::PDR_PRIOR;
use crate::commands::pdr::PdrArgs;
use crate::outcome::{write_error, Failure};
use crate::output::{say, Sink};

/// `stridekit pdr FILE --map FLOORDIR|FILE`: `map` is a floor folder
/// (`geojson_map.json`, `floor_info.json`, `floor_image.png`) or one GeoJSON file.
pub fn run(a: &PdrArgs, map: &Path, sink: &Sink) -> Result<(), Failure> {
    let walk = load_walk(&a.file)?;
    if walk.rec.truncated {
        crate::input::warn_truncated(&a.file);
    }
    let plan_file = read_floor_plan(map).map_err(|e| match e {
        PlanFileError::Io { .. } => e.to_string(), // names the file it could not read
        e => format!("{}: {e}", map.display()),
    })?;
    let plan = Arc::new(
        plan_file
            .build()
            .map_err(|e| format!("{}: {e}", map.display()))?,
    );
    let wp = &walk.rec.truth;
    let (start, said) = match (a.start, wp.first()) {
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
    };
    let r = replay_map(
        &walk.rec,
        Some(Arc::clone(&plan)),
        &MapConfig::default(),
        start,
        &[],
    )?;
    write_csv(sink, &r)?;
    let svg = sink.beside("svg");
    let image = if map.is_dir() {
        map.join("floor_image.png")
    } else {
        map.with_file_name("floor_image.png")
    };
    let pts = |t: &[stridekit_lab::pdr::metrics::TrackPoint]| -> Vec<(f64, f64)> {
        t.iter().map(|p| (p.x_m, p.y_m)).collect()
    };
    let (live, smoothed) = (pts(&r.live), pts(&r.smoothed));
    let truth: Vec<(f64, f64)> = wp.iter().map(|w| (w.1, w.2)).collect();
    if let Some(svg) = &svg {
        map_svg(
            svg,
            &walk.rec.name,
            &plan,
            image.is_file().then_some(image.as_path()),
            &[
                Layer {
                    name: "live",
                    color: "#1f77b4",
                    points: &live,
                    dots: false,
                },
                Layer {
                    name: "smoothed",
                    color: "#2ca02c",
                    points: &smoothed,
                    dots: false,
                },
                Layer {
                    name: "waypoints",
                    color: "#d62728",
                    points: &truth,
                    dots: false,
                },
                Layer {
                    name: "",
                    color: "#d62728",
                    points: &truth,
                    dots: true,
                },
            ],
        )?;
    }
    let last = r.rows.last();
    let mut summary = format!(
        "{}: {} samples on floor {} of {} ({} walls, built from {} features{}); start {said}\n\
         trajectory {} ({} rows){}\n\
         {} steps, {:.1} m walked; {} recoveries{}\n",
        walk.rec.name,
        walk.rec.samples.len(),
        plan.floor(),
        map.display(),
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
        sink.name(),
        r.rows.len(),
        svg.as_ref()
            .map(|s| format!(", plot {}", s.display()))
            .unwrap_or_default(),
        last.map_or(0, |e| e.steps),
        last.map_or(0.0, |e| e.distance_m),
        r.recoveries,
        match r.converged_at_s {
            Some(t) => format!(", converged {:.1} s after the start", t - r.live[0].t_s),
            None => ", never converged".into(),
        }
    );
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
    if last.is_some_and(|e| e.steps > 0) {
        summary += &format!(
            "rests on: the floor plan's walls and the start; step length: {PDR_PRIOR}, \
             its scale learned per particle; heading: the magnetometer (north) and the \
             gyroscope, its offset learned per particle\n"
        );
    }
    say!("{}", summary.trim_end());
    if last.is_some_and(|e| e.steps > 0) {
        Ok(())
    } else {
        Err(Failure::Failed("no step detected: no trajectory".into()))
    }
}

fn write_csv(sink: &Sink, r: &MapReplay) -> Result<(), Failure> {
    let name = sink.name();
    let err = write_error(&name);
    let mut f = sink.open()?;
    writeln!(
        f,
        "t_s,x_m,y_m,position_std_m,smoothed_x_m,smoothed_y_m,floor,converged,ambiguous,recovered,steps"
    )
    .map_err(&err)?;
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
        )
        .map_err(&err)?;
    }
    f.flush().map_err(&err)
}
