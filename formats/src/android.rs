//! Reader for Android sensor logs: one sensor event per line, as an app logs them
//! from a `SensorEventListener` (the format of the Microsoft Indoor Location
//! Competition 2.0 data), plain text or gzip (`.gz`).
//!
//! ```text
//! #  startTime:1574559495255                       header lines start with '#':
//! #  SiteID:…  FloorName:F1                         tab-separated key:value pairs
//! 1574559495263  TYPE_WAYPOINT  81.317215  93.31349
//! 1574559495401  TYPE_ACCELEROMETER  -0.855  1.824  9.826  2
//! 1574559495401  TYPE_GYROSCOPE  -0.391  -0.079  0.092  3
//! 1574559495401  TYPE_MAGNETIC_FIELD  29.78  6.42  -30.06  3
//! 1574559495401  TYPE_ROTATION_VECTOR  0.062  0.079  0.570  3
//! ```
//!
//! (shown with spaces; the file has one tab between columns). Columns are separated
//! by tabs (any whitespace is accepted). Column 1 is the time
//! in milliseconds (any clock, e.g. `SensorEvent.timestamp` / 1e6 or the wall clock,
//! the same for every line); `t_s = ms / 1000` on that clock. Column 2 is the event
//! type, then its values:
//!
//! | type | values | unit |
//! |---|---|---|
//! | `TYPE_ACCELEROMETER` | x y z [accuracy] | m/s², gravity included, device axes |
//! | `TYPE_GYROSCOPE` | x y z [accuracy] | rad/s |
//! | `TYPE_MAGNETIC_FIELD` | x y z [accuracy] | µT (calibrated by Android) |
//! | `TYPE_GYROSCOPE_UNCALIBRATED` | x y z bx by bz [accuracy] | rad/s, with Android's bias estimate |
//! | `TYPE_MAGNETIC_FIELD_UNCALIBRATED` | x y z bx by bz [accuracy] | µT, with the hard-iron estimate |
//! | `TYPE_ROTATION_VECTOR` | x y z [w or accuracy] | unit quaternion's vector part; device → ENU |
//! | `TYPE_WAYPOINT` | x y | metres in the map's frame (the ground truth) |
//!
//! | `TYPE_ACCELEROMETER_UNCALIBRATED` | x y z bx by bz [accuracy] | m/s², with the bias estimate |
//!
//! The calibrated streams are used when the log has them. A log without any
//! `TYPE_ACCELEROMETER`, `TYPE_GYROSCOPE` or `TYPE_MAGNETIC_FIELD` event (some apps
//! and devices log only the uncalibrated sensors) gets that stream from its
//! `…_UNCALIBRATED` events with Android's own bias estimate removed (raw − bias), the
//! same quantity Android reports as calibrated; the two are never mixed within a log.
//! Other types (WiFi, Bluetooth, …) are skipped and counted by type; so are lines whose values do not parse (counted as
//! `malformed TYPE_…`). The three motion streams' values are read as 32-bit floats:
//! `SensorEvent.values` is a `float[]` and the log prints each with
//! `Float.toString`, so this recovers exactly the value the app had (and an app
//! replaying the log through the SDK gets the same samples as this reader).
//!
//! IMU samples: the accelerometer, gyroscope and magnetometer events go, in file
//! order (the order the app received them), through the SDK's one merge rule,
//! [`stridekit_core::imu::ImuMerger`] with its defaults, the rule an app's
//! `PhoneNavigator.pushSensorEventsPacked` runs: one sample per accelerometer event,
//! the gyroscope and magnetometer interpolated linearly between their events around
//! it (held up to `DEFAULT_MAX_HOLD_S`, 0.1 s, beyond a stream's ends and across gaps), then the
//! end of the file releases what still waits. Accelerometer events with no
//! gyroscope within that reach are skipped and counted (`accelerometer without
//! gyroscope`); the magnetometer is `None` where it has none. An event the merger
//! refuses (a repeated or earlier timestamp within its stream, a value that is not
//! finite or out of range) is skipped and counted by the reader, by stream and reason.
//!
//! **Cut-off logs.** A log whose header has `startTime` must end with its `endTime`
//! header line (as the Indoor Location Competition logs do); one without it, one that
//! ends inside a line, or a gzip stream that ends early was cut off mid-write: the
//! events before the cut are read and [`InertialRecording::truncated`] says so. Plain
//! text or gzip is told by the content (gzip's magic bytes), not by the name.
//!
//! Rotation vector: a 4th value in −1..=1 is taken as w (API 18+ reports it in
//! `values[3]`), otherwise (absent, or an accuracy such as 3) w = √(1 − x² − y² − z²).
//!
//! **Logging it yourself** (Kotlin, in a `SensorEventListener`):
//!
//! ```kotlin
//! override fun onSensorChanged(e: SensorEvent) {
//!     val name = when (e.sensor.type) {
//!         Sensor.TYPE_ACCELEROMETER -> "TYPE_ACCELEROMETER"
//!         Sensor.TYPE_GYROSCOPE -> "TYPE_GYROSCOPE"
//!         Sensor.TYPE_MAGNETIC_FIELD -> "TYPE_MAGNETIC_FIELD"
//!         Sensor.TYPE_ROTATION_VECTOR -> "TYPE_ROTATION_VECTOR"
//!         else -> return
//!     }
//!     val ms = e.timestamp / 1_000_000          // elapsedRealtimeNanos → ms
//!     out.write("$ms\t$name\t${e.values.take(3).joinToString("\t")}\t${e.accuracy}\n")
//! }
//! ```
//!
//! and, for ground truth, `"$ms\tTYPE_WAYPOINT\t$x\t$y\n"` when the walker passes a
//! surveyed point (same clock).

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use stridekit_core::imu::{ImuEvent, ImuMerger, MergeConfig, SensorKind};
use stridekit_core::input::InputError;

