//! `stridekit pace FILE`: replay a real activity file through the pace tracker into
//! one row per GNSS epoch (and per pedometer-only update during outages), then render
//! the CSV, the speed chart and the summary (rejected samples, the reader's cleanup,
//! what the distance rests on: GNSS, a learned or imported step length, or the prior).

use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::{PaceConfig, PaceEstimate, PaceMode, PaceSample, PaceTracker};
use stridekit_formats::Activity;

use super::basis::{share_pct, PACE_CALIBRATED, PACE_PRIOR};
use super::{ReplayError, Usable};
use crate::activity::{prepare, Prepared};
use crate::rejected::Rejected;
use crate::report::{line_chart, Band, Chart, Series, Style, YFormat};

/// A gap between fixes longer than this is drawn as a band on the speed chart, s.
const NO_FIX_S: f64 = 5.0;

/// A pedometer-only row is written at most this often during an outage, s.
const OUTAGE_ROW_S: f64 = 0.5;

/// What `stridekit pace` reads, for messages.
pub const EXPECTS: &str = "one activity file (FIT, TCX, GPX or an activity CSV)";

/// The CSV header.
const HEADER: &str = "t_s,t_unix_s,speed_mps,pace_s_per_km,pace_min_per_km,speed_std_mps,cadence_spm,step_length_m,gnss_weight,distance_m,source";

/// How to replay (the tracker's configuration comes apart: `config`).
#[derive(Clone, Debug, Default)]
pub struct PaceOptions {
    /// Leave out every GNSS fix (`--no-gnss`).
    pub no_gnss: bool,
    /// The calibration file the configuration was given, for the summary.
    pub calibration_file: Option<PathBuf>,
}

/// A replayed activity: the rows written, and what the summary needs.
pub struct PaceReplay {
    pub activity: Activity,
    pub prepared: Prepared,
    /// The estimates written, one CSV row each.
    pub rows: Vec<PaceEstimate>,
    pub rejected: Rejected,
    /// The tracker as the replay left it (its learned calibration).
    pub tracker: PaceTracker,
    pub options: PaceOptions,
}

/// Reads an activity file of any supported format.
pub fn read(path: &Path) -> Result<Activity, ReplayError> {
    stridekit_formats::read_activity(path)
        .map_err(|e| super::input::read_error(path, e, EXPECTS).into())
}

/// Replays `activity` through a tracker made with `config`.
pub fn replay(
    activity: Activity,
    config: PaceConfig,
    options: PaceOptions,
) -> Result<PaceReplay, ReplayError> {
    let mut prepared = prepare(&activity);
    if options.no_gnss {
        prepared
            .samples
            .retain(|s| !matches!(s, PaceSample::Fix(_)));
        prepared.track.clear();
    }
    let mut tracker = PaceTracker::new(config).map_err(|e| e.to_string())?;
    let mut rejected = Rejected::default();
    let rows = push_all(&mut tracker, &prepared.samples, &mut rejected);
    Ok(PaceReplay {
        activity,
        prepared,
        rows,
        rejected,
        tracker,
        options,
    })
}

/// Pushes every sample; the estimates worth a row: at each fix, and during an outage
/// (no GNSS weight) at most every [`OUTAGE_ROW_S`], never going back in time.
fn push_all(
    tracker: &mut PaceTracker,
    samples: &[PaceSample],
    rejected: &mut Rejected,
) -> Vec<PaceEstimate> {
    let mut rows = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    for s in samples {
        if let Err(e) = tracker.push(s) {
            rejected.pace(&e);
            continue;
        }
        let Some(e) = tracker.estimate() else {
            continue;
        };
        let emit = matches!(s, PaceSample::Fix(_))
            || (e.t_s > last_t + OUTAGE_ROW_S && e.gnss_weight == 0.0);
        if emit && e.t_s > last_t {
            last_t = e.t_s;
            rows.push(e);
        }
    }
    rows
}

