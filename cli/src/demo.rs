//! `stridekit demo`: the built-in default job. Simulates a 40-minute run with GNSS
//! disturbance zones, outages and stops, replays it through every method, prints a
//! summary and writes a report folder with SVG plots.

use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::geo::LocalFrame;
use stridekit_core::PaceConfig;
use stridekit_lab::pace::{replay, score, sim_reference, Replay, Scores, METHODS};
const _: () = assert!(METHODS.len() == NAMES.len());
use stridekit_sim::{simulate_run, RunScenario, SimulatedRun, ZoneKind};

use stridekit_lab::report::{
    inline_html, line_chart, track_chart, Band, Chart, Series, Style, YFormat,
};

use crate::demo_facts::{Facts, NextSession, FAST_MPS, RUN_MIN_MPS};

/// The methods as the report names them everywhere (table, legends, explanations), in
/// the order of `stridekit_lab::pace::METHODS`.
const NAMES: [&str; 4] = [
    "raw GNSS diff",
    "GNSS EMA",
    "AsPublished",
    "stridekit (default)",
];

/// Slowest speed whose pace is drawn, m/s (16:40 /km): slower is standing or shuffling.
const PACE_MIN_MPS: f64 = 1.0;

fn series(name: &str, t: &[f64], v: &[f64], color: (u8, u8, u8), style: Style) -> Series {
    Series {
        name: name.to_string(),
        points: t.iter().zip(v).map(|(&a, &b)| (a, b)).collect(),
        color: Some(color),
        style,
    }
}

/// The simulated run replayed through every method, and what the report says of it.
struct Demo {
    seed: u64,
    scenario: RunScenario,
    run: SimulatedRun,
    r: Replay,
    /// The true speed on the replay's grid, m/s.
    truth: Vec<f64>,
    s: Scores,
    truth_dist: f64,
    /// The GNSS fixes, m east / north of the scenario's origin.
    fixes: Vec<(f64, f64)>,
    /// The tracker's positions are relative to its first fix.
    origin: (f64, f64),
    treadmill: Option<Treadmill>,
    facts: Facts,
}

/// The summary as printed, and what the HTML page repeats of it.
struct Summary {
    text: String,
    rows_html: String,
    pace_note: String,
    /// Median step length over the last minute, estimated and true, m.
    last_len: Option<(f64, f64)>,
}

