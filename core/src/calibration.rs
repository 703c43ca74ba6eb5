//! The text form shared by the personal calibrations a user carries between sessions
//! ([`crate::pdr::PdrCalibration`], [`crate::pace::PaceCalibration`]): a first line
//! `MAGIC VERSION`, `#` comment lines anywhere, one record per line (a name and its
//! fields separated by white space), numbers written as shortest round-trip floats so
//! that writing then reading is exact. Each calibration names its records; this module
//! checks the size, the first line and the numbers, with typed errors.

use std::fmt::Write as _;

/// Largest calibration text accepted, bytes.
pub const MAX_CALIBRATION_BYTES: usize = 64 * 1024;
/// Most lines accepted (comments included).
pub const MAX_CALIBRATION_LINES: usize = 1000;

/// Why a calibration text or record was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CalibrationError {
    #[error("calibration text is {bytes} bytes, more than the {max} accepted")]
    TooLarge { bytes: usize, max: usize },
    #[error("calibration text has more than {max} lines")]
    TooManyLines { max: usize },
    #[error("not a {expected} file (first line {found:?})")]
    NotCalibration {
        /// The first word the text should start with.
        expected: &'static str,
        found: String,
    },
    #[error("calibration format version {found} is not supported (this build reads {supported})")]
    Version { found: String, supported: u32 },
    #[error("calibration line {line}: {reason}")]
    Line { line: usize, reason: String },
    #[error("calibration has no {0} record")]
    Missing(&'static str),
    #[error("calibration value {field} is not valid: {reason}")]
    Invalid { field: &'static str, reason: String },
}

/// The first line and the comments of a calibration text.
pub(crate) fn header(magic: &str, version: u32, comments: &[String]) -> String {
    let mut s = format!("{magic} {version}\n");
    for c in comments {
        for line in c.lines() {
            let _ = writeln!(s, "# {line}");
        }
    }
    s
}

/// One record line: its number (1-based) and its fields, the record's name first.
pub(crate) struct Record<'a> {
    pub line: usize,
    pub fields: Vec<&'a str>,
}

impl Record<'_> {
    pub fn name(&self) -> &str {
        self.fields[0]
    }

    /// An error about this line.
    pub fn error(&self, reason: impl Into<String>) -> CalibrationError {
        CalibrationError::Line {
            line: self.line,
            reason: reason.into(),
        }
    }

    /// Field `i` as a finite number.
    pub fn number(&self, i: usize) -> Result<f64, CalibrationError> {
        let s = self.fields.get(i).copied().unwrap_or("");
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(format!("{:?} is not a finite number", truncate(s)))),
        }
    }

    /// An error unless the record has exactly `n` fields (its name included).
    pub fn expect_fields(&self, n: usize, layout: &str) -> Result<(), CalibrationError> {
        if self.fields.len() == n {
            Ok(())
        } else {
            Err(self.error(format!("expected: {layout}")))
        }
    }
}

/// The record lines of a calibration text after checking its size and first line
/// (`magic version`); comments and blank lines are left out.
pub(crate) fn records<'a>(
    text: &'a str,
    magic: &'static str,
    version: u32,
) -> Result<Vec<Record<'a>>, CalibrationError> {
    if text.len() > MAX_CALIBRATION_BYTES {
        return Err(CalibrationError::TooLarge {
            bytes: text.len(),
            max: MAX_CALIBRATION_BYTES,
        });
    }
    let mut lines = text.lines().enumerate();
    let first = lines.next().map(|(_, l)| l.trim()).unwrap_or("");
    let mut head = first.split_whitespace();
    if head.next() != Some(magic) {
        return Err(CalibrationError::NotCalibration {
            expected: magic,
            found: first.chars().take(60).collect(),
        });
    }
    let found = head.next().unwrap_or("");
    if found != version.to_string() || head.next().is_some() {
        return Err(CalibrationError::Version {
            found: found.chars().take(20).collect(),
            supported: version,
        });
    }
    let mut out = Vec::new();
    for (i, raw) in lines {
        let line = i + 1;
        if line > MAX_CALIBRATION_LINES {
            return Err(CalibrationError::TooManyLines {
                max: MAX_CALIBRATION_LINES,
            });
        }
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        out.push(Record {
            line,
            fields: l.split_whitespace().collect(),
        });
    }
    Ok(out)
}

/// At most 40 characters of `s`, for error messages.
pub(crate) fn truncate(s: &str) -> String {
    s.chars().take(40).collect()
}
