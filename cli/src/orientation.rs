//! `stridekit orientation FILE [--out q.csv] [--imu-only]`: replays a recording with
//! IMU (and magnetometer) samples through the default orientation filter and writes
//! one CSV row per accepted sample: `t_s,qw,qx,qy,qz` (body → East-North-Up) and the
//! filter's flags (0/1). Samples the filter rejects are skipped and counted by
//! reason; one bad sample never aborts the replay. With optical truth in the file
//! (BROAD), the benchmark's errors are printed too. An Android sensor log (`*.txt`,
//! `*.txt.gz`, see `stridekit pdr`) is read as well; when it holds Android's own
//! rotation vector, the RMS difference to it is printed as a second opinion (Android's
//! fusion is not truth; the first few seconds, while both settle, are not scored).
//! The format is told by the content. The summary says whether the heading rests on
//! the magnetometer; a replay with no accepted sample (or whose IMU stream was
//! refused for its units) exits 1.

use std::io::Write;
use std::path::Path;

use stridekit_core::ahrs::{Ahrs, AhrsFlags, AhrsSettings};
use stridekit_formats::{read_android_log, read_broad, Content, FootFormat};

use stridekit_lab::orientation::metric::{error_angles, ErrorSums};
use stridekit_lab::rejected::Rejected;
use stridekit_lab::report::{line_chart, Chart, Series, Style, YFormat};

use crate::commands::orientation::OrientationArgs;
use crate::outcome::{check_usable, write_error, Failure};
use crate::output::{say, Sink};

/// What `stridekit orientation` reads, for messages.
const EXPECTS: &str = "an IMU recording (a BROAD CSV, plain or gzip, or an Android sensor log)";

/// Seconds of an Android log not compared with the rotation vector while both settle.
const ANDROID_SETTLE_S: f64 = 5.0;
/// How far the rotation vector's event may be from a sample to be compared with it.
const ANDROID_MATCH_S: f64 = 0.05;

/// One replayable sample and what it is compared with.
struct Row {
    t_s: f64,
    gyro_rads: [f64; 3],
    accel_mps2: [f64; 3],
    mag_ut: Option<[f64; 3]>,
    /// Truth or reference quaternion, body → earth, when this sample is scored.
    reference: Option<[f64; 4]>,
}

