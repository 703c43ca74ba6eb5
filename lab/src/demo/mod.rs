//! `stridekit demo`: the built-in default job. Simulates a 40-minute run with GNSS
//! disturbance zones, outages and stops, replays it through every method
//! ([`Demo::simulate`]), then renders the summary ([`Demo::summary`]) and the report
//! folder with SVG plots ([`Demo::write_report`]).

mod captions;
mod charts;
pub mod facts;
mod treadmill;

use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::geo::LocalFrame;
use stridekit_core::PaceConfig;
use stridekit_sim::{simulate_run, RunScenario, SimulatedRun, ZoneKind};

use crate::pace::{replay, score, sim_reference, Replay, Scores, METHODS};
use crate::replay::pace::min_s;
use crate::report::inline_html;
use crate::table::Table;
use captions::{figures, METHODS_EXPLAINED, METHODS_HTML};
use facts::{Facts, NextSession, RUN_MIN_MPS};
use treadmill::Treadmill;

const _: () = assert!(METHODS.len() == NAMES.len());

/// The methods as the report names them everywhere (table, legends, explanations), in
/// the order of `crate::pace::METHODS`.
const NAMES: [&str; 4] = [
    "raw GNSS diff",
    "GNSS EMA",
    "AsPublished",
    "stridekit (default)",
];

/// Slowest speed whose pace is drawn, m/s (16:40 /km): slower is standing or shuffling.
const PACE_MIN_MPS: f64 = 1.0;

/// The simulated run replayed through every method, and what the report says of it.
pub struct Demo {
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
pub struct Summary {
    /// The summary as printed (markdown).
    pub text: String,
    rows_html: String,
    pace_note: String,
    /// Median step length over the last minute, estimated and true, m.
    last_len: Option<(f64, f64)>,
}

impl Demo {
    /// The demo run of `seed`, replayed and scored.
    pub fn simulate(seed: u64) -> Self {
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
    pub fn summary(&self) -> Summary {
        let Self {
            seed,
            scenario,
            run,
            r,
            truth_dist,
            treadmill,
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
        let (table, rows_html) = self.method_table();
        summary.push_str(&table.render());
        let pace_note = format!(
            "Beside each speed RMSE (m/s): the median pace error where the runner runs (faster than {} /km), in s/km.",
            min_s(1000.0 / RUN_MIN_MPS)
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
        let last_len = (!est.is_empty() && !tru.is_empty())
            .then(|| (crate::stats::median(est), crate::stats::median(tru)));
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

    /// The table of methods, and its rows as HTML.
    fn method_table(&self) -> (Table, String) {
        let Self {
            s,
            truth_dist,
            facts,
            ..
        } = self;
        let truth_dist = *truth_dist;
        let mut table = Table::new([
            "method",
            "speed RMSE where GNSS (m/s)",
            "in disturbance zones",
            "in outages",
            "distance (m)",
        ]);
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
            table.row([
                name.to_string(),
                fp(cells[0], pe[0], false),
                fp(cells[1], pe[1], false),
                fp(cells[2], pe[2], false),
                d.clone(),
            ]);
            let _ = write!(
                rows_html,
                "<tr{}><td>{name}</td><td>{}</td><td>{}</td><td>{}</td><td>{d}</td></tr>",
                if m == 3 { " class=ours" } else { "" },
                fp(cells[0], pe[0], true),
                fp(cells[1], pe[1], true),
                fp(cells[2], pe[2], true),
            );
        }
        (table, rows_html)
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
            min_s(1000.0 * scenario.duration_s / truth_dist)
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
}

impl Demo {
    /// The report into `out_dir` (which exists): the charts, summary.md and index.html;
    /// returns the figures' file names.
    pub fn write_report(
        &self,
        out_dir: &Path,
        summary: &Summary,
    ) -> Result<Vec<&'static str>, String> {
        let summary_html = self.summary_html(summary);
        self.write_charts(out_dir)?;
        let shown = figures(&self.facts, self.treadmill.is_some());
        write_pages(out_dir, &summary.text, &summary_html, &shown)?;
        Ok(shown.iter().map(|(f, _)| *f).collect())
    }
}

/// summary.md (the summary, the methods, each figure with its caption) and index.html.
fn write_pages(
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
