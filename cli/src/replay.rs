//! `stridekit pace FILE`: replay a real activity file and write one CSV line per GNSS
//! epoch (and per pedometer-only update during outages) to `--out FILE` (a speed
//! chart beside it) or, with `--out -`, to stdout. Samples the tracker rejects
//! (duplicate or reversed timestamps, NaN, out of range, wrong units) are skipped and
//! counted by reason; the summary says them, what the file reader cleaned up before
//! (records merged, sorted, values dropped, a file cut off), and what the distance
//! rests on: GNSS, a learned or imported step length, or the population prior.

use std::io::Write as _;
use std::path::Path;

use stridekit_core::{PaceConfig, PaceMode, PaceSample, PaceTracker};

use stridekit_lab::activity::prepare;
use stridekit_lab::rejected::Rejected;
use stridekit_lab::report::{line_chart, Band, Chart, Series, Style, YFormat};

use crate::basis::{share_pct, PACE_CALIBRATED, PACE_PRIOR};
use crate::commands::pace::PaceArgs;
use crate::outcome::{check_usable, write_error, Failure};
use crate::output::{say, Sink};

/// A gap between fixes longer than this is drawn as a band on the speed chart, s.
const NO_FIX_S: f64 = 5.0;

/// What `stridekit pace` reads, for messages.
pub const EXPECTS: &str = "one activity file (FIT, TCX, GPX or an activity CSV)";

/// Replays `a.file` with `config` (made from `a`), the CSV to `sink`; returns the
/// tracker as the replay left it.
pub fn run(a: &PaceArgs, config: PaceConfig, sink: &Sink) -> Result<PaceTracker, Failure> {
    let path = a.file.as_path();
    let activity = stridekit_formats::read_activity(path)
        .map_err(|e| crate::input::read_error(path, e, EXPECTS))?;
    if activity.cleanup.truncated {
        crate::input::warn_truncated(path);
    }
    let mut p = prepare(&activity);
    if a.no_gnss {
        p.samples.retain(|s| !matches!(s, PaceSample::Fix(_)));
        p.track.clear();
    }
    let mut tracker = PaceTracker::new(config).map_err(|e| e.to_string())?;
    let sink_name = sink.name();
    let io = write_error(&sink_name);
    let mut out = sink.open()?;
    // (minutes, speed m/s) of the rows written.
    let mut speed_series: Vec<(f64, f64)> = Vec::new();
    out.write_all(b"t_s,t_unix_s,speed_mps,pace_s_per_km,pace_min_per_km,speed_std_mps,cadence_spm,step_length_m,gnss_weight,distance_m,source\n").map_err(&io)?;
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.3}")).unwrap_or_default();
    let mut rejected = Rejected::default();
    let mut last_t = f64::NEG_INFINITY;
    for s in &p.samples {
        if let Err(e) = tracker.push(s) {
            rejected.pace(&e);
            continue;
        }
        let Some(e) = tracker.estimate() else {
            continue;
        };
        let emit =
            matches!(s, PaceSample::Fix(_)) || (e.t_s > last_t + 0.5 && e.gnss_weight == 0.0);
        if emit && e.t_s > last_t {
            last_t = e.t_s;
            speed_series.push((e.t_s / 60.0, e.speed_mps));
            writeln!(
                out,
                "{:.3},{:.3},{:.3},{},{},{},{},{},{:.3},{:.2},{:?}",
                e.t_s,
                e.t_s + p.t0_unix_s,
                e.speed_mps,
                opt(e.pace_s_per_km),
                e.pace_s_per_km.map(min_s).unwrap_or_default(),
                opt(e.speed_std_mps),
                opt(e.cadence_spm),
                opt(e.step_length_m),
                e.gnss_weight,
                e.distance_m,
                e.source
            )
            .map_err(&io)?;
        }
    }
    out.flush().map_err(&io)?;
    drop(out);
    if let Some(svg) = sink.beside("svg") {
        speed_chart(&svg, &activity, &p, speed_series, a.no_gnss)?;
        say!("speed chart: {}", svg.display());
    }
    let distance_m = tracker.estimate().map_or(0.0, |e| e.distance_m);
    let moving_s = p.samples.last().map(|s| s.t_s()).unwrap_or(0.0)
        - p.samples.first().map(|s| s.t_s()).unwrap_or(0.0);
    let average = if distance_m > 0.0 {
        format!(
            ", average pace {} /km over the elapsed time",
            min_s(1000.0 * moving_s / distance_m)
        )
    } else {
        String::new()
    };
    say!(
        "{}: {} samples, {} rejected, distance {:.0} m{average}, {} GNSS fixes, step data: {}",
        p.name,
        p.samples.len(),
        rejected.total(),
        distance_m,
        p.track.len(),
        if p.has_steps { "yes" } else { "no" }
    );
    for line in rejected.report().lines() {
        say!("{line}");
    }
    for (why, n) in activity.cleanup.reasons() {
        say!("  reader {n}: {why}");
    }
    if distance_m > 0.0 {
        say!("{}", rests_on(&tracker, &p, moving_s, a));
        if let Some(device_m) = device_distance_m(&activity) {
            say!(
                "  the file's own distance (the device's: GNSS or a foot pod): {device_m:.0} m; \
                 this replay's differs by {:+.1} %",
                share_pct(distance_m - device_m, device_m)
            );
        }
    }
    let fixes = p
        .samples
        .iter()
        .filter(|s| matches!(s, PaceSample::Fix(_)))
        .count() as u64;
    let streams = [("GNSS", fixes), ("step", p.samples.len() as u64 - fixes)];
    check_usable(
        distance_m > 0.0,
        "no distance: neither GNSS nor steps gave a speed",
        &rejected,
        &streams,
    )?;
    Ok(tracker)
}

