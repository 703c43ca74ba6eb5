//! `stridekit foot FILE`: replay a foot-mounted IMU recording (pyshoe / UofT or x-io
//! NGIMU CSV) through the foot navigator, with the device assumptions of
//! [`config_for`](super::foot_config::config_for); then render the trajectory CSV
//! (local ENU from where the walk started), the top-view and height SVGs, the summary.
//!
//! Truth columns (`gt_*`) are mirrored as `eval foot` does
//! ([`crate::foot::eval::mirror_truth`]) and carried into the estimate's frame by the
//! best rotation about the vertical + translation, so that they compare directly.

use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::foot::{FootConfig, FootEstimate, AT_RANGE, MIN_CLIP_HITS};
use stridekit_formats::{read_foot_csv, Content, FootRecording};

use super::foot_config::{config_for, FootOptions};
use super::ReplayError;
use crate::foot::device::evidence;
use crate::foot::eval::{align, replay_counted, Method, Replayed, Trial};
use crate::report::{line_chart, track_chart, Chart, Series, Style, YFormat};

/// What `stridekit foot` reads, for messages.
const EXPECTS: &str = "a foot IMU CSV (pyshoe / UofT or x-io NGIMU layout)";

/// At most about this many points per plotted line.
const PLOT_POINTS: usize = 4000;

/// Below this distance walked, m, the loop closure is given without a percentage.
const MIN_WALKED_M: f64 = 0.01;

/// The CSV header.
const HEADER: &str = "t_s,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,yaw_rad,stance,strides,distance_m,gt_east_m,gt_north_m,gt_up_m";

/// Reads a foot IMU CSV (refusing recordings of another kind by their content).
pub fn read(path: &Path) -> Result<FootRecording, ReplayError> {
    let what = |e| super::input::read_error(path, e, EXPECTS);
    match stridekit_formats::sniff(path).map_err(what)?.content {
        Content::Foot(_) | Content::Broad | Content::Unknown => {}
        other => return Err(super::input::other_content(path, other, EXPECTS).into()),
    }
    Ok(read_foot_csv(path).map_err(what)?)
}

/// Where the accelerometer's ceiling the navigator used came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AccelCeilingFrom {
    /// The range given (`--accel-range`, the app's config), m/s², and the largest
    /// magnitude the file holds, m/s².
    Given { range_mps2: f64, peak_mps2: f64 },
    /// Neither: the navigator's streaming rule, if it met one.
    Streaming,
}

/// A replayed recording.
pub struct FootReplay {
    pub trial: Trial,
    /// The device assumptions made ([`config_for`]).
    pub described: String,
    /// (unreadable rows, the first one's line).
    pub unreadable: (usize, Option<usize>),
    pub replayed: Replayed,
    /// The same replay with the level floor off (when it was on): the filter's own
    /// height.
    pub unlevelled: Option<Vec<(usize, FootEstimate)>>,
    /// Truth per estimate, in the estimate's frame (files with truth columns).
    pub truth: Option<Vec<[f64; 3]>>,
    pub calibration: Option<PathBuf>,
    pub accel_ceiling_from: AccelCeilingFrom,
    alignment_s: f64,
}

/// Replays `rec` (read from `path`) under `o`: a bad calibration file or label column
/// is a [`ReplayError::Usage`] of its flag.
pub fn replay(
    path: &Path,
    mut rec: FootRecording,
    o: &FootOptions,
) -> Result<FootReplay, ReplayError> {
    // (--axes is checked by clap: what can fail here is the calibration file.)
    let device = evidence(&[&rec]);
    let (config, described) =
        config_for(o, rec.format, &device).map_err(|why| match o.calibration {
            Some(_) => ReplayError::Usage {
                flag: "--calibration",
                why,
            },
            None => ReplayError::Failed(why),
        })?;
    if let Some(t) = rec.truth_m.as_mut() {
        crate::foot::eval::mirror_truth(t);
    }
    check_labels(path, &rec, o)?;
    let unreadable = (rec.unreadable_rows, rec.first_unreadable_line);
    let accel_ceiling_from = match (o.accel_range_mps2, device.accel.ceiling_mps2()) {
        (Some(range_mps2), _) => AccelCeilingFrom::Given {
            range_mps2,
            peak_mps2: device.accel.peak_mps2(),
        },
        (None, _) => AccelCeilingFrom::Streaming,
    };
    let trial = Trial {
        best: "shoe_opt".into(),
        runner_up: None,
        pyshoe_best_m: None,
        run: false,
        path_m: 0.0,
        rec,
    };
    let m = Method {
        name: "replay".into(),
        config,
        labels: o.label_column().map(str::to_string),
    };
    let replayed = replay_counted(&trial, &m)?;
    let unlevelled = own_height(&trial, &m)?;
    let truth = aligned_truth(&trial.rec, &replayed.estimates);
    Ok(FootReplay {
        trial,
        described,
        unreadable,
        replayed,
        unlevelled,
        truth,
        calibration: o.calibration.clone(),
        accel_ceiling_from,
        alignment_s: m.config.alignment_s,
    })
}

