//! Reader for the Oxford Step Counter data set (Salvi et al., 2018, CC BY 4.0): one
//! folder per trace named `<Phone>_<User>_<Surface>_<Position>_<n>`, holding
//! `accelerometer.csv` (no header: timestamp ns since boot, accuracy flag, ax, ay, az in
//! m/s², gravity included) and `stepcounter.csv` (no header: timestamp ns, foot-1
//! contact, foot-2 contact as 0/1 from a shoe-worn reference). Every 0→1 transition in
//! either contact column is one heel strike; the first row only sets the initial state
//! (this reproduces the totals of the set's `_stats.csv` exactly).

use std::path::{Path, PathBuf};

use crate::error::{FormatError, Unreadable};

const FORMAT: &str = "Oxford";

/// Where the phone was carried (folder-name spelling variants are normalised:
/// `ArmBand`/`Armband`, `Backpocket`/`BackPocket`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OxfordPosition {
    InHand,
    FrontPocket,
    BackPocket,
    Purse,
    NeckPouch,
    Armband,
    SwingingArm,
    /// A folder whose name does not follow the set's `<Phone>_<User>_<Surface>_<Position>_<n>`
    /// with one of the positions above (a recording of your own, renamed traces): the
    /// trace is read all the same. Not in [`OxfordPosition::ALL`].
    Other,
}

impl OxfordPosition {
    /// All positions, in the order tables list them.
    pub const ALL: [OxfordPosition; 7] = [
        OxfordPosition::InHand,
        OxfordPosition::FrontPocket,
        OxfordPosition::BackPocket,
        OxfordPosition::Purse,
        OxfordPosition::NeckPouch,
        OxfordPosition::Armband,
        OxfordPosition::SwingingArm,
    ];

    /// Parses a folder-name token, ignoring case.
    pub fn parse(token: &str) -> Option<Self> {
        let t = token.to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|p| p.name().to_ascii_lowercase() == t)
    }

    /// Canonical name.
    pub fn name(self) -> &'static str {
        match self {
            OxfordPosition::InHand => "InHand",
            OxfordPosition::FrontPocket => "FrontPocket",
            OxfordPosition::BackPocket => "BackPocket",
            OxfordPosition::Purse => "Purse",
            OxfordPosition::NeckPouch => "NeckPouch",
            OxfordPosition::Armband => "Armband",
            OxfordPosition::SwingingArm => "SwingingArm",
            OxfordPosition::Other => "Other",
        }
    }
}

impl std::fmt::Display for OxfordPosition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One accelerometer sample: time in seconds since boot, acceleration in m/s².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OxfordAccel {
    pub t_s: f64,
    pub accel_mps2: [f64; 3],
}

/// One trace of the set.
#[derive(Clone, Debug, PartialEq)]
pub struct OxfordTrace {
    /// Folder name, e.g. `Pixel_Jamie_Hard_InHand_1`.
    pub name: String,
    pub phone: String,
    pub user: String,
    /// `Hard` or `Carpet`.
    pub surface: String,
    pub position: OxfordPosition,
    /// Accelerometer samples in time order (rows with non-finite values or a timestamp
    /// not after the previous one are dropped).
    pub accel: Vec<OxfordAccel>,
    /// Reference heel-strike times, seconds since boot (same clock as `accel`).
    pub heel_strikes_t_s: Vec<f64>,
}

impl OxfordTrace {
    /// Mean accelerometer rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        match (self.accel.first(), self.accel.last()) {
            (Some(a), Some(b)) if b.t_s > a.t_s => (self.accel.len() - 1) as f64 / (b.t_s - a.t_s),
            _ => f64::NAN,
        }
    }
}

/// The five `_`-separated parts of `<Phone>_<User>_<Surface>_<Position>_<n>`.
fn name_parts(name: &str) -> Option<[&str; 5]> {
    name.split('_').collect::<Vec<&str>>().try_into().ok()
}

/// Parses `<Phone>_<User>_<Surface>_<Position>_<n>`.
fn parse_name(name: &str) -> Result<(String, String, String, OxfordPosition), FormatError> {
    let parts = name_parts(name).ok_or_else(|| {
        FormatError::parse(
            FORMAT,
            format!("folder name {name:?} is not <Phone>_<User>_<Surface>_<Position>_<n>"),
        )
    })?;
    let position = OxfordPosition::parse(parts[3]).ok_or_else(|| {
        FormatError::parse(
            FORMAT,
            format!("unknown position {:?} in {name:?}", parts[3]),
        )
    })?;
    Ok((
        parts[0].to_string(),
        parts[1].to_string(),
        parts[2].to_string(),
        position,
    ))
}

fn field<'a>(
    it: &mut impl Iterator<Item = &'a str>,
    file: &str,
    line: usize,
) -> Result<&'a str, FormatError> {
    it.next()
        .map(str::trim)
        .ok_or_else(|| FormatError::parse(FORMAT, format!("{file} line {line}: too few columns")))
}

fn number<T: std::str::FromStr>(s: &str, file: &str, line: usize) -> Result<T, FormatError> {
    s.parse()
        .map_err(|_| FormatError::parse(FORMAT, format!("{file} line {line}: bad number {s:?}")))
}

