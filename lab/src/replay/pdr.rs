//! `stridekit pdr FILE`: replay a phone recording (an Android sensor log) through the
//! phone navigator with no GNSS into one row per step (east / north of where the walk
//! started), then render the CSV, the track over the aligned waypoints (SVG) and the
//! summary: the accuracy measures with waypoints, and what step length and heading rest on.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::basis::{PDR_CALIBRATED, PDR_PRIOR};
use super::{ReplayError, Usable};
use crate::pdr::metrics::{apply_rigid, best_rigid, evaluate, track_at, Metrics};
use crate::pdr::walks::{load_walk, Replay, ReplayOptions, Walk};
use crate::report::{track_chart, Series, Style};

/// How to replay (`stridekit pdr`'s flags).
#[derive(Clone, Debug, Default)]
pub struct PdrOptions {
    /// A personal calibration written by `stridekit calibrate pdr`.
    pub calibration_file: Option<PathBuf>,
    /// Ignore the magnetometer.
    pub no_mag: bool,
    /// The gyroscope's bias is not removed by the platform.
    pub raw_gyro: bool,
}

/// A replayed walk: the steps, and the accuracy measures when it has waypoints.
pub struct PdrReplay {
    pub walk: Walk,
    pub replay: Replay,
    /// Against the waypoints (at least two).
    pub metrics: Option<Metrics>,
    pub options: PdrOptions,
}

/// Reads one walk (an Android sensor log, plain or gzip).
pub fn read(path: &Path) -> Result<Walk, ReplayError> {
    Ok(load_walk(path)?)
}

/// Replays `walk` with the calibration and flags of `options`.
pub fn replay(walk: Walk, options: PdrOptions) -> Result<PdrReplay, ReplayError> {
    let calibration = match &options.calibration_file {
        Some(p) => Some(
            crate::pdr::calibrate::read(p).map_err(|why| ReplayError::Usage {
                flag: "--calibration",
                why,
            })?,
        ),
        None => None,
    };
    let o = ReplayOptions {
        mag: !options.no_mag,
        calibration,
        config: stridekit_core::pdr::NavigatorConfig {
            gyro_calibrated: !options.raw_gyro,
            ..Default::default()
        },
        ..Default::default()
    };
    let replay = crate::pdr::walks::replay(&walk.rec, &o)?;
    let wp = &walk.rec.truth;
    let metrics = (wp.len() >= 2)
        .then(|| evaluate(&replay.track, wp))
        .flatten();
    Ok(PdrReplay {
        walk,
        replay,
        metrics,
        options,
    })
}

impl PdrReplay {
    /// The CSV: `t_s,east_m,north_m,step_length_m,azimuth_deg,steps`.
    pub fn write_csv(&self, f: &mut dyn Write) -> std::io::Result<()> {
        writeln!(f, "t_s,east_m,north_m,step_length_m,azimuth_deg,steps")?;
        for (i, s) in self.replay.steps.iter().enumerate() {
            writeln!(
                f,
                "{:.3},{:.3},{:.3},{:.3},{:.1},{}",
                s.t_s,
                s.east_m,
                s.north_m,
                s.length_m,
                s.azimuth_rad.to_degrees(),
                i + 1
            )?;
        }
        Ok(())
    }

    /// The track, and with waypoints the waypoints carried into the track's frame (the
    /// inverse of the best rigid map of the track, at the waypoint times, onto them),
    /// as SVG.
    pub fn chart(&self, svg: &Path) -> Result<(), String> {
        let r = &self.replay;
        let wp = &self.walk.rec.truth;
        let mut series = vec![Series {
            name: "PDR track".into(),
            points: r.track.iter().map(|p| (p.x_m, p.y_m)).collect(),
            color: None,
            style: Style::Line,
        }];
        if wp.len() >= 2 {
            let est: Vec<(f64, f64)> = wp
                .iter()
                .map(|w| {
                    let p = track_at(&r.track, w.0);
                    (p.0, p.1)
                })
                .collect();
            let truth: Vec<(f64, f64)> = wp.iter().map(|w| (w.1, w.2)).collect();
            let inv = best_rigid(&truth, &est);
            let aligned: Vec<(f64, f64)> = truth.iter().map(|p| apply_rigid(*p, inv)).collect();
            series.push(Series {
                name: "waypoints (aligned)".into(),
                points: aligned.clone(),
                color: Some((214, 39, 40)),
                style: Style::Line,
            });
            series.push(Series {
                name: String::new(),
                points: aligned,
                style: Style::Points,
                color: Some((214, 39, 40)),
            });
        }
        track_chart(svg, &self.walk.rec.name, &series).map_err(|e| e.to_string())
    }

    /// The summary; `written_to` names where the CSV went, `svg` the plot if any.
    pub fn summary(&self, written_to: &str, svg: Option<&Path>) -> String {
        let (rec, r) = (&self.walk.rec, &self.replay);
        let mut summary = format!(
            "{}: {} samples, {} steps, {:.1} m walked; trajectory {} ({} rows){}\n",
            rec.name,
            rec.samples.len(),
            r.steps.len(),
            r.steps.last().map_or(0.0, |s| s.distance_m),
            written_to,
            r.steps.len(),
            svg.map(|s| format!(", plot {}", s.display()))
                .unwrap_or_default()
        );
        if r.rejected.total() == 0 {
            summary += "rejected samples: none\n";
        } else {
            summary += &format!("rejected samples: {}\n", r.rejected.total());
            summary += &r.rejected.report();
        }
        for (why, n) in &rec.skipped {
            summary += &format!("  skipped by the reader {n}: {why}\n");
        }
        if let Some(m) = &self.metrics {
            summary += &format!(
                "against {} waypoints ({:.1} m polyline): ATE {:.2} m, start-pinned {:.2} m, end {:.1} %, distance {:+.1} %\n",
                rec.truth.len(),
                m.polyline_m,
                m.ate_m,
                m.start_pinned_m,
                m.end_pct,
                m.distance_pct
            );
        }
        if !r.steps.is_empty() {
            summary += &self.rests_on();
        }
        summary.trim_end().to_string()
    }

    /// "rests on: …": the step length (the prior or the calibration) and the heading.
    fn rests_on(&self) -> String {
        format!(
            "rests on: no GNSS; step length: {}; heading: {}\n",
            match &self.options.calibration_file {
                Some(f) => format!("{} ({PDR_CALIBRATED})", f.display()),
                None => PDR_PRIOR.to_string(),
            },
            if self.options.no_mag {
                "the gyroscope from the initial heading (--no-mag: north is not known)"
            } else if self.walk.rec.samples.iter().any(|s| s.mag_ut.is_some()) {
                "the magnetometer (north) and the gyroscope"
            } else {
                "the gyroscope from the initial heading (no magnetometer in the file: north is not known)"
            }
        )
    }

    /// Whether a step was detected, and the stream pushed.
    pub fn usable(&self) -> Usable<'_> {
        Usable {
            produced: !self.replay.steps.is_empty(),
            what: "no step detected: no trajectory",
            rejected: &self.replay.rejected,
            streams: vec![("IMU", self.walk.rec.samples.len() as u64)],
        }
    }
}
