//! The cross-checks between GNSS and the steps on real runs (issue 36): cadence in
//! strides per minute fed as steps, a calibration of another runner, the same run
//! without GNSS. Each replays a real run of `../shared/data/pace/original` (or
//! `$STRIDEKIT_DATA`) and skips with a message when the data are absent.

use std::path::PathBuf;

use stridekit_core::{
    PaceCalibration, PaceConfig, PaceEstimate, PaceFlags, PaceSample, PaceTracker, StepSample,
};
use stridekit_lab::activity::prepare;

/// A 42-minute run of one runner, 912 fixes, cadence ≈ 170–185 steps/min.
const RUN: &str = "2020-12-02T06_08_29-300_Running.tcx";

fn run_samples(name: &str) -> Option<Vec<PaceSample>> {
    let Some(dir) = stridekit_formats::data_dir().map(|d| d.join("pace/original")) else {
        eprintln!(
            "SKIPPED: real runs not found (../shared/data/pace/original; set STRIDEKIT_DATA)"
        );
        return None;
    };
    let path: PathBuf = dir.join(name);
    let activity = stridekit_formats::read_activity(&path).expect("readable run");
    Some(prepare(&activity).samples)
}

/// The same samples with each cadence report halved: strides per minute, as FIT, TCX
/// and Garmin's APIs call "cadence", fed as steps per minute.
fn as_strides(samples: &[PaceSample]) -> Vec<PaceSample> {
    samples
        .iter()
        .map(|s| match *s {
            PaceSample::Steps(StepSample::Cadence { t_s, steps_per_min }) => {
                PaceSample::Steps(StepSample::Cadence {
                    t_s,
                    steps_per_min: steps_per_min / 2.0,
                })
            }
            other => other,
        })
        .collect()
}

/// Replays `samples`; returns the last estimate and the time each flag was first set.
fn replay(config: PaceConfig, samples: &[PaceSample]) -> (PaceEstimate, [Option<f64>; 3]) {
    let mut tr = PaceTracker::new(config).unwrap();
    let mut first = [None; 3];
    for s in samples {
        tr.push(s).unwrap();
        let e = tr.estimate().unwrap();
        let PaceFlags {
            cadence_doubled,
            cadence_may_be_strides,
            pedometer_disagrees,
        } = e.flags;
        for (slot, on) in
            first
                .iter_mut()
                .zip([cadence_doubled, cadence_may_be_strides, pedometer_disagrees])
        {
            if on && slot.is_none() {
                *slot = Some(e.t_s);
            }
        }
    }
    (tr.estimate().unwrap(), first)
}

fn first_fix_t(samples: &[PaceSample]) -> f64 {
    samples
        .iter()
        .find_map(|s| match s {
            PaceSample::Fix(f) => Some(f.t_s),
            _ => None,
        })
        .unwrap()
}

#[test]
fn strides_fed_as_steps_are_doubled_within_a_minute_and_the_distance_is_right() {
    let Some(samples) = run_samples(RUN) else {
        return;
    };
    let (normal, normal_flags) = replay(PaceConfig::default(), &samples);
    assert_eq!(
        normal_flags, [None; 3],
        "the run as recorded raises no flag"
    );
    let strides = as_strides(&samples);
    let (e, first) = replay(PaceConfig::default(), &strides);
    // Before: 2 100 m against 6 899 m, the pedometer held against 912 good fixes.
    let rel = e.distance_m / normal.distance_m - 1.0;
    assert!(
        rel.abs() < 0.04,
        "strides: {:.0} m against {:.0} m as recorded ({:+.1} %)",
        e.distance_m,
        normal.distance_m,
        100.0 * rel
    );
    let doubled_at = first[0].expect("cadence never doubled") - first_fix_t(&strides);
    assert!(
        doubled_at <= 75.0,
        "doubled {doubled_at:.0} s after the first fix"
    );
    assert!(e.flags.cadence_doubled && !e.flags.cadence_may_be_strides);
    // Cadence and step length are given for steps.
    let c = e.cadence_spm.unwrap();
    assert!((150.0..200.0).contains(&c), "cadence {c}");
    let l = e.step_length_m.unwrap();
    assert!((0.8..1.1).contains(&l), "step length {l}");
}

#[test]
fn without_gnss_a_stride_cadence_is_flagged_not_corrected() {
    let Some(samples) = run_samples(RUN) else {
        return;
    };
    let no_fix = |s: &&PaceSample| !matches!(s, PaceSample::Fix(_));
    let steps: Vec<PaceSample> = samples.iter().filter(no_fix).copied().collect();
    let strides: Vec<PaceSample> = as_strides(&samples)
        .iter()
        .filter(no_fix)
        .copied()
        .collect();
    let (e, first) = replay(PaceConfig::default(), &strides);
    assert!(
        first[1].is_some(),
        "a stride cadence without GNSS is not flagged"
    );
    assert!(e.flags.cadence_may_be_strides, "{:?}", e.flags);
    assert!(
        !e.flags.cadence_doubled,
        "nothing can confirm strides without GNSS"
    );
    // The same run in steps is not flagged while running (the walk at its start is
    // too short to be taken for strides).
    let (e, first) = replay(PaceConfig::default(), &steps);
    assert_eq!(first, [None; 3], "{:?}", e.flags);
}

#[test]
fn a_calibration_of_another_runner_is_learned_again_from_gnss() {
    let Some(samples) = run_samples(RUN) else {
        return;
    };
    let (normal, _) = replay(PaceConfig::default(), &samples);
    // A learned line 1.58× this runner's (1.5 m at 176 steps/min, ±2 cm).
    let wrong = PaceCalibration {
        step_length_m: 1.5,
        cadence_spm: 176.0,
        slope_m_per_spm: 0.5 / 60.0,
        step_length_std_m: 0.02,
        accel_model: None,
    };
    let config = PaceConfig {
        calibration: Some(wrong),
        ..PaceConfig::default()
    };
    let (e, first) = replay(config, &samples);
    // Before: +23.6 % (8 525 m), the imported line held for 17 minutes.
    let rel = e.distance_m / normal.distance_m - 1.0;
    assert!(
        rel.abs() < 0.04,
        "{:.0} m against {:.0} m with no calibration ({:+.1} %)",
        e.distance_m,
        normal.distance_m,
        100.0 * rel
    );
    let flagged = first[2].expect("the disagreement is never flagged") - first_fix_t(&samples);
    assert!(
        flagged <= 120.0,
        "flagged {flagged:.0} s after the first fix"
    );
    assert!(!e.flags.pedometer_disagrees, "still disagreeing at the end");
    assert!(!e.flags.cadence_doubled);
}
