//! What a file holds, told from its first bytes: the readers choose by content, the
//! file name is only a hint where the content does not say (an Oxford CSV renamed
//! `my_walk.csv` is still read). Missing paths and folders get their own errors.
//!
//! Rules, in order, on the first [`HEAD_BYTES`] (decompressed when the file is
//! gzip, told by its magic bytes `1f 8b`, not by `.gz`):
//!
//! - bytes 8..12 `.FIT` → FIT;
//! - a document starting with `<` → TCX (`<TrainingCenterDatabase`) or GPX (`<gpx`);
//! - a line whose second whitespace-separated field starts with `TYPE_` → Android
//!   sensor log;
//! - the first line not starting with `#`, as a CSV header, by its column names:
//!   `t_s`/`t_unix_s` + `lat_deg` + `lon_deg` → activity CSV; `Time (s)` +
//!   `Gyroscope X (deg/s)` → x-io foot CSV; `t_s` + `acc_x_mps2` + `gyr_x_rads` →
//!   BROAD when it also has `mag_x_ut` or `opt_qw`, else pyshoe foot CSV;
//!   `acce_x` with `time_s` → RoNIN export, with `time` → RIDI;
//! - rows of numbers without a header: five (ns, accuracy, ax, ay, az) → Oxford
//!   `accelerometer.csv`, three (ns, 0/1, 0/1) → Oxford `stepcounter.csv`.

use std::io::Read;
use std::path::Path;

use crate::foot::FootFormat;
use crate::FormatError;

/// How much of a file the sniffer reads, bytes (decompressed).
pub const HEAD_BYTES: usize = 64 * 1024;
/// Lines of the head looked at for an Android event type.
const SNIFF_LINES: usize = 64;

/// What a file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Content {
    /// Garmin FIT.
    Fit,
    /// Garmin Training Center XML.
    Tcx,
    /// GPS Exchange Format.
    Gpx,
    /// The activity CSV of `read_csv` (`t_s`, `lat_deg`, `lon_deg`, …).
    ActivityCsv,
    /// An Android sensor log (`TYPE_…` events).
    AndroidLog,
    /// An Oxford Step Counter `accelerometer.csv` (ns, accuracy, ax, ay, az).
    OxfordAccel,
    /// An Oxford Step Counter `stepcounter.csv` (ns, foot 1, foot 2).
    OxfordSteps,
    /// A foot-mounted IMU CSV.
    Foot(FootFormat),
    /// A BROAD orientation trial (IMU, magnetometer, optical truth).
    Broad,
    /// A RIDI `data.csv`.
    Ridi,
    /// A RoNIN CSV export.
    Ronin,
    /// None of the above.
    Unknown,
}

impl Content {
    /// What the content is, for messages.
    pub fn name(self) -> &'static str {
        match self {
            Content::Fit => "FIT activity file",
            Content::Tcx => "TCX activity file",
            Content::Gpx => "GPX track",
            Content::ActivityCsv => "activity CSV (t_s, lat_deg, lon_deg, …)",
            Content::AndroidLog => "Android sensor log",
            Content::OxfordAccel => "Oxford Step Counter accelerometer.csv",
            Content::OxfordSteps => "Oxford Step Counter stepcounter.csv (reference steps)",
            Content::Foot(FootFormat::Pyshoe) => "foot IMU CSV (pyshoe / UofT layout)",
            Content::Foot(FootFormat::Xio) => "foot IMU CSV (x-io NGIMU export)",
            Content::Broad => "BROAD orientation trial",
            Content::Ridi => "RIDI data.csv",
            Content::Ronin => "RoNIN CSV export",
            Content::Unknown => "file of no format stridekit reads",
        }
    }

    /// The activity formats `read_activity` reads.
    pub fn is_activity(self) -> bool {
        matches!(
            self,
            Content::Fit | Content::Tcx | Content::Gpx | Content::ActivityCsv
        )
    }
}

/// A file's content and whether it is gzip-compressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sniffed {
    pub content: Content,
    pub gzip: bool,
}

