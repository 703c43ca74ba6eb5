//! Imports every real activity file of the shared data set and compares it with its
//! reference conversion (`pace/csv/`, made with python-fitparse / runpandas).
//!
//! The data is not part of the repository: without `../shared/data` (or `STRIDEKIT_DATA`)
//! every test prints a skip message and passes.

use std::path::PathBuf;

use stridekit_formats::{data_dir, read_activity, read_csv, Record};

/// `<data>/pace`, or `None` after printing why the test is skipped.
fn pace_dir() -> Option<PathBuf> {
    match data_dir() {
        Some(dir) => Some(dir.join("pace")),
        None => {
            eprintln!("skipping: ../shared/data not found (set STRIDEKIT_DATA)");
            None
        }
    }
}

/// Checks one optional field: present in both or in neither, and within `tolerance`.
fn assert_close(
    file: &str,
    index: usize,
    field: &str,
    ours: Option<f64>,
    reference: Option<f64>,
    tolerance: f64,
) {
    let ok = match (ours, reference) {
        (None, None) => true,
        (Some(a), Some(b)) => (a - b).abs() <= tolerance,
        _ => false,
    };
    assert!(
        ok,
        "{file}: record {index}: {field} is {ours:?}, reference {reference:?} (tolerance {tolerance})"
    );
}

/// Imports `original` and compares it with `reference`, record by record.
///
/// `reference_duplicates` is the number of reference rows that repeat the timestamp of the
/// row before: the importer merges such rows into one record (first row wins), so it
/// returns that many records fewer than the reference has rows.
fn compare(original: &str, reference: &str, reference_duplicates: usize) {
    let Some(pace) = pace_dir() else {
        return;
    };
    let activity = read_activity(&pace.join("original").join(original))
        .unwrap_or_else(|e| panic!("{original}: {e}"));
    let expected_name = original.rsplit_once('.').unwrap().0;
    assert_eq!(activity.name, expected_name);

    let reference_text = std::fs::read_to_string(pace.join("csv").join(reference))
        .unwrap_or_else(|e| panic!("{reference}: {e}"));
    let reference_times: Vec<&str> = reference_text
        .lines()
        .skip(1)
        .filter(|line| !line.trim().is_empty())
        .map(|line| line.split(',').next().unwrap())
        .collect();
    let duplicates = reference_times.windows(2).filter(|w| w[0] == w[1]).count();
    assert_eq!(
        duplicates, reference_duplicates,
        "{reference}: repeated timestamps"
    );
    let expected: Vec<Record> = read_csv(&reference_text).unwrap();
    assert_eq!(expected.len(), reference_times.len() - reference_duplicates);

    let records = &activity.records;
    assert_eq!(
        records.len(),
        expected.len(),
        "{original}: {} records, reference {} rows ({} repeated timestamps merged)",
        records.len(),
        reference_times.len(),
        reference_duplicates
    );
    for (i, (ours, theirs)) in records.iter().zip(&expected).enumerate() {
        assert_eq!(ours.t_s, theirs.t_s, "{original}: record {i}: time");
        assert_close(original, i, "lat_deg", ours.lat_deg, theirs.lat_deg, 1e-6);
        assert_close(original, i, "lon_deg", ours.lon_deg, theirs.lon_deg, 1e-6);
        assert_close(original, i, "alt_m", ours.alt_m, theirs.alt_m, 1e-6);
        assert_close(
            original,
            i,
            "device_distance_m",
            ours.device_distance_m,
            theirs.device_distance_m,
            0.01,
        );
        assert_close(
            original,
            i,
            "device_speed_mps",
            ours.device_speed_mps,
            theirs.device_speed_mps,
            1e-6,
        );
        assert_close(
            original,
            i,
            "steps_per_min",
            ours.steps_per_min,
            theirs.steps_per_min,
            1e-9,
        );
        assert_close(
            original,
            i,
            "heart_rate_bpm",
            ours.heart_rate_bpm,
            theirs.heart_rate_bpm,
            1e-9,
        );
        assert_eq!(ours.horizontal_accuracy_m, None);
        assert_eq!(ours.step_count, None);
    }
    for pair in records.windows(2) {
        assert!(
            pair[0].t_s < pair[1].t_s,
            "{original}: times not increasing"
        );
    }
    eprintln!("{original}: {} records match {reference}", records.len());
}

#[test]
fn fit_fenix2_run() {
    compare(
        "fitparse-activity-small-fenix2-run.fit",
        "pyfitparse_fenix2_run.csv",
        0,
    );
}

