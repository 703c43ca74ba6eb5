//! `stridekit demo`: the built-in default job. Simulates a 40-minute run with GNSS
//! disturbance zones, outages and stops, replays it through every method, prints a
//! summary and writes a report folder with SVG plots.

use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::geo::LocalFrame;
use stridekit_core::PaceConfig;
use stridekit_lab::pace::{replay, score, sim_reference, METHODS};
use stridekit_sim::{simulate_run, RunScenario, ZoneKind};

use stridekit_lab::report::{line_chart, track_chart, Band, Chart, Series, Style, YFormat};

fn series(name: &str, t: &[f64], v: &[f64], color: (u8, u8, u8), style: Style) -> Series {
    Series {
        name: name.to_string(),
        points: t.iter().zip(v).map(|(&a, &b)| (a, b)).collect(),
        color: Some(color),
        style,
    }
}

pub fn run(out_dir: &Path, seed: u64) -> Result<(), String> {
    let scenario = RunScenario::demo(seed);
    let run = simulate_run(&scenario);
    let samples = run.samples();
    let r = replay(&samples, PaceConfig::as_published(), PaceConfig::default());
    let truth = sim_reference(&run, &r);
    let s = score(&r, &truth, &run.zones);
    let truth_dist = run.truth.last().map(|t| t.distance_m).unwrap_or(0.0);

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
    let mut rows_html = String::new();
    for (m, name) in METHODS.iter().enumerate() {
        let d = if m >= 2 {
            let d = s.distance_m[m - 2];
            format!("{d:.0} ({:+.2} %)", 100.0 * (d - truth_dist) / truth_dist)
        } else {
            "—".into()
        };
        let _ = writeln!(
            summary,
            "| {name} | {} | {} | {} | {d} |",
            f(s.all[m]),
            f(s.disturbed[m]),
            f(s.outage[m])
        );
        let shown = if *name == "default" {
            "stridekit (default)"
        } else {
            name
        };
        let _ = write!(
            rows_html,
            "<tr{}><td>{shown}</td><td>{}</td><td>{}</td><td>{}</td><td>{d}</td></tr>",
            if *name == "default" {
                " class=ours"
            } else {
                ""
            },
            f(s.all[m]),
            f(s.disturbed[m]),
            f(s.outage[m])
        );
    }
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
    // The next session without GNSS (a treadmill): this run's steps alone, with the
    // calibration this run exported and with the population prior.
    let treadmill = r
        .calibration
        .and_then(|c| Treadmill::measure(&run, &samples, c));
    if let Some(tm) = &treadmill {
        let _ = writeln!(summary, "\n{}", tm.sentence());
    }
    print!("{summary}");
    let mean_pace = if truth_dist > 0.0 {
        crate::replay::min_s(1000.0 * scenario.duration_s / truth_dist)
    } else {
        String::new()
    };
    let summary_html = format!(
        "<h1>stridekit demo: a simulated run (seed {seed})</h1>\
         <p>{:.0} minutes, {:.2} km (average pace {mean_pace} /km including stops), {} GNSS fixes, \
         step counts once per second. The run crosses {} stretches of disturbed GNSS, {} without \
         GNSS and {} stops.</p>\
         <table><tr><th>method</th><th>speed RMSE where GNSS is good (m/s)</th>\
         <th>in disturbed GNSS</th><th>without GNSS</th><th>distance (m, error)</th></tr>{rows_html}</table>\
         <p>True distance {truth_dist:.0} m.{}</p>{}{METHODS_HTML}",
        scenario.duration_s / 60.0,
        truth_dist / 1000.0,
        run.fixes.len(),
        run.zones.iter().filter(|z| z.kind == ZoneKind::Disturbance).count(),
        run.zones.iter().filter(|z| z.kind == ZoneKind::Outage).count(),
        run.zones.iter().filter(|z| z.kind == ZoneKind::Stop).count(),
        last_len
            .map(|(l, t)| format!(
                " Step length over the last minute (median): {l:.2} m (true {t:.2} m)."
            ))
            .unwrap_or_default(),
        treadmill
            .as_ref()
            .map(|tm| format!("<p>{}</p>", tm.sentence().replace("**", "")))
            .unwrap_or_default()
    );

    std::fs::create_dir_all(out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    // Time in minutes, as a runner reads a run.
    let min = |v: f64| v / 60.0;
    let bands: Vec<Band> = run
        .zones
        .iter()
        .map(|z| Band {
            start: min(z.start_s),
            end: min(z.end_s),
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
        .collect();
    let t: Vec<f64> = r.t_s.iter().map(|&v| min(v)).collect();
    let t = &t;
    // Pace in min/km; below a walk (1.5 m/s) pace is not a useful number: a gap.
    let pace = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .map(|&s| {
                if s >= 1.5 {
                    1000.0 / s / 60.0
                } else {
                    f64::NAN
                }
            })
            .collect()
    };
    let truth_pace = pace(&truth);
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
            "raw GNSS (fix to fix)",
            t,
            &pace(&r.speed[0]),
            (190, 190, 190),
            Style::Points,
        ),
        series("truth", t, &truth_pace, (0, 0, 0), Style::Line),
        series(
            "stridekit",
            t,
            &pace(&r.speed[3]),
            (220, 30, 60),
            Style::Line,
        ),
    ];
    let write = |name: &str, res: Result<(), stridekit_lab::report::ReportError>| {
        res.map_err(|e| format!("cannot write {name}: {e}"))
    };
    write(
        "pace.svg",
        line_chart(
            &out_dir.join("pace.svg"),
            &Chart {
                title: "Pace: what the runner sees",
                x_label: "time (min)",
                y_label: "pace (min/km, lower is faster)",
                series: &pace_series,
                bands: &bands,
                y_range: Some(pace_range),
                y_format: YFormat::MinSec,
            },
        ),
    )?;
    let mut top = 0.0f64;
    for v in truth.iter().filter(|v| v.is_finite()) {
        top = top.max(*v);
    }
    let speed = [
        series("truth", t, &truth, (0, 0, 0), Style::Line),
        series("GNSS EMA", t, &r.speed[1], (230, 140, 40), Style::Line),
        series("AsPublished", t, &r.speed[2], (60, 120, 220), Style::Line),
        series("stridekit", t, &r.speed[3], (220, 30, 60), Style::Line),
    ];
    write(
        "speed.svg",
        line_chart(
            &out_dir.join("speed.svg"),
            &Chart {
                title: "Speed by method (spikes above the axis are clipped)",
                x_label: "time (min)",
                y_label: "speed (m/s)",
                series: &speed,
                bands: &bands,
                y_range: Some((0.0, (1.6 * top).max(1.0))),
                y_format: YFormat::Number,
            },
        ),
    )?;
    let weight = [
        series("AsPublished", t, &r.weight[0], (60, 120, 220), Style::Line),
        series("stridekit", t, &r.weight[1], (220, 30, 60), Style::Line),
    ];
    write(
        "gnss_weight.svg",
        line_chart(
            &out_dir.join("gnss_weight.svg"),
            &Chart {
                title: "How much the speed follows GNSS (1 = GNSS only, 0 = steps only)",
                x_label: "time (min)",
                y_label: "GNSS weight",
                series: &weight,
                bands: &bands,
                y_range: Some((0.0, 1.45)),
                y_format: YFormat::Number,
            },
        ),
    )?;
    let truth_len: Vec<f64> = r
        .t_s
        .iter()
        .map(|&t| run.truth_at(t).step_length_m)
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
            "stridekit (learned from GNSS)",
            t,
            &r.step_length,
            (220, 30, 60),
            Style::Line,
        ),
    ];
    write(
        "step_length.svg",
        line_chart(
            &out_dir.join("step_length.svg"),
            &Chart {
                title: "Step length",
                x_label: "time (min)",
                y_label: "step length (m)",
                series: &steps,
                bands: &bands,
                y_range: Some(len_range),
                y_format: YFormat::Number,
            },
        ),
    )?;
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
            name: "stridekit".into(),
            points: fused,
            color: Some((220, 30, 60)),
            style: Style::Line,
        },
    ];
    write(
        "track.svg",
        track_chart(
            &out_dir.join("track.svg"),
            "Track (metres east / north of the start)",
            &track,
        ),
    )?;
    if let Some(tm) = &treadmill {
        let g: Vec<f64> = tm.t_s.iter().map(|&v| min(v)).collect();
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
        write(
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
        )?;
    }
    let mut md = summary.clone();
    md.push_str(&format!("\n{METHODS_EXPLAINED}\n"));
    for (f, caption) in figures(treadmill.is_some()) {
        md.push_str(&format!("\n![{f}]({f})\n\n{caption}\n"));
    }
    std::fs::write(out_dir.join("summary.md"), md).map_err(|e| e.to_string())?;
    let shown = figures(treadmill.is_some());
    std::fs::write(out_dir.join("index.html"), html(&summary_html, &shown))
        .map_err(|e| e.to_string())?;
    println!(
        "\nReport written to {}/ (index.html, summary.md, {})",
        out_dir.display(),
        shown.iter().map(|(f, _)| *f).collect::<Vec<_>>().join(", ")
    );
    Ok(())
}

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
             with the calibration this run exported (`PaceTracker::calibration()`, imported through \
             `PaceConfig::calibration`) speed RMSE {rc:.3} m/s, distance {dc:+.1} %; with the \
             population prior {rp:.3} m/s, {dp:+.1} %."
        )
    }
}

