//! `stridekit pdr FILE [--out traj.csv] [--calibration FILE] [--no-mag] [--raw-gyro]`: replay a
//! phone recording (an Android sensor log, `.txt` or `.txt.gz`, or any recording
//! `stridekit-formats` reads) through `PhoneNavigator` with no GNSS.
//!
//! Writes the trajectory CSV, one row per step at the step's own time (`t_s` on the
//! file's clock: ms / 1000 for Android logs), in the navigator's local frame (east /
//! north of where the walk started; north from the magnetometer, or the initial
//! heading with `--no-mag`):
//!
//! ```text
//! t_s,east_m,north_m,step_length_m,azimuth_deg,steps
//! ```
//!
//! and beside it (same name, `.svg`) the track with the recording's waypoints
//! carried into the track's frame by the best rotation + translation (the map's axes
//! are not north-aligned). Rejected samples are skipped and counted by reason; the
//! accuracy measures are printed when the file has at least two waypoints. The
//! summary says what the step length (the model with population parameters, or a
//! calibration) and the heading (magnetometer or not) rest on; a replay with no step
//! (or whose IMU stream was refused for its units) exits 1.

use std::io::Write;

use stridekit_lab::pdr::metrics::{apply_rigid, best_rigid, evaluate, track_at};
use stridekit_lab::pdr::walks::{load_walk, replay, ReplayOptions};
use stridekit_lab::report::{track_chart, Series, Style};

use crate::basis::{PDR_CALIBRATED, PDR_PRIOR};
use crate::commands::pdr::PdrArgs;
use crate::outcome::{check_usable, write_error, Failure};
use crate::output::{say, Sink};

pub fn run(a: &PdrArgs, sink: &Sink) -> Result<(), Failure> {
    let walk = load_walk(&a.file)?;
    if walk.rec.truncated {
        crate::input::warn_truncated(&a.file);
    }
    let calibration = match &a.calibration {
        Some(p) => Some(
            stridekit_lab::pdr::calibrate::read(p)
                .map_err(|e| crate::outcome::usage("--calibration", e))?,
        ),
        None => None,
    };
    let o = ReplayOptions {
        mag: !a.no_mag,
        calibration,
        config: stridekit_core::pdr::NavigatorConfig {
            gyro_calibrated: !a.raw_gyro,
            ..Default::default()
        },
        ..Default::default()
    };
    let r = replay(&walk.rec, &o)?;
    write_csv(sink, &r.steps)?;
    let svg = sink.beside("svg");
    let mut summary = format!(
        "{}: {} samples, {} steps, {:.1} m walked; trajectory {} ({} rows){}\n",
        walk.rec.name,
        walk.rec.samples.len(),
        r.steps.len(),
        r.steps.last().map_or(0.0, |s| s.distance_m),
        sink.name(),
        r.steps.len(),
        svg.as_ref()
            .map(|s| format!(", plot {}", s.display()))
            .unwrap_or_default()
    );
    if r.rejected.total() == 0 {
        summary += "rejected samples: none\n";
    } else {
        summary += &format!("rejected samples: {}\n", r.rejected.total());
        summary += &r.rejected.report();
    }
    for (why, n) in &walk.rec.skipped {
        summary += &format!("  skipped by the reader {n}: {why}\n");
    }
    let wp = &walk.rec.truth;
    let track: Vec<(f64, f64)> = r.track.iter().map(|p| (p.x_m, p.y_m)).collect();
    let mut series = vec![Series {
        name: "PDR track".into(),
        points: track,
        color: None,
        style: Style::Line,
    }];
    if wp.len() >= 2 {
        // Waypoints into the track's frame: the inverse of the best rigid map of the
        // track (at the waypoint times) onto them.
        let est: Vec<(f64, f64)> = wp
            .iter()
            .map(|w| {
                let p = track_at(&r.track, w.0);
                (p.0, p.1)
            })
            .collect();
        let truth: Vec<(f64, f64)> = wp.iter().map(|w| (w.1, w.2)).collect();
        let inv = best_rigid(&truth, &est);
        series.push(Series {
            name: "waypoints (aligned)".into(),
            points: truth.iter().map(|p| apply_rigid(*p, inv)).collect(),
            color: Some((214, 39, 40)),
            style: Style::Line,
        });
        series.push(Series {
            name: String::new(),
            points: truth.iter().map(|p| apply_rigid(*p, inv)).collect(),
            style: Style::Points,
            color: Some((214, 39, 40)),
        });
        if let Some(m) = evaluate(&r.track, wp) {
            summary += &format!(
                "against {} waypoints ({:.1} m polyline): ATE {:.2} m, start-pinned {:.2} m, end {:.1} %, distance {:+.1} %\n",
                wp.len(),
                m.polyline_m,
                m.ate_m,
                m.start_pinned_m,
                m.end_pct,
                m.distance_pct
            );
        }
    }
    if let Some(svg) = &svg {
        track_chart(svg, &walk.rec.name, &series).map_err(|e| e.to_string())?;
    }
    if !r.steps.is_empty() {
        summary += &format!(
            "rests on: no GNSS; step length: {}; heading: {}\n",
            match &a.calibration {
                Some(f) => format!("{} ({PDR_CALIBRATED})", f.display()),
                None => PDR_PRIOR.to_string(),
            },
            if a.no_mag {
                "the gyroscope from the initial heading (--no-mag: north is not known)"
            } else if walk.rec.samples.iter().any(|s| s.mag_ut.is_some()) {
                "the magnetometer (north) and the gyroscope"
            } else {
                "the gyroscope from the initial heading (no magnetometer in the file: north is not known)"
            }
        );
    }
    say!("{}", summary.trim_end());
    check_usable(
        !r.steps.is_empty(),
        "no step detected: no trajectory",
        &r.rejected,
        &[("IMU", walk.rec.samples.len() as u64)],
    )
}

fn write_csv(sink: &Sink, steps: &[stridekit_lab::pdr::walks::StepRow]) -> Result<(), Failure> {
    let name = sink.name();
    let err = write_error(&name);
    let mut f = sink.open()?;
    writeln!(f, "t_s,east_m,north_m,step_length_m,azimuth_deg,steps").map_err(&err)?;
    for (i, s) in steps.iter().enumerate() {
        writeln!(
            f,
            "{:.3},{:.3},{:.3},{:.3},{:.1},{}",
            s.t_s,
            s.east_m,
            s.north_m,
            s.length_m,
            s.azimuth_rad.to_degrees(),
            i + 1
        )
        .map_err(&err)?;
    }
    f.flush().map_err(&err)
}
