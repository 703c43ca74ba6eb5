//! Reader for the BROAD orientation benchmark as converted to CSV (Laidig, Caruso,
//! Cereatti, Seel, "BROAD — A Benchmark for Robust Inertial Orientation Estimation",
//! Data 6(7), 2021; `../shared/data/orientation/broad/`, one `.csv.gz` per trial).
//!
//! Columns (order free, unknown columns ignored): `t_s`; `gyr_x_rads gyr_y_rads
//! gyr_z_rads` (rad/s); `acc_x_mps2 acc_y_mps2 acc_z_mps2` (specific force, gravity
//! included); `mag_x_ut mag_y_ut mag_z_ut` (µT); `opt_qw opt_qx opt_qy opt_qz`
//! (optical orientation, sensor → East-North-Up, empty where the markers were
//! occluded); `movement` (1 in the phases the benchmark scores).
//!
//! A gzip file (told by its magic bytes) is decompressed on the fly. A file that ends
//! inside a row, or a gzip stream cut short, was cut off mid-write: the rows before
//! the cut are read and [`OrientationRecording::truncated`] says so. An empty sensor
//! cell reads as NaN (the
//! engine then rejects that one sample and a replay counts it); empty truth cells
//! give `None`. A row with text that is not a number, too few cells or no time is
//! skipped and counted (`unreadable`); a file with no
//! readable row is the first row's typed [`FormatError::Parse`] naming the line.

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use crate::error::{FormatError, Unreadable};
use crate::inertial::{Columns, InertialSample};

const FORMAT: &str = "BROAD CSV";

/// One BROAD trial: IMU samples (sensor axes) and, per sample, the optical truth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OrientationRecording {
    /// File name without `.csv` / `.csv.gz`, e.g. `01_undisturbed_slow_rotation_A`.
    pub name: String,
    /// Gyroscope, accelerometer and magnetometer per sample (`mag_ut` is `None` when
    /// the file has no magnetometer columns).
    pub samples: Vec<InertialSample>,
    /// Optical orientation per sample, `[w, x, y, z]`, sensor → ENU; `None` where the
    /// markers were occluded (or the file has no truth columns).
    pub truth: Vec<Option<[f64; 4]>>,
    /// Per sample: inside a scored movement phase (all `true` without the column).
    pub movement: Vec<bool>,
    /// Rows that could not be read (too few cells, text where a number belongs, no
    /// time), skipped.
    pub unreadable: Unreadable,
    /// The file was cut off mid-write (it ends inside a row, or its gzip stream ends
    /// early); the rows before the cut are read.
    pub truncated: bool,
}

impl OrientationRecording {
    pub fn len(&self) -> usize {
        self.samples.len()
    }
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }
    /// The trial number at the start of the name (`"01_…"` → 1), if any.
    pub fn trial_number(&self) -> Option<u32> {
        let digits: String = self.name.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().ok()
    }
}

/// Reads one trial (`.csv` or `.csv.gz`).
pub fn read_broad(path: &Path) -> Result<OrientationRecording, FormatError> {
    crate::sniff::check_file(path)?;
    let gz = crate::sniff::file_is_gzip(path)?;
    let file = std::fs::File::open(path)?;
    let reader: Box<dyn Read> = if gz {
        Box::new(flate2::read::GzDecoder::new(file))
    } else {
        Box::new(file)
    };
    let mut rec = parse_broad(BufReader::new(reader))?;
    rec.name = trial_name(path);
    Ok(rec)
}