/// What the methods in the tables and plots are.
const METHODS_EXPLAINED: &str = "Methods: **raw GNSS diff** = distance between consecutive fixes \
over their time (what a naive app shows); **GNSS EMA** = the same, smoothed (exponential moving \
average); **AsPublished** = the pace-fusion method as its paper publishes it (GNSS and pedometer \
blended by a fixed rule); **default** = stridekit's filter (GNSS, cadence and a step length \
learned from GNSS in one Kalman filter, with GNSS outliers rejected).";

const METHODS_HTML: &str = "<dl>\
<dt>raw GNSS</dt><dd>distance between consecutive fixes over their time: what a naive app shows.</dd>\
<dt>GNSS EMA</dt><dd>the same, smoothed by an exponential moving average.</dd>\
<dt>AsPublished</dt><dd>the pace-fusion method exactly as its paper publishes it: GNSS and the pedometer blended by a fixed rule.</dd>\
<dt>stridekit (default)</dt><dd>the SDK's filter: GNSS, cadence and a step length learned from GNSS in one Kalman filter, GNSS outliers rejected; in outages the speed comes from the steps.</dd>\
</dl>";

/// The figures of the report, with the sentence under each (the treadmill one when
/// the run exported a calibration).
fn figures(treadmill: bool) -> Vec<(&'static str, &'static str)> {
    let mut f = FIGURES.to_vec();
    if treadmill {
        f.push(TREADMILL_FIGURE);
    }
    f
}

