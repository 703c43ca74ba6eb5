//! `stridekit steps FILE`: replay a phone accelerometer recording (an Oxford Step
//! Counter trace folder, an Oxford-format accelerometer CSV or an Android sensor log,
//! told by the content) through the default step detector into one row per step.
//!
//! Another format plugs in as one more arm of [`read`] returning an
//! [`AccelRecording`]. Samples the detector rejects are skipped and counted by reason.

use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig, StepEvent, StepOrigin};
use stridekit_formats::{Content, FormatError};

use super::basis::STEPS_DETECTOR;
use super::{display_name, ReplayError, Usable};
use crate::rejected::Rejected;
use crate::report::{line_chart, Chart, Series, Style, YFormat};

/// What `stridekit steps` reads, for messages.
const EXPECTS: &str = "an accelerometer recording (an Oxford Step Counter trace folder, an \
     Oxford accelerometer CSV: ns, accuracy, ax, ay, az in m/s², or an Android sensor log)";

/// Intervals of one bout are shorter than this, s (a longer one starts a new bout).
const BOUT_GAP_S: f64 = 2.5;

/// The cadence is taken over up to this many intervals of the same bout.
const CADENCE_INTERVALS: usize = 4;

/// Accelerometer samples in file order, on the recording's own clock.
pub struct AccelRecording {
    /// The path given, for the summary.
    pub path: PathBuf,
    /// What was read, for the summary (e.g. `Oxford trace folder`).
    pub format: &'static str,
    /// (t s, acceleration m/s² with gravity, device axes), as recorded.
    pub samples: Vec<(f64, [f64; 3])>,
    /// Reference step times on the same clock, when the recording has them.
    pub reference_steps: Option<Vec<f64>>,
    /// What the reader skipped (unreadable rows, …), with counts.
    pub reader_skipped: Vec<(String, u64)>,
    /// The file was cut off mid-write (read up to the cut).
    pub truncated: bool,
}

/// Reads any supported accelerometer recording, told by its content.
pub fn read(path: &Path) -> Result<AccelRecording, ReplayError> {
    let err = |e: FormatError| super::input::read_error(path, e, EXPECTS);
    if path.is_dir() {
        let csv = path.join("accelerometer.csv");
        if !csv.is_file() {
            return Err(format!(
                "{} is a folder without accelerometer.csv; this command reads {EXPECTS}",
                path.display()
            )
            .into());
        }
        return Ok(read_oxford(path, &csv, "Oxford trace folder").map_err(err)?);
    }
    match stridekit_formats::sniff(path).map_err(err)?.content {
        Content::OxfordAccel => {
            Ok(read_oxford(path, path, "Oxford-format accelerometer CSV").map_err(err)?)
        }
        Content::AndroidLog => read_android(path),
        other => Err(super::input::other_content(path, other, EXPECTS).into()),
    }
}

/// The Android sensor log (docs/phone.md): its accelerometer stream, ms → s on the
/// file's own clock.
fn read_android(path: &Path) -> Result<AccelRecording, ReplayError> {
    let rec = stridekit_formats::read_android_log(path)
        .map_err(|e| super::input::read_error(path, e, EXPECTS))?;
    if rec.samples.is_empty() {
        return Err(format!("{}: no accelerometer samples", path.display()).into());
    }
    Ok(AccelRecording {
        path: path.to_path_buf(),
        format: "Android sensor log",
        samples: rec.samples.iter().map(|s| (s.t_s, s.accel_mps2)).collect(),
        reference_steps: None,
        reader_skipped: rec.skipped.clone(),
        truncated: rec.truncated,
    })
}

/// An Oxford-format accelerometer CSV, with the trace's reference steps when it is a
/// trace's `accelerometer.csv` beside its `stepcounter.csv`.
fn read_oxford(
    path: &Path,
    csv: &Path,
    format: &'static str,
) -> Result<AccelRecording, FormatError> {
    let rows = stridekit_formats::read_oxford_accel_raw(csv)?;
    let samples = rows.samples.iter().map(|a| (a.t_s, a.accel_mps2)).collect();
    let reader_skipped = rows.unreadable.reason().into_iter().collect();
    let dir = csv.parent().unwrap_or(Path::new("."));
    let in_trace = csv.file_name().is_some_and(|n| n == "accelerometer.csv")
        && dir.join("stepcounter.csv").is_file();
    let reference = if in_trace {
        stridekit_formats::read_oxford_trace(dir)
            .ok()
            .map(|t| t.heel_strikes_t_s)
    } else {
        None
    };
    Ok(AccelRecording {
        path: path.to_path_buf(),
        format,
        samples,
        reference_steps: reference,
        reader_skipped,
        truncated: rows.truncated,
    })
}

/// A replayed recording: the steps detected and the samples refused.
pub struct StepsReplay {
    pub recording: AccelRecording,
    pub steps: Vec<StepEvent>,
    pub rejected: Rejected,
}