/// `--labels` names a column the file has (or `best` / `runner-up`).
fn check_labels(path: &Path, rec: &FootRecording, o: &FootOptions) -> Result<(), ReplayError> {
    let Some(l) = o
        .label_column()
        .filter(|l| !["best", "runner-up"].contains(l))
    else {
        return Ok(());
    };
    if rec.label(l).is_some() {
        return Ok(());
    }
    let have: Vec<String> = rec.labels.iter().map(|(n, _)| format!("zv_{n}")).collect();
    Err(ReplayError::Usage {
        flag: "--labels",
        why: format!(
            "{}: no label column zv_{l} (the file has: {})",
            path.display(),
            if have.is_empty() {
                "none".to_string()
            } else {
                have.join(", ")
            }
        ),
    })
}

/// With the level floor on, the filter's own height too (for the report and the height
/// plot): the same replay with it off.
fn own_height(trial: &Trial, m: &Method) -> Result<Option<Vec<(usize, FootEstimate)>>, String> {
    if m.config.level_stride_max_grade.is_none() {
        return Ok(None);
    }
    let off = Method {
        config: FootConfig {
            level_stride_max_grade: None,
            ..m.config.clone()
        },
        ..m.clone()
    };
    Ok(Some(replay_counted(trial, &off)?.estimates))
}

/// The truth at each estimate, carried into the estimate's frame.
fn aligned_truth(rec: &FootRecording, est: &[(usize, FootEstimate)]) -> Option<Vec<[f64; 3]>> {
    if est.is_empty() {
        return None;
    }
    rec.truth_m.as_ref().map(|t| {
        let g: Vec<[f64; 3]> = est.iter().map(|(k, _)| t[*k]).collect();
        let e: Vec<[f64; 3]> = est.iter().map(|(_, e)| e.position_m).collect();
        let (th, tr) = align(&e, &g);
        g.iter().map(|p| into_estimate_frame(th, tr, *p)).collect()
    })
}

/// A truth point in the estimate's frame: `R(−θ)·(g − t)`.
fn into_estimate_frame(th: f64, t: [f64; 3], g: [f64; 3]) -> [f64; 3] {
    let (s, c) = th.sin_cos();
    let (x, y) = (g[0] - t[0], g[1] - t[1]);
    [c * x + s * y, -s * x + c * y, g[2] - t[2]]
}

impl FootReplay {
    fn estimates(&self) -> &[(usize, FootEstimate)] {
        &self.replayed.estimates
    }

    /// The first lines of the summary, said before anything is written: the device
    /// assumptions, the rows and the samples skipped.
    pub fn head(&self) -> String {
        let (rec, r, unreadable) = (&self.trial.rec, &self.replayed, self.unreadable);
        let mut d = r.skipped.describe();
        if unreadable.0 > 0 {
            let u = format!(
                "{} unreadable rows (first at line {})",
                unreadable.0,
                unreadable.1.unwrap_or(0)
            );
            d = if d == "none" { u } else { format!("{d}, {u}") };
        }
        let mut text = format!(
            "{}: {}\n  {} rows, {} samples skipped: {d}",
            rec.name,
            self.described,
            rec.len() + unreadable.0,
            r.skipped.total() + unreadable.0,
        );
        if let Some((i, e)) = &r.skipped.first {
            text += &format!("\n  first skipped: row {} ({e})", i + 2);
        }
        text
    }

    /// Fails when the navigator never aligned (no estimate).
    pub fn check_aligned(&self) -> Result<(), String> {
        if self.estimates().is_empty() {
            return Err(format!(
                "{}: no estimate: the navigator never aligned (it needs {} s of rest at the start, in m/s² and rad/s)",
                self.trial.rec.name, self.alignment_s
            ));
        }
        Ok(())
    }