use crate::error::FormatError;
use crate::inertial::{InertialRecording, InertialSample, Uncalibrated};

const FORMAT: &str = "Android sensor log";
/// Largest file this reader accepts, bytes (decompressed): 1 GiB.
pub const MAX_LOG_BYTES: u64 = 1 << 30;

/// Reads an Android sensor log (gzip or plain text, told by the content).
pub fn read_android_log(path: &Path) -> Result<InertialRecording, FormatError> {
    crate::sniff::check_file(path)?;
    let gz = crate::sniff::file_is_gzip(path)?;
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    let mut cut_gzip = false;
    if gz {
        match flate2::read::GzDecoder::new(file)
            .take(MAX_LOG_BYTES + 1)
            .read_to_end(&mut bytes)
        {
            Ok(_) => {}
            // A gzip stream cut short: the lines before the cut are read.
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => cut_gzip = true,
            Err(e) => return Err(e.into()),
        }
    } else {
        file.take(MAX_LOG_BYTES + 1).read_to_end(&mut bytes)?;
    }
    if bytes.len() as u64 > MAX_LOG_BYTES {
        return Err(FormatError::parse(FORMAT, "larger than 1 GiB"));
    }
    let text = String::from_utf8_lossy(&bytes);
    let mut rec = parse_android_log(&log_name(path), &text)?;
    rec.truncated |= cut_gzip;
    Ok(rec)
}

/// The file name without `.gz` and `.txt`.
fn log_name(path: &Path) -> String {
    let mut name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    for ext in [".gz", ".txt"] {
        if name.len() > ext.len() && name.to_ascii_lowercase().ends_with(ext) {
            name.truncate(name.len() - ext.len());
        }
    }
    name
}

/// Whether a path looks like an Android sensor log (`*.txt` or `*.txt.gz`).
pub fn is_android_log(path: &Path) -> bool {
    let n = path
        .file_name()
        .map(|s| s.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    path.is_file() && (n.ends_with(".txt") || n.ends_with(".txt.gz"))
}

/// Every Android sensor log under `dir` (recursively), sorted by path.
pub fn list_android_logs(dir: &Path) -> Result<Vec<PathBuf>, FormatError> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d)? {
            let p = e?.path();
            if p.is_dir() {
                stack.push(p);
            } else if is_android_log(&p) {
                out.push(p);
            }
        }
    }
    out.sort();
    Ok(out)
}

