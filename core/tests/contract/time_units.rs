//! Time units refused from the first samples, one cause named once, on real
//! recordings (issue 36): a run's fix and step times in milliseconds (relative, as a
//! replay makes them, and as Unix time), and an Oxford accelerometer trace whose
//! millisecond column was read as nanoseconds. Each skips with a message when the
//! shared data are absent.

use std::path::PathBuf;

use stridekit_core::input::{InputError, LikelyTimeUnit, Stream};
use stridekit_core::stepdetect::{StepDetectError, StepDetector};
use stridekit_core::{PaceConfig, PaceError, PaceSample, PaceSource, PaceTracker, StepSample};
use stridekit_lab::activity::prepare;

const RUN: &str = "pace/original/2020-12-02T06_08_29-300_Running.tcx";
const OXFORD: &str = "steps/oxford/Pixel_Jamie_Hard_InHand_3/accelerometer.csv";

fn shared(rel: &str) -> Option<PathBuf> {
    let path = stridekit_formats::data_dir().map(|d| d.join(rel));
    if path.as_ref().is_none_or(|p| !p.exists()) {
        eprintln!("SKIPPED: {rel} not found (../shared/data; set STRIDEKIT_DATA)");
        return None;
    }
    path
}

fn scale_times(samples: &[PaceSample], k: f64) -> Vec<PaceSample> {
    samples
        .iter()
        .map(|s| match *s {
            PaceSample::Fix(f) => PaceSample::Fix(stridekit_core::GnssFix {
                t_s: k * f.t_s,
                ..f
            }),
            PaceSample::Steps(StepSample::Cadence { t_s, steps_per_min }) => {
                PaceSample::Steps(StepSample::Cadence {
                    t_s: k * t_s,
                    steps_per_min,
                })
            }
            other => other,
        })
        .collect()
}

/// What a replay of `samples` did: per stream, the refusals and the units they named;
/// whether any estimate moved.
#[derive(Default)]
struct Outcome {
    refused: [usize; 2],
    first_refused: [Option<usize>; 2],
    other_errors: Vec<String>,
    units: Vec<(Stream, LikelyTimeUnit)>,
    moved: bool,
}

fn replay(samples: &[PaceSample]) -> Outcome {
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let mut o = Outcome::default();
    let mut n = [0usize; 2];
    for s in samples {
        let k = usize::from(matches!(s, PaceSample::Steps(_)));
        match tr.push(s) {
            Ok(_) => {}
            Err(PaceError::Input(InputError::TimeUnit { stream, likely, .. })) => {
                o.refused[k] += 1;
                o.first_refused[k].get_or_insert(n[k]);
                if !o.units.contains(&(stream, likely)) {
                    o.units.push((stream, likely));
                }
            }
            Err(e) => o.other_errors.push(e.to_string()),
        }
        n[k] += 1;
        let e = tr.estimate();
        o.moved |= e.is_some_and(|e| {
            e.distance_m > 0.0 || e.speed_mps > 0.0 || e.source != PaceSource::Initializing
        });
    }
    o
}

#[test]
fn a_run_with_millisecond_times_is_refused_and_changes_nothing() {
    let Some(path) = shared(RUN) else {
        return;
    };
    let activity = stridekit_formats::read_activity(&path).unwrap();
    let samples = scale_times(&prepare(&activity).samples, 1000.0);
    let fixes = samples
        .iter()
        .filter(|s| matches!(s, PaceSample::Fix(_)))
        .count();
    let steps = samples.len() - fixes;
    let o = replay(&samples);
    assert!(o.other_errors.is_empty(), "{:?}", &o.other_errors[..3]);
    // Before: 909 fixes refused (898 "microseconds", 11 "milliseconds"), the first 3
    // used, every step sample accepted.
    assert_eq!(o.units.len(), 2, "one unit per stream: {:?}", o.units);
    for stream in [Stream::Gnss, Stream::Steps] {
        assert!(
            o.units.contains(&(stream, LikelyTimeUnit::Milliseconds)),
            "{:?}",
            o.units
        );
    }
    // The first samples are held (the unit is not known from one time); from the
    // third slow interval on every sample is refused, and none ever counted.
    assert_eq!(o.first_refused, [Some(3), Some(3)]);
    assert_eq!(o.refused, [fixes - 3, steps - 3]);
    assert!(!o.moved, "a sample in milliseconds changed the estimate");
}

#[test]
fn a_run_in_unix_milliseconds_is_refused_from_its_first_sample() {
    let Some(path) = shared(RUN) else {
        return;
    };
    let mut activity = stridekit_formats::read_activity(&path).unwrap();
    for r in &mut activity.records {
        r.t_s *= 1000.0;
    }
    // A replay keeps times the input layer refuses by their size as they are.
    let samples = prepare(&activity).samples;
    let o = replay(&samples);
    assert_eq!(o.first_refused, [Some(0), Some(0)]);
    assert_eq!(o.refused.iter().sum::<usize>(), samples.len());
    assert_eq!(o.units.len(), 2, "{:?}", o.units);
    assert!(o
        .units
        .iter()
        .all(|&(_, u)| u == LikelyTimeUnit::Milliseconds));
    assert!(!o.moved);
}

#[test]
fn milliseconds_read_as_nanoseconds_are_named_not_counted_as_duplicates() {
    let Some(path) = shared(OXFORD) else {
        return;
    };
    let rows = stridekit_formats::read_oxford_accel_raw(&path).unwrap();
    let mut d = StepDetector::default();
    let (mut too_fine, mut duplicate, mut other) = (0usize, 0usize, 0usize);
    let mut first_t = None;
    for s in &rows.samples {
        // The column held milliseconds; a reader divided by 10⁹ as for nanoseconds.
        let t = s.t_s * 1e3 / 1e9;
        let t0 = *first_t.get_or_insert(t);
        match d.push_accel(t - t0 + 0.01, s.accel_mps2) {
            Ok(_) => {}
            Err(StepDetectError::Input(InputError::TimeTooFine { .. })) => too_fine += 1,
            Err(StepDetectError::Input(e)) if e.is_duplicate_time() => duplicate += 1,
            Err(_) => other += 1,
        }
    }
    let n = rows.samples.len();
    // Before: every sample after the first a "duplicate timestamp" (30 152 on another
    // trace), the unit never named.
    assert!(
        too_fine as f64 >= 0.99 * n as f64,
        "{too_fine} of {n} named (duplicates {duplicate}, other {other})"
    );
    assert_eq!(d.step_count(), 0);
}