/// `stridekit demo`: simulate, print the summary, write the charts and the report.
pub fn run(out_dir: &Path, seed: u64) -> Result<(), String> {
    let d = Demo::simulate(seed);
    let summary = d.summary();
    print!("{}", summary.text);
    let summary_html = d.summary_html(&summary);
    std::fs::create_dir_all(out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    d.write_charts(out_dir)?;
    let shown = figures(&d.facts, d.treadmill.is_some());
    write_report(out_dir, &summary.text, &summary_html, &shown)?;
    println!(
        "\nReport written to {}/ (index.html, summary.md, {})",
        out_dir.display(),
        shown.iter().map(|(f, _)| *f).collect::<Vec<_>>().join(", ")
    );
    Ok(())
}

impl Demo {
    /// The demo run of `seed`, replayed and scored.
    fn simulate(seed: u64) -> Self {
        let scenario = RunScenario::demo(seed);
        let run = simulate_run(&scenario);
        let samples = run.samples();
        let r = replay(&samples, PaceConfig::as_published(), PaceConfig::default());
        let truth = sim_reference(&run, &r);
        let s = score(&r, &truth, &run.zones);
        let truth_dist = run.truth.last().map(|t| t.distance_m).unwrap_or(0.0);
        let frame = LocalFrame::new(scenario.origin_lat_deg, scenario.origin_lon_deg, 0.0);
        let fixes: Vec<(f64, f64)> = run
            .fixes
            .iter()
            .map(|f| {
                let p = frame.to_enu(f.lat_deg, f.lon_deg, 0.0);
                (p[0], p[1])
            })
            .collect();
        // The tracker's positions are relative to its first fix.
        let origin = fixes.first().copied().unwrap_or((0.0, 0.0));
        // The next session without GNSS (a treadmill): this run's steps alone, with the
        // calibration this run exported and with the population prior.
        let treadmill = r
            .calibration
            .and_then(|c| Treadmill::measure(&run, &samples, c));
        let facts = Facts::measure(
            &run,
            &r,
            &truth,
            &s,
            origin,
            treadmill.as_ref().map(|tm| NextSession {
                truth: &tm.truth,
                calibrated: &tm.calibrated,
                prior: &tm.prior,
            }),
        );
        Self {
            seed,
            scenario,
            run,
            r,
            truth,
            s,
            truth_dist,
            fixes,
            origin,
            treadmill,
            facts,
        }
    }

    /// The summary: the run, the table of methods, the step length, the treadmill.
    fn summary(&self) -> Summary {
        let Self {
            seed,
            scenario,
            run,
            r,
            s,
            truth_dist,
            treadmill,
            facts,
            ..
        } = self;
        let truth_dist = *truth_dist;
        let mut summary = String::new();
        let _ = writeln!(summary, "# stridekit demo: simulated run (seed {seed})\n");
        let _ = writeln!(
            summary,
            "{:.0} min, {} GNSS fixes, {} step samples, true distance {:.0} m; zones: {} GNSS disturbance, {} outage, {} stop.\n",
            scenario.duration_s / 60.0,
            run.fixes.len(),
            run.steps.len(),
            truth_dist,
            run.zones.iter().filter(|z| z.kind == ZoneKind::Disturbance).count(),
            run.zones.iter().filter(|z| z.kind == ZoneKind::Outage).count(),
            run.zones.iter().filter(|z| z.kind == ZoneKind::Stop).count(),
        );
        let _ = writeln!(summary, "| method | speed RMSE where GNSS (m/s) | in disturbance zones | in outages | distance (m) |");
        let _ = writeln!(summary, "|---|---|---|---|---|");
        let f = |v: f64| {
            if v.is_finite() {
                format!("{v:.3}")
            } else {
                "—".into()
            }
        };
        // Beside each speed error, the pace error a runner reads (s/km).
        let fp = |v: f64, p: f64, html: bool| match (v.is_finite() && p.is_finite(), html) {
            (true, false) => format!("{v:.3} · {p:.0} s/km"),
            (true, true) => format!("{v:.3}<br><small>{p:.0} s/km</small>"),
            (false, _) => f(v),
        };
        let mut rows_html = String::new();
        for (m, name) in NAMES.iter().enumerate() {
            let d = if m >= 2 {
                let d = s.distance_m[m - 2];
                format!("{d:.0} ({:+.2} %)", 100.0 * (d - truth_dist) / truth_dist)
            } else {
                "—".into()
            };
            let cells = [s.all[m], s.disturbed[m], s.outage[m]];
            let pe = facts.pace_error[m];
            let _ = writeln!(
                summary,
                "| {name} | {} | {} | {} | {d} |",
                fp(cells[0], pe[0], false),
                fp(cells[1], pe[1], false),
                fp(cells[2], pe[2], false),
            );
            let _ = write!(
                rows_html,
                "<tr{}><td>{name}</td><td>{}</td><td>{}</td><td>{}</td><td>{d}</td></tr>",
                if m == 3 { " class=ours" } else { "" },
                fp(cells[0], pe[0], true),
                fp(cells[1], pe[1], true),
                fp(cells[2], pe[2], true),
            );
        }
        let pace_note = format!(
            "Beside each speed RMSE (m/s): the median pace error where the runner runs (faster than {} /km), in s/km.",
            crate::replay::min_s(1000.0 / RUN_MIN_MPS)
        );
        let _ = writeln!(summary, "\n{pace_note}");
        // Step length over the last minute (medians: the very last grid point can fall
        // between the last step sample and the end of the recording).
        let t_end = r.t_s.last().copied().unwrap_or(0.0);
        let est: Vec<f64> = r
            .t_s
            .iter()
            .zip(&r.step_length)
            .filter(|(t, l)| **t >= t_end - 60.0 && l.is_finite())
            .map(|(_, l)| *l)
            .collect();
        let tru: Vec<f64> = run
            .truth
            .iter()
            .filter(|p| p.t_s >= t_end - 60.0 && p.cadence_spm > 0.0)
            .map(|p| p.step_length_m)
            .collect();
        let last_len = (!est.is_empty() && !tru.is_empty()).then(|| {
            (
                stridekit_lab::stats::median(est),
                stridekit_lab::stats::median(tru),
            )
        });
        if let Some((l, t)) = last_len {
            let _ = writeln!(
                summary,
                "\nStep length over the last minute (median): {l:.2} m (true {t:.2} m)."
            );
        }
        if let Some(tm) = &treadmill {
            let _ = writeln!(summary, "\n{}", tm.sentence());
        }
        Summary {
            text: summary,
            rows_html,
            pace_note,
            last_len,
        }
    }

    /// The HTML page's summary: the same facts as the printed one.
    fn summary_html(&self, summary: &Summary) -> String {
        let Self {
            seed,
            scenario,
            run,
            truth_dist,
            treadmill,
            ..
        } = self;
        let truth_dist = *truth_dist;
        let Summary {
            rows_html,
            pace_note,
            last_len,
            ..
        } = summary;
        let mean_pace = if truth_dist > 0.0 {
            crate::replay::min_s(1000.0 * scenario.duration_s / truth_dist)
        } else {
            String::new()
        };
        format!(
            "<h1>stridekit demo: a simulated run (seed {seed})</h1>\
             <p>{:.0} minutes, {:.2} km (average pace {mean_pace} /km including stops), {} GNSS fixes, \
             step counts once per second. The run crosses {} stretches of disturbed GNSS, {} without \
             GNSS and {} stops.</p>\
             <table><tr><th>method</th><th>speed RMSE where GNSS is good (m/s)</th>\
             <th>in disturbed GNSS</th><th>without GNSS</th><th>distance (m, error)</th></tr>{rows_html}</table>\
             <p>{}</p><p>True distance {truth_dist:.0} m.{}</p>{}{METHODS_HTML}",
            scenario.duration_s / 60.0,
            truth_dist / 1000.0,
            run.fixes.len(),
            run.zones.iter().filter(|z| z.kind == ZoneKind::Disturbance).count(),
            run.zones.iter().filter(|z| z.kind == ZoneKind::Outage).count(),
            run.zones.iter().filter(|z| z.kind == ZoneKind::Stop).count(),
            inline_html(pace_note),
            last_len
                .map(|(l, t)| format!(
                    " Step length over the last minute (median): {l:.2} m (true {t:.2} m)."
                ))
                .unwrap_or_default(),
            treadmill
                .as_ref()
                .map(|tm| format!("<p>{}</p>", inline_html(&tm.sentence())))
                .unwrap_or_default()
        )
    }

    /// The report's charts: pace, speed, GNSS weight, step length, track, treadmill.
    fn write_charts(&self, out_dir: &Path) -> Result<(), String> {
        let bands = self.bands();
        let t: Vec<f64> = self.r.t_s.iter().map(|&v| minutes(v)).collect();
        self.pace_chart(out_dir, &t, &bands)?;
        self.speed_chart(out_dir, &t, &bands)?;
        self.weight_chart(out_dir, &t, &bands)?;
        self.step_length_chart(out_dir, &t, &bands)?;
        self.track_chart(out_dir)?;
        if let Some(tm) = &self.treadmill {
            treadmill_chart(out_dir, tm, self.top_speed_mps())?;
        }
        Ok(())
    }

    /// The zones of the run as bands on the time charts.
    fn bands(&self) -> Vec<Band> {
        self.run
            .zones
            .iter()
            .map(|z| Band {
                start: minutes(z.start_s),
                end: minutes(z.end_s),
                label: match z.kind {
                    ZoneKind::Disturbance => "GNSS disturbed (urban canyon, trees)",
                    ZoneKind::Outage => "no GNSS (tunnel)",
                    ZoneKind::Stop => "runner stopped",
                }
                .to_string(),
                color: match z.kind {
                    ZoneKind::Disturbance => (255, 190, 60),
                    ZoneKind::Outage => (120, 120, 120),
                    ZoneKind::Stop => (60, 150, 255),
                },
            })
            .collect()
    }

    /// The fastest true speed, m/s (the speed axes reach 1.6 times it).
    fn top_speed_mps(&self) -> f64 {
        let mut top = 0.0f64;
        for v in self.truth.iter().filter(|v| v.is_finite()) {
            top = top.max(*v);
        }
        top
    }

    /// pace.svg: raw GNSS, truth and the default tracker, min/km.
    fn pace_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let Self { r, truth, .. } = self;
        let truth_pace = pace_min_per_km(truth);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &p in truth_pace.iter().filter(|p| p.is_finite()) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let pace_range = if lo < hi {
            ((lo - 0.75).max(0.0), hi + 1.5)
        } else {
            (3.0, 9.0)
        };
        let pace_series = [
            series(
                NAMES[0],
                t,
                &pace_min_per_km(&r.speed[0]),
                (190, 190, 190),
                Style::Points,
            ),
            series("truth", t, &truth_pace, (0, 0, 0), Style::Line),
            series(
                NAMES[3],
                t,
                &pace_min_per_km(&r.speed[3]),
                (220, 30, 60),
                Style::Line,
            ),
        ];
        written(
            "pace.svg",
            line_chart(
                &out_dir.join("pace.svg"),
                &Chart {
                    title: "Pace: what the runner sees",
                    x_label: "time (min)",
                    y_label: "pace (min/km, lower is faster)",
                    series: &pace_series,
                    bands,
                    y_range: Some(pace_range),
                    y_format: YFormat::MinSec,
                },
            ),
        )?;
        Ok(())
    }

    /// speed.svg: every method against the truth (GNSS-only ones where GNSS is).
    fn speed_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let Self { r, truth, .. } = self;
        let top = self.top_speed_mps();
        // The GNSS-only methods have no value without GNSS (the replay holds their last
        // one): not drawn there.
        let gnss_only = |m: usize| -> Vec<f64> {
            r.speed[m]
                .iter()
                .zip(&r.has_gnss)
                .map(|(&v, &g)| if g { v } else { f64::NAN })
                .collect()
        };
        let speed = [
            series("truth", t, truth, (0, 0, 0), Style::Line),
            series(NAMES[1], t, &gnss_only(1), (230, 140, 40), Style::Line),
            series(NAMES[2], t, &r.speed[2], (60, 120, 220), Style::Line),
            series(NAMES[3], t, &r.speed[3], (220, 30, 60), Style::Line),
        ];
        written(
            "speed.svg",
            line_chart(
                &out_dir.join("speed.svg"),
                &Chart {
                    title: "Speed by method (spikes above the axis are clipped)",
                    x_label: "time (min)",
                    y_label: "speed (m/s)",
                    series: &speed,
                    bands,
                    y_range: Some((0.0, (1.6 * top).max(1.0))),
                    y_format: YFormat::Number,
                },
            ),
        )?;
        Ok(())
    }

    /// gnss_weight.svg: how much the speed follows GNSS.
    fn weight_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let r = &self.r;
        let weight = [
            series(NAMES[2], t, &r.weight[0], (60, 120, 220), Style::Line),
            series(NAMES[3], t, &r.weight[1], (220, 30, 60), Style::Line),
        ];
        written(
            "gnss_weight.svg",
            line_chart(
                &out_dir.join("gnss_weight.svg"),
                &Chart {
                    title: "How much the speed follows GNSS (1 = GNSS only, 0 = steps only)",
                    x_label: "time (min)",
                    y_label: "GNSS weight",
                    series: &weight,
                    bands,
                    y_range: Some(GNSS_WEIGHT_RANGE),
                    y_format: YFormat::Number,
                },
            ),
        )?;
        Ok(())
    }

    /// step_length.svg: the learned step length against the true one.
    fn step_length_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let Self { run, r, .. } = self;
        // The true step length where the runner steps (none while standing).
        let truth_len: Vec<f64> = r
            .t_s
            .iter()
            .map(|&t| {
                let p = run.truth_at(t);
                if p.cadence_spm > 0.0 {
                    p.step_length_m
                } else {
                    f64::NAN
                }
            })
            .collect();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in truth_len
            .iter()
            .chain(&r.step_length)
            .filter(|v| v.is_finite())
        {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        let len_range = if lo < hi {
            let pad = 0.1 * (hi - lo);
            ((lo - pad).max(0.0), hi + 4.0 * pad)
        } else {
            (0.4, 1.8)
        };
        let steps = [
            series("truth", t, &truth_len, (0, 0, 0), Style::Line),
            series(
                &format!("{}, learned from GNSS", NAMES[3]),
                t,
                &r.step_length,
                (220, 30, 60),
                Style::Line,
            ),
        ];
        written(
            "step_length.svg",
            line_chart(
                &out_dir.join("step_length.svg"),
                &Chart {
                    title: "Step length",
                    x_label: "time (min)",
                    y_label: "step length (m)",
                    series: &steps,
                    bands,
                    y_range: Some(len_range),
                    y_format: YFormat::Number,
                },
            ),
        )?;
        Ok(())
    }

    /// track.svg: the fixes, the truth and the tracker's positions.
    fn track_chart(&self, out_dir: &Path) -> Result<(), String> {
        let Self { run, r, origin, .. } = self;
        let origin = *origin;
        let fixes = self.fixes.clone();
        let fused: Vec<(f64, f64)> = r
            .position_enu_m
            .iter()
            .map(|&(e, n)| (origin.0 + e, origin.1 + n))
            .collect();
        let track = [
            Series {
                name: "GNSS fixes".into(),
                points: fixes,
                color: Some((230, 160, 60)),
                style: Style::Points,
            },
            Series {
                name: "truth".into(),
                points: run.truth.iter().map(|p| (p.east_m, p.north_m)).collect(),
                color: Some((0, 0, 0)),
                style: Style::Line,
            },
            Series {
                name: NAMES[3].into(),
                points: fused,
                color: Some((220, 30, 60)),
                style: Style::Line,
            },
        ];
        written(
            "track.svg",
            track_chart(
                &out_dir.join("track.svg"),
                "Track (metres east / north of the start)",
                &track,
            ),
        )?;
        Ok(())
    }
}

