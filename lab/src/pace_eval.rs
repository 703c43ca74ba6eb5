//! `stridekit eval pace`: speed RMSE of the four methods on the simulator and on real
//! runs with injected GNSS degradation; distance agreement on the clean real runs.

use std::fmt::Write as _;
use std::path::Path;

use crate::pace::{
    distance_against, replay, score, sim_reference, smoothed_track_speed, Scores, METHODS,
};
use stridekit_core::PaceConfig;
use stridekit_sim::{simulate_run, RunScenario};

use crate::activity::{degraded, prepare};
use crate::table::Table;

/// Half-width of the centred smoothing that makes the real-run reference speed, s.
pub const REFERENCE_HALF_WINDOW_S: f64 = 6.0;

fn fmt(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3}")
    } else {
        "—".to_string()
    }
}

fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{v:+.2} %")
    } else {
        "—".to_string()
    }
}

/// Root of the mean of squares (pools per-run RMSEs), ignoring NaN.
fn pooled(vals: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0);
    for v in vals.filter(|v| v.is_finite()) {
        s += v * v;
        n += 1;
    }
    if n == 0 {
        f64::NAN
    } else {
        (s / n as f64).sqrt()
    }
}

/// Simulator table over `seeds` demo runs.
pub fn simulator_table(seeds: u64, default: PaceConfig) -> (String, Vec<Scores>) {
    let mut all = Vec::new();
    let mut with_speed = Vec::new();
    let mut dist_err = [Vec::new(), Vec::new()];
    for seed in 1..=seeds {
        let run = simulate_run(&RunScenario::demo(seed));
        let r = replay(&run.samples(), PaceConfig::as_published(), default);
        let reference = sim_reference(&run, &r);
        let s = score(&r, &reference, &run.zones);
        let truth = run.truth.last().map(|t| t.distance_m).unwrap_or(f64::NAN);
        for (errs, d) in dist_err.iter_mut().zip(s.distance_m) {
            errs.push(100.0 * (d - truth) / truth);
        }
        all.push(s);
        // The same run with a receiver (Doppler) speed on every fix.
        let run = simulate_run(&RunScenario {
            receiver_speed: true,
            ..RunScenario::demo(seed)
        });
        let r = replay(&run.samples(), PaceConfig::as_published(), default);
        with_speed.push(score(&r, &sim_reference(&run, &r), &run.zones));
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Simulator: {seeds} runs of the demo scenario (40 min: intervals, stops, GNSS disturbance zones, outages), speed RMSE against truth, m/s\n"
    );
    let _ = writeln!(out, "| method | RMSE where GNSS | RMSE in disturbance zones | RMSE in outages | distance error (mean) |");
    let _ = writeln!(out, "|---|---|---|---|---|");
    for (m, name) in METHODS.iter().enumerate() {
        let d = if m >= 2 {
            let v = &dist_err[m - 2];
            pct(v.iter().sum::<f64>() / v.len() as f64)
        } else {
            "—".into()
        };
        let _ = writeln!(
            out,
            "| {name} | {} | {} | {} | {d} |",
            fmt(pooled(all.iter().map(|s| s.all[m]))),
            fmt(pooled(all.iter().map(|s| s.disturbed[m]))),
            fmt(pooled(all.iter().map(|s| s.outage[m]))),
        );
    }
    let _ = writeln!(
        out,
        "| default + receiver speed | {} | {} | {} | |",
        fmt(pooled(with_speed.iter().map(|s| s.all[3]))),
        fmt(pooled(with_speed.iter().map(|s| s.disturbed[3]))),
        fmt(pooled(with_speed.iter().map(|s| s.outage[3]))),
    );
    let _ = writeln!(
        out,
        "\nThe last row feeds each fix's receiver (Doppler) speed with its accuracy (simulated: 0.1 m/s in the open, 0.6 m/s in disturbance zones where receivers report 0.4 m/s); the other rows use positions only, as the paper does."
    );
    (out, all)
}

/// One real run scored (see [`real_runs`]).
#[derive(Clone, Debug)]
pub struct RealRun {
    pub name: String,
    pub minutes: f64,
    /// Speed RMSE of the four methods on the degraded file.
    pub scores: Scores,
    /// The default filter's distance on the clean file against the clean-track
    /// reference, %.
    pub distance_error_pct: f64,
    /// The default filter's distance on the clean file, m.
    pub distance_m: f64,
    /// Raw fix-to-fix chord sum, m.
    pub chords_m: f64,
    /// The device's own distance (NaN when it has none), m.
    pub device_m: f64,
}

/// `eval pace`'s real runs, computed ([`RealRunsReport::render`] writes it).
#[derive(Clone, Debug)]
pub struct RealRunsReport {
    pub dir: std::path::PathBuf,
    pub runs: Vec<RealRun>,
    /// Files not scored, with the reason.
    pub skipped: Vec<String>,
    /// [`crate::pace_device::outage_table`] as it renders.
    pub outage_table: String,
    /// Pedometer-only pace of one runner's runs.
    pub pedometer_only: crate::pace_device::PedometerOnlyReport,
}

