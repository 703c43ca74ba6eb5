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

use crate::activity::{degraded, prepare, Prepared};
use crate::table::Table;

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

/// Pedometer-only pace on one runner's real runs, leave one run out, rendered by
/// [`PedometerOnlyReport::render`].
#[derive(Clone, Debug)]
pub struct PedometerOnlyReport {
    /// The file-name prefix of the runner's runs.
    prefix: String,
    rows: Vec<PedometerRow>,
}

/// One held-out run: speed RMSE vs the device and vs the GNSS track, and distance
/// error, %.
#[derive(Clone, Debug)]
struct PedometerRow {
    name: String,
    /// Calibrations of the other runs.
    calibrations: usize,
    /// The mean over those calibrations; `None` with no other run to calibrate from.
    calibrated: Option<[f64; 3]>,
    /// With the population prior only.
    prior: [f64; 3],
}

/// One run with its GNSS session's calibration.
struct CalibratedRun {
    path: PathBuf,
    activity: Activity,
    prepared: Prepared,
    calibration: Option<PaceCalibration>,
}

/// Pedometer-only pace on the runs `prefix*` in `dir`, each calibrated from the others.
pub fn pedometer_only(dir: &Path, prefix: &str) -> Result<PedometerOnlyReport, String> {
    let runs = runner_files(dir, prefix)?
        .iter()
        .map(|f| calibrated_run(f))
        .collect::<Result<Vec<_>, String>>()?;
    Ok(PedometerOnlyReport {
        prefix: prefix.to_string(),
        rows: (0..runs.len()).map(|i| held_out_row(&runs, i)).collect(),
    })
}

/// The files of `dir` whose names start with `prefix`, sorted.
fn runner_files(dir: &Path, prefix: &str) -> Result<Vec<PathBuf>, String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("cannot read {}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(prefix))
        })
        .collect();
    files.sort();
    Ok(files)
}

/// One run read and replayed with GNSS: what the user's phone or watch would export.
fn calibrated_run(f: &Path) -> Result<CalibratedRun, String> {
    let activity =
        stridekit_formats::read_activity(f).map_err(|e| format!("{}: {e}", f.display()))?;
    let prepared = prepare(&activity);
    let mut tr = PaceTracker::new(PaceConfig::default()).expect("valid");
    for s in &prepared.samples {
        let _ = tr.push(s);
    }
    Ok(CalibratedRun {
        path: f.to_path_buf(),
        activity,
        prepared,
        calibration: tr.calibration(),
    })
}

/// Run `i` held out: scored with each other run's calibration (mean) and with the prior.
fn held_out_row(runs: &[CalibratedRun], i: usize) -> PedometerRow {
    let run = &runs[i];
    let cals: Vec<PaceCalibration> = runs
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != i)
        .filter_map(|(_, r)| r.calibration)
        .collect();
    let mut cal = [0.0f64; 3];
    for c in &cals {
        let s = pedometer_score(
            run,
            PaceConfig {
                calibration: Some(*c),
                ..PaceConfig::default()
            },
        );
        for (a, b) in cal.iter_mut().zip(s) {
            *a += b / cals.len() as f64;
        }
    }
    PedometerRow {
        name: run
            .path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned(),
        calibrations: cals.len(),
        calibrated: (!cals.is_empty()).then_some(cal),
        prior: pedometer_score(run, PaceConfig::default()),
    }
}

/// Cadence-only pace of `run` under `config`: speed RMSE vs the device, vs the GNSS
/// track reference, and the distance error against the reference integral, %.
fn pedometer_score(run: &CalibratedRun, config: PaceConfig) -> [f64; 3] {
    let p = &run.prepared;
    let (grid, speed) = steps_only(&p.samples, config);
    let dev = device_speed(&run.activity, &grid);
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
}

impl PedometerOnlyReport {
    /// The text, then the table with its **pooled** row.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "Pedometer-only pace on the real runs of one runner ({} runs, {}*): every fix removed (a treadmill, an indoor track, a watch without GNSS), cadence only. Calibration: exported by `PaceTracker::calibration()` after replaying each *other* run with GNSS, imported through `PaceConfig::calibration` (leave one run out; the cell is the mean over the other runs); or none (population prior 1.0 m at 168 steps/min). Speed RMSE in m/s against the watch's speed channel / the GNSS-track reference (±6 s), distance error against the GNSS-track reference integral.\n", self.rows.len(), self.prefix);
        out.push_str(&self.table().render());
        out
    }

    fn table(&self) -> Table {
        let mut t = Table::new([
            "held-out run",
            "calibrations (other runs)",
            "calibrated: RMSE vs device / vs GNSS track, distance",
            "prior only: RMSE vs device / vs GNSS track, distance",
        ]);
        for r in &self.rows {
            let cal_cell = match r.calibrated {
                Some(cal) => format!("{} / {} / {:+.1} %", fmt(cal[0]), fmt(cal[1]), cal[2]),
                None => "– (no other run to calibrate from)".to_string(),
            };
            t.row([
                r.name.clone(),
                r.calibrations.to_string(),
                cal_cell,
                format!(
                    "{} / {} / {:+.1} %",
                    fmt(r.prior[0]),
                    fmt(r.prior[1]),
                    r.prior[2]
                ),
            ]);
        }
        if !self.rows.is_empty() {
            let [c, p] = self.pooled();
            t.row(["**pooled**".to_string(), String::new(), c, p]);
        }
        t
    }

    /// The pooled cells, calibrated and prior only: RMS of the RMSEs, mean |distance
    /// error| (a run without a calibrated cell stays out of that pool).
    fn pooled(&self) -> [String; 2] {
        let mut pooled = [[0.0f64; 3]; 2];
        let mut n = [0usize; 2];
        for r in &self.rows {
            for (k, v) in [r.calibrated, Some(r.prior)].iter().enumerate() {
                let Some(v) = v else { continue };
                pooled[k][0] += v[0] * v[0];
                pooled[k][1] += v[1] * v[1];
                pooled[k][2] += v[2].abs();
                n[k] += 1;
            }
        }
        [0, 1].map(|k| {
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
        })
    }
}