    /// The trajectory CSV: positions and distances to 0.1 mm, velocities to 0.1 mm/s,
    /// yaw to 1e-5 rad, time to 1 µs (finer than the navigator resolves, and than
    /// VICON's truth).
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "{HEADER}")?;
        let mm = |v: f64| fixed(v, 4);
        let truth = self.truth.as_deref();
        for (j, (_, e)) in self.estimates().iter().enumerate() {
            let gs = truth.map_or(",,".to_string(), |g| {
                format!("{},{},{}", mm(g[j][0]), mm(g[j][1]), mm(g[j][2]))
            });
            let [x, y, z] = e.position_m.map(mm);
            let [vx, vy, vz] = e.velocity_mps.map(mm);
            writeln!(
                w,
                "{:.6},{x},{y},{z},{vx},{vy},{vz},{},{},{},{},{gs}",
                e.t_s,
                fixed(e.yaw_rad, 5),
                e.stance as u8,
                e.strides,
                mm(e.distance_m),
            )?;
        }
        Ok(())
    }

    /// The top view (estimate, truth, stride ends) to `top` and the height over time
    /// (with the filter's own height when the level floor was on) to `height`.
    pub fn plot(&self, top: &Path, height: &Path) -> Result<(), String> {
        let (track, heights) = self.plot_series();
        let name = &self.trial.rec.name;
        let title = format!("{name}: foot trajectory, top view (local ENU)");
        track_chart(top, &title, &track).map_err(|e| format!("{}: {e}", top.display()))?;
        let title = format!("{name}: foot height");
        line_chart(
            height,
            &Chart {
                title: &title,
                x_label: "time (s)",
                y_label: "up (m)",
                series: &heights,
                bands: &[],
                y_range: None,
                y_format: YFormat::Number,
            },
        )
        .map_err(|e| format!("{}: {e}", height.display()))
    }

    /// The series of the top view and of the height plot, thinned to about
    /// [`PLOT_POINTS`].
    fn plot_series(&self) -> (Vec<Series>, Vec<Series>) {
        let est = self.estimates();
        let step = (est.len() / PLOT_POINTS).max(1);
        let thin = |f: &dyn Fn(usize) -> (f64, f64)| -> Vec<(f64, f64)> {
            (0..est.len()).step_by(step).map(f).collect()
        };
        let line = |name: &str, points, color| Series {
            name: name.into(),
            points,
            color: Some(color),
            style: Style::Line,
        };
        let mut track = Vec::new();
        let mut heights = Vec::new();
        if let Some(g) = &self.truth {
            track.push(line(
                "truth (aligned)",
                thin(&|j| (g[j][0], g[j][1])),
                (0, 0, 0),
            ));
            heights.push(line(
                "truth (aligned)",
                thin(&|j| (est[j].1.t_s, g[j][2])),
                (0, 0, 0),
            ));
        }
        let blue = (31, 119, 180);
        track.push(line(
            "estimate",
            thin(&|j| (est[j].1.position_m[0], est[j].1.position_m[1])),
            blue,
        ));
        track.push(Series {
            name: "stride ends".into(),
            points: est
                .iter()
                .filter(|(_, e)| e.stride.is_some())
                .map(|(_, e)| (e.position_m[0], e.position_m[1]))
                .collect(),
            color: Some((214, 39, 40)),
            style: Style::Points,
        });
        if let Some(raw) = &self.unlevelled {
            let points = raw
                .iter()
                .step_by(step)
                .map(|(_, e)| (e.t_s, e.position_m[2]))
                .collect();
            heights.push(line(
                "the filter's own height (level floor off)",
                points,
                (150, 150, 150),
            ));
        }
        heights.push(line(
            "estimate",
            thin(&|j| (est[j].1.t_s, est[j].1.position_m[2])),
            blue,
        ));
        (track, heights)
    }

    /// The rest of the summary (after [`Self::head`]); `written` names the CSV and the
    /// two plots, `None` when the CSV went to stdout. Call after
    /// [`Self::check_aligned`].
    pub fn summary(&self, written: Option<(&str, &Path, &Path)>) -> String {
        let est = self.estimates();
        let (first, last) = (est[0].1, est[est.len() - 1].1);
        let r = &self.replayed;
        let mut lines = vec![format!(
            "  {} estimates at {:.1} Hz (detector window {} samples), {} strides, {:.2} m walked, {:.1} s",
            est.len(),
            r.rate_hz,
            r.window,
            last.strides,
            last.distance_m,
            last.t_s - first.t_s,
        )];
        lines.extend(self.level_floor());
        lines.push(loop_closure(&first, &last));
        if r.resets > 0 {
            lines.push(format!("  divergence-guard resets: {}", r.resets));
        }
        lines.extend(self.accel_clipped());
        lines.extend(self.truth_rmse());
        lines.push(format!(
            "  rests on: the IMU alone (zero-velocity updates at each stance; no GNSS, no step-length model); accelerometer alignment: {}",
            match &self.calibration {
                Some(f) => format!("the device calibration {}", f.display()),
                None => "none given (`stridekit calibrate foot` learns it from level walks; without it the height may climb by a centimetre a stride, see docs/foot.md)".into(),
            }
        ));
        lines.push(match written {
            Some((csv, top, height)) => format!(
                "  trajectory in {csv}, plots in {} and {}",
                top.display(),
                height.display()
            ),
            None => "  trajectory on stdout (no plots)".into(),
        });
        lines.join("\n")
    }

    /// When the accelerometer clipped: where, what the ceiling rests on (the app's
    /// range or the streaming rule) and what follows.
    fn accel_clipped(&self) -> Option<String> {
        let (c, from) = match self.accel_ceiling_from {
            AccelCeilingFrom::Given {
                range_mps2,
                peak_mps2,
            } => {
                let c = AT_RANGE * range_mps2;
                (peak_mps2 >= c).then_some((c, "99 % of the range given (--accel-range), the samples at it taken for clipped".to_string()))?
            }
            AccelCeilingFrom::Streaming => (
                self.replayed.accel_ceiling_mps2?,
                format!("found while streaming: the impacts before its {MIN_CLIP_HITS}th clipped run were trusted"),
            ),
        };
        Some(format!(
            "  accelerometer clipped at {c:.1} m/s² ({:.1} g), {from}: the velocity over clipped samples is not trusted and the detector takes each clipped impact's peak from its flanks; expect larger errors than from an unclipped IMU (docs/foot.md, \"Accelerometer clipping\")",
            c / crate::perturb::kinds::G0_MPS2
        ))
    }

    /// With the level floor on: the strides taken as level, and the filter's own height.
    fn level_floor(&self) -> Option<String> {
        let raw = self.unlevelled.as_ref()?;
        let strides: Vec<_> = self
            .estimates()
            .iter()
            .filter_map(|(_, e)| e.stride)
            .collect();
        let levelled: Vec<f64> = strides
            .iter()
            .filter(|s| s.levelled_m != 0.0)
            .map(|s| s.levelled_m)
            .collect();
        let own_end = match (raw.first(), raw.last()) {
            (Some(a), Some(b)) => b.1.position_m[2] - a.1.position_m[2],
            _ => 0.0,
        };
        Some(format!(
            "  level floor: {} of {} strides taken as level, their height change set to zero ({:+.3} m in all, median {:+.3} m per levelled stride); the other strides climbed {:+.3} m; the filter's own height ends at {:+.3} m (--no-level-floor)",
            levelled.len(),
            strides.len(),
            levelled.iter().sum::<f64>(),
            if levelled.is_empty() {
                0.0
            } else {
                crate::stats::median(levelled.iter().copied())
            },
            strides.iter().map(|s| s.climb_m).sum::<f64>(),
            own_end,
        ))
    }

    /// The position RMSE against the aligned truth (3-D and horizontal).
    fn truth_rmse(&self) -> Option<String> {
        let g = self.truth.as_ref()?;
        let est = self.estimates();
        let sum_sq = |axes: usize| -> f64 {
            est.iter()
                .zip(g)
                .map(|((_, e), g)| {
                    (0..axes)
                        .map(|i| (e.position_m[i] - g[i]).powi(2))
                        .sum::<f64>()
                })
                .sum()
        };
        Some(format!(
            "  position RMSE against the aligned truth: {:.3} m (horizontal {:.3} m)",
            (sum_sq(3) / est.len() as f64).sqrt(),
            (sum_sq(2) / est.len() as f64).sqrt()
        ))
    }

    /// Why the replay produced nothing usable: no stride, or the samples refused for
    /// their units (in g, timestamps not in seconds) outnumber the accepted ones;
    /// `None` when usable.
    pub fn unusable(&self) -> Option<String> {
        let skipped = &self.replayed.skipped;
        let samples = self.trial.rec.len();
        let strides = self.estimates().last().map_or(0, |(_, e)| e.strides);
        let mut causes = Vec::new();
        if strides == 0 {
            causes.push(if skipped.total() >= samples {
                "no stride: every sample was refused".to_string()
            } else {
                "no stride detected: no trajectory (the foot never left a stance the detector saw)"
                    .to_string()
            });
        }
        let units = [
            (
                skipped.in_g,
                "accelerations look like g, not m/s² (multiply by 9.80665)",
            ),
            (
                skipped.time_unit,
                skipped
                    .time_unit_message
                    .as_deref()
                    .unwrap_or("timestamps not in seconds"),
            ),
        ];
        for (n, why) in units {
            if 2 * n > samples {
                causes.push(format!(
                    "the IMU stream was refused for its units ({n} of its samples): {why}"
                ));
            }
        }
        (!causes.is_empty()).then(|| causes.join("; "))
    }
}