/// Parses BROAD CSV text from any buffered reader (the name is left empty).
pub fn parse_broad(mut input: impl BufRead) -> Result<OrientationRecording, FormatError> {
    let mut header = String::new();
    if input.read_line(&mut header)? == 0 {
        return Err(FormatError::Empty);
    }
    let layout = Layout::of(&header)?;
    let mut rec = OrientationRecording::default();
    let mut first_error = None;
    let mut text = String::new();
    let mut line_no = 1;
    loop {
        text.clear();
        match input.read_line(&mut text) {
            Ok(0) => break,
            Ok(_) => {}
            // A gzip stream cut short: the rows before the cut are read.
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                rec.truncated = true;
                break;
            }
            Err(e) => return Err(e.into()),
        }
        line_no += 1;
        let line = text.trim_end_matches(['\r', '\n']);
        if line.trim().is_empty() {
            continue;
        }
        // A row that cannot be read (too few cells, text, no time: a truncated last
        // line) is skipped and counted, not fatal.
        match layout.row(line, line_no) {
            Ok((sample, truth, moving)) => {
                rec.samples.push(sample);
                rec.truth.push(truth);
                rec.movement.push(moving);
            }
            Err(e) => {
                rec.unreadable.add(line_no);
                first_error.get_or_insert(e);
                rec.truncated |= !text.ends_with('\n');
            }
        }
    }
    if let (true, Some(e)) = (rec.samples.is_empty(), first_error) {
        return Err(e);
    }
    if rec.samples.is_empty() {
        return Err(FormatError::Empty);
    }
    Ok(rec)
}

/// One row as read: the sample, the optical truth (None where occluded) and whether
/// it lies in a movement phase.
type Row = (InertialSample, Option<[f64; 4]>, bool);

/// Where each quantity sits in a BROAD file's rows, from its header.
struct Layout {
    t: usize,
    gyr: [usize; 3],
    acc: [usize; 3],
    mag: Option<[usize; 3]>,
    opt: Option<[usize; 4]>,
    movement: Option<usize>,
    width: usize,
}

impl Layout {
    fn of(header: &str) -> Result<Self, FormatError> {
        let c = Columns(header.trim_end().split(',').map(str::trim).collect());
        let three = |x: &'static str,
                     y: &'static str,
                     z: &'static str|
         -> Result<[usize; 3], FormatError> {
            Ok([c.get(x)?, c.get(y)?, c.get(z)?])
        };
        let mag = match (c.opt("mag_x_ut"), c.opt("mag_y_ut"), c.opt("mag_z_ut")) {
            (Some(x), Some(y), Some(z)) => Some([x, y, z]),
            _ => None,
        };
        let opt = match (
            c.opt("opt_qw"),
            c.opt("opt_qx"),
            c.opt("opt_qy"),
            c.opt("opt_qz"),
        ) {
            (Some(w), Some(x), Some(y), Some(z)) => Some([w, x, y, z]),
            _ => None,
        };
        Ok(Layout {
            t: c.get("t_s")?,
            gyr: three("gyr_x_rads", "gyr_y_rads", "gyr_z_rads")?,
            acc: three("acc_x_mps2", "acc_y_mps2", "acc_z_mps2")?,
            mag,
            opt,
            movement: c.opt("movement"),
            width: c.0.len(),
        })
    }

    /// One data line (`line_no` for messages).
    fn row(&self, line: &str, line_no: usize) -> Result<Row, FormatError> {
        let cells = Cells::split(line, line_no, self.width)?;
        let t_s = cells
            .get(self.t)?
            .ok_or_else(|| FormatError::parse(FORMAT, format!("line {line_no}: empty t_s")))?;
        let sample = InertialSample {
            t_s,
            gyro_rads: cells.sensor(self.gyr)?,
            accel_mps2: cells.sensor(self.acc)?,
            mag_ut: self.mag.map(|m| cells.sensor(m)).transpose()?,
        };
        let truth = match self.opt {
            Some(q) => cells.quaternion(q)?,
            None => None,
        };
        let moving = match self.movement {
            Some(i) => cells.get(i)?.is_some_and(|v| v > 0.5),
            None => true,
        };
        Ok((sample, truth, moving))
    }
}

/// The cells of one data line.
struct Cells<'a> {
    fields: Vec<&'a str>,
    line_no: usize,
}