/// Replays `recording` through the default step detector.
pub fn replay(recording: AccelRecording) -> Result<StepsReplay, ReplayError> {
    let mut detector =
        StepDetector::new(StepDetectorConfig::default()).map_err(|e| e.to_string())?;
    let mut rejected = Rejected::default();
    let mut steps: Vec<StepEvent> = Vec::new();
    for &(t_s, a) in &recording.samples {
        match detector.push_accel(t_s, a) {
            Ok(first) => steps.extend(first),
            Err(e) => rejected.steps(&e),
        }
        while let Some(e) = detector.pop_step() {
            steps.push(e);
        }
    }
    Ok(StepsReplay {
        recording,
        steps,
        rejected,
    })
}

impl StepsReplay {
    /// The step times, s.
    fn times(&self) -> Vec<f64> {
        self.steps.iter().map(|e| e.t_s).collect()
    }

    /// The CSV: `t_s,step,cadence_spm,interval_s,origin`, one row per step (`origin`:
    /// [`origin_name`]).
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "t_s,step,cadence_spm,interval_s,origin")?;
        let times = self.times();
        for (i, e) in self.steps.iter().enumerate() {
            let cad = cadence_spm(&times, i)
                .map(|c| format!("{c:.1}"))
                .unwrap_or_default();
            let iv = if e.duration_s.is_finite() {
                format!("{:.3}", e.duration_s)
            } else {
                String::new()
            };
            let origin = origin_name(e.origin);
            writeln!(w, "{:.3},{},{cad},{iv},{origin}", e.t_s, i + 1)?;
        }
        Ok(())
    }

    /// The summary; `written_to` names where the CSV went.
    pub fn summary(&self, written_to: &str) -> String {
        let rec = &self.recording;
        let span = match (rec.samples.first(), rec.samples.last()) {
            (Some(a), Some(b)) => b.0 - a.0,
            _ => 0.0,
        };
        let mut lines = vec![format!(
            "{} ({}): {} samples over {:.0} s, {} rejected; {} steps written to {}",
            rec.path.display(),
            rec.format,
            rec.samples.len(),
            span,
            self.rejected.total(),
            self.steps.len(),
            written_to
        )];
        lines.extend(self.rejected.report().lines().map(str::to_string));
        if let Some(filled) = self.filled_line() {
            lines.push(filled);
        }
        for (why, n) in &rec.reader_skipped {
            lines.push(format!("  skipped by the reader {n}: {why}"));
        }
        if let Some(r) = &rec.reference_steps {
            let n = r.len() as f64;
            lines.push(format!(
                "  reference (stepcounter.csv): {} steps, count error {:+.2} %",
                r.len(),
                100.0 * (self.steps.len() as f64 - n) / n
            ));
        }
        if !self.steps.is_empty() {
            lines.push(format!("  rests on: {STEPS_DETECTOR}; no distance (a distance needs a step length: `stridekit pdr`, or `stridekit pace` with GNSS or a calibration)"));
        }
        lines.join("\n")
    }

    /// How many of the steps were credited without being seen, by cause (`None`
    /// without steps).
    fn filled_line(&self) -> Option<String> {
        if self.steps.is_empty() {
            return None;
        }
        let count = |o: StepOrigin| self.steps.iter().filter(|e| e.origin == o).count();
        let (gap, missed, between) = (
            count(StepOrigin::FilledAcrossGap),
            count(StepOrigin::FilledMissed),
            count(StepOrigin::FilledBetweenBouts),
        );
        Some(format!(
            "  filled in at the walk's cadence, not seen: {} of the {} steps ({gap} across \
             dropped samples, {missed} too weak inside a walk, {between} between two bouts of \
             one walk; column `origin`)",
            gap + missed + between,
            self.steps.len()
        ))
    }

    /// Whether a step was detected, and the stream pushed.
    pub fn usable(&self) -> Usable<'_> {
        Usable {
            produced: !self.steps.is_empty(),
            what: "no step detected",
            rejected: &self.rejected,
            streams: vec![("accelerometer", self.recording.samples.len() as u64)],
        }
    }

    /// Cadence over time (one point per step with a cadence), the reference's beside
    /// it when the recording has one, as SVG.
    pub fn chart(&self, svg: &Path) -> Result<(), String> {
        let detected = self.times();
        let reference = self.recording.reference_steps.as_deref();
        let t0 = detected
            .first()
            .copied()
            .into_iter()
            .chain(reference.and_then(|r| r.first().copied()))
            .fold(f64::INFINITY, f64::min);
        let points = |times: &[f64]| -> Vec<(f64, f64)> {
            (0..times.len())
                .filter_map(|i| Some((times[i] - t0, cadence_spm(times, i)?)))
                .collect()
        };
        let mut series = Vec::new();
        if let Some(r) = reference {
            series.push(Series {
                name: "reference (stepcounter.csv)".into(),
                points: points(r),
                color: Some((150, 150, 150)),
                style: Style::Line,
            });
        }
        series.push(Series {
            name: format!("stridekit ({} steps)", detected.len()),
            points: points(&detected),
            color: Some((220, 30, 60)),
            style: Style::Line,
        });
        line_chart(
            svg,
            &Chart {
                title: &format!("Cadence: {}", display_name(&self.recording.path)),
                x_label: "time from the first step (s)",
                y_label: "cadence (steps/min)",
                series: &series,
                bands: &[],
                y_range: None,
                y_format: YFormat::Number,
            },
        )
        .map_err(|e| format!("cannot write {}: {e}", svg.display()))
    }
}

