//! `stridekit demo`: the built-in default job. Simulates a 40-minute run with GNSS
//! disturbance zones, outages and stops, replays it through every method, prints a
//! summary and writes a report folder with SVG plots.

use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::geo::LocalFrame;
use stridekit_core::PaceConfig;
use stridekit_lab::pace::{replay, score, sim_reference, METHODS};
use stridekit_sim::{simulate_run, RunScenario, ZoneKind};

use crate::report::{line_chart, track_chart, Band, Chart, Series, Style};

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
    }
    let last_len = r.step_length.iter().rev().find(|v| v.is_finite()).copied();
    if let Some(l) = last_len {
        let _ = writeln!(
            summary,
            "\nLearned step length at the end: {l:.2} m (true {:.2} m).",
            run.truth
                .last()
                .map(|t| t.step_length_m)
                .unwrap_or(f64::NAN)
        );
    }
    print!("{summary}");

    std::fs::create_dir_all(out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let bands: Vec<Band> = run
        .zones
        .iter()
        .map(|z| Band {
            start: z.start_s,
            end: z.end_s,
            label: match z.kind {
                ZoneKind::Disturbance => "GNSS disturbance",
                ZoneKind::Outage => "GNSS outage",
                ZoneKind::Stop => "stop",
            }
            .to_string(),
            color: match z.kind {
                ZoneKind::Disturbance => (255, 200, 120),
                ZoneKind::Outage => (200, 200, 200),
                ZoneKind::Stop => (170, 210, 255),
            },
        })
        .collect();
    let t = &r.t_s;
    let speed = [
        series("truth", t, &truth, (0, 0, 0), Style::Line),
        series(
            "raw GNSS diff",
            t,
            &r.speed[0],
            (200, 200, 200),
            Style::Points,
        ),
        series("GNSS EMA", t, &r.speed[1], (230, 140, 40), Style::Line),
        series("AsPublished", t, &r.speed[2], (60, 120, 220), Style::Line),
        series("default", t, &r.speed[3], (220, 30, 60), Style::Line),
    ];
    let write = |name: &str, res: Result<(), crate::report::ReportError>| {
        res.map_err(|e| format!("cannot write {name}: {e}"))
    };
    write(
        "speed.svg",
        line_chart(
            &out_dir.join("speed.svg"),
            &Chart {
                title: "Speed: truth vs GNSS vs fused",
                x_label: "time (s)",
                y_label: "speed (m/s)",
                series: &speed,
                bands: &bands,
                y_range: Some((0.0, 8.0)),
            },
        ),
    )?;
    let weight = [
        series("AsPublished", t, &r.weight[0], (60, 120, 220), Style::Line),
        series("default", t, &r.weight[1], (220, 30, 60), Style::Line),
    ];
    write(
        "gnss_weight.svg",
        line_chart(
            &out_dir.join("gnss_weight.svg"),
            &Chart {
                title: "GNSS weight in the fused speed",
                x_label: "time (s)",
                y_label: "weight",
                series: &weight,
                bands: &bands,
                y_range: Some((0.0, 1.05)),
            },
        ),
    )?;
    let truth_len: Vec<f64> = r
        .t_s
        .iter()
        .map(|&t| run.truth_at(t).step_length_m)
        .collect();
    let steps = [
        series("truth", t, &truth_len, (0, 0, 0), Style::Line),
        series(
            "default (learned)",
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
                x_label: "time (s)",
                y_label: "step length (m)",
                series: &steps,
                bands: &bands,
                y_range: Some((0.4, 1.8)),
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
    let track = [
        Series {
            name: "GNSS fixes".into(),
            points: fixes,
            color: Some((230, 140, 40)),
            style: Style::Points,
        },
        Series {
            name: "truth".into(),
            points: run.truth.iter().map(|p| (p.east_m, p.north_m)).collect(),
            color: Some((0, 0, 0)),
            style: Style::Line,
        },
    ];
    write(
        "track.svg",
        track_chart(&out_dir.join("track.svg"), "Track (local ENU)", &track),
    )?;
    let mut md = summary.clone();
    md.push_str("\n![speed](speed.svg)\n\n![GNSS weight](gnss_weight.svg)\n\n![step length](step_length.svg)\n\n![track](track.svg)\n");
    std::fs::write(out_dir.join("summary.md"), md).map_err(|e| e.to_string())?;
    let html = format!(
        "<!doctype html><meta charset=utf-8><title>stridekit demo</title><body style=\"font-family:sans-serif;max-width:1000px\"><pre>{}</pre>{}</body>",
        summary.replace('&', "&amp;").replace('<', "&lt;"),
        ["speed.svg", "gnss_weight.svg", "step_length.svg", "track.svg"]
            .iter()
            .map(|f| format!("<p><img src=\"{f}\" style=\"max-width:100%\"></p>"))
            .collect::<String>()
    );
    std::fs::write(out_dir.join("index.html"), html).map_err(|e| e.to_string())?;
    println!("\nReport written to {}/ (index.html, summary.md, speed.svg, gnss_weight.svg, step_length.svg, track.svg)", out_dir.display());
    Ok(())
}
