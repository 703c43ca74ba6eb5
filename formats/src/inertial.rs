//! The common recording of phone inertial odometry data: IMU samples in the
//! device frame and ground-truth positions, whatever the source (RIDI CSV, RoNIN
//! CSV export, the simulator through the CLI).

use std::path::Path;

use crate::error::{FormatError, Unreadable};

/// One IMU sample, device frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InertialSample {
    pub t_s: f64,
    /// Specific force, gravity included, m/s².
    pub accel_mps2: [f64; 3],
    pub gyro_rads: [f64; 3],
    pub mag_ut: Option<[f64; 3]>,
}

/// An uncalibrated gyroscope or magnetometer event with the platform's bias
/// estimate (Android `TYPE_*_UNCALIBRATED`): rad/s or µT, device frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Uncalibrated {
    pub t_s: f64,
    /// `true`: magnetometer (µT); `false`: gyroscope (rad/s).
    pub magnetometer: bool,
    pub raw: [f64; 3],
    pub bias: [f64; 3],
}

/// IMU samples and true positions (x, y horizontal, z up, metres; the truth's own
/// frame: ENU for the simulator, the Tango frame for RIDI / RoNIN, the floor map for
/// Android logs with waypoints).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InertialRecording {
    pub name: String,
    /// Placement name when known (`in_hand`, `bag`, …, as in the odometry model).
    pub placement: Option<String>,
    pub samples: Vec<InertialSample>,
    /// (t s, x m, y m): dense for RIDI / RoNIN / the simulator, the surveyed
    /// waypoints for Android logs.
    pub truth: Vec<(f64, f64, f64)>,
    /// The platform's own orientation (Android `TYPE_ROTATION_VECTOR`), device → ENU,
    /// `(t_s, [w, x, y, z])`; empty when not recorded.
    pub orientation: Vec<(f64, [f64; 4])>,
    /// Uncalibrated gyroscope / magnetometer events, when recorded.
    pub uncalibrated: Vec<Uncalibrated>,
    /// Header key/value pairs (Android logs: `FloorName`, `Model`, …).
    pub meta: Vec<(String, String)>,
    /// Lines or events the reader skipped, by reason, with counts.
    pub skipped: Vec<(String, u64)>,
    /// The file was cut off mid-write (Android logs: see [`crate::read_android_log`]);
    /// what came before the cut is read.
    pub truncated: bool,
}

impl InertialRecording {
    /// The first header value under `key`.
    pub fn meta_value(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// True horizontal position at `t` (linear interpolation, clamped at the ends).
    pub fn position_at(&self, t: f64) -> (f64, f64) {
        let tr = &self.truth;
        if tr.is_empty() {
            return (0.0, 0.0);
        }
        let i = tr.partition_point(|p| p.0 <= t);
        if i == 0 {
            return (tr[0].1, tr[0].2);
        }
        if i >= tr.len() {
            let p = tr[tr.len() - 1];
            return (p.1, p.2);
        }
        let (a, b) = (tr[i - 1], tr[i]);
        let f = ((t - a.0) / (b.0 - a.0).max(1e-12)).clamp(0.0, 1.0);
        (a.1 + f * (b.1 - a.1), a.2 + f * (b.2 - a.2))
    }
}

/// Columns of a header, by name.
pub(crate) struct Columns<'a>(pub Vec<&'a str>);

impl Columns<'_> {
    pub(crate) fn get(&self, name: &'static str) -> Result<usize, FormatError> {
        self.0
            .iter()
            .position(|h| *h == name)
            .ok_or(FormatError::MissingColumn(name))
    }
    pub(crate) fn opt(&self, name: &'static str) -> Option<usize> {
        self.0.iter().position(|h| *h == name)
    }
}

/// Samples and truth `(t_s, east_m, north_m)` of a parsed recording.
/// Samples, truth, and what was skipped (reason, count).
type Rows = (
    Vec<InertialSample>,
    Vec<(f64, f64, f64)>,
    Vec<(String, u64)>,
);