impl PaceReplay {
    /// The CSV: the header and one row per estimate written.
    pub fn write_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        writeln!(out, "{HEADER}")?;
        let opt = |v: Option<f64>| v.map(|v| format!("{v:.3}")).unwrap_or_default();
        for e in &self.rows {
            writeln!(
                out,
                "{:.3},{:.3},{:.3},{},{},{},{},{},{:.3},{:.2},{:?}",
                e.t_s,
                e.t_s + self.prepared.t0_unix_s,
                e.speed_mps,
                opt(e.pace_s_per_km),
                e.pace_s_per_km.map(min_s).unwrap_or_default(),
                opt(e.speed_std_mps),
                opt(e.cadence_spm),
                opt(e.step_length_m),
                e.gnss_weight,
                e.distance_m,
                e.source
            )?;
        }
        Ok(())
    }

    /// The distance at the end of the replay, m (0 without an estimate).
    pub fn distance_m(&self) -> f64 {
        self.tracker.estimate().map_or(0.0, |e| e.distance_m)
    }

    /// From the first sample to the last, s.
    fn elapsed_s(&self) -> f64 {
        let s = &self.prepared.samples;
        s.last().map(|s| s.t_s()).unwrap_or(0.0) - s.first().map(|s| s.t_s()).unwrap_or(0.0)
    }

    /// The summary: counts and distance, the rejected samples, the reader's cleanup,
    /// what the distance rests on and the file's own distance.
    pub fn summary(&self) -> String {
        let p = &self.prepared;
        let distance_m = self.distance_m();
        let average = if distance_m > 0.0 {
            format!(
                ", average pace {} /km over the elapsed time",
                min_s(1000.0 * self.elapsed_s() / distance_m)
            )
        } else {
            String::new()
        };
        let mut lines = vec![format!(
            "{}: {} samples, {} rejected, distance {:.0} m{average}, {} GNSS fixes, step data: {}",
            p.name,
            p.samples.len(),
            self.rejected.total(),
            distance_m,
            p.track.len(),
            if p.has_steps { "yes" } else { "no" }
        )];
        lines.extend(self.rejected.report().lines().map(str::to_string));
        for (why, n) in self.activity.cleanup.reasons() {
            lines.push(format!("  reader {n}: {why}"));
        }
        if distance_m > 0.0 {
            lines.push(self.rests_on());
            if let Some(device_m) = device_distance_m(&self.activity) {
                lines.push(format!(
                    "  the file's own distance (the device's: GNSS or a foot pod): {device_m:.0} m; \
                     this replay's differs by {:+.1} %",
                    share_pct(distance_m - device_m, device_m)
                ));
            }
        }
        lines.join("\n")
    }

    /// "rests on: …": the GNSS fixes and the share of the time they cover, and what
    /// the steps' length rests on (imported, learned from this file's GNSS, or the
    /// prior).
    fn rests_on(&self) -> String {
        let p = &self.prepared;
        let covered_s: f64 = p
            .track
            .windows(2)
            .map(|w| w[1].0 - w[0].0)
            .filter(|&gap| gap <= NO_FIX_S)
            .sum();
        let gnss = match p.track.len() {
            0 if self.options.no_gnss => "no GNSS (--no-gnss)".to_string(),
            0 => "no GNSS (the file has no position)".to_string(),
            n => format!(
                "GNSS ({n} fixes, covering {:.0} % of the time)",
                share_pct(covered_s, self.elapsed_s())
            ),
        };
        if !p.has_steps {
            return format!("  rests on: {gnss} alone (no step data)");
        }
        let length = match (
            self.options.calibration_file.as_deref(),
            self.tracker.config().mode,
        ) {
            (Some(f), _) => format!(
                "the imported calibration {} ({PACE_CALIBRATED})",
                f.display()
            ),
            (None, PaceMode::AsPublished) => {
                "the published filter's, learned from GNSS where it had it".into()
            }
            (None, _) if self.tracker.calibration().is_some() => {
                "learned from this file's GNSS".into()
            }
            (None, _) => PACE_PRIOR.into(),
        };
        format!("  rests on: {gnss} and the steps; step length: {length}")
    }

    /// Whether the replay gave a distance, and the streams pushed.
    pub fn usable(&self) -> Usable<'_> {
        let samples = &self.prepared.samples;
        let fixes = samples
            .iter()
            .filter(|s| matches!(s, PaceSample::Fix(_)))
            .count() as u64;
        Usable {
            produced: self.distance_m() > 0.0,
            what: "no distance: neither GNSS nor steps gave a speed",
            rejected: &self.rejected,
            streams: vec![("GNSS", fixes), ("step", samples.len() as u64 - fixes)],
        }
    }

    /// The speed over time beside the device's own, with the stretches without GNSS,
    /// as SVG.
    pub fn chart(&self, svg: &Path) -> Result<(), String> {
        let p = &self.prepared;
        let series = self.speed_series();
        let bands = self.no_fix_bands();
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

    /// The device's own speed (when recorded) and the replay's, minutes and m/s.
    fn speed_series(&self) -> Vec<Series> {
        let t0 = self.prepared.t0_unix_s;
        let device: Vec<(f64, f64)> = self
            .activity
            .records
            .iter()
            .filter_map(|r| Some(((r.t_s - t0) / 60.0, r.device_speed_mps?)))
            .collect();
        let mut series = vec![Series {
            name: "stridekit".into(),
            points: self
                .rows
                .iter()
                .map(|e| (e.t_s / 60.0, e.speed_mps))
                .collect(),
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
        series
    }

    /// Where the file has no position for longer than [`NO_FIX_S`] (the steps alone
    /// carry the speed there), and the whole run with `--no-gnss`.
    fn no_fix_bands(&self) -> Vec<Band> {
        let p = &self.prepared;
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
            (self.options.no_gnss, p.samples.first(), p.samples.last())
        {
            bands.push(Band {
                start: first.t_s() / 60.0,
                end: last.t_s() / 60.0,
                label: "GNSS left out (--no-gnss): steps only".into(),
                color: (250, 200, 90),
            });
        }
        bands
    }
}

/// The distance the device recorded over the file (last − first), when it did.
fn device_distance_m(activity: &Activity) -> Option<f64> {
    let mut d = activity.records.iter().filter_map(|r| r.device_distance_m);
    let first = d.next()?;
    let last = d.next_back()?;
    (last > first).then_some(last - first)
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