/// Fails with [`FormatError::Missing`] or [`FormatError::Folder`] unless `path` is a
/// file (or a link to one).
pub fn check_file(path: &Path) -> Result<(), FormatError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(FormatError::Folder),
        Ok(_) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(FormatError::Missing),
        Err(e) => Err(FormatError::Io(e)),
    }
}

/// What the file at `path` holds (see the module docs).
pub fn sniff(path: &Path) -> Result<Sniffed, FormatError> {
    check_file(path)?;
    let mut raw = Vec::with_capacity(HEAD_BYTES);
    std::fs::File::open(path)?
        .take(HEAD_BYTES as u64)
        .read_to_end(&mut raw)?;
    let gzip = is_gzip(&raw);
    let head = if gzip { gunzip_head(path)? } else { raw };
    Ok(Sniffed {
        content: sniff_bytes(&head),
        gzip,
    })
}

/// Whether `bytes` start with the gzip magic number.
pub fn is_gzip(bytes: &[u8]) -> bool {
    bytes.starts_with(&[0x1f, 0x8b])
}

/// Whether the file at `path` is gzip-compressed (by its first two bytes).
pub(crate) fn file_is_gzip(path: &Path) -> Result<bool, FormatError> {
    let mut magic = Vec::with_capacity(2);
    std::fs::File::open(path)?.take(2).read_to_end(&mut magic)?;
    Ok(is_gzip(&magic))
}

/// Up to [`HEAD_BYTES`] of a gzip file, decompressed; a stream cut short gives what
/// it held.
fn gunzip_head(path: &Path) -> Result<Vec<u8>, FormatError> {
    let mut out = Vec::with_capacity(HEAD_BYTES);
    let gz = flate2::read::GzDecoder::new(std::fs::File::open(path)?);
    match gz.take(HEAD_BYTES as u64).read_to_end(&mut out) {
        Ok(_) => Ok(out),
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(out),
        Err(e) => Err(e.into()),
    }
}

/// What the first bytes of a file say it holds (see the module docs).
pub fn sniff_bytes(head: &[u8]) -> Content {
    if head.len() >= 12 && &head[8..12] == b".FIT" {
        return Content::Fit;
    }
    let text = String::from_utf8_lossy(head);
    let text = text.trim_start_matches('\u{feff}').trim_start();
    if text.starts_with('<') {
        return if text.contains("<TrainingCenterDatabase") {
            Content::Tcx
        } else if text.contains("<gpx") {
            Content::Gpx
        } else {
            Content::Unknown
        };
    }
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .take(SNIFF_LINES)
        .collect();
    let data = || lines.iter().filter(|l| !l.starts_with('#'));
    if data().any(|l| {
        l.split_whitespace()
            .nth(1)
            .is_some_and(|kind| kind.starts_with("TYPE_"))
    }) {
        return Content::AndroidLog;
    }
    match data().next() {
        Some(first) => from_first_row(first),
        None => Content::Unknown,
    }
}

/// The content told by the first row of a CSV: a header's column names, or numbers.
fn from_first_row(row: &str) -> Content {
    let cells: Vec<&str> = row
        .split(',')
        .map(|c| c.trim().trim_matches('"').trim())
        .collect();
    let has = |name: &str| cells.iter().any(|c| c.eq_ignore_ascii_case(name));
    if (has("t_s") || has("t_unix_s")) && has("lat_deg") && has("lon_deg") {
        return Content::ActivityCsv;
    }
    if has("Time (s)") && has("Gyroscope X (deg/s)") {
        return Content::Foot(FootFormat::Xio);
    }
    if has("t_s") && has("acc_x_mps2") && has("gyr_x_rads") {
        return if has("mag_x_ut") || has("opt_qw") {
            Content::Broad
        } else {
            Content::Foot(FootFormat::Pyshoe)
        };
    }
    if has("acce_x") && has("time_s") {
        return Content::Ronin;
    }
    if has("acce_x") && has("time") {
        return Content::Ridi;
    }
    if cells.iter().all(|c| c.parse::<f64>().is_ok()) {
        return match cells.len() {
            5 => Content::OxfordAccel,
            3 => Content::OxfordSteps,
            _ => Content::Unknown,
        };
    }
    Content::Unknown
}

