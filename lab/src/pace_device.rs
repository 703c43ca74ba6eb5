//! Real-run checks of `stridekit eval pace` against the watch's own speed channel.
//!
//! The bar for outages is stated against a foot pod's speed. The GNSS-track reference
//! of the main table (a ±6 s line fit of the recorded positions) is itself noisy:
//! in the injected outage zones it differs from the watch's recorded speed channel
//! (Doppler/fused, or a foot pod when paired) by ≈ 0.4 m/s RMS, more than the filter's
//! own error. Here the outage RMSE is also measured against that speed channel, the
//! closest thing to a foot pod the files hold; and pedometer-only pace (steps, no GNSS)
//! is measured leave-one-run-out with a calibration carried from another run of the
//! same runner.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::pace::{replay, rmse};
use stridekit_core::{PaceCalibration, PaceConfig, PaceSample, PaceTracker};
use stridekit_formats::Activity;
use stridekit_sim::{Zone, ZoneKind};

use crate::activity::{degraded, prepare};

/// The watch's speed channel on a replay grid (NaN where no record within 1.5 s).
fn device_speed(activity: &Activity, grid: &[f64]) -> Vec<f64> {
    let t0 = activity.records.first().map(|r| r.t_s).unwrap_or(0.0);
    grid.iter()
        .map(|&t| {
            let k = activity.records.partition_point(|r| r.t_s - t0 < t - 1.5);
            activity.records[k..]
                .iter()
                .take_while(|r| r.t_s - t0 <= t + 1.5)
                .filter_map(|r| r.device_speed_mps)
                .next()
                .unwrap_or(f64::NAN)
        })
        .collect()
}

fn in_outage(zones: &[Zone], t: f64) -> bool {
    zones
        .iter()
        .any(|z| z.kind == ZoneKind::Outage && t >= z.start_s && t < z.end_s)
}

fn fmt(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3}")
    } else {
        "—".into()
    }
}

/// Outage RMSE of AsPublished and the default against the device speed, per file.
pub fn outage_table(files: &[PathBuf], default: PaceConfig) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "Outages on the real runs against the watch's recorded speed channel (the same injected outages as above; files without a speed channel are not scored). Speed RMSE in m/s; last column: the ±6 s GNSS-track reference of the table above against the same channel (its own noise).\n");
    let _ = writeln!(
        out,
        "| file | outage s scored | AsPublished | default | GNSS-track reference vs device |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|");
    let (mut pooled, mut n) = ([0.0f64; 3], 0usize);
    for (i, path) in files.iter().enumerate() {
        let Ok(activity) = stridekit_formats::read_activity(path) else {
            continue;
        };
        let p = prepare(&activity);
        if p.track.len() < 30 || !p.has_steps {
            continue;
        }
        // The same seed as the main table: the same zones.
        let (samples, zones) = degraded(&p, 1000 + i as u64);
        let r = replay(&samples, PaceConfig::as_published(), default);
        let dev = device_speed(&activity, &r.t_s);
        let reference = crate::pace::smoothed_track_speed(
            &p.track,
            &r.t_s,
            crate::pace_eval::REFERENCE_HALF_WINDOW_S,
        );
        let keep = |k: usize| in_outage(&zones, r.t_s[k]);
        let scored = (0..r.t_s.len())
            .filter(|&k| keep(k) && dev[k].is_finite())
            .count();
        if scored == 0 {
            continue;
        }
        let v = [
            rmse(&r.speed[2], &dev, keep),
            rmse(&r.speed[3], &dev, keep),
            rmse(&reference, &dev, keep),
        ];
        for (a, b) in pooled.iter_mut().zip(v) {
            *a += b * b;
        }
        n += 1;
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let _ = writeln!(
            out,
            "| {name} | {scored} | {} | {} | {} |",
            fmt(v[0]),
            fmt(v[1]),
            fmt(v[2])
        );
    }
    if n > 0 {
        let p = pooled.map(|s| (s / n as f64).sqrt());
        let _ = writeln!(
            out,
            "| **pooled ({n} files)** | | {} | {} | {} |",
            fmt(p[0]),
            fmt(p[1]),
            fmt(p[2])
        );
    }
    out
}

/// Steps only (all fixes removed) through a tracker built from `config`; speed on a
/// 1 s grid.
/// The samples' steps alone (every fix left out: a treadmill, an indoor track)
/// through a tracker with `config`: the output speed once a second from the first
/// step sample, m/s (grid times, speeds).
pub fn steps_only(samples: &[PaceSample], config: PaceConfig) -> (Vec<f64>, Vec<f64>) {
    let mut tr = PaceTracker::new(config).expect("valid config");
    let steps: Vec<PaceSample> = samples
        .iter()
        .filter(|s| matches!(s, PaceSample::Steps(_)))
        .copied()
        .collect();
    let (mut grid, mut speed) = (Vec::new(), Vec::new());
    let Some(first) = steps.first() else {
        return (grid, speed);
    };
    let mut t = first.t_s().ceil();
    let end = steps.last().map(|s| s.t_s()).unwrap_or(t);
    let mut i = 0;
    while t <= end {
        while i < steps.len() && steps[i].t_s() <= t {
            let _ = tr.push(&steps[i]);
            i += 1;
        }
        grid.push(t);
        speed.push(tr.estimate().map_or(0.0, |e| e.speed_mps));
        t += 1.0;
    }
    (grid, speed)
}