const TREADMILL_FIGURE: (&str, &str) = ("treadmill.svg", "The next session without any GNSS (a treadmill, an indoor track): the same run's steps alone, paced with the step length this run learned from GNSS (exported as a calibration, imported next time) or with the population prior. The calibrated speed is near the truth from the first steps, where the prior is off by this runner's difference from the population; the fast intervals are read short by both (the line's slope, learned at the run's usual paces, extrapolates). Walks use the population walking line either way.");

const FIGURES: [(&str, &str); 5] = [
    ("pace.svg", "Pace as a watch shows it: the truth, the raw GNSS pace (grey dots: the spikes a naive app shows) and stridekit's. Shaded: disturbed GNSS (yellow), no GNSS (grey), the runner stopped (blue). Below 1.5 m/s (walking, stopped) pace is not drawn."),
    ("speed.svg", "The same run in m/s with every method, for engineers: GNSS EMA lags and follows GNSS errors; AsPublished follows GNSS closely; stridekit stays on the truth through disturbances and outages."),
    ("gnss_weight.svg", "How much each method's speed follows GNSS (1) or the steps (0). AsPublished leans on GNSS whenever it has it; stridekit uses GNSS mostly to learn the step length, so while the runner runs its speed is the steps' (weight near 0) and GNSS errors do not reach it; at stops there are no steps and it follows GNSS (weight 1)."),
    ("step_length.svg", "The step length stridekit learns from GNSS while it is good, against the truth; it carries the speed through the outages."),
    ("track.svg", "Where the runner was: the GNSS fixes, the truth and stridekit's fused position. With GNSS it stays on the truth; without GNSS this input has no compass, so the position goes on in the last direction at the fused speed (the straight lines) and snaps back when GNSS returns."),
];

/// The report page: the summary as HTML and every figure with its caption.
fn html(summary: &str, figures: &[(&str, &str)]) -> String {
    let figures: String = figures
        .iter()
        .map(|(f, caption)| {
            format!(
                "<figure><img src=\"{f}\" alt=\"{f}\"><figcaption>{caption}</figcaption></figure>"
            )
        })
        .collect();
    format!(
        "<!doctype html><html lang=en><meta charset=utf-8><title>stridekit demo</title>\
<style>body{{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}}\
table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #ccc;padding:.35em .7em;text-align:right}}\
td:first-child,th:first-child{{text-align:left}}th{{background:#f3f3f3}}tr.ours td{{font-weight:600;background:#fff3f3}}\
dt{{font-weight:600}}dd{{margin:0 0 .4em 1.5em}}figure{{margin:2em 0}}img{{max-width:100%}}\
figcaption{{color:#555;max-width:900px}}</style><body>{summary}{figures}</body></html>"
    )
}
