//! The fuzz targets of stridekit as plain functions over bytes, named in [`TARGETS`].
//! cargo-fuzz runs them (`fuzz/`, `scripts/fuzz`); `tests/regressions.rs` replays
//! every input in `fuzz/regressions/<target>/` with stable Rust in CI. A target fails
//! by panicking; libFuzzer's timeout catches hangs. Documented in docs/robustness.md.

pub mod bytes;
pub mod engines;
pub mod formats;
pub mod models;
pub mod packed;

use engines::{
    restore, restore_sealed, sequence, Foot, Navigator, Odometry, Orientation, Pace, Placement,
    StepLength, Steps,
};

/// A named target.
pub struct Target {
    pub name: &'static str,
    pub run: fn(&[u8]),
}

macro_rules! targets {
    ($($name:literal => $f:expr),* $(,)?) => {
        /// Every target, by name.
        pub const TARGETS: &[Target] = &[$(Target { name: $name, run: $f }),*];
    };
}

targets! {
    // Readers of stridekit-formats.
    "format_fit" => formats::fit,
    "format_tcx" => formats::tcx,
    "format_gpx" => formats::gpx,
    "format_csv" => formats::csv,
    "format_foot_csv" => formats::foot_csv,
    "format_ridi" => formats::ridi,
    "format_ronin" => formats::ronin,
    "format_inertial_csv" => formats::inertial_csv,
    "format_android_log" => formats::android_log,
    "format_android_log_gz" => formats::android_log_gz,
    "format_broad" => formats::broad,
    "format_oxford_accel" => formats::oxford_accel,
    // Model and calibration parsers.
    "model_svm" => models::svm,
    "model_placement" => models::placement,
    "model_odometry" => models::odometry,
    "model_pdr_calibration" => models::pdr_calibration,
    "model_pace_calibration" => models::pace_calibration,
    // Every engine's restore, raw and behind a valid header + CRC.
    "restore_pace" => restore::<Pace>,
    "restore_pace_sealed" => restore_sealed::<Pace>,
    "restore_ahrs" => restore::<Orientation>,
    "restore_ahrs_sealed" => restore_sealed::<Orientation>,
    "restore_steps" => restore::<Steps>,
    "restore_steps_sealed" => restore_sealed::<Steps>,
    "restore_step_length" => restore::<StepLength>,
    "restore_step_length_sealed" => restore_sealed::<StepLength>,
    "restore_navigator" => restore::<Navigator>,
    "restore_navigator_sealed" => restore_sealed::<Navigator>,
    "restore_foot" => restore::<Foot>,
    "restore_foot_sealed" => restore_sealed::<Foot>,
    "restore_placement" => restore::<Placement>,
    "restore_placement_sealed" => restore_sealed::<Placement>,
    "restore_odometry" => restore::<Odometry>,
    "restore_odometry_sealed" => restore_sealed::<Odometry>,
    // Sample sequences per engine.
    "sequence_pace" => sequence::<Pace>,
    "sequence_ahrs" => sequence::<Orientation>,
    "sequence_steps" => sequence::<Steps>,
    "sequence_step_length" => sequence::<StepLength>,
    "sequence_navigator" => sequence::<Navigator>,
    "sequence_foot" => sequence::<Foot>,
    "sequence_placement" => sequence::<Placement>,
    "sequence_odometry" => sequence::<Odometry>,
    // Packed batch entry points of the bindings.
    "packed_pace_fixes" => packed::pace_fixes,
    "packed_pace_step_counts" => packed::pace_step_counts,
    "packed_pace_accel" => packed::pace_accel,
    "packed_navigator_imu" => packed::navigator_imu,
    "packed_navigator_events" => packed::navigator_events,
    "packed_odometry_imu" => packed::odometry_imu,
    "packed_orientation_imu" => packed::orientation_imu,
    "packed_placement_accel" => packed::placement_accel,
    "packed_foot" => packed::foot,
}

/// Runs the target `name` on `data`; panics if it fails, or if there is no such target.
pub fn run(name: &str, data: &[u8]) {
    let target = TARGETS
        .iter()
        .find(|t| t.name == name)
        .unwrap_or_else(|| panic!("no fuzz target {name}"));
    (target.run)(data);
}

/// Seed inputs for `name` (beside the files scripts/fuzz copies from the data and the
/// shipped models): real snapshots for the restore targets, plausible sample streams
/// for the sequence and packed targets.
pub fn seeds(name: &str) -> Vec<Vec<u8>> {
    fn snaps<E: engines::Engine>(sealed: bool) -> Vec<Vec<u8>> {
        [(1, 300), (2, 2_000)]
            .iter()
            .map(|&(seed, n)| {
                let body = engines::seed_body::<E>(seed, n);
                if sealed {
                    body
                } else {
                    engines::sealed::<E>(&body)
                }
            })
            .collect()
    }
    let sealed = name.ends_with("_sealed");
    match name.trim_end_matches("_sealed") {
        "restore_pace" => snaps::<Pace>(sealed),
        "restore_ahrs" => snaps::<Orientation>(sealed),
        "restore_steps" => snaps::<Steps>(sealed),
        "restore_step_length" => snaps::<StepLength>(sealed),
        "restore_navigator" => snaps::<Navigator>(sealed),
        "restore_foot" => snaps::<Foot>(sealed),
        "restore_placement" => snaps::<Placement>(sealed),
        "restore_odometry" => snaps::<Odometry>(sealed),
        n if n.starts_with("sequence_") || n.starts_with("packed_") => {
            let mut s = engines::plausible_bytes(3, 4_000);
            if n.starts_with("packed_") {
                s[0] = 0; // decoded records
            }
            vec![s]
        }
        "model_pace_calibration" => vec![b"stridekit-pace-calibration 1\n# seed\nline 0.95 176.9 0.0083 0.025\naccel_model 0.378 -4.6e-5 0.0986 at 1.66 6.63 sigma 0.141 0.00199 0.016\n".to_vec()],
        _ => Vec::new(),
    }
}