/// Parse a CSV body of the RIDI column layout (`acce_*`, `gyro_*`, optional
/// `magnet_*`, `pos_x`, `pos_y`; the readers differ only in the time column and its
/// unit) into samples and truth.
pub(crate) fn parse_rows(
    format: &'static str,
    text: &str,
    time_column: &'static str,
    time_scale: f64,
) -> Result<Rows, FormatError> {
    let mut lines = text.lines();
    let header = lines.next().ok_or(FormatError::Empty)?;
    let c = Columns(
        header
            .split(',')
            .map(|h| h.trim().trim_matches('"'))
            .collect(),
    );
    let t = c.get(time_column)?;
    let acc = [c.get("acce_x")?, c.get("acce_y")?, c.get("acce_z")?];
    let gyr = [c.get("gyro_x")?, c.get("gyro_y")?, c.get("gyro_z")?];
    let mag = match (c.opt("magnet_x"), c.opt("magnet_y"), c.opt("magnet_z")) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z]),
        _ => None,
    };
    let pos = [c.get("pos_x")?, c.get("pos_y")?];
    let mut samples = Vec::new();
    let mut truth = Vec::new();
    // Unreadable rows (a truncated last line, text in a number column): skipped and
    // counted.
    let mut unreadable = Unreadable::default();
    let mut first_error = None;
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> Result<f64, FormatError> {
            f.get(i)
                .and_then(|s| s.trim().parse::<f64>().ok())
                .ok_or_else(|| FormatError::parse(format, format!("line {}: column {i}", n + 2)))
        };
        let v3 = |c: [usize; 3]| -> Result<[f64; 3], FormatError> {
            Ok([num(c[0])?, num(c[1])?, num(c[2])?])
        };
        let row = || -> Result<(InertialSample, (f64, f64, f64)), FormatError> {
            let t_s = num(t)? * time_scale;
            Ok((
                InertialSample {
                    t_s,
                    accel_mps2: v3(acc)?,
                    gyro_rads: v3(gyr)?,
                    mag_ut: mag.map(v3).transpose()?,
                },
                (t_s, num(pos[0])?, num(pos[1])?),
            ))
        };
        match row() {
            Ok((sample, position)) => {
                samples.push(sample);
                truth.push(position);
            }
            Err(e) => {
                unreadable.add(n + 2);
                first_error.get_or_insert(e);
            }
        }
    }
    if samples.is_empty() {
        return Err(first_error.unwrap_or(FormatError::Empty));
    }
    let skipped = unreadable.reason().into_iter().collect();
    Ok((samples, truth, skipped))
}

/// Reads a RIDI or RoNIN-export recording or an Android sensor log: a file whose
/// content is an Android sensor log ([`crate::sniff`]; plain or gzip, whatever its
/// name) is read by [`crate::android`]; a CSV whose header has `time_s` is a RoNIN
/// export, one with `time` a RIDI file; a directory holding `processed/data.csv` is a
/// RIDI sequence.
pub fn read_inertial(path: &Path) -> Result<InertialRecording, FormatError> {
    if path.is_file() {
        use crate::Content;
        match crate::sniff::sniff(path)?.content {
            Content::AndroidLog => return crate::android::read_android_log(path),
            Content::Ridi | Content::Ronin | Content::Unknown => {}
            other => {
                return Err(FormatError::OtherContent {
                    found: other.name(),
                    expected: "phone recording (Android sensor log, RIDI or RoNIN CSV)",
                })
            }
        }
    }
    if path.is_dir() && !path.join("processed").join("data.csv").is_file() {
        return Err(FormatError::FolderWithout(
            "processed/data.csv (a RIDI sequence folder has one)",
        ));
    }
    let file = if path.is_dir() {
        path.join("processed").join("data.csv")
    } else {
        path.to_path_buf()
    };
    crate::sniff::check_file(&file)?;
    let text = std::fs::read_to_string(&file)?;
    let first = text.lines().next().unwrap_or("");
    let name = if path.is_dir() { path } else { file.as_path() }
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if first.split(',').any(|h| h.trim() == "time_s") {
        crate::ronin::parse_ronin_csv(&name, &text)
    } else {
        crate::ridi::parse_ridi_csv(&name, &text)
    }
}

/// Every recording in a folder: RIDI sequence folders and `.csv` files, sorted by name.
pub fn read_inertial_dir(dir: &Path) -> Result<Vec<InertialRecording>, FormatError> {
    let mut paths: Vec<_> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.join("processed/data.csv").is_file()
                || p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"))
        })
        .collect();
    paths.sort();
    paths.iter().map(|p| read_inertial(p)).collect()
}