/// Every activity file in `dir` (fit/tcx/gpx) with GNSS and cadence, scored.
pub fn real_runs(dir: &Path, default: PaceConfig) -> Result<RealRunsReport, String> {
    let files = crate::activity::activity_files(dir)?;
    let mut runs = Vec::new();
    let mut skipped = Vec::new();
    for (i, path) in files.iter().enumerate() {
        match real_run(path, i, default) {
            Ok(r) => runs.push(r),
            Err(why) => skipped.push(why),
        }
    }
    Ok(RealRunsReport {
        dir: dir.to_path_buf(),
        runs,
        skipped,
        outage_table: crate::pace_device::outage_table(&files, default),
        pedometer_only: crate::pace_device::pedometer_only(dir, "2020-12-")?,
    })
}

/// One file (the `i`-th: its degradation seed): scored, or why it is not.
fn real_run(path: &Path, i: usize, default: PaceConfig) -> Result<RealRun, String> {
    let activity =
        stridekit_formats::read_activity(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let p = prepare(&activity);
    let name = path
        .file_name()
        .unwrap_or_default()
        .to_string_lossy()
        .to_string();
    if p.track.len() < 30 || !p.has_steps {
        return Err(format!(
            "{name}: {} (not scored)",
            if p.track.len() < 30 {
                "too few GNSS fixes"
            } else {
                "no cadence"
            }
        ));
    }
    let clean = replay(&p.samples, PaceConfig::as_published(), default);
    let clean_ref = smoothed_track_speed(&p.track, &clean.t_s, REFERENCE_HALF_WINDOW_S);
    let (ref_m, est_m) = distance_against(&clean, &clean_ref, 1);
    let (samples, zones) = degraded(&p, 1000 + i as u64);
    let r = replay(&samples, PaceConfig::as_published(), default);
    let reference = smoothed_track_speed(&p.track, &r.t_s, REFERENCE_HALF_WINDOW_S);
    let device = activity
        .records
        .iter()
        .filter_map(|r| r.device_distance_m)
        .fold((f64::NAN, f64::NAN), |(a, _), d| {
            (if a.is_nan() { d } else { a }, d)
        });
    Ok(RealRun {
        name,
        minutes: p.track.last().map(|t| t.0).unwrap_or(0.0) / 60.0,
        scores: score(&r, &reference, &zones),
        distance_error_pct: 100.0 * (est_m - ref_m) / ref_m,
        distance_m: clean.distance[1].last().copied().unwrap_or(0.0),
        chords_m: clean.gnss_track_distance_m,
        device_m: device.1 - device.0,
    })
}

/// "all / disturbed / outage" of method `m`, pooled over the runs.
fn segments_cell<'a>(scores: impl Iterator<Item = &'a Scores> + Clone, m: usize) -> String {
    format!(
        "{} / {} / {}",
        fmt(pooled(scores.clone().map(|s| s.all[m]))),
        fmt(pooled(scores.clone().map(|s| s.disturbed[m]))),
        fmt(pooled(scores.map(|s| s.outage[m])))
    )
}

impl RealRunsReport {
    /// The real-run table and the device tables, as markdown.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Real runs ({}): GNSS degraded by injected bursts and outages on the recorded track; reference = clean-track speed (slope of a centred straight-line fit, ±{REFERENCE_HALF_WINDOW_S} s). Speed RMSE in m/s where GNSS is available / inside the injected disturbance zones / inside the injected outages. Distance: the default filter on the clean file against the integral of the same clean-track reference speed over the same seconds; raw fix-to-fix chord sums are inflated by position noise and device distances come from the watch's own (sometimes foot-pod) fusion, shown for context.\n",
            self.dir.display()
        );
        out.push_str(&self.table().render());
        for s in &self.skipped {
            let _ = writeln!(out, "\nSkipped: {s}");
        }
        let _ = writeln!(out, "\n{}", self.outage_table);
        let _ = writeln!(out, "{}", self.pedometer_only.render());
        out
    }

    /// One row per run, then the pooled row.
    fn table(&self) -> Table {
        let mut t = Table::new([
            "file",
            "min",
            "raw GNSS diff",
            "GNSS EMA",
            "AsPublished",
            "default",
            "default distance vs clean-track reference",
            "distance m: default / raw fix-to-fix chords / device",
        ]);
        for r in &self.runs {
            let s = &r.scores;
            let cell = |m: usize| {
                format!(
                    "{} / {} / {}",
                    fmt(s.all[m]),
                    fmt(s.disturbed[m]),
                    fmt(s.outage[m])
                )
            };
            let device = if r.device_m.is_finite() {
                format!("{:.0}", r.device_m)
            } else {
                "—".into()
            };
            t.row([
                r.name.clone(),
                format!("{:.0}", r.minutes),
                cell(0),
                cell(1),
                cell(2),
                cell(3),
                pct(r.distance_error_pct),
                format!("{:.0} / {:.0} / {device}", r.distance_m, r.chords_m),
            ]);
        }
        if !self.runs.is_empty() {
            let cell = |m: usize| segments_cell(self.runs.iter().map(|r| &r.scores), m);
            let errors: Vec<f64> = self.runs.iter().map(|r| r.distance_error_pct).collect();
            let mut a: Vec<f64> = errors.iter().map(|e| e.abs()).collect();
            a.sort_by(f64::total_cmp);
            t.row([
                "**pooled**".to_string(),
                String::new(),
                cell(0),
                cell(1),
                cell(2),
                cell(3),
                format!(
                    "absolute error: median {:.2} %, mean {:.2} %, max {:.2} %",
                    a[a.len() / 2],
                    errors.iter().map(|e| e.abs()).sum::<f64>() / errors.len() as f64,
                    errors.iter().fold(0.0f64, |m, e| m.max(e.abs())),
                ),
                String::new(),
            ]);
        }
        t
    }
}