/// End − start: the loop closure, 3-D and horizontal, as a share of the distance
/// walked (none when the foot did not walk).
fn loop_closure(first: &FootEstimate, last: &FootEstimate) -> String {
    let d: Vec<f64> = (0..3)
        .map(|i| last.position_m[i] - first.position_m[i])
        .collect();
    let d3 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let dh = d[0].hypot(d[1]);
    let pct = |x: f64| {
        if last.distance_m > MIN_WALKED_M {
            format!("{:.2} %", 100.0 * x / last.distance_m)
        } else {
            "— % (nothing walked)".into()
        }
    };
    format!(
        "  end − start: ({:.3}, {:.3}, {:.3}) m ENU; 3-D {:.3} m = {} of the distance walked, horizontal {:.3} m = {}, height {:+.3} m (loop closure, for a walk that ends where it starts)",
        d[0], d[1], d[2], d3, pct(d3), dh, pct(dh), d[2]
    )
}

/// `v` with `decimals` decimals, without a sign on a value that rounds to zero.
fn fixed(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => text,
    }
}

/// `DIR/NAME.csv` → (`DIR/NAME.svg`, `DIR/NAME_height.svg`).
pub fn svg_paths(out: &Path) -> (PathBuf, PathBuf) {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "foot_trajectory".into());
    (
        out.with_file_name(format!("{stem}.svg")),
        out.with_file_name(format!("{stem}_height.svg")),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foot::device::Evidence;
    use crate::replay::foot_calibrate;
    use crate::replay::foot_config::read_calibration;
    use stridekit_formats::FootFormat;

    /// The replay, its CSV and its plots beside `out`, as `stridekit foot` writes them.
    fn replay_to(path: &Path, o: &FootOptions, out: &Path) -> FootReplay {
        let r = replay(path, read(path).unwrap(), o).unwrap();
        r.check_aligned().unwrap();
        let mut csv = std::fs::File::create(out).unwrap();
        r.write_csv(&mut csv).unwrap();
        let (top, height) = svg_paths(out);
        r.plot(&top, &height).unwrap();
        assert!(r.summary(None).contains("trajectory on stdout"));
        r
    }

    #[test]
    fn alignment_recovers_a_rotation_and_translation() {
        let est: Vec<[f64; 3]> = (0..50)
            .map(|i| {
                let a = i as f64 * 0.2;
                [3.0 * a.cos(), 2.0 * a.sin(), 0.1 * a]
            })
            .collect();
        let (th0, t0) = (0.7_f64, [1.5, -2.0, 0.3]);
        let (s, c) = th0.sin_cos();
        let truth: Vec<[f64; 3]> = est
            .iter()
            .map(|e| {
                [
                    c * e[0] - s * e[1] + t0[0],
                    s * e[0] + c * e[1] + t0[1],
                    e[2] + t0[2],
                ]
            })
            .collect();
        let (th, t) = align(&est, &truth);
        assert!((th - th0).abs() < 1e-12);
        for i in 0..3 {
            assert!((t[i] - t0[i]).abs() < 1e-12);
        }
        for (e, g) in est.iter().zip(&truth) {
            let back = into_estimate_frame(th, t, *g);
            for i in 0..3 {
                assert!((back[i] - e[i]).abs() < 1e-12);
            }
        }
    }

    /// A simulated 400 Hz walk with the sensor z up and tilted on the shoe, written
    /// as an x-io CSV export (deg/s, g) with repeated rows as from a coarse clock,
    /// a reversed timestamp, a NaN and a truncated line: the replay skips and counts
    /// them and the loop closes.
    #[test]
    fn replays_an_xio_export_with_repeated_rows() {
        use stridekit_sim::{simulate_foot, FootScenario};
        let sim = simulate_foot(&FootScenario {
            sample_rate_hz: 400.0,
            mount_rpy_rad: [0.3, -0.5, 0.4],
            loop_m: [10.0, 5.0],
            ..FootScenario::walk(7, 1)
        });
        let dir = std::env::temp_dir().join(format!("stridekit-xio-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("walk.csv");
        let mut text = String::from("Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)\n");
        let row = |t: f64, s: &stridekit_core::foot::FootSample| {
            let w = s.gyro_rads.map(f64::to_degrees);
            let a = s.accel_mps2.map(|v| v / 9.80665);
            format!(
                "{t:.9},{},{},{},{},{},{}\n",
                w[0], w[1], w[2], a[0], a[1], a[2]
            )
        };
        let (mut repeated, mut backwards, mut nan) = (0, 0, 0);
        for (i, s) in sim.samples.iter().enumerate() {
            text.push_str(&row(s.t_s, s));
            if i > 400 && i % 97 == 0 {
                text.push_str(&row(s.t_s, s));
                repeated += 1;
            }
            if i == 5000 {
                text.push_str(&row(s.t_s - 0.1, s));
                backwards += 1;
            }
            if i == 6000 {
                text.push_str(&format!("{},NaN,0,0,0,0,1\n", s.t_s + 1e-4));
                nan += 1;
            }
        }
        text.push_str("12.3,4.5\n");
        std::fs::write(&file, text).unwrap();

        let rec = read_foot_csv(&file).unwrap();
        assert_eq!(rec.format, FootFormat::Xio);
        assert_eq!(rec.unreadable_rows, 1);
        let o = FootOptions {
            axes: Some("flu".into()),
            ..Default::default()
        };
        let (config, _) = config_for(&o, rec.format, &evidence(&[&rec])).unwrap();
        assert!(
            config.gyro_bias_from_alignment,
            "x-io: consumer profile by default"
        );
        let r = replay_to(&file, &o, &dir.join("walk_out.csv"));
        let s = &r.replayed.skipped;
        assert_eq!(s.repeated_time, repeated);
        assert_eq!(s.time_backwards, backwards);
        assert_eq!(s.non_finite, nan);
        assert_eq!(s.total(), repeated + backwards + nan);
        assert!(
            (r.replayed.rate_hz - 400.0).abs() < 1.0,
            "{}",
            r.replayed.rate_hz
        );
        let first = r.replayed.estimates[0].1;
        let last = r.replayed.estimates.last().unwrap().1;
        let d: f64 = (0..3)
            .map(|i| (last.position_m[i] - first.position_m[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        let closure = d / last.distance_m;
        assert!(last.distance_m > 25.0, "{}", last.distance_m);
        assert!(
            closure < 0.01,
            "closure {:.2} % of {:.1} m",
            closure * 100.0,
            last.distance_m
        );
        assert_eq!(r.unusable(), None);
        assert!(dir.join("walk_out.svg").exists());
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A level simulated walk whose accelerometer is turned 1.2° about the lateral
    /// axis against the gyroscope, as an x-io export: `calibrate foot` learns the
    /// angle, and the replay with `--calibration` uses it.
    #[test]
    fn calibrate_learns_the_alignment_and_the_replay_loads_it() {
        use stridekit_sim::{simulate_foot, FootScenario};
        let truth = 0.021_f64;
        let sim = simulate_foot(&FootScenario::walk(3, 1));
        // Turned by −truth about y: x' = c·x − s·z, z' = s·x + c·z.
        let (sn, c) = truth.sin_cos();
        let dir = std::env::temp_dir().join(format!("stridekit-footcal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("level.csv");
        let mut text = String::from("Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)\n");
        for s in &sim.samples {
            let w = s.gyro_rads.map(f64::to_degrees);
            let f = s.accel_mps2;
            let a = [c * f[0] - sn * f[2], f[1], sn * f[0] + c * f[2]].map(|v| v / 9.80665);
            text += &format!(
                "{:.9},{},{},{},{},{},{}\n",
                s.t_s, w[0], w[1], w[2], a[0], a[1], a[2]
            );
        }
        std::fs::write(&file, text).unwrap();
        let cal = dir.join("imu.cal");
        let learned =
            foot_calibrate::learn(std::slice::from_ref(&file), &FootOptions::default()).unwrap();
        std::fs::write(&cal, learned.text()).unwrap();
        let svg = cal.with_extension("svg");
        learned.plot(&svg).unwrap();
        let report = learned.report(&svg);
        assert!(report.contains("| level |"), "{report}");
        assert!(dir.join("imu.svg").exists());
        let a = read_calibration(&cal).unwrap();
        assert!((a[1] - truth).abs() < 0.003, "{a:?}");
        let o = FootOptions {
            calibration: Some(cal.clone()),
            ..Default::default()
        };
        let (config, described) = config_for(&o, FootFormat::Xio, &Evidence::default()).unwrap();
        assert_eq!(config.accel_alignment_rad, a);
        assert!(described.contains("accelerometer alignment"), "{described}");
        replay_to(&file, &o, &dir.join("out.csv"));
        std::fs::write(&cal, "not a calibration\n").unwrap();
        let e = config_for(&o, FootFormat::Xio, &Evidence::default()).unwrap_err();
        assert!(e.contains("imu.cal"), "{e}");
        let e = replay(&file, read(&file).unwrap(), &o).err().unwrap();
        assert!(
            matches!(
                &e,
                ReplayError::Usage {
                    flag: "--calibration",
                    ..
                }
            ),
            "{e:?}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A trial of the UofT VICON set in `../shared/data`, or `None` (the test skips,
    /// saying why).
    fn uoft_trial(name: &str) -> Option<FootRecording> {
        let Some(path) = stridekit_formats::data_dir()
            .map(|d| d.join("foot/pyshoe-vicon").join(format!("{name}.csv")))
            .filter(|p| p.exists())
        else {
            eprintln!("skipping: ../shared/data/foot/pyshoe-vicon/{name}.csv not found (set STRIDEKIT_DATA)");
            return None;
        };
        Some(read_foot_csv(&path).unwrap())
    }

    /// Issue 39, real data: a running trial (2017-11-27-11-18-11) with its
    /// accelerometer clipped at ±4 g, written as the data set's CSV: the replay finds
    /// the ceiling and says what the result rests on; the recording as it is does not
    /// clip.
    #[test]
    fn a_clipped_accelerometer_is_reported() {
        let Some(rec) = uoft_trial("2017-11-27-11-18-11") else {
            return;
        };
        let o = FootOptions::default();
        let path = Path::new("2017-11-27-11-18-11.csv");
        let plain = replay(path, rec.clone(), &o).unwrap();
        assert_eq!(plain.replayed.accel_ceiling_mps2, None);
        assert!(!plain.summary(None).contains("accelerometer clipped"));
        let lim = 4.0 * crate::perturb::kinds::G0_MPS2;
        let mut clipped = rec;
        for a in clipped.accel_mps2.iter_mut() {
            *a = a.map(|x| x.clamp(-lim, lim));
        }
        let r = replay(path, clipped.clone(), &o).unwrap();
        // The pre-scan of the file finds the ceiling and says so; the navigator takes
        // it for clipped once it has met it while streaming.
        assert_eq!(r.accel_ceiling_from, AccelCeilingFrom::Streaming);
        let c = r.replayed.accel_ceiling_mps2.expect("the ceiling is found");
        let level = lim * (1.0 - stridekit_core::foot::ACCEL_LEVEL_SHARE);
        assert!(c >= level - 1e-9 && c <= lim + 1e-9, "{c}");
        assert!(
            r.described
                .contains("the pre-scan of the file finds a ceiling of 39.23"),
            "{}",
            r.described
        );
        let text = r.summary(None);
        assert!(text.contains("(4.0 g), found while streaming"), "{text}");
        // The app's range instead: the summary says so, and a range the file never
        // reaches is no clipping.
        for (range, clips) in [(lim / AT_RANGE, true), (8.0 * lim, false)] {
            let given = FootOptions {
                accel_range_mps2: Some(range),
                ..o.clone()
            };
            let r = replay(path, clipped.clone(), &given).unwrap();
            assert!(r.described.contains("given"), "{}", r.described);
            let text = r.summary(None);
            assert_eq!(
                text.contains("of the range given (--accel-range)"),
                clips,
                "{text}"
            );
            assert_eq!(text.contains("accelerometer clipped"), clips, "{text}");
        }
    }

    /// Issue 36 item 6, real data: the MicroStrain's pitch rate on 2017-11-22-11-44-47
    /// stops at about 9.13 rad/s in 15 swings. The data say so, and the ceiling found is
    /// the clip's; the same motion with every rate ×1.5, as an IMU of 1.5× the range
    /// clipped at 1.5× the rate would record it, is clipped at ×1.5, not at 9.2 rad/s.
    #[test]
    fn a_real_clipped_gyroscope_is_detected_at_its_own_ceiling() {
        let Some(rec) = uoft_trial("2017-11-22-11-44-47") else {
            return;
        };
        let (config, text) =
            config_for(&FootOptions::default(), rec.format, &evidence(&[&rec])).unwrap();
        let r = config.gyro_range_rads.expect("clipping detected");
        assert!((9.0..9.15).contains(&(0.99 * r)), "{r}: {text}");
        assert!(text.contains("clipping detected"), "{text}");
        assert!(text.contains("on sensor y−"), "{text}");
        assert!(!config.gyro_bias_from_alignment, "UofT: calibrated: {text}");

        let mut wide = rec.clone();
        wide.gyro_rads.iter_mut().flatten().for_each(|w| *w *= 1.5);
        let c = evidence(&[&wide]).ceiling.expect("still clipped");
        assert!((1.5 * 9.0..1.5 * 9.15).contains(&c.ceiling_rads), "{c:?}");
    }

    /// Issue 36 item 6, real data: a trial that never clips (2017-11-22-11-26-05,
    /// peak 8.99 rad/s) with every rate ×1.3, its swing peaks at 11.7 rad/s as from a
    /// wider-range IMU on a faster foot, written as a plain `t_s,acc_*,gyr_*` CSV of an
    /// unknown device. Before: the layout meant the UofT MicroStrain, so the calibrated
    /// profile and a 9.2 rad/s range whose "repair" added rotation to every peak above
    /// 9.1 rad/s. Now: no flat tops, no range, nothing repaired, the consumer profile,
    /// and the replay says so.
    #[test]
    fn a_wider_range_imu_is_not_repaired_at_the_microstrain_ceiling() {
        let Some(rec) = uoft_trial("2017-11-22-11-26-05") else {
            return;
        };
        let dir = std::env::temp_dir().join(format!("stridekit-widegyro-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("wide.csv");
        let mut text =
            String::from("t_s,acc_x_mps2,acc_y_mps2,acc_z_mps2,gyr_x_rads,gyr_y_rads,gyr_z_rads\n");
        for i in 0..rec.len() {
            let (a, w) = (rec.accel_mps2[i], rec.gyro_rads[i].map(|w| 1.3 * w));
            text += &format!(
                "{},{},{},{},{},{},{}\n",
                rec.t_s[i], a[0], a[1], a[2], w[0], w[1], w[2]
            );
        }
        std::fs::write(&file, text).unwrap();
        let wide = read_foot_csv(&file).unwrap();
        let device = evidence(&[&wide]);
        assert!(device.peak_rads > 11.0, "{}", device.peak_rads);
        assert_eq!(device.ceiling, None);
        let o = FootOptions::default();
        let (config, described) = config_for(&o, wide.format, &device).unwrap();
        assert_eq!(config.gyro_range_rads, None, "{described}");
        assert!(config.gyro_bias_from_alignment, "consumer: {described}");
        assert!(described.contains("no clipping detected"), "{described}");
        assert!(described.contains("IMU profile consumer"), "{described}");
        // A range the user gives is used, and one the data contradict is questioned.
        let (config, described) = config_for(
            &FootOptions {
                gyro_range_rads: Some(9.2),
                ..o.clone()
            },
            wide.format,
            &device,
        )
        .unwrap();
        assert_eq!(config.gyro_range_rads, Some(9.2));
        assert!(described.contains("above the given range"), "{described}");
        replay_to(&file, &o, &dir.join("out.csv"));
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn numbers_are_written_to_their_precision() {
        assert_eq!(fixed(-0.00000014, 4), "0.0000");
        assert_eq!(fixed(-0.00012, 4), "-0.0001");
        assert_eq!(fixed(0.028743696105534, 4), "0.0287");
    }

    #[test]
    fn svgs_go_next_to_the_csv() {
        let (a, b) = svg_paths(Path::new("out/walk.csv"));
        assert_eq!(a, Path::new("out/walk.svg"));
        assert_eq!(b, Path::new("out/walk_height.svg"));
    }
}