/// The CSV name of a step's origin.
pub fn origin_name(origin: StepOrigin) -> &'static str {
    match origin {
        StepOrigin::Detected => "detected",
        StepOrigin::FilledAcrossGap => "filled_across_gap",
        StepOrigin::FilledMissed => "filled_missed",
        StepOrigin::FilledBetweenBouts => "filled_between_bouts",
    }
}

/// Cadence at a step, steps/min: over the last up to [`CADENCE_INTERVALS`] intervals
/// of the same bout (intervals under [`BOUT_GAP_S`]), `None` for the first step of a
/// bout. `t_s`: step times.
fn cadence_spm(t_s: &[f64], i: usize) -> Option<f64> {
    let mut k = 0;
    while k < CADENCE_INTERVALS && i > k && t_s[i - k] - t_s[i - k - 1] < BOUT_GAP_S {
        k += 1;
    }
    (k > 0).then(|| 60.0 * k as f64 / (t_s[i] - t_s[i - k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recording_with_bad_rows_is_replayed_and_its_rows_counted() {
        let dir = std::env::temp_dir().join(format!("stridekit-steps-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("accelerometer.csv");
        let mut text = String::new();
        // 40 s of a 1.8 steps/s walk at 100 Hz, with a duplicated, a reversed and a
        // NaN row.
        for i in 0..4000 {
            let t = i as f64 / 100.0;
            let phase = std::f64::consts::TAU * 1.8 * t;
            let m = 9.81
                + if t > 3.0 {
                    2.5 * phase.cos() + 1.5 * (2.0 * phase).cos()
                } else {
                    0.0
                };
            let ns = (t * 1e9) as i64 + 1_000_000_000;
            text.push_str(&format!("{ns},3,0.0,0.0,{m}\n"));
            if i == 1000 {
                text.push_str(&format!("{ns},3,0.0,0.0,{m}\n"));
            }
            if i == 2000 {
                text.push_str(&format!("{},3,0.0,0.0,{m}\n", ns - 50_000_000));
                text.push_str(&format!("{},3,NaN,0.0,{m}\n", ns + 1));
            }
            if i == 3000 {
                text.push_str("garbage\n");
            }
        }
        // A truncated last line, as a logger killed mid-write leaves it.
        text.push_str("41000000000,3,0.1");
        std::fs::write(&csv, text).unwrap();
        let rec = read(&dir).unwrap();
        assert_eq!(rec.samples.len(), 4003);
        assert_eq!(
            rec.reader_skipped,
            vec![("unreadable row (first at line 3005)".to_string(), 2)]
        );
        let r = replay(rec).unwrap();
        let mut rows = Vec::new();
        r.write_csv(&mut rows).unwrap();
        let rows = String::from_utf8(rows).unwrap();
        let n = rows.lines().count() - 1;
        // 37 s of walking at 1.8 steps/s ≈ 66 steps.
        assert!((60..=70).contains(&n), "{n} steps");
        assert!(rows.starts_with("t_s,step,cadence_spm,interval_s,origin\n"));
        let svg = dir.join("steps.svg");
        r.chart(&svg).unwrap();
        let svg = std::fs::read_to_string(svg).unwrap();
        assert!(
            svg.contains("Cadence") && svg.contains("stridekit ("),
            "the chart"
        );
        let last: Vec<&str> = rows.lines().last().unwrap().split(',').collect();
        let cadence: f64 = last[2].parse().unwrap();
        assert!((cadence - 108.0).abs() < 5.0, "{cadence}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn message(e: ReplayError) -> String {
        match e {
            ReplayError::Failed(m) => m,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn unknown_files_are_refused_with_a_message() {
        let e = message(read(Path::new("/nonexistent/walk.bin")).err().unwrap());
        assert!(e.contains("no such file or folder"), "{e}");
        let dir = std::env::temp_dir().join(format!("stridekit-steps-kind-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = message(read(&dir).err().unwrap());
        assert!(e.contains("is a folder without accelerometer.csv"), "{e}");
        let run = dir.join("run.csv");
        std::fs::write(&run, "t_s,lat_deg,lon_deg\n1,2,3\n").unwrap();
        let e = message(read(&run).err().unwrap());
        assert!(
            e.contains("activity CSV") && e.contains("stridekit pace"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
