//! Reader for foot-mounted IMU recordings in CSV with a header, as in the pyshoe /
//! University of Toronto VICON set (`t_s, acc_x_mps2, acc_y_mps2, acc_z_mps2,
//! gyr_x_rads, gyr_y_rads, gyr_z_rads`, optional truth `gt_x_m gt_y_m gt_z_m` and
//! optional 0/1 stance label columns `zv_*`). Column order is free; unknown columns
//! are ignored. Also lists the trials of a folder and reads its `_summary.csv`.

use std::path::{Path, PathBuf};

use crate::error::FormatError;

const FORMAT: &str = "foot CSV";

/// One foot IMU recording.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FootRecording {
    pub name: String,
    pub t_s: Vec<f64>,
    /// Specific force, m/s², sensor axes as recorded.
    pub accel_mps2: Vec<[f64; 3]>,
    /// Angular rate, rad/s, sensor axes as recorded.
    pub gyro_rads: Vec<[f64; 3]>,
    /// Truth position per sample, m, when the file has `gt_x_m gt_y_m gt_z_m`.
    pub truth_m: Option<Vec<[f64; 3]>>,
    /// Stance label columns (`zv_...`), name without the `zv_` prefix.
    pub labels: Vec<(String, Vec<bool>)>,
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

/// Reads one recording.
pub fn read_foot_csv(path: &Path) -> Result<FootRecording, FormatError> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or(FormatError::Empty)?
        .split(',')
        .map(str::trim)
        .collect();
    let col = |name: &'static str| -> Result<usize, FormatError> {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or(FormatError::MissingColumn(name))
    };
    let t = col("t_s")?;
    let acc = [col("acc_x_mps2")?, col("acc_y_mps2")?, col("acc_z_mps2")?];
    let gyr = [col("gyr_x_rads")?, col("gyr_y_rads")?, col("gyr_z_rads")?];
    let gt = match (col("gt_x_m"), col("gt_y_m"), col("gt_z_m")) {
        (Ok(x), Ok(y), Ok(z)) => Some([x, y, z]),
        _ => None,
    };
    let label_cols: Vec<(String, usize)> = header
        .iter()
        .enumerate()
        .filter_map(|(i, h)| h.strip_prefix("zv_").map(|n| (n.to_string(), i)))
        .collect();
    let mut rec = FootRecording {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        truth_m: gt.map(|_| Vec::new()),
        labels: label_cols
            .iter()
            .map(|(n, _)| (n.clone(), Vec::new()))
            .collect(),
        ..Default::default()
    };
    for (ln, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |i: usize| -> Result<f64, FormatError> {
            fields
                .get(i)
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| {
                    FormatError::parse(
                        FORMAT,
                        format!("line {}: column {} is not a number", ln + 2, i + 1),
                    )
                })
        };
        rec.t_s.push(num(t)?);
        rec.accel_mps2
            .push([num(acc[0])?, num(acc[1])?, num(acc[2])?]);
        rec.gyro_rads
            .push([num(gyr[0])?, num(gyr[1])?, num(gyr[2])?]);
        if let (Some(g), Some(v)) = (gt, rec.truth_m.as_mut()) {
            v.push([num(g[0])?, num(g[1])?, num(g[2])?]);
        }
        for ((_, c), (_, v)) in label_cols.iter().zip(rec.labels.iter_mut()) {
            v.push(num(*c)? > 0.5);
        }
    }
    if rec.is_empty() {
        return Err(FormatError::Empty);
    }
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