impl<'a> Cells<'a> {
    fn split(line: &'a str, line_no: usize, width: usize) -> Result<Self, FormatError> {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() < width {
            return Err(FormatError::parse(
                FORMAT,
                format!("line {line_no}: {} cells, header has {width}", fields.len()),
            ));
        }
        Ok(Cells { fields, line_no })
    }

    /// Empty cell → None; text that is not a number → error.
    fn get(&self, i: usize) -> Result<Option<f64>, FormatError> {
        let s = self.fields[i];
        if s.is_empty() {
            return Ok(None);
        }
        s.parse::<f64>().map(Some).map_err(|_| {
            FormatError::parse(
                FORMAT,
                format!(
                    "line {}: column {} is not a number: {s:?}",
                    self.line_no,
                    i + 1
                ),
            )
        })
    }

    /// Three axes; an empty cell is NaN (refused by the engines' door).
    fn sensor(&self, cols: [usize; 3]) -> Result<[f64; 3], FormatError> {
        let v = |i| self.get(i).map(|x| x.unwrap_or(f64::NAN));
        Ok([v(cols[0])?, v(cols[1])?, v(cols[2])?])
    }

    /// The optical quaternion, None unless all four cells are finite numbers.
    fn quaternion(&self, q: [usize; 4]) -> Result<Option<[f64; 4]>, FormatError> {
        let q = [
            self.get(q[0])?,
            self.get(q[1])?,
            self.get(q[2])?,
            self.get(q[3])?,
        ];
        Ok(match q {
            [Some(w), Some(x), Some(y), Some(z)] if [w, x, y, z].iter().all(|v| v.is_finite()) => {
                Some([w, x, y, z])
            }
            _ => None,
        })
    }
}

/// The trial files of a folder (`*.csv` / `*.csv.gz` not starting with `_`), sorted
/// by name.
pub fn list_broad_trials(dir: &Path) -> Result<Vec<PathBuf>, FormatError> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default();
            (name.ends_with(".csv") || name.ends_with(".csv.gz")) && !name.starts_with('_')
        })
        .collect();
    out.sort();
    Ok(out)
}

