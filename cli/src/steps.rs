//! `stridekit steps FILE [--out steps.csv]`: replay a phone accelerometer recording
//! through the default step detector and write one row per detected step.
//!
//! Inputs (chosen by [`read_recording`] from the content, not the name): an Oxford
//! Step Counter trace folder (its `accelerometer.csv`, and `stepcounter.csv` as a
//! reference when present), an Oxford-format accelerometer CSV under any name, or an
//! Android sensor log (plain or gzip). Another format plugs in as one more arm of
//! [`read_recording`] returning an [`AccelRecording`].
//!
//! Samples the detector rejects (duplicate or reversed timestamps, NaN, out of range,
//! samples in g) are skipped and counted by reason, never abort the replay; a replay
//! with no step (or whose stream was refused for its units) exits 1.

use std::io::Write as _;
use std::path::Path;

use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig, StepEvent};
use stridekit_formats::Content;

use stridekit_lab::rejected::Rejected;

use crate::basis::STEPS_DETECTOR;
use crate::commands::steps::StepsArgs;
use crate::outcome::{check_usable, write_error, Failure};
use crate::output::{say, Sink};

/// What `stridekit steps` reads, for messages.
const EXPECTS: &str = "an accelerometer recording (an Oxford Step Counter trace folder, an \
     Oxford accelerometer CSV: ns, accuracy, ax, ay, az in m/s², or an Android sensor log)";

/// Accelerometer samples in file order, on the recording's own clock.
pub struct AccelRecording {
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
pub fn read_recording(path: &Path) -> Result<AccelRecording, String> {
    let err = |e: stridekit_formats::FormatError| crate::input::read_error(path, e, EXPECTS);
    if path.is_dir() {
        let csv = path.join("accelerometer.csv");
        if !csv.is_file() {
            return Err(format!(
                "{} is a folder without accelerometer.csv; this command reads {EXPECTS}",
                path.display()
            ));
        }
        return read_oxford(&csv, "Oxford trace folder").map_err(err);
    }
    match stridekit_formats::sniff(path).map_err(err)?.content {
        Content::OxfordAccel => read_oxford(path, "Oxford-format accelerometer CSV").map_err(err),
        Content::AndroidLog => {
            // The Android sensor log (docs/phone.md): its accelerometer stream, ms → s on
            // the file's own clock.
            let rec = stridekit_formats::read_android_log(path).map_err(err)?;
            if rec.samples.is_empty() {
                return Err(format!("{}: no accelerometer samples", path.display()));
            }
            Ok(AccelRecording {
                format: "Android sensor log",
                samples: rec.samples.iter().map(|s| (s.t_s, s.accel_mps2)).collect(),
                reference_steps: None,
                reader_skipped: rec.skipped.clone(),
                truncated: rec.truncated,
            })
        }
        other => Err(crate::input::other_content(path, other, EXPECTS)),
    }
}

/// An Oxford-format accelerometer CSV, with the trace's reference steps when it is a
/// trace's `accelerometer.csv` beside its `stepcounter.csv`.
fn read_oxford(
    csv: &Path,
    format: &'static str,
) -> Result<AccelRecording, stridekit_formats::FormatError> {
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
        format,
        samples,
        reference_steps: reference,
        reader_skipped,
        truncated: rows.truncated,
    })
}

