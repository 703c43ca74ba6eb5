//! Reader for foot-mounted IMU recordings in CSV with a header. Two layouts, told
//! apart by the header (column order is free, unknown columns are ignored):
//!
//! - **pyshoe / University of Toronto** VICON set: `t_s, acc_x_mps2, acc_y_mps2,
//!   acc_z_mps2, gyr_x_rads, gyr_y_rads, gyr_z_rads` (SI units), optional truth
//!   `gt_x_m gt_y_m gt_z_m` and optional 0/1 stance label columns `zv_*`;
//! - **x-io** (NGIMU `sensors.csv` as exported by the NGIMU GUI, and the walks of
//!   x-io's Gait-Tracking examples): `Time (s), Gyroscope X (deg/s), Gyroscope Y
//!   (deg/s), Gyroscope Z (deg/s), Accelerometer X (g), Accelerometer Y (g),
//!   Accelerometer Z (g)` and optionally magnetometer and barometer columns
//!   (ignored). Converted to rad/s and m/s² (1 g = 9.80665 m/s²) at reading. Such
//!   logs repeat rows (a 400 Hz stream on a coarse clock): the reader keeps every
//!   row; the navigator rejects a repeated timestamp and the replay counts it.
//!
//! A row whose time or sensor fields are not numbers (a truncated last line, a
//! logger's text note) is skipped and counted in
//! [`FootRecording::unreadable_rows`]; NaN and ∞ are numbers here and go on to the
//! navigator, which rejects them. A file that ends inside a row was cut off mid-write:
//! [`FootRecording::truncated`]. Also lists the trials of a folder.

use std::path::{Path, PathBuf};

use crate::error::FormatError;

const FORMAT: &str = "foot CSV";
/// Standard gravity, m/s² per g.
const G_MPS2: f64 = 9.80665;

/// Which column layout a recording was read from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FootFormat {
    /// pyshoe / UofT (SI units; the data set's axes are x forward, y right, z down).
    #[default]
    Pyshoe,
    /// x-io NGIMU / Gait-Tracking export (deg/s and g in the file).
    Xio,
}

impl FootFormat {
    pub fn name(self) -> &'static str {
        match self {
            FootFormat::Pyshoe => "pyshoe CSV",
            FootFormat::Xio => "x-io CSV",
        }
    }
}

/// One foot IMU recording.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FootRecording {
    pub name: String,
    pub format: FootFormat,
    pub t_s: Vec<f64>,
    /// Specific force, m/s², sensor axes as recorded.
    pub accel_mps2: Vec<[f64; 3]>,
    /// Angular rate, rad/s, sensor axes as recorded.
    pub gyro_rads: Vec<[f64; 3]>,
    /// Truth position per sample, m, when the file has `gt_x_m gt_y_m gt_z_m`.
    pub truth_m: Option<Vec<[f64; 3]>>,
    /// Stance label columns (`zv_...`), name without the `zv_` prefix.
    pub labels: Vec<(String, Vec<bool>)>,
    /// Data rows skipped because a needed field was not a number, and the line
    /// number (1-based, header = 1) of the first one.
    pub unreadable_rows: usize,
    pub first_unreadable_line: Option<usize>,
    /// The file ends inside a row: it was cut off mid-write (the rows before the cut
    /// are read).
    pub truncated: bool,
}

impl FootRecording {
    pub fn len(&self) -> usize {
        self.t_s.len()
    }
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }
    pub fn label(&self, name: &str) -> Option<&[bool]> {
        self.labels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
}

/// Column indices of one layout and the factors to SI units.
struct Layout {
    format: FootFormat,
    t: usize,
    acc: [usize; 3],
    gyr: [usize; 3],
    acc_scale: f64,
    gyr_scale: f64,
}