/// `dir/01_x.csv.gz` → `01_x`.
fn trial_name(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let lower = name.to_ascii_lowercase();
    for ext in [".csv.gz", ".csv", ".gz"] {
        if lower.ends_with(ext) {
            return name[..name.len() - ext.len()].to_string();
        }
    }
    name
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    const TEXT: &str = "\
t_s,gyr_x_rads,gyr_y_rads,gyr_z_rads,acc_x_mps2,acc_y_mps2,acc_z_mps2,mag_x_ut,mag_y_ut,mag_z_ut,opt_qw,opt_qx,opt_qy,opt_qz,movement
0.000000,0.001,-0.002,0.003,-0.23,-0.36,9.91,0.22,15.8,-38.3,0.9997327,-0.0196427,0.0121226,-0.0012889,0
0.003500,0,0,0.006,-0.23,-0.32,9.89,0.22,15.8,-38.3,,,,,1

0.007000,,0,0,0,0,9.8,1,2,3,1,0,0,0,1
";

    #[test]
    fn parses_columns_truth_gaps_and_movement() {
        let rec = parse_broad(TEXT.as_bytes()).unwrap();
        assert_eq!(rec.len(), 3);
        let s = &rec.samples[0];
        assert_eq!(s.t_s, 0.0);
        assert_eq!(s.gyro_rads, [0.001, -0.002, 0.003]);
        assert_eq!(s.accel_mps2, [-0.23, -0.36, 9.91]);
        assert_eq!(s.mag_ut, Some([0.22, 15.8, -38.3]));
        assert_eq!(
            rec.truth[0],
            Some([0.9997327, -0.0196427, 0.0121226, -0.0012889])
        );
        assert_eq!(rec.truth[1], None, "occluded markers");
        assert_eq!(rec.movement, vec![false, true, true]);
        // An empty sensor cell is NaN: the engine rejects that sample, a replay
        // counts it.
        assert!(rec.samples[2].gyro_rads[0].is_nan());
        assert_eq!(rec.samples[2].t_s, 0.007);
    }

    #[test]
    fn typed_errors_name_the_problem() {
        assert!(matches!(
            parse_broad("".as_bytes()),
            Err(FormatError::Empty)
        ));
        assert!(matches!(
            parse_broad("t_s,gyr_x_rads\n".as_bytes()),
            Err(FormatError::MissingColumn("gyr_y_rads"))
        ));
        let header = TEXT.lines().next().unwrap();
        assert!(matches!(
            parse_broad(format!("{header}\n").as_bytes()),
            Err(FormatError::Empty)
        ));
        let bad = format!("{header}\n0,1,2,x,0,0,9.8,1,2,3,1,0,0,0,1\n");
        match parse_broad(bad.as_bytes()) {
            Err(FormatError::Parse { message, .. }) => {
                assert!(
                    message.contains("line 2") && message.contains("column 4"),
                    "{message}"
                )
            }
            other => panic!("{other:?}"),
        }
        let short = format!("{header}\n0,1,2\n");
        assert!(matches!(
            parse_broad(short.as_bytes()),
            Err(FormatError::Parse { .. })
        ));
        // With readable rows, the unreadable ones are skipped and counted.
        let good = TEXT.lines().nth(1).unwrap();
        let mixed = format!("{header}\n{good}\n0,1,2\n{good}\n0,1,2,x,0,0,9.8,1,2,3,1,0,0,0,1\n");
        let rec = parse_broad(mixed.as_bytes()).unwrap();
        assert_eq!(rec.len(), 2);
        assert_eq!(
            (rec.unreadable.rows, rec.unreadable.first_line),
            (2, Some(3))
        );
        // Without magnetometer, truth and movement columns: IMU only, unscored truth.
        let imu = "t_s,gyr_x_rads,gyr_y_rads,gyr_z_rads,acc_x_mps2,acc_y_mps2,acc_z_mps2\n\
                   0,0,0,0,0,0,9.8\n";
        let rec = parse_broad(imu.as_bytes()).unwrap();
        assert_eq!(rec.samples[0].mag_ut, None);
        assert_eq!(rec.truth, vec![None]);
        assert_eq!(rec.movement, vec![true]);
    }

    #[test]
    fn reads_gzip_and_plain_files_and_lists_trials() {
        let dir = std::env::temp_dir().join(format!("stridekit-broad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let gz_path = dir.join("07_undisturbed_fast_rotation_B.csv.gz");
        let mut enc = flate2::write::GzEncoder::new(
            std::fs::File::create(&gz_path).unwrap(),
            flate2::Compression::fast(),
        );
        enc.write_all(TEXT.as_bytes()).unwrap();
        enc.finish().unwrap();
        std::fs::write(dir.join("02_plain.csv"), TEXT).unwrap();
        std::fs::write(dir.join("_trials.json"), "{}").unwrap();
        let list = list_broad_trials(&dir).unwrap();
        assert_eq!(list.len(), 2);
        let a = read_broad(&list[0]).unwrap();
        let b = read_broad(&list[1]).unwrap();
        assert_eq!(a.name, "02_plain");
        assert_eq!(b.name, "07_undisturbed_fast_rotation_B");
        assert_eq!(b.trial_number(), Some(7));
        // (Compared as bits: sample 2 holds a NaN.)
        let bits = |r: &OrientationRecording| {
            r.samples
                .iter()
                .map(|s| (s.t_s.to_bits(), s.gyro_rads.map(f64::to_bits)))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(a.truth, b.truth);
        assert!(!a.truncated && !b.truncated);
        assert!(matches!(
            read_broad(&dir.join("missing.csv.gz")),
            Err(FormatError::Missing)
        ));
        // Cut off: the gzip stream ends early; a plain file ends inside a row.
        let whole = std::fs::read(&gz_path).unwrap();
        let cut = dir.join("cut.csv.gz");
        std::fs::write(&cut, &whole[..whole.len() - 12]).unwrap();
        let r = read_broad(&cut).unwrap();
        assert!(r.truncated && !r.is_empty());
        let plain = dir.join("cut.csv");
        std::fs::write(&plain, &TEXT[..TEXT.len() - 8]).unwrap();
        let r = read_broad(&plain).unwrap();
        assert!(r.truncated);
        assert_eq!(r.len(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