/// "rests on: …": the GNSS fixes and the share of the time they cover, and what the
/// steps' length rests on (imported, learned from this file's GNSS, or the prior).
fn rests_on(
    tracker: &PaceTracker,
    p: &stridekit_lab::activity::Prepared,
    elapsed_s: f64,
    a: &PaceArgs,
) -> String {
    let covered_s: f64 = p
        .track
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .filter(|&gap| gap <= NO_FIX_S)
        .sum();
    let gnss = match p.track.len() {
        0 if a.no_gnss => "no GNSS (--no-gnss)".to_string(),
        0 => "no GNSS (the file has no position)".to_string(),
        n => format!(
            "GNSS ({n} fixes, covering {:.0} % of the time)",
            share_pct(covered_s, elapsed_s)
        ),
    };
    if !p.has_steps {
        return format!("  rests on: {gnss} alone (no step data)");
    }
    let length = match (a.calibration.as_deref(), tracker.config().mode) {
        (Some(f), _) => format!(
            "the imported calibration {} ({PACE_CALIBRATED})",
            f.display()
        ),
        (None, PaceMode::AsPublished) => {
            "the published filter's, learned from GNSS where it had it".into()
        }
        (None, _) if tracker.calibration().is_some() => "learned from this file's GNSS".into(),
        (None, _) => PACE_PRIOR.into(),
    };
    format!("  rests on: {gnss} and the steps; step length: {length}")
}

/// The distance the device recorded over the file (last − first), when it did.
fn device_distance_m(activity: &stridekit_formats::Activity) -> Option<f64> {
    let mut d = activity.records.iter().filter_map(|r| r.device_distance_m);
    let first = d.next()?;
    let last = d.next_back()?;
    (last > first).then_some(last - first)
}

/// The speed over time beside the device's own, with the stretches without GNSS.
fn speed_chart(
    svg: &Path,
    activity: &stridekit_formats::Activity,
    p: &stridekit_lab::activity::Prepared,
    speed_series: Vec<(f64, f64)>,
    no_gnss: bool,
) -> Result<(), String> {
    let device: Vec<(f64, f64)> = activity
        .records
        .iter()
        .filter_map(|r| Some(((r.t_s - p.t0_unix_s) / 60.0, r.device_speed_mps?)))
        .collect();
    let mut series = vec![Series {
        name: "stridekit".into(),
        points: speed_series,
        color: Some((220, 30, 60)),
        style: Style::Line,
    }];
    if !device.is_empty() {
        series.insert(
            0,
            Series {
                name: "the device's own speed (as recorded)".into(),
                points: device,
                color: Some((150, 150, 150)),
                style: Style::Line,
            },
        );
    }
    // Where the file has no position for longer than NO_FIX_S: the steps alone
    // carry the speed there.
    let mut bands: Vec<Band> = p
        .track
        .windows(2)
        .filter(|w| w[1].0 - w[0].0 > NO_FIX_S)
        .map(|w| Band {
            start: w[0].0 / 60.0,
            end: w[1].0 / 60.0,
            label: format!("no GNSS fix for more than {NO_FIX_S} s"),
            color: (250, 200, 90),
        })
        .collect();
    if let (true, Some(first), Some(last)) = (no_gnss, p.samples.first(), p.samples.last()) {
        bands.push(Band {
            start: first.t_s() / 60.0,
            end: last.t_s() / 60.0,
            label: "GNSS left out (--no-gnss): steps only".into(),
            color: (250, 200, 90),
        });
    }
    line_chart(
        svg,
        &Chart {
            title: &format!("Speed: {}", p.name),
            x_label: "time (min)",
            y_label: "speed (m/s)",
            series: &series,
            bands: &bands,
            y_range: None,
            y_format: YFormat::Number,
        },
    )
    .map_err(|e| format!("cannot write {}: {e}", svg.display()))
}

/// Pace as a runner reads it: seconds per km as `m:ss` (330.7 → "5:31").
pub fn min_s(s_per_km: f64) -> String {
    if !s_per_km.is_finite() || s_per_km < 0.0 {
        return String::new();
    }
    let t = s_per_km.round() as u64;
    format!("{}:{:02}", t / 60, t % 60)
}

#[cfg(test)]
mod tests {
    #[test]
    fn pace_reads_as_minutes_and_seconds() {
        assert_eq!(super::min_s(330.676), "5:31");
        assert_eq!(super::min_s(59.6), "1:00");
        assert_eq!(super::min_s(f64::NAN), "");
    }
}
