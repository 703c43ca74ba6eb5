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
mod floorplan;
mod foot;
mod gpx;
mod inertial;
mod oxford;
mod record;
mod ridi;
mod ronin;
mod tcx;
mod xml;

use std::path::Path;

pub use crate::android::{is_android_log, list_android_logs, parse_android_log, read_android_log};
pub use crate::broad::{list_broad_trials, parse_broad, read_broad, OrientationRecording};
pub use crate::csv::{read_csv, read_csv_counted};
pub use crate::data::{data_dir, DATA_ENV_VAR};
pub use crate::error::{FormatError, Unreadable};
pub use crate::fit::{read_fit, read_fit_counted};
pub use crate::floorplan::{
    parse_competition_plan, parse_geojson_plan, read_floor_plan, PlanFile, PlanFileError,
    MAX_PLAN_BYTES,
};
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
pub use crate::tcx::{read_tcx, read_tcx_counted};

/// Reads an activity file, choosing the reader from the file extension (case-insensitive):
/// `fit`, `tcx`, `gpx` or `csv`. The activity name is the file stem.
pub fn read_activity(path: &Path) -> Result<Activity, FormatError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let (records, cleanup) = match extension.as_str() {
        "fit" => read_fit_counted(&std::fs::read(path)?)?,
        "tcx" => read_tcx_counted(&read_text(path)?)?,
        "gpx" => read_gpx_counted(&read_text(path)?)?,
        "csv" => read_csv_counted(&read_text(path)?)?,
        _ => return Err(FormatError::UnknownExtension(extension)),
    };
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Activity {
        name,
        records,
        cleanup,
    })
}

/// Reads a text file; bytes that are not UTF-8 (seen in names and notes of some exports)
/// are replaced rather than rejected, since the numeric fields are ASCII.
fn read_text(path: &Path) -> Result<String, FormatError> {
    let bytes = std::fs::read(path)?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
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
            Err(FormatError::Io(_))
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
