//! `stridekit orientation FILE`: replay a recording with IMU (and magnetometer)
//! samples (a BROAD CSV or an Android sensor log, told by the content) through the
//! default orientation filter into one row per accepted sample (`t_s,qw,qx,qy,qz`,
//! body → ENU, and the flags), scored against BROAD's optical truth or, as a second
//! opinion, Android's rotation vector; then rendered as CSV, chart and summary.

use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::ahrs::{Ahrs, AhrsFlags, AhrsSettings};
use stridekit_formats::{read_android_log, read_broad, Content, FootFormat, InertialRecording};

use super::{display_name, ReplayError, Usable};
use crate::orientation::metric::{error_angles, ErrorSums};
use crate::rejected::Rejected;
use crate::report::{line_chart, Chart, Series, Style, YFormat};

/// What `stridekit orientation` reads, for messages.
const EXPECTS: &str = "an IMU recording (a BROAD CSV, plain or gzip, or an Android sensor log)";

/// Seconds of an Android log not compared with the rotation vector while both settle.
const ANDROID_SETTLE_S: f64 = 5.0;
/// How far the rotation vector's event may be from a sample to be compared with it.
const ANDROID_MATCH_S: f64 = 0.05;
/// Chart points per second of recording.
const CHART_POINTS_HZ: f64 = 10.0;

/// One replayable sample and what it is compared with.
pub struct Row {
    pub t_s: f64,
    pub gyro_rads: [f64; 3],
    pub accel_mps2: [f64; 3],
    pub mag_ut: Option<[f64; 3]>,
    /// Truth or reference quaternion, body → earth, when this sample is scored.
    pub reference: Option<[f64; 4]>,
}

/// A recording's samples, read.
pub struct ImuRecording {
    pub path: PathBuf,
    /// An Android sensor log (its reference is the rotation vector, not truth).
    pub android: bool,
    pub rows: Vec<Row>,
    /// What the reader skipped, with counts.
    pub reader_skipped: Vec<(String, u64)>,
    /// The file was cut off mid-write.
    pub truncated: bool,
}

/// Reads a BROAD CSV (or a pyshoe foot CSV, which has its columns) or an Android
/// sensor log, told by the content.
pub fn read(path: &Path) -> Result<ImuRecording, ReplayError> {
    let what = |e| super::input::read_error(path, e, EXPECTS);
    let android = match stridekit_formats::sniff(path).map_err(what)?.content {
        Content::AndroidLog => true,
        // A pyshoe foot CSV has the BROAD columns but the magnetometer and the truth.
        Content::Broad | Content::Foot(FootFormat::Pyshoe) | Content::Unknown => false,
        other => return Err(super::input::other_content(path, other, EXPECTS).into()),
    };
    let (rows, reader_skipped, truncated) = if android {
        let rec = read_android_log(path).map_err(what)?;
        (android_rows(&rec), rec.skipped.clone(), rec.truncated)
    } else {
        let rec = read_broad(path).map_err(what)?;
        let rows = rec
            .samples
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
            .collect();
        (
            rows,
            rec.unreadable.reason().into_iter().collect(),
            rec.truncated,
        )
    };
    Ok(ImuRecording {
        path: path.to_path_buf(),
        android,
        rows,
        reader_skipped,
        truncated,
    })
}

/// An Android log's samples, each with the rotation vector nearest in time (within
/// [`ANDROID_MATCH_S`], after the first [`ANDROID_SETTLE_S`]) as its reference.
fn android_rows(rec: &InertialRecording) -> Vec<Row> {
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
}

/// Chart points, thinned to about [`CHART_POINTS_HZ`]: (t, azimuth) and (t, tilt) of
/// the estimate and, when scored, (t, heading error) and (t, inclination error), °.
#[derive(Default)]
pub struct ChartPoints {
    pub attitude: [Vec<(f64, f64)>; 2],
    pub errors: [Vec<(f64, f64)>; 2],
    next_t: f64,
}

/// A replayed recording: the estimates, the errors against the reference.
pub struct OrientationReplay {
    pub recording: ImuRecording,
    pub imu_only: bool,
    /// (t_s, quaternion body → ENU, flags) per accepted sample.
    pub estimates: Vec<(f64, [f64; 4], AhrsFlags)>,
    pub rejected: Rejected,
    pub sums: ErrorSums,
    pub points: ChartPoints,
}

/// Replays `recording` through the default filter (the magnetometer left out with
/// `imu_only`).
pub fn replay(recording: ImuRecording, imu_only: bool) -> Result<OrientationReplay, ReplayError> {
    let mut ahrs = Ahrs::new(AhrsSettings::default()).map_err(|e| e.to_string())?;
    let mut rejected = Rejected::default();
    let mut sums = ErrorSums::default();
    let mut estimates = Vec::with_capacity(recording.rows.len());
    let t_first = recording.rows.first().map_or(0.0, |r| r.t_s);
    let mut points = ChartPoints {
        next_t: f64::NEG_INFINITY,
        ..Default::default()
    };
    for s in &recording.rows {
        let mag = if imu_only { None } else { s.mag_ut };
        match ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, mag) {
            Ok(flags) => {
                let q = ahrs.quaternion().unwrap_or([1.0, 0.0, 0.0, 0.0]);
                estimates.push((s.t_s, q, flags));
                if let Some(t) = &s.reference {
                    sums.add(&q, t);
                }
                points.add(s, &q, t_first);
            }
            Err(e) => rejected.ahrs(&e),
        }
    }
    Ok(OrientationReplay {
        recording,
        imu_only,
        estimates,
        rejected,
        sums,
        points,
    })
}

