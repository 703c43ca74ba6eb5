//! `stridekit steps FILE [--out steps.csv]`: replay a phone accelerometer recording
//! through the default step detector and write one row per detected step.
//!
//! Inputs (chosen by [`read_recording`]): an Oxford Step Counter trace folder (its
//! `accelerometer.csv`, and `stepcounter.csv` as a reference when present) or an
//! Oxford-format `accelerometer.csv` itself. Further formats (the Android sensor-log
//! reader of the PDR work) plug in as one more arm of [`read_recording`] returning an
//! [`AccelRecording`].
//!
//! Samples the detector rejects (duplicate or reversed timestamps, NaN, out of range,
//! samples in g) are skipped and counted by reason (stderr), never abort the replay.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig, StepEvent};

use stridekit_lab::rejected::Rejected;

/// Options of `stridekit steps`.
pub struct StepsArgs {
    pub file: PathBuf,
    /// Output CSV (default `steps.csv`).
    pub out: Option<PathBuf>,
}

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
}

/// Reads any supported accelerometer recording.
pub fn read_recording(path: &Path) -> Result<AccelRecording, String> {
    let err = |e: stridekit_formats::FormatError| format!("{}: {e}", path.display());
    let oxford_csv = if path.is_dir() {
        path.join("accelerometer.csv")
    } else {
        path.to_path_buf()
    };
    let is_oxford = oxford_csv
        .file_name()
        .is_some_and(|n| n == "accelerometer.csv")
        && oxford_csv.is_file();
    if is_oxford {
        let rows = stridekit_formats::read_oxford_accel_raw(&oxford_csv).map_err(err)?;
        let samples = rows.samples.iter().map(|a| (a.t_s, a.accel_mps2)).collect();
        let reader_skipped = rows.unreadable.reason().into_iter().collect();
        let dir = oxford_csv.parent().unwrap_or(Path::new("."));
        let reference = if dir.join("stepcounter.csv").is_file() {
            stridekit_formats::read_oxford_trace(dir)
                .ok()
                .map(|t| t.heel_strikes_t_s)
        } else {
            None
        };
        return Ok(AccelRecording {
            format: if path.is_dir() {
                "Oxford trace folder"
            } else {
                "Oxford accelerometer.csv"
            },
            samples,
            reference_steps: reference,
            reader_skipped,
        });
    }
    if stridekit_formats::is_android_log(path) {
        // The Android sensor log (docs/phone.md): its accelerometer stream, ms → s on the
        // file's own clock.
        let rec = stridekit_formats::read_android_log(path).map_err(err)?;
        if rec.samples.is_empty() {
            return Err(format!("{}: no accelerometer samples", path.display()));
        }
        return Ok(AccelRecording {
            format: "Android sensor log",
            samples: rec.samples.iter().map(|s| (s.t_s, s.accel_mps2)).collect(),
            reference_steps: None,
            reader_skipped: rec.skipped.clone(),
        });
    }
    Err(format!(
        "{}: not a supported accelerometer recording (an Oxford Step Counter trace folder, its accelerometer.csv: ns, accuracy, ax, ay, az in m/s², or an Android sensor log .txt / .txt.gz)",
        path.display()
    ))
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

pub fn run(args: &StepsArgs) -> Result<(), String> {
    let rec = read_recording(&args.file)?;
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
    let out_path = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("steps.csv"));
    let file = std::fs::File::create(&out_path)
        .map_err(|e| format!("cannot write {}: {e}", out_path.display()))?;
    let mut w = std::io::BufWriter::new(file);
    let io = |e: std::io::Error| e.to_string();
    writeln!(w, "t_s,step,cadence_spm,interval_s").map_err(io)?;
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
        writeln!(w, "{:.3},{},{cad},{iv}", e.t_s, i + 1).map_err(io)?;
    }
    w.flush().map_err(io)?;
    drop(w);
    let svg = out_path.with_extension("svg");
    cadence_chart(&svg, &args.file, &times, rec.reference_steps.as_deref())?;
    let span = match (rec.samples.first(), rec.samples.last()) {
        (Some(a), Some(b)) => b.0 - a.0,
        _ => 0.0,
    };
    eprintln!(
        "{} ({}): {} samples over {:.0} s, {} rejected; {} steps written to {}",
        args.file.display(),
        rec.format,
        rec.samples.len(),
        span,
        rejected.total(),
        steps.len(),
        out_path.display()
    );
    eprint!("{}", rejected.report());
    for (why, n) in &rec.reader_skipped {
        eprintln!("  skipped by the reader {n}: {why}");
    }
    if let Some(r) = &rec.reference_steps {
        let n = r.len() as f64;
        eprintln!(
            "  reference (stepcounter.csv): {} steps, count error {:+.2} %",
            r.len(),
            100.0 * (steps.len() as f64 - n) / n
        );
    }
    Ok(())
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
        run(&StepsArgs {
            file: dir.clone(),
            out: Some(out.clone()),
        })
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
        assert!(e.contains("not a supported"), "{e}");
    }
}