fn layout(header: &[String]) -> Result<Layout, FormatError> {
    let find = |name: &str| header.iter().position(|h| h.eq_ignore_ascii_case(name));
    let all3 = |names: [&str; 3]| -> Option<[usize; 3]> {
        Some([find(names[0])?, find(names[1])?, find(names[2])?])
    };
    if let Some(t) = find("t_s") {
        let acc = all3(["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]).ok_or(
            FormatError::MissingColumn("acc_x_mps2 acc_y_mps2 acc_z_mps2"),
        )?;
        let gyr = all3(["gyr_x_rads", "gyr_y_rads", "gyr_z_rads"]).ok_or(
            FormatError::MissingColumn("gyr_x_rads gyr_y_rads gyr_z_rads"),
        )?;
        return Ok(Layout {
            format: FootFormat::Pyshoe,
            t,
            acc,
            gyr,
            acc_scale: 1.0,
            gyr_scale: 1.0,
        });
    }
    if let Some(t) = find("Time (s)") {
        let acc = all3([
            "Accelerometer X (g)",
            "Accelerometer Y (g)",
            "Accelerometer Z (g)",
        ])
        .ok_or(FormatError::MissingColumn(
            "Accelerometer X (g), Accelerometer Y (g), Accelerometer Z (g)",
        ))?;
        let gyr = all3([
            "Gyroscope X (deg/s)",
            "Gyroscope Y (deg/s)",
            "Gyroscope Z (deg/s)",
        ])
        .ok_or(FormatError::MissingColumn(
            "Gyroscope X (deg/s), Gyroscope Y (deg/s), Gyroscope Z (deg/s)",
        ))?;
        return Ok(Layout {
            format: FootFormat::Xio,
            t,
            acc,
            gyr,
            acc_scale: G_MPS2,
            gyr_scale: std::f64::consts::PI / 180.0,
        });
    }
    Err(FormatError::parse(
        FORMAT,
        "the header has neither a pyshoe time column (t_s, with acc_*_mps2 and gyr_*_rads) \
         nor an x-io one (Time (s), with Gyroscope X (deg/s)… and Accelerometer X (g)…)",
    ))
}

/// Reads one recording.
pub fn read_foot_csv(path: &Path) -> Result<FootRecording, FormatError> {
    crate::sniff::check_file(path)?;
    let text = std::fs::read_to_string(path)?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    parse_foot_csv(&text, name)
}

/// Parses a recording from CSV text (see the module docs); `name` names it.
pub fn parse_foot_csv(text: &str, name: String) -> Result<FootRecording, FormatError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .ok_or(FormatError::Empty)?
        .split(',')
        .map(|h| h.trim().trim_matches('"').trim().to_string())
        .collect();
    let lay = layout(&header)?;
    let find = |name: &str| header.iter().position(|h| h == name);
    let gt = match (find("gt_x_m"), find("gt_y_m"), find("gt_z_m")) {
        (Some(x), Some(y), Some(z)) if lay.format == FootFormat::Pyshoe => Some([x, y, z]),
        _ => None,
    };
    let label_cols: Vec<(String, usize)> = header
        .iter()
        .enumerate()
        .filter_map(|(i, h)| h.strip_prefix("zv_").map(|n| (n.to_string(), i)))
        .collect();
    let mut rec = FootRecording {
        name,
        format: lay.format,
        truth_m: gt.map(|_| Vec::new()),
        labels: label_cols
            .iter()
            .map(|(n, _)| (n.clone(), Vec::new()))
            .collect(),
        ..Default::default()
    };
    let mut last_read = true;
    for (ln, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |i: usize| -> Option<f64> { fields.get(i)?.parse::<f64>().ok() };
        let row = (|| {
            let t = num(lay.t)?;
            let a = [num(lay.acc[0])?, num(lay.acc[1])?, num(lay.acc[2])?];
            let w = [num(lay.gyr[0])?, num(lay.gyr[1])?, num(lay.gyr[2])?];
            let g = match gt {
                Some(g) => Some([num(g[0])?, num(g[1])?, num(g[2])?]),
                None => None,
            };
            let mut l = Vec::with_capacity(label_cols.len());
            for (_, c) in &label_cols {
                l.push(num(*c)? > 0.5);
            }
            Some((t, a, w, g, l))
        })();
        last_read = row.is_some();
        let Some((t, a, w, g, l)) = row else {
            rec.unreadable_rows += 1;
            rec.first_unreadable_line.get_or_insert(ln + 2);
            continue;
        };
        rec.t_s.push(t);
        rec.accel_mps2.push(a.map(|v| v * lay.acc_scale));
        rec.gyro_rads.push(w.map(|v| v * lay.gyr_scale));
        if let (Some(g), Some(v)) = (g, rec.truth_m.as_mut()) {
            v.push(g);
        }
        for (x, (_, v)) in l.into_iter().zip(rec.labels.iter_mut()) {
            v.push(x);
        }
    }
    if rec.is_empty() {
        return Err(FormatError::Empty);
    }
    rec.truncated = crate::sniff::cut_mid_row(text, last_read);
    Ok(rec)
}