/// `N` values of a `SensorEvent` as the app had them (`float`), widened exactly.
fn floats<const N: usize>(fields: &[&str]) -> Option<[f64; N]> {
    if fields.len() < N {
        return None;
    }
    let mut v = [0.0; N];
    for (x, f) in v.iter_mut().zip(fields) {
        *x = f64::from(f.parse::<f32>().ok()?);
    }
    Some(v)
}

fn numbers<const N: usize>(fields: &[&str]) -> Option<[f64; N]> {
    if fields.len() < N {
        return None;
    }
    let mut v = [0.0; N];
    for (x, f) in v.iter_mut().zip(fields) {
        *x = f.parse().ok()?;
    }
    Some(v)
}

/// Where a motion event of the log came from: a calibrated stream, or an
/// uncalibrated one with Android's bias estimate removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Source {
    Calibrated(SensorKind),
    Uncalibrated(SensorKind),
}

/// The reason a merger refused an event, counted by the reader.
fn refused(kind: SensorKind, e: &InputError) -> String {
    let stream = kind.stream();
    match e {
        InputError::TimeNotIncreasing { .. } if e.is_duplicate_time() => {
            format!("{stream} stream: duplicate timestamp (equal to the previous event's)")
        }
        InputError::TimeNotIncreasing { .. } => {
            format!("{stream} stream: timestamp before the previous event's")
        }
        InputError::NonFinite { field } => format!("{field} not a finite number"),
        InputError::OutOfRange { field, .. } => format!("{field} out of range"),
        other => format!("{stream} stream: {other}"),
    }
}

/// The events of the streams chosen (calibrated where the log has any, else the
/// uncalibrated ones less their bias), in file order.
fn chosen(events: &[(Source, f64, [f64; 3])]) -> impl Iterator<Item = ImuEvent> + '_ {
    let has = |k: SensorKind| events.iter().any(|e| e.0 == Source::Calibrated(k));
    let wanted = [
        SensorKind::Accelerometer,
        SensorKind::Gyroscope,
        SensorKind::Magnetometer,
    ]
    .map(|k| {
        if has(k) {
            Source::Calibrated(k)
        } else {
            Source::Uncalibrated(k)
        }
    });
    events
        .iter()
        .filter(move |e| wanted.contains(&e.0))
        .map(|&(source, t_s, values)| {
            let (Source::Calibrated(kind) | Source::Uncalibrated(kind)) = source;
            ImuEvent { t_s, kind, values }
        })
}

/// The accelerometer, gyroscope and magnetometer events of an Android sensor log's
/// text, in file order (the streams [`parse_android_log`] merges), for replaying a
/// log as an app receives it.
pub fn android_motion_events(text: &str) -> Vec<ImuEvent> {
    chosen(&parse_lines(text).events).collect()
}

/// The events of the streams chosen, through the merge rule; refused events
/// counted in `skipped`.
fn merge_events(
    events: &[(Source, f64, [f64; 3])],
    skipped: &mut BTreeMap<String, u64>,
) -> Vec<InertialSample> {
    let mut merger = ImuMerger::new(MergeConfig::default()).expect("the default rule is valid");
    let mut samples = Vec::new();
    let mut out = |s: stridekit_core::ImuSample| {
        samples.push(InertialSample {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
            gyro_rads: s.gyro_rads,
            mag_ut: s.mag_ut,
        })
    };
    for e in chosen(events) {
        if let Err(err) = merger.push(&e, &mut out) {
            *skipped.entry(refused(e.kind, &err)).or_default() += 1;
        }
    }
    merger.flush(&mut out);
    let without = merger.counts().without_gyro;
    if without > 0 {
        *skipped
            .entry("accelerometer without gyroscope".into())
            .or_default() += without;
    }
    samples
}