impl ChartPoints {
    /// The estimate `q` at sample `s`, when the last point is 1 / [`CHART_POINTS_HZ`] ago.
    fn add(&mut self, s: &Row, q: &[f64; 4], t_first: f64) {
        if s.t_s < self.next_t {
            return;
        }
        self.next_t = s.t_s + 1.0 / CHART_POINTS_HZ;
        let x = s.t_s - t_first;
        let (azimuth, tilt) = azimuth_tilt_deg(q);
        // A wrap through north breaks the line instead of crossing the chart.
        if self.attitude[0]
            .last()
            .is_some_and(|p| (p.1 - azimuth).abs() > 180.0)
        {
            self.attitude[0].push((x, f64::NAN));
        }
        self.attitude[0].push((x, azimuth));
        self.attitude[1].push((x, tilt));
        if let Some(t) = &s.reference {
            let (_, h, i) = error_angles(q, t);
            self.errors[0].push((x, h.to_degrees()));
            self.errors[1].push((x, i.to_degrees()));
        }
    }
}

impl OrientationReplay {
    /// The CSV: `t_s,qw,qx,qy,qz` and the flags, one row per accepted sample.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        write!(w, "t_s,qw,qx,qy,qz")?;
        for name in AhrsFlags::NAMES {
            write!(w, ",{name}")?;
        }
        writeln!(w)?;
        for (t_s, q, flags) in &self.estimates {
            write!(
                w,
                "{:.6},{:.9},{:.9},{:.9},{:.9}",
                t_s, q[0], q[1], q[2], q[3]
            )?;
            for f in flags.to_array() {
                write!(w, ",{}", f as u8)?;
            }
            writeln!(w)?;
        }
        Ok(())
    }

    fn name(&self) -> String {
        display_name(&self.recording.path)
    }

    /// The errors against the reference over time when scored, else the azimuth and
    /// the tilt, as SVG.
    pub fn chart(&self, svg: &Path) -> Result<(), String> {
        let named = |name: &str, points: &[(f64, f64)], color| Series {
            name: name.into(),
            points: points.to_vec(),
            color: Some(color),
            style: Style::Line,
        };
        let [heading_err, inclination_err] = &self.points.errors;
        let (series, title, y_label) = if heading_err.is_empty() {
            let [azimuth, tilt] = &self.points.attitude;
            let series = vec![
                named(
                    "azimuth of the +y axis (° from north, clockwise)",
                    azimuth,
                    (31, 119, 180),
                ),
                named("tilt of the +z axis from up (°)", tilt, (255, 127, 14)),
            ];
            (series, format!("Orientation: {}", self.name()), "degrees")
        } else {
            let mut series = vec![named("inclination", inclination_err, (255, 127, 14))];
            if !self.imu_only {
                series.insert(0, named("heading", heading_err, (31, 119, 180)));
            }
            let title = format!("Difference to {}: {}", self.reference_name(), self.name());
            (series, title, "error angle (°)")
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
    }

    fn reference_name(&self) -> &'static str {
        if self.recording.android {
            "Android's rotation vector"
        } else {
            "the optical truth"
        }
    }

    /// The summary; `written_to` names where the CSV went.
    pub fn summary(&self, written_to: &str) -> String {
        let rows = &self.recording.rows;
        let mut lines = vec![format!(
            "{}: {} samples, {} accepted, written to {}",
            self.name(),
            rows.len(),
            self.estimates.len(),
            written_to
        )];
        lines.extend(self.rejected.report().lines().map(str::to_string));
        for (why, n) in &self.recording.reader_skipped {
            lines.push(format!("  skipped by the reader {n}: {why}"));
        }
        if !self.estimates.is_empty() {
            lines.push(format!(
                "  rests on: the gyroscope and the accelerometer (tilt); heading: {}",
                self.heading_rests_on()
            ));
        }
        if self.sums.n > 0 {
            lines.push(self.scored());
        }
        lines.join("\n")
    }

    /// What the heading rests on: the magnetometer (and how many samples have one), or
    /// the start.
    fn heading_rests_on(&self) -> String {
        let rows = &self.recording.rows;
        let with_mag = rows.iter().filter(|r| r.mag_ut.is_some()).count();
        if self.imu_only {
            "relative to the start (--imu-only): it drifts with the gyroscope's bias".to_string()
        } else if with_mag == 0 {
            "relative to the start (no magnetometer in the file): it drifts with the gyroscope's bias".to_string()
        } else {
            format!(
                "the magnetometer (north; {:.0} % of the samples have one) with its disturbances rejected",
                100.0 * with_mag as f64 / rows.len() as f64
            )
        }
    }

    /// The RMS errors against the reference.
    fn scored(&self) -> String {
        let r = self.sums.rmse();
        let against = if self.recording.android {
            format!(
                "against Android's rotation vector (its own fusion, a second opinion, not truth; \
                 {} samples after the first {ANDROID_SETTLE_S} s)",
                self.sums.n
            )
        } else {
            format!(
                "against the optical truth (BROAD metric, {} scored samples)",
                self.sums.n
            )
        };
        if self.imu_only {
            format!(
                "{against}: inclination RMSE {:.2}° (IMU only: the heading is relative to the start)",
                r.inclination_deg
            )
        } else {
            format!(
                "{against}: RMSE total {:.2}°, heading {:.2}°, inclination {:.2}°",
                r.total_deg, r.heading_deg, r.inclination_deg
            )
        }
    }

    /// Whether a sample was accepted, and the stream pushed.
    pub fn usable(&self) -> Usable<'_> {
        Usable {
            produced: !self.estimates.is_empty(),
            what: "no orientation: no sample was accepted",
            rejected: &self.rejected,
            streams: vec![("IMU", self.recording.rows.len() as u64)],
        }
    }
}

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