/// The trial CSVs of a folder (files not starting with `_`), sorted by name.
pub fn list_foot_trials(dir: &Path) -> Result<Vec<PathBuf>, FormatError> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension().is_some_and(|e| e == "csv")
                && !p
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with('_'))
        })
        .collect();
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_an_xio_export_with_repeated_rows() {
        let text = "Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g),Magnetometer X (uT),Magnetometer Y (uT),Magnetometer Z (uT),Barometer (hPa)\r\n\
0,180,-90,0,0,0,1,1,2,3,1000\r\n\
0.0025,0,0,0,0.5,0,1,1,2,3,1000\r\n\
0.0025,0,0,0,0.5,0,1,1,2,3,1000\r\n\
0.005,1,2\r\n";
        let r = parse_foot_csv(text, "walk".into()).unwrap();
        assert_eq!(r.format, FootFormat::Xio);
        assert_eq!(r.t_s, [0.0, 0.0025, 0.0025]);
        assert!((r.gyro_rads[0][0] - std::f64::consts::PI).abs() < 1e-12);
        assert!((r.gyro_rads[0][1] + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(r.accel_mps2[1], [0.5 * G_MPS2, 0.0, G_MPS2]);
        assert!(r.truth_m.is_none());
        assert_eq!(r.unreadable_rows, 1);
        assert_eq!(r.first_unreadable_line, Some(5));
        assert!(!r.truncated, "a short row with its line end is not a cut");
        let cut = parse_foot_csv(text.trim_end(), "walk".into()).unwrap();
        assert!(cut.truncated);
    }

    #[test]
    fn reads_the_pyshoe_layout_in_any_column_order() {
        let text = "gyr_x_rads,gyr_y_rads,gyr_z_rads,t_s,acc_x_mps2,acc_y_mps2,acc_z_mps2,gt_x_m,gt_y_m,gt_z_m,zv_shoe_opt\n\
0.1,0.2,0.3,0.0,1,2,-9.8,5,6,7,1\n\
0.1,0.2,0.3,0.005,1,2,NaN,5,6,7,0\n";
        let r = parse_foot_csv(text, "t".into()).unwrap();
        assert_eq!(r.format, FootFormat::Pyshoe);
        assert_eq!(r.t_s, [0.0, 0.005]);
        assert_eq!(r.gyro_rads[0], [0.1, 0.2, 0.3]);
        assert_eq!(r.accel_mps2[0], [1.0, 2.0, -9.8]);
        // NaN is a number for the reader: the navigator rejects it.
        assert!(r.accel_mps2[1][2].is_nan());
        assert_eq!(r.truth_m.as_ref().unwrap()[1], [5.0, 6.0, 7.0]);
        assert_eq!(r.label("shoe_opt"), Some(&[true, false][..]));
        assert_eq!(r.unreadable_rows, 0);
    }

    #[test]
    fn an_unknown_header_is_a_typed_error() {
        assert!(matches!(
            parse_foot_csv("a,b,c\n1,2,3\n", "x".into()),
            Err(FormatError::Parse { .. })
        ));
        assert!(matches!(
            parse_foot_csv("t_s,acc_x_mps2\n1,2\n", "x".into()),
            Err(FormatError::MissingColumn(_))
        ));
        assert!(matches!(
            parse_foot_csv("t_s,acc_x_mps2,acc_y_mps2,acc_z_mps2,gyr_x_rads,gyr_y_rads,gyr_z_rads\nx,1,2,3,4,5,6\n", "x".into()),
            Err(FormatError::Empty)
        ));
    }
}