/// treadmill.svg: the next session's steps alone, calibrated or with the prior.
fn treadmill_chart(out_dir: &Path, tm: &Treadmill, top: f64) -> Result<(), String> {
    let g: Vec<f64> = tm.t_s.iter().map(|&v| minutes(v)).collect();
    let lines = [
        series("truth", &g, &tm.truth, (0, 0, 0), Style::Line),
        series(
            "steps only, population prior",
            &g,
            &tm.prior,
            (150, 150, 150),
            Style::Line,
        ),
        series(
            "steps only, this run's calibration",
            &g,
            &tm.calibrated,
            (220, 30, 60),
            Style::Line,
        ),
    ];
    written(
        "treadmill.svg",
        line_chart(
            &out_dir.join("treadmill.svg"),
            &Chart {
                title: "Next session without GNSS: the same steps, calibrated or not",
                x_label: "time (min)",
                y_label: "speed (m/s)",
                series: &lines,
                bands: &[],
                y_range: Some((0.0, (1.6 * top).max(1.0))),
                y_format: YFormat::Number,
            },
        ),
    )
}

/// Time in minutes, as a runner reads a run.
fn minutes(t_s: f64) -> f64 {
    t_s / 60.0
}

/// Pace in min/km; slower than [`PACE_MIN_MPS`] (standing, shuffling) is a gap.
fn pace_min_per_km(v: &[f64]) -> Vec<f64> {
    v.iter()
        .map(|&s| {
            if s >= PACE_MIN_MPS {
                1000.0 / s / 60.0
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// A chart's writing error, naming the chart.
fn written(name: &str, res: Result<(), stridekit_lab::report::ReportError>) -> Result<(), String> {
    res.map_err(|e| format!("cannot write {name}: {e}"))
}

/// summary.md (the summary, the methods, each figure with its caption) and index.html.
fn write_report(
    out_dir: &Path,
    summary: &str,
    summary_html: &str,
    shown: &[(&'static str, String)],
) -> Result<(), String> {
    let mut md = summary.to_string();
    md.push_str(&format!("\n{METHODS_EXPLAINED}\n"));
    for (f, caption) in shown {
        md.push_str(&format!("\n![{f}]({f})\n\n{caption}\n"));
    }
    std::fs::write(out_dir.join("summary.md"), md).map_err(|e| e.to_string())?;
    std::fs::write(out_dir.join("index.html"), html(summary_html, shown))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// The GNSS weight's axis: the weight is a share, 0..1.
const GNSS_WEIGHT_RANGE: (f64, f64) = (0.0, 1.0);

/// The run's steps replayed alone (a treadmill the next day), with the calibration
/// the GNSS session exported and with the population prior.
struct Treadmill {
    t_s: Vec<f64>,
    truth: Vec<f64>,
    calibrated: Vec<f64>,
    prior: Vec<f64>,
}

impl Treadmill {
    /// The steps of `samples` with `calibration` (what the GNSS session exported) and
    /// with the prior; `None` without any step.
    fn measure(
        run: &stridekit_sim::SimulatedRun,
        samples: &[stridekit_core::PaceSample],
        calibration: stridekit_core::PaceCalibration,
    ) -> Option<Self> {
        use stridekit_lab::pace_device::steps_only;
        let (t_s, calibrated) = steps_only(
            samples,
            PaceConfig {
                calibration: Some(calibration),
                ..PaceConfig::default()
            },
        );
        if t_s.is_empty() {
            return None;
        }
        let (_, prior) = steps_only(samples, PaceConfig::default());
        let truth = t_s.iter().map(|&t| run.truth_at(t).speed_mps).collect();
        Some(Self {
            t_s,
            truth,
            calibrated,
            prior,
        })
    }

    /// Speed RMSE against the truth, m/s, and the distance error, %.
    fn score(&self, speed: &[f64]) -> (f64, f64) {
        let n = self.t_s.len().max(1) as f64;
        let se: f64 = speed
            .iter()
            .zip(&self.truth)
            .map(|(v, t)| (v - t).powi(2))
            .sum();
        let (d, dt): (f64, f64) = (speed.iter().sum(), self.truth.iter().sum());
        ((se / n).sqrt(), 100.0 * (d - dt) / dt)
    }

    fn sentence(&self) -> String {
        let (rc, dc) = self.score(&self.calibrated);
        let (rp, dp) = self.score(&self.prior);
        format!(
            "**Next session without GNSS** (a treadmill: this run's steps alone, every fix left out): \
             with the calibration this run exported (`PaceTracker.calibration()`, imported through \
             `PaceConfig.calibration` in Kotlin and Swift) speed RMSE {rc:.3} m/s, distance {dc:+.1} %; \
             with the population prior {rp:.3} m/s, {dp:+.1} %."
        )
    }
}

/// What the methods in the tables and plots are (names as [`NAMES`]).
const METHODS_EXPLAINED: &str = "Methods: **raw GNSS diff** = distance between consecutive fixes \
over their time (what a naive app shows); **GNSS EMA** = the same, smoothed (exponential moving \
average); **AsPublished** = the pace-fusion method as its paper publishes it (GNSS and pedometer \
blended by a fixed rule); **stridekit (default)** = the SDK's filter (GNSS, cadence and a step \
length learned from GNSS in one Kalman filter, with GNSS outliers rejected).";

const METHODS_HTML: &str = "<dl>\
<dt>raw GNSS diff</dt><dd>distance between consecutive fixes over their time: what a naive app shows.</dd>\
<dt>GNSS EMA</dt><dd>the same, smoothed by an exponential moving average.</dd>\
<dt>AsPublished</dt><dd>the pace-fusion method exactly as its paper publishes it: GNSS and the pedometer blended by a fixed rule.</dd>\
<dt>stridekit (default)</dt><dd>the SDK's filter: GNSS, cadence and a step length learned from GNSS in one Kalman filter, GNSS outliers rejected; in outages the speed comes from the steps.</dd>\
</dl>";

/// `4.7` m/s as the captions write speeds.
fn mps(v: f64) -> String {
    format!("{v:.1} m/s")
}

/// Signed percent of `v` against `truth`.
fn pct(v: f64, truth: f64) -> String {
    format!("{:+.0} %", 100.0 * (v - truth) / truth)
}

/// "first" … for the captions.
fn ordinal(k: usize) -> &'static str {
    ["first", "second", "third", "fourth"]
        .get(k)
        .copied()
        .unwrap_or("next")
}

/// The figures of the report with the caption under each: what the chart shows, with
/// the figures measured on this run (`facts`); the treadmill one when the run exported
/// a calibration.
fn figures(facts: &Facts, treadmill: bool) -> Vec<(&'static str, String)> {
    let ours = NAMES[3];
    let pe = &facts.pace_error;
    let mut f = vec![
        (
            "pace.svg",
            format!(
                "Pace as a watch shows it: the truth, the raw GNSS diff pace (grey dots: the spikes a \
                 naive app shows) and {ours}'s. Shaded: disturbed GNSS (yellow), no GNSS (grey), the \
                 runner stopped (blue). Slower than {} /km (standing) pace is not drawn. Where the \
                 runner runs with GNSS, {ours}'s pace is within {:.0} s/km of the truth half of the \
                 time (raw GNSS diff: {:.0} s/km); without GNSS, {:.0} s/km.",
                crate::replay::min_s(1000.0 / PACE_MIN_MPS),
                pe[3][0],
                pe[0][0],
                pe[3][2],
            ),
        ),
        ("speed.svg", speed_caption(facts)),
        (
            "gnss_weight.svg",
            format!(
                "How much each method's speed rests on GNSS (1) or on the steps (0). AsPublished \
                 leans on GNSS whenever it has it (median weight {:.2} while running); {ours} \
                 learns its step length from GNSS and reports GNSS's share of what is known about \
                 the last minute's pace: while the runner runs, GNSS and the learned steps share it \
                 (median weight {:.2}), and the speed follows the steps between fixes, so GNSS \
                 errors do not reach it; at stops there are no steps and it follows GNSS (median \
                 weight {:.2}). Without GNSS (grey) both run on the steps (median weights {:.2} and \
                 {:.2}).",
                facts.weight_running[0],
                facts.weight_running[1],
                facts.weight_stopped,
                facts.weight_outage[0],
                facts.weight_outage[1],
            ),
        ),
        ("step_length.svg", step_caption(facts)),
        ("track.svg", track_caption(facts)),
    ];
    if treadmill {
        f.push(("treadmill.svg", treadmill_caption(facts)));
    }
    f
}

fn speed_caption(facts: &Facts) -> String {
    let d = &facts.disturbed_rmse;
    let mut s = format!(
        "The same run in m/s with every method, for engineers (GNSS EMA has no value without \
         GNSS). In the disturbed stretches \
         (yellow) GNSS EMA and AsPublished follow the GNSS errors (speed RMSE there {:.2} and \
         {:.2} m/s); {}'s RMSE there is {:.2} m/s. Without GNSS (grey) the speed comes from \
         the steps:",
        d[1], d[2], NAMES[3], d[3]
    );
    for (k, o) in facts.outages.iter().enumerate() {
        s += &format!(
            " in the {} outage ({:.0}–{:.0} min) the truth averages {}, {} {} ({}) and \
             AsPublished {} ({}); at the outage's top speed, {}, {} reads {} ({});",
            ordinal(k),
            o.start_min,
            o.end_min,
            mps(o.truth_mps),
            NAMES[3],
            mps(o.ours_mps),
            pct(o.ours_mps, o.truth_mps),
            mps(o.published_mps),
            pct(o.published_mps, o.truth_mps),
            mps(o.top_truth_mps),
            NAMES[3],
            mps(o.top_ours_mps),
            pct(o.top_ours_mps, o.top_truth_mps),
        );
    }
    s.pop();
    s += ". Where the runner goes faster than anything the step length was learned at, the \
          steps are read short (step length chart).";
    s
}

fn step_caption(facts: &Facts) -> String {
    let mut s = format!(
        "The step length {} learns from GNSS while it is good (a line against cadence), against \
         the truth; in outages it carries the speed:",
        NAMES[3]
    );
    for (k, o) in facts.outages.iter().enumerate() {
        s += &format!(
            " {:.2} m against {:.2} m in the {} ({});",
            o.ours_step_m,
            o.truth_step_m,
            ordinal(k),
            pct(o.ours_step_m, o.truth_step_m)
        );
    }
    s.pop();
    s += ". At stops there are no steps: the truth is not drawn and the learned value is held.";
    s
}

fn track_caption(facts: &Facts) -> String {
    let worst: Vec<String> = facts
        .outages
        .iter()
        .enumerate()
        .map(|(k, o)| {
            if k == 0 {
                format!(
                    "{:.0} m from the truth in the first outage",
                    o.worst_position_m
                )
            } else {
                format!("{:.0} m in the {}", o.worst_position_m, ordinal(k))
            }
        })
        .collect();
    format!(
        "Where the runner was: the GNSS fixes, the truth and {}'s fused position. With GNSS it \
         stays on the truth; without GNSS this input has no compass, so the position goes on in \
         the last direction at the fused speed (the straight lines; at worst {}), and snaps back \
         when GNSS returns.",
        NAMES[3],
        worst.join(" and ")
    )
}

fn treadmill_caption(facts: &Facts) -> String {
    let mut s = String::from(
        "The next session without any GNSS (a treadmill, an indoor track): the same run's steps \
         alone, paced with the step length this run learned from GNSS (exported as a calibration, \
         imported next time) or with the population prior.",
    );
    if let Some(u) = facts.usual {
        s += &format!(
            " At the run's usual paces (slower than {} /km) the truth averages {}: calibrated {} \
             ({}), prior {} ({}), this runner's difference from the population.",
            crate::replay::min_s(1000.0 / FAST_MPS),
            mps(u.truth),
            mps(u.calibrated),
            pct(u.calibrated, u.truth),
            mps(u.prior),
            pct(u.prior, u.truth),
        );
    }
    if let Some(f) = facts.fast {
        s += &format!(
            " In the fast intervals ({} and faster) the truth averages {}: calibrated {} ({}), \
             its line learned at the usual paces extrapolating short; prior {} ({}).",
            mps(FAST_MPS),
            mps(f.truth),
            mps(f.calibrated),
            pct(f.calibrated, f.truth),
            mps(f.prior),
            pct(f.prior, f.truth),
        );
    }
    s + " Walks use the population walking line either way."
}

/// The report page: the summary as HTML and every figure with its caption.
fn html(summary: &str, figures: &[(&str, String)]) -> String {
    let figures: String = figures
        .iter()
        .map(|(f, caption)| {
            format!(
                "<figure><img src=\"{f}\" alt=\"{f}\"><figcaption>{}</figcaption></figure>",
                inline_html(caption)
            )
        })
        .collect();
    format!(
        "<!doctype html><html lang=en><meta charset=utf-8><title>stridekit demo</title>\
<style>body{{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}}\
table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #ccc;padding:.35em .7em;text-align:right}}\
td:first-child,th:first-child{{text-align:left}}th{{background:#f3f3f3}}tr.ours td{{font-weight:600;background:#fff3f3}}\
td small{{color:#555;font-weight:400}}code{{font-family:ui-monospace,monospace;background:#f3f3f3;padding:0 .2em}}\
dt{{font-weight:600}}dd{{margin:0 0 .4em 1.5em}}figure{{margin:2em 0}}img{{max-width:100%}}\
figcaption{{color:#555;max-width:900px}}</style><body>{summary}{figures}</body></html>"
    )
}