pub fn run(args: &OrientationArgs, sink: &Sink) -> Result<(), Failure> {
    let what = |e| crate::input::read_error(&args.file, e, EXPECTS);
    let android = match stridekit_formats::sniff(&args.file).map_err(what)?.content {
        Content::AndroidLog => true,
        // A pyshoe foot CSV has the BROAD columns but the magnetometer and the truth.
        Content::Broad | Content::Foot(FootFormat::Pyshoe) | Content::Unknown => false,
        other => return Err(crate::input::other_content(&args.file, other, EXPECTS).into()),
    };
    let mut reader_skipped: Vec<(String, u64)> = Vec::new();
    let truncated;
    let rows: Vec<Row> = if android {
        let rec = read_android_log(&args.file).map_err(what)?;
        truncated = rec.truncated;
        reader_skipped.clone_from(&rec.skipped);
        let t0 = rec.samples.first().map_or(0.0, |s| s.t_s);
        let rv = &rec.orientation;
        let mut k = 0;
        rec.samples
            .iter()
            .map(|s| {
                while k + 1 < rv.len() && rv[k + 1].0 <= s.t_s {
                    k += 1;
                }
                let near = [k, k + 1]
                    .into_iter()
                    .filter_map(|i| rv.get(i))
                    .filter(|(t, _)| (t - s.t_s).abs() <= ANDROID_MATCH_S)
                    .min_by(|a, b| (a.0 - s.t_s).abs().total_cmp(&(b.0 - s.t_s).abs()));
                Row {
                    t_s: s.t_s,
                    gyro_rads: s.gyro_rads,
                    accel_mps2: s.accel_mps2,
                    mag_ut: s.mag_ut,
                    reference: near
                        .filter(|_| s.t_s - t0 >= ANDROID_SETTLE_S)
                        .map(|(_, q)| *q),
                }
            })
            .collect()
    } else {
        let rec = read_broad(&args.file).map_err(what)?;
        truncated = rec.truncated;
        reader_skipped.extend(rec.unreadable.reason());
        rec.samples
            .iter()
            .zip(&rec.truth)
            .zip(&rec.movement)
            .map(|((s, truth), &moving)| Row {
                t_s: s.t_s,
                gyro_rads: s.gyro_rads,
                accel_mps2: s.accel_mps2,
                mag_ut: s.mag_ut,
                reference: truth.filter(|_| moving),
            })
            .collect()
    };
    if truncated {
        crate::input::warn_truncated(&args.file);
    }
    let mut ahrs = Ahrs::new(AhrsSettings::default()).map_err(|e| e.to_string())?;
    let sink_name = sink.name();
    let io = write_error(&sink_name);
    let mut w = sink.open()?;
    write!(w, "t_s,qw,qx,qy,qz").map_err(&io)?;
    for name in AhrsFlags::NAMES {
        write!(w, ",{name}").map_err(&io)?;
    }
    writeln!(w).map_err(&io)?;
    let mut rejected = Rejected::default();
    let mut sums = ErrorSums::default();
    let mut accepted = 0usize;
    // Chart points, thinned to about CHART_POINTS_HZ: (t, azimuth, tilt) of the
    // estimate and, when scored, (t, heading error, inclination error) in degrees.
    let t_first = rows.first().map_or(0.0, |r| r.t_s);
    let mut next_point_t = f64::NEG_INFINITY;
    let mut attitude: [Vec<(f64, f64)>; 2] = Default::default();
    let mut errors: [Vec<(f64, f64)>; 2] = Default::default();
    for s in &rows {
        let mag = if args.imu_only { None } else { s.mag_ut };
        match ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, mag) {
            Ok(flags) => {
                accepted += 1;
                let q = ahrs.quaternion().unwrap_or([1.0, 0.0, 0.0, 0.0]);
                write!(
                    w,
                    "{:.6},{:.9},{:.9},{:.9},{:.9}",
                    s.t_s, q[0], q[1], q[2], q[3]
                )
                .map_err(&io)?;
                for f in flags.to_array() {
                    write!(w, ",{}", f as u8).map_err(&io)?;
                }
                writeln!(w).map_err(&io)?;
                if let Some(t) = &s.reference {
                    sums.add(&q, t);
                }
                if s.t_s >= next_point_t {
                    next_point_t = s.t_s + 1.0 / CHART_POINTS_HZ;
                    let x = s.t_s - t_first;
                    let (azimuth, tilt) = azimuth_tilt_deg(&q);
                    // A wrap through north breaks the line instead of crossing the chart.
                    if attitude[0]
                        .last()
                        .is_some_and(|p| (p.1 - azimuth).abs() > 180.0)
                    {
                        attitude[0].push((x, f64::NAN));
                    }
                    attitude[0].push((x, azimuth));
                    attitude[1].push((x, tilt));
                    if let Some(t) = &s.reference {
                        let (_, h, i) = error_angles(&q, t);
                        errors[0].push((x, h.to_degrees()));
                        errors[1].push((x, i.to_degrees()));
                    }
                }
            }
            Err(e) => rejected.ahrs(&e),
        }
    }
    w.flush().map_err(&io)?;
    drop(w);
    let svg = sink.beside("svg");
    let reference_name = if android {
        "Android's rotation vector"
    } else {
        "the optical truth"
    };
    let chart = |series: Vec<Series>, title: String, y_label: &str| {
        let Some(svg) = &svg else {
            return Ok(());
        };
        line_chart(
            svg,
            &Chart {
                title: &title,
                x_label: "time (s)",
                y_label,
                series: &series,
                bands: &[],
                y_range: None,
                y_format: YFormat::Number,
            },
        )
        .map_err(|e| format!("cannot write {}: {e}", svg.display()))
    };
    let named = |name: &str, points: Vec<(f64, f64)>, color| Series {
        name: name.into(),
        points,
        color: Some(color),
        style: Style::Line,
    };
    let [heading_err, inclination_err] = errors;
    if heading_err.is_empty() {
        let [azimuth, tilt] = attitude;
        chart(
            vec![
                named(
                    "azimuth of the +y axis (° from north, clockwise)",
                    azimuth,
                    (31, 119, 180),
                ),
                named("tilt of the +z axis from up (°)", tilt, (255, 127, 14)),
            ],
            format!("Orientation: {}", display_name(&args.file)),
            "degrees",
        )?;
    } else {
        let mut series = vec![named("inclination", inclination_err, (255, 127, 14))];
        if !args.imu_only {
            series.insert(0, named("heading", heading_err, (31, 119, 180)));
        }
        chart(
            series,
            format!(
                "Difference to {reference_name}: {}",
                display_name(&args.file)
            ),
            "error angle (°)",
        )?;
    }
    say!(
        "{}: {} samples, {accepted} accepted, written to {}",
        display_name(&args.file),
        rows.len(),
        sink_name
    );
    for line in rejected.report().lines() {
        say!("{line}");
    }
    for (why, n) in &reader_skipped {
        say!("  skipped by the reader {n}: {why}");
    }
    if accepted > 0 {
        let with_mag = rows.iter().filter(|r| r.mag_ut.is_some()).count();
        say!(
            "  rests on: the gyroscope and the accelerometer (tilt); heading: {}",
            if args.imu_only {
                "relative to the start (--imu-only): it drifts with the gyroscope's bias"
                    .to_string()
            } else if with_mag == 0 {
                "relative to the start (no magnetometer in the file): it drifts with the gyroscope's bias".to_string()
            } else {
                format!(
                    "the magnetometer (north; {:.0} % of the samples have one) with its disturbances rejected",
                    100.0 * with_mag as f64 / rows.len() as f64
                )
            }
        );
    }
    if sums.n > 0 {
        let r = sums.rmse();
        let against = if android {
            format!(
                "against Android's rotation vector (its own fusion, a second opinion, not truth; \
                 {} samples after the first {ANDROID_SETTLE_S} s)",
                sums.n
            )
        } else {
            format!(
                "against the optical truth (BROAD metric, {} scored samples)",
                sums.n
            )
        };
        if args.imu_only {
            say!(
                "{against}: inclination RMSE {:.2}° (IMU only: the heading is relative to the start)",
                r.inclination_deg
            );
        } else {
            say!(
                "{against}: RMSE total {:.2}°, heading {:.2}°, inclination {:.2}°",
                r.total_deg,
                r.heading_deg,
                r.inclination_deg
            );
        }
    }
    check_usable(
        accepted > 0,
        "no orientation: no sample was accepted",
        &rejected,
        &[("IMU", rows.len() as u64)],
    )
}

/// Chart points per second of recording.
const CHART_POINTS_HZ: f64 = 10.0;

/// Azimuth of the body's +y axis (degrees from north, clockwise, 0..360) and the tilt of
/// its +z axis from up (degrees), for a body → ENU quaternion `[w, x, y, z]`.
fn azimuth_tilt_deg(q: &[f64; 4]) -> (f64, f64) {
    let [w, x, y, z] = *q;
    // Columns of the rotation matrix: the body's y and z axes in ENU.
    let y_axis = [
        2.0 * (x * y - w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z + w * x),
    ];
    let z_up = 1.0 - 2.0 * (x * x + y * y);
    let azimuth = y_axis[0].atan2(y_axis[1]).to_degrees().rem_euclid(360.0);
    (azimuth, z_up.clamp(-1.0, 1.0).acos().to_degrees())
}

fn display_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