/// Pedometer-only pace, leave one run out, on the runs of one runner (file names
/// starting with `prefix`): each run is replayed with its steps only, the calibration
/// exported from every other run (replayed with GNSS) imported; RMSE against the
/// device's speed channel and the GNSS-track reference, and the distance error.
pub fn pedometer_only_table(dir: &Path, prefix: &str) -> Result<String, String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("cannot read {}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(prefix))
        })
        .collect();
    files.sort();
    let mut runs = Vec::new();
    for f in &files {
        let a = stridekit_formats::read_activity(f).map_err(|e| format!("{}: {e}", f.display()))?;
        let p = prepare(&a);
        // Session with GNSS: what the user's phone or watch would export.
        let mut tr = PaceTracker::new(PaceConfig::default()).expect("valid");
        for s in &p.samples {
            let _ = tr.push(s);
        }
        runs.push((f.clone(), a, p, tr.calibration()));
    }
    let mut out = String::new();
    let _ = writeln!(out, "Pedometer-only pace on the real runs of one runner ({} runs, {prefix}*): every fix removed (a treadmill, an indoor track, a watch without GNSS), cadence only. Calibration: exported by `PaceTracker::calibration()` after replaying each *other* run with GNSS, imported through `PaceConfig::calibration` (leave one run out; the cell is the mean over the other runs); or none (population prior 1.0 m at 168 steps/min). Speed RMSE in m/s against the watch's speed channel / the GNSS-track reference (±6 s), distance error against the GNSS-track reference integral.\n", runs.len());
    let _ = writeln!(
        out,
        "| held-out run | calibrations (other runs) | calibrated: RMSE vs device / vs GNSS track, distance | prior only: RMSE vs device / vs GNSS track, distance |"
    );
    let _ = writeln!(out, "|---|---|---|---|");
    let mut pooled = [[0.0f64; 3]; 2];
    let mut n = [0usize; 2];
    for (i, (path, act, p, _)) in runs.iter().enumerate() {
        let cals: Vec<PaceCalibration> = runs
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .filter_map(|(_, r)| r.3)
            .collect();
        let score = |config: PaceConfig| {
            let (grid, speed) = steps_only(&p.samples, config);
            let dev = device_speed(act, &grid);
            let reference = crate::pace::smoothed_track_speed(
                &p.track,
                &grid,
                crate::pace_eval::REFERENCE_HALF_WINDOW_S,
            );
            let (mut de, mut dr) = (0.0, 0.0);
            for k in 1..grid.len() {
                if reference[k].is_finite() && reference[k - 1].is_finite() {
                    de += 0.5 * (speed[k] + speed[k - 1]);
                    dr += 0.5 * (reference[k] + reference[k - 1]);
                }
            }
            [
                rmse(&speed, &dev, |_| true),
                rmse(&speed, &reference, |_| true),
                100.0 * (de - dr) / dr,
            ]
        };
        let mut cal = [0.0f64; 3];
        for c in &cals {
            let s = score(PaceConfig {
                calibration: Some(*c),
                ..PaceConfig::default()
            });
            for (a, b) in cal.iter_mut().zip(s) {
                *a += b / cals.len() as f64;
            }
        }
        let prior = score(PaceConfig::default());
        // A run with no other run to calibrate from (a folder of one run) has no
        // calibrated cell and stays out of that pool.
        let calibrated = !cals.is_empty();
        for (k, v) in [cal, prior].iter().enumerate() {
            if k == 0 && !calibrated {
                continue;
            }
            pooled[k][0] += v[0] * v[0];
            pooled[k][1] += v[1] * v[1];
            pooled[k][2] += v[2].abs();
            n[k] += 1;
        }
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let cal_cell = if calibrated {
            format!("{} / {} / {:+.1} %", fmt(cal[0]), fmt(cal[1]), cal[2])
        } else {
            "– (no other run to calibrate from)".to_string()
        };
        let _ = writeln!(
            out,
            "| {name} | {} | {cal_cell} | {} / {} / {:+.1} % |",
            cals.len(),
            fmt(prior[0]),
            fmt(prior[1]),
            prior[2]
        );
    }
    if n[1] > 0 {
        let c = |k: usize| {
            if n[k] == 0 {
                return "–".to_string();
            }
            let m = n[k] as f64;
            format!(
                "{} / {} / mean |error| {:.1} %",
                fmt((pooled[k][0] / m).sqrt()),
                fmt((pooled[k][1] / m).sqrt()),
                pooled[k][2] / m
            )
        };
        let _ = writeln!(out, "| **pooled** | | {} | {} |", c(0), c(1));
    }
    Ok(out)
}
