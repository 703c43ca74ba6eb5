//! `stridekit foot FILE.csv`: replay a foot-mounted IMU recording through the foot
//! navigator and write the trajectory as CSV plus SVG plots next to it.
//!
//! When the file has truth columns (`gt_x_m gt_y_m gt_z_m`, e.g. the pyshoe VICON
//! trials), the truth is mirrored as `eval foot` does (see `eval_foot::mirror_truth`)
//! and then carried into the estimate's ENU frame by the best rotation about the
//! vertical + translation, so that the `gt_*` columns and the plots compare directly.
//!
//! Outputs for `--out DIR/NAME.csv`: `DIR/NAME.csv` (one row per estimate),
//! `DIR/NAME.svg` (top view: estimate, truth, stride ends) and `DIR/NAME_height.svg`
//! (height over time).

use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::foot::{FootConfig, FootEstimate};
use stridekit_formats::read_foot_csv;

use crate::eval_foot::{align, replay, Method, Trial};
use crate::report::{line_chart, track_chart, Chart, Series, Style};

/// Plots keep at most about this many points per series (the CSV keeps all).
const PLOT_POINTS: usize = 4000;

pub fn run(
    file: &Path,
    out: &Path,
    config: FootConfig,
    labels: Option<String>,
) -> Result<(), String> {
    let mut rec = read_foot_csv(file).map_err(|e| format!("{}: {e}", file.display()))?;
    if let Some(t) = rec.truth_m.as_mut() {
        crate::eval_foot::mirror_truth(t);
    }
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
        labels,
    };
    let est = replay(&trial, &m)?;
    // Truth per estimate, in the estimate's frame.
    let truth: Option<Vec<[f64; 3]>> = trial.rec.truth_m.as_ref().map(|t| {
        let g: Vec<[f64; 3]> = est.iter().map(|(k, _)| t[*k]).collect();
        let e: Vec<[f64; 3]> = est.iter().map(|(_, e)| e.position_m).collect();
        let (th, tr) = align(&e, &g);
        g.iter().map(|p| into_estimate_frame(th, tr, *p)).collect()
    });

    write_csv(out, &est, truth.as_deref())?;
    let (top, height) = svg_paths(out);
    plot(&top, &height, &trial.rec.name, &est, truth.as_deref())?;

    if let Some((_, last)) = est.last() {
        println!(
            "{}: {} samples, {} strides, {:.2} m walked, end at ({:.2}, {:.2}, {:.2}) m",
            trial.rec.name,
            est.len(),
            last.strides,
            last.distance_m,
            last.position_m[0],
            last.position_m[1],
            last.position_m[2],
        );
        if let Some(g) = &truth {
            let se: f64 = est
                .iter()
                .zip(g)
                .map(|((_, e), g)| {
                    (0..3)
                        .map(|i| (e.position_m[i] - g[i]).powi(2))
                        .sum::<f64>()
                })
                .sum();
            println!(
                "  position RMSE against the aligned truth: {:.3} m",
                (se / est.len() as f64).sqrt()
            );
        }
    }
    println!(
        "  trajectory in {}, plots in {} and {}",
        out.display(),
        top.display(),
        height.display()
    );
    Ok(())
}

/// `DIR/NAME.csv` → (`DIR/NAME.svg`, `DIR/NAME_height.svg`).
fn svg_paths(out: &Path) -> (PathBuf, PathBuf) {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "foot_trajectory".into());
    (
        out.with_file_name(format!("{stem}.svg")),
        out.with_file_name(format!("{stem}_height.svg")),
    )
}

fn write_csv(
    out: &Path,
    est: &[(usize, FootEstimate)],
    truth: Option<&[[f64; 3]]>,
) -> Result<(), String> {
    let io = |e: std::io::Error| format!("{}: {e}", out.display());
    let mut w = std::io::BufWriter::new(std::fs::File::create(out).map_err(io)?);
    writeln!(w, "t_s,x_m,y_m,z_m,vx_mps,vy_mps,vz_mps,yaw_rad,stance,strides,distance_m,gt_x_m,gt_y_m,gt_z_m").map_err(io)?;
    for (j, (_, e)) in est.iter().enumerate() {
        let gs = truth.map_or(",,".to_string(), |g| {
            format!("{},{},{}", g[j][0], g[j][1], g[j][2])
        });
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            e.t_s,
            e.position_m[0],
            e.position_m[1],
            e.position_m[2],
            e.velocity_mps[0],
            e.velocity_mps[1],
            e.velocity_mps[2],
            e.yaw_rad,
            e.stance as u8,
            e.strides,
            e.distance_m,
            gs
        )
        .map_err(io)?;
    }
    w.flush().map_err(io)
}

fn plot(
    top: &Path,
    height: &Path,
    name: &str,
    est: &[(usize, FootEstimate)],
    truth: Option<&[[f64; 3]]>,
) -> Result<(), String> {
    let step = (est.len() / PLOT_POINTS).max(1);
    let thin = |f: &dyn Fn(usize) -> (f64, f64)| -> Vec<(f64, f64)> {
        (0..est.len()).step_by(step).map(f).collect()
    };
    let mut track = Vec::new();
    let mut heights = Vec::new();
    if let Some(g) = truth {
        track.push(Series {
            name: "truth (aligned)".into(),
            points: thin(&|j| (g[j][0], g[j][1])),
            color: Some((0, 0, 0)),
            style: Style::Line,
        });
        heights.push(Series {
            name: "truth (aligned)".into(),
            points: thin(&|j| (est[j].1.t_s, g[j][2])),
            color: Some((0, 0, 0)),
            style: Style::Line,
        });
    }
    track.push(Series {
        name: "estimate".into(),
        points: thin(&|j| (est[j].1.position_m[0], est[j].1.position_m[1])),
        color: Some((31, 119, 180)),
        style: Style::Line,
    });
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
    heights.push(Series {
        name: "estimate".into(),
        points: thin(&|j| (est[j].1.t_s, est[j].1.position_m[2])),
        color: Some((31, 119, 180)),
        style: Style::Line,
    });
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
        },
    )
    .map_err(|e| format!("{}: {e}", height.display()))
}

/// A truth point in the estimate's frame: `R(−θ)·(g − t)`.
fn into_estimate_frame(th: f64, t: [f64; 3], g: [f64; 3]) -> [f64; 3] {
    let (s, c) = th.sin_cos();
    let (x, y) = (g[0] - t[0], g[1] - t[1]);
    [c * x + s * y, -s * x + c * y, g[2] - t[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn svgs_go_next_to_the_csv() {
        let (a, b) = svg_paths(Path::new("out/walk.csv"));
        assert_eq!(a, Path::new("out/walk.svg"));
        assert_eq!(b, Path::new("out/walk_height.svg"));
    }
}