#[test]
fn fit_fenix5_run() {
    compare(
        "fitparse-garmin-fenix-5-run.fit",
        "pyfitparse_fenix5_run_57s.csv",
        0,
    );
}

#[test]
fn fit_fenix5_walk() {
    compare(
        "fitparse-garmin-fenix-5-walk.fit",
        "pyfitparse_fenix5_walk_46s.csv",
        0,
    );
}

/// Foot pod only, no GNSS; the FR70 had no clock sync, so its timestamps are "system
/// time" (seconds since power-on), kept raw like the reference.
#[test]
fn fit_fr70_footpod_no_gnss() {
    compare(
        "fitparse-compressed-speed-distance.fit",
        "pyfitparse_fr70_sdm4_footpod_nogps.csv",
        0,
    );
    let Some(pace) = pace_dir() else {
        return;
    };
    let activity =
        read_activity(&pace.join("original/fitparse-compressed-speed-distance.fit")).unwrap();
    assert!(activity.records.iter().all(|r| r.lat_deg.is_none()));
    assert!(activity.records.iter().any(|r| r.steps_per_min.is_some()));
}

#[test]
fn fit_runpandas_run() {
    compare("runpandas-run.fit", "runpandas_run_fit.csv", 0);
}

#[test]
fn tcx_2020_12_02() {
    compare(
        "2020-12-02T06_08_29-300_Running.tcx",
        "runpandas_2020-12-02T06_08_29-300_Running.csv",
        0,
    );
}

#[test]
fn tcx_2020_12_04() {
    compare(
        "2020-12-04T19_09_21-300_Running.tcx",
        "runpandas_2020-12-04T19_09_21-300_Running.csv",
        0,
    );
}

#[test]
fn tcx_2020_12_08() {
    compare(
        "2020-12-08T06_36_12-300_Running.tcx",
        "runpandas_2020-12-08T06_36_12-300_Running.csv",
        0,
    );
}

#[test]
fn tcx_2020_12_16() {
    compare(
        "2020-12-16T05_44_18-300_Running.tcx",
        "runpandas_2020-12-16T05_44_18-300_Running.csv",
        0,
    );
}

#[test]
fn tcx_2020_12_26() {
    compare(
        "2020-12-26T06_03_49-300_Running.tcx",
        "runpandas_2020-12-26T06_03_49-300_Running.csv",
        0,
    );
}

#[test]
fn tcx_runpandas_11km() {
    compare("runpandas-11km.tcx", "runpandas_11km.csv", 0);
}

#[test]
fn tcx_runpandas_run_garmin() {
    compare("runpandas-run_garmin.tcx", "runpandas_run_garmin.csv", 0);
}

/// Two trackpoints share 2021-01-10T09:43:05Z (heart rate 113 then 112): merged into one
/// record that keeps the first (113).
#[test]
fn tcx_runpandas_stopped_example() {
    compare(
        "runpandas-stopped_example.tcx",
        "runpandas_stopped_example.csv",
        1,
    );
    assert_merged_duplicate("runpandas-stopped_example.tcx");
}

/// Strava's GPX export of the same run as `runpandas-stopped_example.tcx`, with the same
/// repeated timestamp.
#[test]
fn gpx_runpandas_strava_export() {
    compare(
        "runpandas-strava_export.gpx",
        "runpandas_strava_export_gpx.csv",
        1,
    );
    assert_merged_duplicate("runpandas-strava_export.gpx");
}

fn assert_merged_duplicate(original: &str) {
    let Some(pace) = pace_dir() else {
        return;
    };
    let activity = read_activity(&pace.join("original").join(original)).unwrap();
    let merged = activity
        .records
        .iter()
        .find(|r| r.t_s == 1_610_271_785.0)
        .expect("the repeated timestamp is present once");
    assert_eq!(merged.heart_rate_bpm, Some(113.0));
}

/// Every original file has a test above, so a file added to the folder is not forgotten.
#[test]
fn every_original_file_is_covered() {
    let Some(pace) = pace_dir() else {
        return;
    };
    let mut names: Vec<String> = std::fs::read_dir(pace.join("original"))
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| {
            let lower = name.to_ascii_lowercase();
            [".fit", ".tcx", ".gpx"]
                .iter()
                .any(|ext| lower.ends_with(ext))
        })
        .collect();
    names.sort();
    let source = include_str!("real_files.rs");
    for name in &names {
        // Whole files: none is taken for one cut off mid-write.
        let activity = read_activity(&pace.join("original").join(name))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!activity.cleanup.truncated, "{name} read as cut off");
        assert!(
            source.contains(&format!("\"{name}\"")),
            "{name} has no comparison test"
        );
    }
}