/// Cadence over time (one point per step with a cadence), the reference's beside it
/// when the recording has one, as SVG.
fn cadence_chart(
    svg: &Path,
    input: &Path,
    detected: &[f64],
    reference: Option<&[f64]>,
) -> Result<(), String> {
    use stridekit_lab::report::{line_chart, Chart, Series, Style, YFormat};
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
        points: points(detected),
        color: Some((220, 30, 60)),
        style: Style::Line,
    });
    let name = input
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    line_chart(
        svg,
        &Chart {
            title: &format!("Cadence: {name}"),
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

/// Cadence at a step, steps/min: over the last up to 4 intervals of the same bout
/// (intervals under 2.5 s), `None` for the first step of a bout. `t_s`: step times.
fn cadence_spm(t_s: &[f64], i: usize) -> Option<f64> {
    let mut k = 0;
    while k < 4 && i > k && t_s[i - k] - t_s[i - k - 1] < 2.5 {
        k += 1;
    }
    (k > 0).then(|| 60.0 * k as f64 / (t_s[i] - t_s[i - k]))
}

pub fn run(args: &StepsArgs, sink: &Sink) -> Result<(), Failure> {
    let rec = read_recording(&args.file)?;
    if rec.truncated {
        crate::input::warn_truncated(&args.file);
    }
    let mut detector =
        StepDetector::new(StepDetectorConfig::default()).map_err(|e| e.to_string())?;
    let mut rejected = Rejected::default();
    let mut steps: Vec<StepEvent> = Vec::new();
    for &(t_s, a) in &rec.samples {
        match detector.push_accel(t_s, a) {
            Ok(first) => steps.extend(first),
            Err(e) => rejected.steps(&e),
        }
        while let Some(e) = detector.pop_step() {
            steps.push(e);
        }
    }
    let sink_name = sink.name();
    let io = write_error(&sink_name);
    let mut w = sink.open()?;
    writeln!(w, "t_s,step,cadence_spm,interval_s").map_err(&io)?;
    let times: Vec<f64> = steps.iter().map(|e| e.t_s).collect();
    for (i, e) in steps.iter().enumerate() {
        let cad = cadence_spm(&times, i)
            .map(|c| format!("{c:.1}"))
            .unwrap_or_default();
        let iv = if e.duration_s.is_finite() {
            format!("{:.3}", e.duration_s)
        } else {
            String::new()
        };
        writeln!(w, "{:.3},{},{cad},{iv}", e.t_s, i + 1).map_err(&io)?;
    }
    w.flush().map_err(&io)?;
    drop(w);
    if let Some(svg) = sink.beside("svg") {
        cadence_chart(&svg, &args.file, &times, rec.reference_steps.as_deref())?;
    }
    let span = match (rec.samples.first(), rec.samples.last()) {
        (Some(a), Some(b)) => b.0 - a.0,
        _ => 0.0,
    };
    say!(
        "{} ({}): {} samples over {:.0} s, {} rejected; {} steps written to {}",
        args.file.display(),
        rec.format,
        rec.samples.len(),
        span,
        rejected.total(),
        steps.len(),
        sink_name
    );
    for line in rejected.report().lines() {
        say!("{line}");
    }
    for (why, n) in &rec.reader_skipped {
        say!("  skipped by the reader {n}: {why}");
    }
    if let Some(r) = &rec.reference_steps {
        let n = r.len() as f64;
        say!(
            "  reference (stepcounter.csv): {} steps, count error {:+.2} %",
            r.len(),
            100.0 * (steps.len() as f64 - n) / n
        );
    }
    if !steps.is_empty() {
        say!("  rests on: {STEPS_DETECTOR}; no distance (a distance needs a step length: `stridekit pdr`, or `stridekit pace` with GNSS or a calibration)");
    }
    check_usable(
        !steps.is_empty(),
        "no step detected",
        &rejected,
        &[("accelerometer", rec.samples.len() as u64)],
    )
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
        let rec = read_recording(&dir).unwrap();
        assert_eq!(rec.samples.len(), 4003);
        assert_eq!(
            rec.reader_skipped,
            vec![("unreadable row (first at line 3005)".to_string(), 2)]
        );
        let out = dir.join("steps.csv");
        run(
            &StepsArgs {
                file: dir.clone(),
                out: out.clone(),
            },
            &Sink::from_arg(&out, "csv").unwrap(),
        )
        .unwrap();
        let rows = std::fs::read_to_string(&out).unwrap();
        let n = rows.lines().count() - 1;
        // 37 s of walking at 1.8 steps/s ≈ 66 steps.
        assert!((60..=70).contains(&n), "{n} steps");
        assert!(rows.starts_with("t_s,step,cadence_spm,interval_s\n"));
        let svg = std::fs::read_to_string(dir.join("steps.svg")).unwrap();
        assert!(
            svg.contains("Cadence") && svg.contains("stridekit ("),
            "the chart"
        );
        let last: Vec<&str> = rows.lines().last().unwrap().split(',').collect();
        let cadence: f64 = last[2].parse().unwrap();
        assert!((cadence - 108.0).abs() < 5.0, "{cadence}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn unknown_files_are_refused_with_a_message() {
        let e = read_recording(Path::new("/nonexistent/walk.bin"))
            .err()
            .unwrap();
        assert!(e.contains("no such file or folder"), "{e}");
        let dir = std::env::temp_dir().join(format!("stridekit-steps-kind-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = read_recording(&dir).err().unwrap();
        assert!(e.contains("is a folder without accelerometer.csv"), "{e}");
        let run = dir.join("run.csv");
        std::fs::write(&run, "t_s,lat_deg,lon_deg\n1,2,3\n").unwrap();
        let e = read_recording(&run).err().unwrap();
        assert!(
            e.contains("activity CSV") && e.contains("stridekit pace"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