/// Reads one trace folder.
pub fn read_oxford_trace(dir: &Path) -> Result<OxfordTrace, FormatError> {
    let name = dir
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    // A name outside the set's pattern is not an error: the samples and the reference
    // are what count; phone, user and surface are then "?" and the position Other.
    let (phone, user, surface, position) = parse_name(&name).unwrap_or_else(|_| {
        let [phone, user, surface, ..] = name_parts(&name).unwrap_or(["?"; 5]);
        (
            phone.to_string(),
            user.to_string(),
            surface.to_string(),
            OxfordPosition::Other,
        )
    });

    let text = std::fs::read_to_string(dir.join("accelerometer.csv"))?;
    let mut accel: Vec<OxfordAccel> = Vec::with_capacity(text.len() / 40);
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let mut it = line.split(',');
        let t_ns: i64 = number(
            field(&mut it, "accelerometer.csv", i + 1)?,
            "accelerometer.csv",
            i + 1,
        )?;
        let _accuracy = field(&mut it, "accelerometer.csv", i + 1)?;
        let mut a = [0.0f64; 3];
        for v in &mut a {
            *v = number(
                field(&mut it, "accelerometer.csv", i + 1)?,
                "accelerometer.csv",
                i + 1,
            )?;
        }
        let t_s = t_ns as f64 * 1e-9;
        let ok = a.iter().all(|v| v.is_finite()) && accel.last().is_none_or(|p| t_s > p.t_s);
        if ok {
            accel.push(OxfordAccel { t_s, accel_mps2: a });
        }
    }
    if accel.is_empty() {
        return Err(FormatError::Empty);
    }

    let text = std::fs::read_to_string(dir.join("stepcounter.csv"))?;
    let mut heel_strikes_t_s = Vec::new();
    let mut prev: Option<(u8, u8)> = None;
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let mut it = line.split(',');
        let t_ns: i64 = number(
            field(&mut it, "stepcounter.csv", i + 1)?,
            "stepcounter.csv",
            i + 1,
        )?;
        let f1: u8 = number(
            field(&mut it, "stepcounter.csv", i + 1)?,
            "stepcounter.csv",
            i + 1,
        )?;
        let f2: u8 = number(
            field(&mut it, "stepcounter.csv", i + 1)?,
            "stepcounter.csv",
            i + 1,
        )?;
        if let Some((p1, p2)) = prev {
            let t_s = t_ns as f64 * 1e-9;
            if f1 == 1 && p1 == 0 {
                heel_strikes_t_s.push(t_s);
            }
            if f2 == 1 && p2 == 0 {
                heel_strikes_t_s.push(t_s);
            }
        }
        prev = Some((f1, f2));
    }
    Ok(OxfordTrace {
        name,
        phone,
        user,
        surface,
        position,
        accel,
        heel_strikes_t_s,
    })
}

/// The rows of an Oxford-format `accelerometer.csv` as recorded
/// ([`read_oxford_accel_raw`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OxfordAccelRows {
    /// Samples in file order.
    pub samples: Vec<OxfordAccel>,
    /// Rows that are not a timestamp, an accuracy flag and three numbers (a header, a
    /// truncated last line, garbage), skipped.
    pub unreadable: Unreadable,
    /// The file ends inside a row: it was cut off mid-write (the rows before the cut
    /// are read).
    pub truncated: bool,
}

/// Every row of an Oxford-format `accelerometer.csv` (no header: timestamp ns, accuracy
/// flag, ax, ay, az in m/s²) in file order, as recorded: unlike [`read_oxford_trace`],
/// rows with non-finite values or timestamps that repeat or go backwards are kept, so
/// a replay can skip and count them. A row that is not five numbers is skipped and
/// counted; a file with no readable row is [`FormatError::Empty`]; a file that ends
/// inside a row is flagged [`OxfordAccelRows::truncated`].
pub fn read_oxford_accel_raw(path: &Path) -> Result<OxfordAccelRows, FormatError> {
    crate::sniff::check_file(path)?;
    let text = std::fs::read_to_string(path)?;
    let file = "accelerometer.csv";
    let mut out = OxfordAccelRows {
        samples: Vec::with_capacity(text.len() / 40),
        ..Default::default()
    };
    let mut last_read = true;
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let row = || -> Result<OxfordAccel, FormatError> {
            let mut it = line.split(',');
            let t_ns: i64 = number(field(&mut it, file, i + 1)?, file, i + 1)?;
            let _accuracy = field(&mut it, file, i + 1)?;
            let mut a = [0.0f64; 3];
            for v in &mut a {
                *v = number(field(&mut it, file, i + 1)?, file, i + 1)?;
            }
            Ok(OxfordAccel {
                t_s: t_ns as f64 * 1e-9,
                accel_mps2: a,
            })
        };
        last_read = match row() {
            Ok(a) => {
                out.samples.push(a);
                true
            }
            Err(_) => {
                out.unreadable.add(i + 1);
                false
            }
        };
    }
    if out.samples.is_empty() {
        return Err(FormatError::Empty);
    }
    out.truncated = crate::sniff::cut_mid_row(&text, last_read);
    Ok(out)
}

/// Trace folders under `root` (those holding an `accelerometer.csv`), sorted by name.
pub fn list_oxford_traces(root: &Path) -> Result<Vec<PathBuf>, FormatError> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("accelerometer.csv").is_file())
        .collect();
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names_and_spelling_variants() {
        let (phone, user, surface, pos) = parse_name("Samsung_Dario_Hard_ArmBand_1").unwrap();
        assert_eq!(
            (phone.as_str(), user.as_str(), surface.as_str()),
            ("Samsung", "Dario", "Hard")
        );
        assert_eq!(pos, OxfordPosition::Armband);
        assert_eq!(
            parse_name("X_Y_Hard_Backpocket_2").unwrap().3,
            OxfordPosition::BackPocket
        );
        assert!(parse_name("X_Y_Hard_Pocket_2").is_err());
        assert!(parse_name("nonsense").is_err());
    }
}
