//! `stridekit pace FILE`: replay a real activity file and print one CSV line per
//! GNSS epoch (and per pedometer-only update during outages). Samples the tracker
//! rejects (duplicate or reversed timestamps, NaN, out of range) are skipped and
//! counted by reason; the counts go to stderr with the summary, with what the file
//! reader cleaned up before (records merged, sorted, values dropped).

use std::io::Write as _;
use std::path::Path;

use stridekit_core::{PaceConfig, PaceSample, PaceTracker};

use stridekit_lab::activity::prepare;
use stridekit_lab::rejected::Rejected;
use stridekit_lab::report::{line_chart, Band, Chart, Series, Style, YFormat};

/// A gap between fixes longer than this is drawn as a band on the speed chart, s.
const NO_FIX_S: f64 = 5.0;

/// How a file is replayed.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options<'a> {
    /// Write the CSV here (and a speed chart beside it, same name with `.svg`);
    /// `None`: stdout.
    pub csv_out: Option<&'a Path>,
    /// Leave out every GNSS fix (a treadmill replay).
    pub no_gnss: bool,
}

/// Replays `path`; returns the tracker as the replay left it.
pub fn run(path: &Path, config: PaceConfig, options: &Options) -> Result<PaceTracker, String> {
    let csv_out = options.csv_out;
    let activity =
        stridekit_formats::read_activity(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut p = prepare(&activity);
    if options.no_gnss {
        p.samples.retain(|s| !matches!(s, PaceSample::Fix(_)));
        p.track.clear();
    }
    let mut tracker = PaceTracker::new(config).map_err(|e| e.to_string())?;
    let sink: Box<dyn std::io::Write> = match csv_out {
        Some(f) => Box::new(
            std::fs::File::create(f).map_err(|e| format!("cannot write {}: {e}", f.display()))?,
        ),
        None => Box::new(std::io::stdout().lock()),
    };
    let mut out = std::io::BufWriter::new(sink);
    // (minutes, speed m/s) of the rows written.
    let mut speed_series: Vec<(f64, f64)> = Vec::new();
    let w = |out: &mut dyn std::io::Write, s: String| {
        out.write_all(s.as_bytes()).map_err(|e| e.to_string())
    };
    w(&mut out, "t_s,t_unix_s,speed_mps,pace_s_per_km,pace_min_per_km,speed_std_mps,cadence_spm,step_length_m,gnss_weight,distance_m,source\n".into())?;
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
            w(
                &mut out,
                format!(
                    "{:.3},{:.3},{:.3},{},{},{},{},{},{:.3},{:.2},{:?}\n",
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
                ),
            )?;
        }
    }
    out.flush().map_err(|e| e.to_string())?;
    drop(out);
    if let Some(csv) = csv_out {
        let svg = csv.with_extension("svg");
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
        if let (true, Some(first), Some(last)) =
            (options.no_gnss, p.samples.first(), p.samples.last())
        {
            bands.push(Band {
                start: first.t_s() / 60.0,
                end: last.t_s() / 60.0,
                label: "GNSS left out (--no-gnss): steps only".into(),
                color: (250, 200, 90),
            });
        }
        line_chart(
            &svg,
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
        .map_err(|e| format!("cannot write {}: {e}", svg.display()))?;
        eprintln!("speed chart: {}", svg.display());
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
    eprintln!(
        "{}: {} samples, {} rejected, distance {:.0} m{average}, {} GNSS fixes, step data: {}",
        p.name,
        p.samples.len(),
        rejected.total(),
        distance_m,
        p.track.len(),
        if p.has_steps { "yes" } else { "no" }
    );
    eprint!("{}", rejected.report());
    for (why, n) in activity.cleanup.reasons() {
        eprintln!("  reader {n}: {why}");
    }
    Ok(tracker)
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