/// The text ends inside a row: its last line has no line end and `last_row_read` is
/// false (the reader could not read it). A file cut exactly at a line end cannot be
/// told from a whole one by this test.
pub(crate) fn cut_mid_row(text: &str, last_row_read: bool) -> bool {
    let body = text.trim_end_matches([' ', '\t']);
    !body.is_empty() && !body.ends_with('\n') && !last_row_read
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_content_decides() {
        let fit = [14u8, 0x10, 0, 0, 0, 0, 0, 0, b'.', b'F', b'I', b'T', 0, 0];
        assert_eq!(sniff_bytes(&fit), Content::Fit);
        assert_eq!(
            sniff_bytes(b"\xef\xbb\xbf <?xml version=\"1.0\"?>\n<TrainingCenterDatabase>"),
            Content::Tcx
        );
        assert_eq!(sniff_bytes(b"<?xml?><gpx version=\"1.1\">"), Content::Gpx);
        assert_eq!(
            sniff_bytes(b"#\tstartTime:1\n1000\tTYPE_ACCELEROMETER\t0\t0\t9.8\n"),
            Content::AndroidLog
        );
        assert_eq!(
            sniff_bytes(b"# note\nT_S, lat_deg, lon_deg\n1,2,3\n"),
            Content::ActivityCsv
        );
        assert_eq!(
            sniff_bytes(b"263239144953734,2,1.94,5.16,10.16\n263239149989134,2,1.5,4.9,9.8\n"),
            Content::OxfordAccel
        );
        assert_eq!(sniff_bytes(b"1,0,1\n2,1,0\n"), Content::OxfordSteps);
        assert_eq!(
            sniff_bytes(
                b"t_s,acc_x_mps2,acc_y_mps2,acc_z_mps2,gyr_x_rads,gyr_y_rads,gyr_z_rads,gt_x_m\n"
            ),
            Content::Foot(FootFormat::Pyshoe)
        );
        assert_eq!(
            sniff_bytes(b"t_s,gyr_x_rads,acc_x_mps2,mag_x_ut,opt_qw\n"),
            Content::Broad
        );
        assert_eq!(
            sniff_bytes(b"Time (s),Gyroscope X (deg/s),Accelerometer X (g)\n"),
            Content::Foot(FootFormat::Xio)
        );
        assert_eq!(sniff_bytes(b"time_s,acce_x\n"), Content::Ronin);
        assert_eq!(sniff_bytes(b"time,acce_x\n"), Content::Ridi);
        assert_eq!(sniff_bytes(b"hello world\n"), Content::Unknown);
        assert_eq!(sniff_bytes(b""), Content::Unknown);
    }

    #[test]
    fn folders_missing_paths_and_gzip() {
        use std::io::Write;
        let dir = std::env::temp_dir().join(format!("stridekit-sniff-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(matches!(sniff(&dir), Err(FormatError::Folder)));
        assert!(matches!(
            sniff(&dir.join("nothing.csv")),
            Err(FormatError::Missing)
        ));
        // A gzip file named .csv: told by its magic bytes.
        let path = dir.join("walk.csv");
        let mut gz = flate2::write::GzEncoder::new(
            std::fs::File::create(&path).unwrap(),
            flate2::Compression::fast(),
        );
        gz.write_all(b"1000\tTYPE_GYROSCOPE\t0\t0\t0\n").unwrap();
        gz.finish().unwrap();
        let s = sniff(&path).unwrap();
        assert_eq!((s.content, s.gzip), (Content::AndroidLog, true));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_row_cut_mid_write() {
        assert!(cut_mid_row("a,b\n1,2\n3,", false));
        assert!(!cut_mid_row("a,b\n1,2\n3,4", true));
        assert!(!cut_mid_row("a,b\n1,2\ngarbage\n", false));
        assert!(!cut_mid_row("", false));
    }
}
