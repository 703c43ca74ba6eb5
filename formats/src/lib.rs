//! Importers for real activity files: FIT, TCX, GPX and CSV; and for the recordings
//! the evaluations replay (Oxford steps, pyshoe foot, RIDI / RoNIN, BROAD orientation).
//!
//! Every reader returns the same [`Record`] list: sorted by time, with records that share a
//! timestamp merged into one (the first record wins, later ones only fill its missing
//! fields), and every number finite (NaN or infinite values become `None`).
//!
//! Cadence is always reported as `steps_per_min`, counting both feet. FIT, TCX
//! (`RunCadence`, `Cadence`) and GPX (`gpxtpx:cad`) store strides per minute (one foot), so
//! their values are doubled.

mod android;
mod broad;
mod csv;
mod data;
mod error;
mod fit;
mod foot;
mod gpx;
mod inertial;
mod oxford;
mod record;
mod ridi;
mod ronin;
mod sniff;
mod tcx;
mod xml;

use std::path::Path;

pub use crate::android::{
    android_motion_events, is_android_log, list_android_logs, parse_android_log, read_android_log,
};
pub use crate::broad::{list_broad_trials, parse_broad, read_broad, OrientationRecording};
pub use crate::csv::{read_csv, read_csv_counted};
pub use crate::data::{data_dir, DATA_ENV_VAR};
pub use crate::error::{FormatError, Unreadable};
pub use crate::fit::{read_fit, read_fit_counted};
pub use crate::foot::{list_foot_trials, parse_foot_csv, read_foot_csv, FootFormat, FootRecording};
pub use crate::gpx::{read_gpx, read_gpx_counted};
pub use crate::inertial::{
    read_inertial, read_inertial_dir, InertialRecording, InertialSample, Uncalibrated,
};
pub use crate::oxford::{
    list_oxford_traces, read_oxford_accel_raw, read_oxford_trace, OxfordAccel, OxfordAccelRows,
    OxfordPosition, OxfordTrace,
};
pub use crate::record::{Activity, Cleanup, Record};
pub use crate::ridi::{parse_ridi_csv, ridi_placement};
pub use crate::ronin::parse_ronin_csv;
pub use crate::sniff::{check_file, sniff, sniff_bytes, Content, Sniffed};
pub use crate::tcx::{read_tcx, read_tcx_counted};

/// Reads an activity file: FIT, TCX, GPX or the activity CSV, told from the content
/// ([`sniff`]); the extension (`fit`, `tcx`, `gpx`, `csv`, case-insensitive) decides
/// only when the content does not (then the reader of that format says what is
/// wrong). A gzip-compressed file (e.g. Strava's `.fit.gz`) is decompressed. The
/// activity name is the file name without its extensions.
pub fn read_activity(path: &Path) -> Result<Activity, FormatError> {
    let sniffed = sniff(path)?;
    let extension = activity_extension(path);
    let content = match sniffed.content {
        c if c.is_activity() => c,
        Content::Unknown => match extension.as_str() {
            "fit" => Content::Fit,
            "tcx" => Content::Tcx,
            "gpx" => Content::Gpx,
            "csv" => Content::ActivityCsv,
            _ => return Err(FormatError::UnknownExtension(extension)),
        },
        other => {
            return Err(FormatError::OtherContent {
                found: other.name(),
                expected: "activity file (FIT, TCX, GPX or an activity CSV)",
            })
        }
    };
    let bytes = read_bytes(path, sniffed.gzip)?;
    let text = || String::from_utf8_lossy(&bytes);
    let (records, cleanup) = match content {
        Content::Fit => read_fit_counted(&bytes)?,
        Content::Tcx => read_tcx_counted(&text())?,
        Content::Gpx => read_gpx_counted(&text())?,
        _ => read_csv_counted(&text())?,
    };
    Ok(Activity {
        name: activity_name(path),
        records,
        cleanup,
    })
}

/// Largest activity file read, bytes (decompressed): 1 GiB.
const MAX_ACTIVITY_BYTES: u64 = 1 << 30;

/// The extension that names the format, lower case (`run.fit.gz` → `fit`).
fn activity_extension(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    Path::new(name)
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The file name without the format's extension (and `.gz`).
fn activity_name(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match name.len().checked_sub(3) {
        Some(k) if name.is_char_boundary(k) && name[k..].eq_ignore_ascii_case(".gz") => {
            name[..k].to_string()
        }
        _ => name,
    };
    Path::new(&name)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The file's bytes, decompressed when `gzip`. A gzip stream cut short gives the bytes
/// it held (the reader of the format then finds the cut).
fn read_bytes(path: &Path, gzip: bool) -> Result<Vec<u8>, FormatError> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    let read = if gzip {
        flate2::read::GzDecoder::new(file)
            .take(MAX_ACTIVITY_BYTES + 1)
            .read_to_end(&mut bytes)
    } else {
        file.take(MAX_ACTIVITY_BYTES + 1).read_to_end(&mut bytes)
    };
    match read {
        Ok(_) => {}
        Err(e) if gzip && e.kind() == std::io::ErrorKind::UnexpectedEof => {}
        Err(e) => return Err(e.into()),
    }
    if bytes.len() as u64 > MAX_ACTIVITY_BYTES {
        return Err(FormatError::parse("activity", "larger than 1 GiB"));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatches_on_extension_case_insensitively() {
        let dir = std::env::temp_dir().join(format!("stridekit-formats-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("Morning Run.CSV");
        std::fs::write(&path, "t_s,lat_deg,lon_deg\n1,2,3\n").unwrap();
        let activity = read_activity(&path).unwrap();
        assert_eq!(activity.name, "Morning Run");
        assert_eq!(activity.records.len(), 1);

        let other = dir.join("notes.txt");
        std::fs::write(&other, "hello").unwrap();
        assert!(matches!(
            read_activity(&other),
            Err(FormatError::UnknownExtension(e)) if e == "txt"
        ));
        assert!(matches!(
            read_activity(&dir.join("missing.fit")),
            Err(FormatError::Missing)
        ));
        assert!(matches!(read_activity(&dir), Err(FormatError::Folder)));
        // The content decides: a CSV named .gpx, an Oxford trace named .csv.
        let renamed = dir.join("run.gpx");
        std::fs::write(&renamed, "t_s,lat_deg,lon_deg\n1,2,3\n").unwrap();
        assert_eq!(read_activity(&renamed).unwrap().name, "run");
        let oxford = dir.join("my_walk.csv");
        std::fs::write(&oxford, "263239144953734,2,1.94,5.16,10.16\n").unwrap();
        assert!(matches!(
            read_activity(&oxford),
            Err(FormatError::OtherContent { found, .. }) if found.contains("Oxford")
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