/// Parse the text of an Android sensor log (see the module docs).
pub fn parse_android_log(name: &str, text: &str) -> Result<InertialRecording, FormatError> {
    let Lines {
        meta,
        mut skipped,
        events,
        mut truth,
        orientation,
        uncalibrated,
        last_read,
    } = parse_lines(text);
    let has = |key: &str| meta.iter().any(|(k, _)| k == key);
    let truncated =
        (has("startTime") && !has("endTime")) || crate::sniff::cut_mid_row(text, last_read);
    if !events.iter().any(|e| {
        matches!(
            e.0,
            Source::Calibrated(SensorKind::Accelerometer)
                | Source::Uncalibrated(SensorKind::Accelerometer)
        )
    }) {
        return Err(FormatError::Empty);
    }
    truth.sort_by(|a, b| a.0.total_cmp(&b.0));
    let samples = merge_events(&events, &mut skipped);
    if samples.is_empty() {
        return Err(FormatError::parse(FORMAT, "no gyroscope events"));
    }
    Ok(InertialRecording {
        name: name.to_string(),
        placement: None,
        samples,
        truth,
        orientation,
        uncalibrated,
        meta,
        skipped: skipped.into_iter().collect(),
        truncated,
    })
}

/// What the lines of a log hold, before the merge.
struct Lines {
    meta: Vec<(String, String)>,
    skipped: BTreeMap<String, u64>,
    /// The motion events in file order (the order the app received them).
    events: Vec<(Source, f64, [f64; 3])>,
    truth: Vec<(f64, f64, f64)>,
    orientation: Vec<(f64, [f64; 4])>,
    uncalibrated: Vec<Uncalibrated>,
    /// Whether the last non-empty line was read whole (a cut-off line is not).
    last_read: bool,
}

fn parse_lines(text: &str) -> Lines {
    let mut meta = Vec::new();
    let mut skipped: BTreeMap<String, u64> = BTreeMap::new();
    let mut events: Vec<(Source, f64, [f64; 3])> = Vec::new();
    let mut truth = Vec::new();
    let mut orientation = Vec::new();
    let mut uncalibrated = Vec::new();
    let mut last_read = true;
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        last_read = false;
        if let Some(h) = line.strip_prefix('#') {
            for kv in h.split('\t') {
                if let Some((k, v)) = kv.trim().split_once(':') {
                    meta.push((k.trim().to_string(), v.trim().to_string()));
                }
            }
            last_read = true;
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let (Some(ms), Some(kind)) = (fields.first(), fields.get(1)) else {
            *skipped.entry("malformed line".into()).or_default() += 1;
            continue;
        };
        let values = &fields[2..];
        let t_s = match ms.parse::<f64>() {
            Ok(ms) if ms.is_finite() => ms / 1000.0,
            _ => {
                *skipped.entry(format!("malformed {kind}")).or_default() += 1;
                continue;
            }
        };
        let ok = match *kind {
            "TYPE_ACCELEROMETER" | "TYPE_GYROSCOPE" | "TYPE_MAGNETIC_FIELD" => floats::<3>(values)
                .map(|v| {
                    let k = match *kind {
                        "TYPE_ACCELEROMETER" => SensorKind::Accelerometer,
                        "TYPE_GYROSCOPE" => SensorKind::Gyroscope,
                        _ => SensorKind::Magnetometer,
                    };
                    events.push((Source::Calibrated(k), t_s, v));
                }),
            "TYPE_GYROSCOPE_UNCALIBRATED"
            | "TYPE_MAGNETIC_FIELD_UNCALIBRATED"
            | "TYPE_ACCELEROMETER_UNCALIBRATED" => floats::<6>(values).map(|v| {
                let (raw, bias) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
                let k = match *kind {
                    "TYPE_GYROSCOPE_UNCALIBRATED" => SensorKind::Gyroscope,
                    "TYPE_MAGNETIC_FIELD_UNCALIBRATED" => SensorKind::Magnetometer,
                    _ => SensorKind::Accelerometer,
                };
                if k != SensorKind::Accelerometer {
                    uncalibrated.push(Uncalibrated {
                        t_s,
                        magnetometer: k == SensorKind::Magnetometer,
                        raw,
                        bias,
                    });
                }
                // Raw − Android's bias estimate: what Android reports as calibrated.
                events.push((
                    Source::Uncalibrated(k),
                    t_s,
                    [0, 1, 2].map(|i| raw[i] - bias[i]),
                ));
            }),
            "TYPE_ROTATION_VECTOR" => numbers::<3>(values).map(|[x, y, z]| {
                let w4 = values.get(3).and_then(|s| s.parse::<f64>().ok());
                let w = match w4 {
                    // A 4th value that is a plausible w (API 18+: values[3]) and makes
                    // a unit quaternion; an accuracy (e.g. 3) is not.
                    Some(w)
                        if w.abs() <= 1.0 && (x * x + y * y + z * z + w * w - 1.0).abs() < 1e-3 =>
                    {
                        w
                    }
                    _ => (1.0 - x * x - y * y - z * z).max(0.0).sqrt(),
                };
                orientation.push((t_s, [w, x, y, z]));
            }),
            "TYPE_WAYPOINT" => numbers::<2>(values).map(|[x, y]| truth.push((t_s, x, y))),
            other => {
                *skipped.entry(other.to_string()).or_default() += 1;
                Some(())
            }
        };
        if ok.is_none() {
            *skipped.entry(format!("malformed {kind}")).or_default() += 1;
        }
        last_read = ok.is_some();
    }
    Lines {
        meta,
        skipped,
        events,
        truth,
        orientation,
        uncalibrated,
        last_read,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "#\tstartTime:1000\n\
#\tSiteID:abc\tSiteName:Mall\tFloorName:F2\n\
1000\tTYPE_WAYPOINT\t1.5\t2.5\n\
1000\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t3\n\
1000\tTYPE_MAGNETIC_FIELD\t10\t20\t-30\t3\n\
1000\tTYPE_GYROSCOPE\t0.01\t0.02\t0.03\t3\n\
1000\tTYPE_ROTATION_VECTOR\t0\t0\t0.6\t3\n\
1000\tTYPE_WIFI\tssid\tbssid\t-60\n\
1020\tTYPE_ACCELEROMETER\t0.3\t0.2\t9.8\t3\n\
1020\tTYPE_GYROSCOPE\t0.03\t0.02\t0.03\t3\n\
1020\tTYPE_MAGNETIC_FIELD_UNCALIBRATED\t1\t2\t3\t0.5\t0.5\t0.5\t3\n\
1030\tTYPE_GYROSCOPE\tnot-a-number\t0\t0\t3\n\
1040\tTYPE_ACCELEROMETER\t0.5\t0.2\t9.8\t3\n\
1040\tTYPE_GYROSCOPE\t0.05\t0.02\t0.03\t3\n\
1040\tTYPE_MAGNETIC_FIELD\t12\t20\t-30\t3\n\
1060\tTYPE_ACCELEROMETER\t0.5\t0.2\t9.8\t3\n\
2000\tTYPE_WAYPOINT\t3.5\t2.5\n";

    /// Values as the reader holds them: `SensorEvent` floats, widened.
    fn w(v: [f32; 3]) -> [f64; 3] {
        v.map(f64::from)
    }

    #[test]
    fn reads_a_small_log() {
        let r = parse_android_log("walk", SMALL).unwrap();
        assert_eq!(r.samples.len(), 4);
        let s = &r.samples;
        assert_eq!(s[0].t_s, 1.0);
        assert!((s[1].t_s - 1.02).abs() < 1e-12);
        assert_eq!(s[0].accel_mps2, w([0.1, 0.2, 9.8]));
        assert_eq!(s[1].gyro_rads, w([0.03, 0.02, 0.03]));
        // Magnetometer interpolated between 1.000 and 1.040 s.
        let m = s[1].mag_ut.unwrap();
        assert!((m[0] - 11.0).abs() < 1e-9 && m[1] == 20.0);
        // Held 20 ms past the last gyro/mag event.
        assert_eq!(s[3].gyro_rads, w([0.05, 0.02, 0.03]));
        assert_eq!(s[3].mag_ut, Some([12.0, 20.0, -30.0]));
        assert_eq!(r.truth, vec![(1.0, 1.5, 2.5), (2.0, 3.5, 2.5)]);
        let (w, x, y, z) = (
            r.orientation[0].1[0],
            r.orientation[0].1[1],
            r.orientation[0].1[2],
            r.orientation[0].1[3],
        );
        assert!((w - 0.8).abs() < 1e-12 && x == 0.0 && y == 0.0 && z == 0.6);
        assert_eq!(r.uncalibrated.len(), 1);
        assert!(r.uncalibrated[0].magnetometer);
        assert_eq!(r.uncalibrated[0].bias, [0.5; 3]);
        assert_eq!(r.meta_value("FloorName"), Some("F2"));
        assert_eq!(r.meta_value("startTime"), Some("1000"));
        let skipped: BTreeMap<_, _> = r.skipped.iter().cloned().collect();
        assert_eq!(skipped.get("TYPE_WIFI"), Some(&1));
        assert_eq!(skipped.get("malformed TYPE_GYROSCOPE"), Some(&1));
        assert_eq!(skipped.len(), 2, "{skipped:?}");
        let (x, y) = r.position_at(1.5);
        assert!((x - 2.5).abs() < 1e-12 && y == 2.5);
    }

    #[test]
    fn rotation_vector_with_w_and_repeated_times_are_kept() {
        let text = "5\tTYPE_GYROSCOPE\t0\t0\t0\n\
5\tTYPE_ACCELEROMETER\t0\t0\t9.8\n\
5\tTYPE_ACCELEROMETER\t0\t0\t9.9\n\
5\tTYPE_ROTATION_VECTOR\t0\t0\t0.6\t0.8\t0.1\n";
        let r = parse_android_log("x", text).unwrap();
        // Both events at the same time: the merge rule refuses the second, the
        // reader counts it.
        assert_eq!(r.samples.len(), 1);
        assert_eq!(r.samples[0].accel_mps2, [0.0, 0.0, f64::from(9.8f32)]);
        assert_eq!(
            r.skipped,
            vec![(
                "accelerometer stream: duplicate timestamp (equal to the previous event's)".into(),
                1
            )]
        );
        assert_eq!(r.orientation[0].1, [0.8, 0.0, 0.0, 0.6]);
        assert!(r.samples[0].mag_ut.is_none());
    }

    #[test]
    fn uncalibrated_streams_stand_in_for_missing_calibrated_ones() {
        // No calibrated accelerometer, gyroscope or magnetometer: raw − bias.
        let text = "1000\tTYPE_ACCELEROMETER_UNCALIBRATED\t0.5\t0.2\t10.0\t0.5\t0.0\t0.2\t3\n\
1000\tTYPE_GYROSCOPE_UNCALIBRATED\t0.11\t0.02\t0.03\t0.1\t0.0\t0.0\t3\n\
1000\tTYPE_MAGNETIC_FIELD_UNCALIBRATED\t40\t20\t-30\t30\t0\t0\t3\n\
1020\tTYPE_ACCELEROMETER_UNCALIBRATED\t0.5\t0.2\t10.0\t0.5\t0.0\t0.2\n\
1020\tTYPE_GYROSCOPE_UNCALIBRATED\t0.11\t0.02\t0.03\t0.1\t0.0\t0.0\n";
        let r = parse_android_log("x", text).unwrap();
        assert_eq!(r.samples.len(), 2);
        let s = &r.samples[0];
        assert!(s.accel_mps2[0].abs() < 1e-6 && (s.accel_mps2[2] - 9.8).abs() < 1e-6);
        assert!((s.gyro_rads[0] - 0.01).abs() < 1e-6);
        assert_eq!(s.mag_ut, Some([10.0, 20.0, -30.0]));
        // With calibrated streams present, the uncalibrated ones do not mix in.
        let both =
            format!("{text}1000\tTYPE_GYROSCOPE\t0.5\t0\t0\n1030\tTYPE_GYROSCOPE\t0.5\t0\t0\n");
        let r = parse_android_log("x", &both).unwrap();
        assert_eq!(r.samples[0].gyro_rads, [0.5, 0.0, 0.0]);
        assert_eq!(r.samples[1].gyro_rads, [0.5, 0.0, 0.0]);
    }

    #[test]
    fn errors_are_typed() {
        assert!(matches!(
            parse_android_log("x", "# only a header\n"),
            Err(FormatError::Empty)
        ));
        assert!(matches!(
            parse_android_log("x", "1\tTYPE_ACCELEROMETER\t0\t0\t9.8\n"),
            Err(FormatError::Parse { .. })
        ));
        // Accelerometer far from any gyroscope event: skipped and counted.
        let r = parse_android_log(
            "x",
            "1000\tTYPE_GYROSCOPE\t0\t0\t0\n1000\tTYPE_ACCELEROMETER\t0\t0\t9.8\n5000\tTYPE_ACCELEROMETER\t0\t0\t9.8\n",
        )
        .unwrap();
        assert_eq!(r.samples.len(), 1);
        assert_eq!(
            r.skipped,
            vec![("accelerometer without gyroscope".into(), 1)]
        );
    }

    #[test]
    fn a_cut_off_log_is_flagged() {
        // SMALL has startTime and no endTime: cut off.
        assert!(parse_android_log("x", SMALL).unwrap().truncated);
        let whole = format!("{SMALL}#\tendTime:2000\n");
        assert!(!parse_android_log("x", &whole).unwrap().truncated);
        // No header at all: only a line cut short tells.
        let plain = "1000\tTYPE_GYROSCOPE\t0\t0\t0\n1000\tTYPE_ACCELEROMETER\t0\t0\t9.8\n";
        assert!(!parse_android_log("x", plain).unwrap().truncated);
        let cut = format!("{plain}1020\tTYPE_ACCELEROMETER\t0.1");
        assert!(parse_android_log("x", &cut).unwrap().truncated);
    }

    #[test]
    fn reads_gzip_and_names_the_log() {
        use std::io::Write;
        let dir = std::env::temp_dir().join(format!("stridekit-android-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("F2")).unwrap();
        let path = dir.join("F2").join("walk1.txt.gz");
        let mut gz = flate2::write::GzEncoder::new(
            std::fs::File::create(&path).unwrap(),
            flate2::Compression::fast(),
        );
        gz.write_all(SMALL.as_bytes()).unwrap();
        gz.finish().unwrap();
        std::fs::write(dir.join("plain.txt"), SMALL).unwrap();
        let a = read_android_log(&path).unwrap();
        let b = read_android_log(&dir.join("plain.txt")).unwrap();
        assert_eq!(a.name, "walk1");
        assert_eq!(b.name, "plain");
        assert_eq!(a.samples, b.samples);
        let logs = list_android_logs(&dir).unwrap();
        assert_eq!(logs.len(), 2);
        // Gzip told by the content; a stream cut short keeps what it held.
        let renamed = dir.join("walk1.txt");
        std::fs::copy(&path, &renamed).unwrap();
        assert_eq!(read_android_log(&renamed).unwrap().samples, a.samples);
        let whole = format!("{SMALL}#\tendTime:2000\n");
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(whole.as_bytes()).unwrap();
        let bytes = gz.finish().unwrap();
        let full = dir.join("full.txt.gz");
        std::fs::write(&full, &bytes).unwrap();
        assert!(!read_android_log(&full).unwrap().truncated);
        let cut = dir.join("cut.txt.gz");
        std::fs::write(&cut, &bytes[..bytes.len() - 10]).unwrap();
        assert!(read_android_log(&cut).unwrap().truncated);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
