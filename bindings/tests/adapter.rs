//! The adapter layer: conversions, error mapping, batch rejection semantics, packed
//! buffers, snapshots, threads. These call the exported Rust functions directly; the
//! Kotlin tests in `tests/` run the same paths through the generated bindings.

use std::sync::Arc;

use stridekit::packed::{FIX_RECORD_BYTES, STEP_COUNT_RECORD_BYTES};
#[cfg(feature = "testing")]
use stridekit::testing::simulate_run;
use stridekit::{
    default_pace_config, GnssFix, PaceConfig, PaceError, PaceEstimate, PaceFlags, PaceMode,
    PaceSample, PaceSource, PaceTracker, SensorStream, StepSample,
};
use stridekit_core::pace as core;

const LAT: f64 = 50.2945;
const LON: f64 = 18.6714;

fn fix(t_s: f64) -> GnssFix {
    GnssFix {
        t_s,
        // ~3.3 m/s north-east.
        lat_deg: LAT + t_s * 2.1e-5,
        lon_deg: LON + t_s * 3.3e-5,
        alt_m: None,
        horizontal_accuracy_m: Some(4.0),
        speed_mps: None,
        speed_accuracy_mps: None,
    }
}

fn count(t_s: f64, steps: i64) -> StepSample {
    StepSample::Count { t_s, steps }
}

/// A short interleaved run: steps every second, fixes every second, 60 s.
fn short_run() -> Vec<PaceSample> {
    let mut out = Vec::new();
    for i in 0..60i64 {
        let t = i as f64;
        out.push(PaceSample::Steps {
            sample: count(t + 0.5, 1000 + 3 * i),
        });
        out.push(PaceSample::Fix { fix: fix(t + 1.0) });
    }
    out
}

fn core_reference(samples: &[PaceSample]) -> (Vec<core::PaceEstimate>, core::PaceTracker) {
    let mut t = core::PaceTracker::new(core::PaceConfig::default()).unwrap();
    let mut est = Vec::new();
    for s in samples {
        if let Ok(Some(e)) = t.push(&(*s).try_into().unwrap()) {
            est.push(e);
        }
    }
    (est, t)
}

fn to_core(e: &[PaceEstimate]) -> Vec<core::PaceEstimate> {
    e.iter().map(|&e| e.into()).collect()
}

/// Bitwise equality of estimates (NaN-safe, −0 ≠ +0).
fn bits(e: &core::PaceEstimate) -> Vec<u64> {
    let o = |v: Option<f64>| v.map_or(u64::MAX - 1, f64::to_bits);
    vec![
        e.t_s.to_bits(),
        e.speed_mps.to_bits(),
        o(e.pace_s_per_km),
        o(e.speed_std_mps),
        o(e.cadence_spm),
        o(e.step_length_m),
        e.gnss_weight.to_bits(),
        e.distance_m.to_bits(),
        e.source as u64,
    ]
}

fn assert_bit_identical(a: &[core::PaceEstimate], b: &[core::PaceEstimate]) {
    assert_eq!(a.len(), b.len());
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(bits(x), bits(y), "estimate {i} differs: {x:?} vs {y:?}");
    }
}

// ---------------------------------------------------------------- conversions

#[test]
fn records_round_trip_through_core_types() {
    let f = GnssFix {
        t_s: 12.5,
        lat_deg: -33.9,
        lon_deg: 151.2,
        alt_m: Some(-3.0),
        horizontal_accuracy_m: Some(5.5),
        speed_mps: Some(3.1),
        speed_accuracy_mps: Some(0.4),
    };
    let c: core::GnssFix = f.into();
    assert_eq!(c.alt_m, Some(-3.0));
    assert_eq!(c.speed_accuracy_mps, Some(0.4));
    assert_eq!(GnssFix::from(c), f);

    for s in [
        count(1.0, i64::MAX),
        StepSample::Event { t_s: 2.0 },
        StepSample::Cadence {
            t_s: 3.0,
            steps_per_min: 172.5,
        },
    ] {
        let c: core::StepSample = s.try_into().unwrap();
        assert_eq!(c.t_s(), s_t(&s));
        assert_eq!(StepSample::from(c), s);
        let p = PaceSample::Steps { sample: s };
        assert_eq!(PaceSample::from(core::PaceSample::try_from(p).unwrap()), p);
    }
    let p = PaceSample::Fix { fix: f };
    assert_eq!(
        core::PaceSample::try_from(p).unwrap(),
        core::PaceSample::Fix(c)
    );

    for src in [
        PaceSource::Initializing,
        PaceSource::Stationary,
        PaceSource::Gnss,
        PaceSource::Fused,
        PaceSource::Pedometer,
    ] {
        assert_eq!(PaceSource::from(core::PaceSource::from(src)), src);
    }
    let e = PaceEstimate {
        t_s: 1.0,
        speed_mps: 3.0,
        pace_s_per_km: Some(333.3),
        speed_std_mps: None,
        cadence_spm: Some(170.0),
        step_length_m: None,
        gnss_weight: 0.5,
        distance_m: 42.0,
        source: PaceSource::Fused,
        flags: PaceFlags {
            cadence_doubled: true,
            cadence_may_be_strides: false,
            pedometer_disagrees: true,
        },
    };
    assert_eq!(PaceEstimate::from(core::PaceEstimate::from(e)), e);
}

fn s_t(s: &StepSample) -> f64 {
    match *s {
        StepSample::Count { t_s, .. }
        | StepSample::Event { t_s }
        | StepSample::Cadence { t_s, .. } => t_s,
    }
}

#[test]
fn config_defaults_match_core() {
    let core_default = core::PaceConfig::default();
    let d = default_pace_config();
    assert_eq!(d, PaceConfig::from(core_default));
    // The literal defaults declared on the uniffi record (`#[uniffi(default = ..)]`):
    assert_eq!(d.mode, PaceMode::Adaptive);
    assert_eq!(d.initial_step_length_m, None);
    assert_eq!(d.stationary_after_s, 2.0);
    // Only the three exposed fields change; the rest stays at the core defaults.
    assert_eq!(d.calibration, None);
    let c: core::PaceConfig = PaceConfig {
        mode: PaceMode::AsPublished,
        initial_step_length_m: Some(1.1),
        stationary_after_s: 3.5,
        calibration: None,
    }
    .into();
    assert_eq!(c.mode, core::PaceMode::AsPublished);
    assert_eq!(c.initial_step_length_m, Some(1.1));
    assert_eq!(c.stationary_after_s, 3.5);
    assert_eq!(c.published, core_default.published);
    assert_eq!(c.adaptive, core_default.adaptive);

    let t = PaceTracker::new(PaceConfig {
        mode: PaceMode::AsPublished,
        initial_step_length_m: Some(1.1),
        stationary_after_s: 3.5,
        calibration: None,
    })
    .unwrap();
    assert_eq!(t.config().mode, PaceMode::AsPublished);
    assert_eq!(PaceTracker::with_defaults().config(), d);
}

// ---------------------------------------------------------------- errors

#[test]
fn invalid_config_is_an_error() {
    let err = PaceTracker::new(PaceConfig {
        initial_step_length_m: Some(10.0),
        ..default_pace_config()
    })
    .unwrap_err();
    assert!(matches!(err, PaceError::InvalidConfig { .. }), "{err:?}");
    assert!(err.to_string().contains("initial_step_length_m"), "{err}");
    let err = PaceTracker::new(PaceConfig {
        stationary_after_s: f64::NAN,
        ..default_pace_config()
    })
    .unwrap_err();
    assert!(matches!(err, PaceError::InvalidConfig { .. }), "{err:?}");
}

#[test]
fn sample_errors_map_to_typed_variants() {
    let t = PaceTracker::with_defaults();
    let nan = GnssFix {
        lat_deg: f64::NAN,
        ..fix(1.0)
    };
    assert_eq!(
        t.push_fix(nan).unwrap_err(),
        PaceError::NonFinite {
            field: "lat_deg".into()
        }
    );
    let err = t
        .push_fix(GnssFix {
            lat_deg: 91.0,
            ..fix(1.0)
        })
        .unwrap_err();
    match &err {
        PaceError::OutOfRange { field, value, .. } => {
            assert_eq!(field, "lat_deg");
            assert_eq!(*value, 91.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().contains("out of range"), "{err}");

    t.push_fix(fix(5.0)).unwrap();
    assert_eq!(
        t.push_fix(fix(4.0)).unwrap_err(),
        PaceError::TimeNotIncreasing {
            stream: SensorStream::Gnss,
            t_s: 4.0,
            last_t_s: 5.0
        }
    );
    t.push_steps(count(5.0, 10)).unwrap();
    let err = t.push_steps(count(5.0, 11)).unwrap_err();
    assert!(
        matches!(
            err,
            PaceError::TimeNotIncreasing {
                stream: SensorStream::Steps,
                ..
            }
        ),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "step sample at t = 5 s is not after the previous one at 5 s"
    );
    let err = t
        .push_steps(StepSample::Cadence {
            t_s: 6.0,
            steps_per_min: 900.0,
        })
        .unwrap_err();
    assert!(matches!(err, PaceError::OutOfRange { .. }), "{err:?}");
    // The tracker keeps working after errors.
    t.push_fix(fix(6.0)).unwrap();
    t.push_steps(count(6.0, 13)).unwrap();
}

#[test]
fn rejected_samples_leave_state_untouched() {
    let t = PaceTracker::with_defaults();
    let samples = short_run();
    t.push_samples(samples[..40].to_vec());
    let before = t.snapshot();
    assert!(t
        .push_fix(GnssFix {
            lon_deg: f64::INFINITY,
            ..fix(100.0)
        })
        .is_err());
    assert!(t.push_fix(fix(1.0)).is_err());
    assert!(t.push_steps(StepSample::Event { t_s: f64::NAN }).is_err());
    assert_eq!(t.snapshot(), before);
}

#[test]
fn bad_snapshots_are_errors() {
    for bytes in [
        vec![],
        b"not a snapshot at all".to_vec(),
        vec![0u8; 3],
        {
            let mut s = PaceTracker::with_defaults().snapshot();
            let n = s.len();
            s[n / 2] ^= 0x10;
            s
        },
        {
            let mut s = PaceTracker::with_defaults().snapshot();
            s.truncate(s.len() - 5);
            s
        },
    ] {
        let err = PaceTracker::restore(bytes.clone()).unwrap_err();
        assert!(
            matches!(err, PaceError::InvalidSnapshot { .. }),
            "{bytes:?}: {err:?}"
        );
        assert!(
            err.to_string().starts_with("cannot restore snapshot"),
            "{err}"
        );
    }
}

// ---------------------------------------------------------------- batches

#[test]
fn batch_rejections_are_reported_by_index_and_skipped() {
    let good: Vec<GnssFix> = (1..=10).map(|i| fix(i as f64)).collect();
    let mut batch = good.clone();
    batch.insert(
        2,
        GnssFix {
            lat_deg: f64::NAN,
            ..fix(2.5)
        },
    );
    batch.insert(5, fix(1.0)); // time going backwards
    batch.push(GnssFix {
        horizontal_accuracy_m: Some(-1.0),
        ..fix(20.0)
    });

    let t = PaceTracker::with_defaults();
    let r = t.push_fixes(batch);
    let idx: Vec<i32> = r.rejected.iter().map(|x| x.index).collect();
    assert_eq!(idx, vec![2, 5, 12]);
    assert!(matches!(r.rejected[0].error, PaceError::NonFinite { .. }));
    assert!(matches!(
        r.rejected[1].error,
        PaceError::TimeNotIncreasing { .. }
    ));
    assert!(matches!(r.rejected[2].error, PaceError::OutOfRange { .. }));
    for x in &r.rejected {
        assert_eq!(x.reason, x.error.to_string());
    }
    assert_eq!(r.estimates.len(), good.len());
    assert_eq!(r.latest, t.estimate());

    // Same as the good fixes pushed one by one.
    let one = PaceTracker::with_defaults();
    let singles: Vec<PaceEstimate> = good.iter().map(|&f| one.push_fix(f).unwrap()).collect();
    assert_bit_identical(&to_core(&r.estimates), &to_core(&singles));
    assert_eq!(t.snapshot(), one.snapshot());
}

#[test]
fn mixed_batches_match_core_push_batch() {
    let mut samples = short_run();
    samples.insert(
        7,
        PaceSample::Steps {
            sample: StepSample::Event { t_s: f64::NAN },
        },
    );
    let t = PaceTracker::with_defaults();
    let r = t.push_samples(samples.clone());

    let mut c = core::PaceTracker::new(core::PaceConfig::default()).unwrap();
    let core_samples: Vec<core::PaceSample> =
        samples.iter().map(|&s| s.try_into().unwrap()).collect();
    let out = c.push_batch(&core_samples);
    assert_bit_identical(&to_core(&r.estimates), &out.estimates);
    let ri: Vec<(i32, PaceError)> = r
        .rejected
        .iter()
        .map(|x| (x.index, x.error.clone()))
        .collect();
    let ci: Vec<(i32, PaceError)> = out
        .rejected
        .iter()
        .map(|x| (x.index as i32, x.error.clone().into()))
        .collect();
    assert_eq!(ri, ci);
    assert_eq!(ri[0].0, 7);
    assert_eq!(t.snapshot(), c.snapshot());
}

#[test]
fn batches_of_any_size_give_the_same_estimates() {
    let samples = short_run();
    let (reference, core_tracker) = core_reference(&samples);
    for size in [1usize, 2, 7, 64, 1000] {
        let t = PaceTracker::with_defaults();
        let mut est = Vec::new();
        for chunk in samples.chunks(size) {
            let r = t.push_samples(chunk.to_vec());
            assert!(r.rejected.is_empty());
            est.extend(r.estimates);
        }
        assert_bit_identical(&to_core(&est), &reference);
        assert_eq!(t.snapshot(), core_tracker.snapshot());
    }
    // Streams pushed separately (all steps, then all fixes) is also legal.
    let t = PaceTracker::with_defaults();
    let steps: Vec<StepSample> = samples
        .iter()
        .filter_map(|s| match s {
            PaceSample::Steps { sample } => Some(*sample),
            _ => None,
        })
        .collect();
    let r = t.push_step_samples(steps.clone());
    assert!(r.estimates.is_empty() && r.rejected.is_empty());
    assert_eq!(r.latest, t.estimate());
}

#[test]
fn empty_batches_are_fine() {
    let t = PaceTracker::with_defaults();
    for r in [
        t.push_fixes(vec![]),
        t.push_step_samples(vec![]),
        t.push_samples(vec![]),
        t.push_fixes_packed(vec![]).unwrap(),
        t.push_step_counts_packed(vec![]).unwrap(),
    ] {
        assert!(r.estimates.is_empty() && r.rejected.is_empty());
        assert_eq!(r.latest, t.estimate());
    }
}

// ---------------------------------------------------------------- packed buffers

#[test]
fn packed_layout_is_as_documented() {
    let f = GnssFix {
        alt_m: Some(250.0),
        speed_mps: None,
        ..fix(3.0)
    };
    let b = stridekit::packed::pack_fixes(vec![f]);
    assert_eq!(b.len(), FIX_RECORD_BYTES);
    let at = |o: usize| f64::from_le_bytes(b[o..o + 8].try_into().unwrap());
    assert_eq!(at(0), 3.0);
    assert_eq!(at(8), f.lat_deg);
    assert_eq!(at(16), f.lon_deg);
    assert_eq!(at(24), 250.0);
    assert_eq!(at(32), 4.0);
    assert!(at(40).is_nan());
    assert!(at(48).is_nan());
    let decoded: Vec<core::GnssFix> = stridekit::packed::fixes(&b).unwrap().collect();
    assert_eq!(decoded, vec![core::GnssFix::from(f)]);

    let b = stridekit::packed::pack_step_counts(vec![
        count(1.5, 0x0102_0304_0506_0708),
        StepSample::Event { t_s: 2.0 }, // no packed form: skipped
    ]);
    assert_eq!(b.len(), STEP_COUNT_RECORD_BYTES);
    assert_eq!(&b[..8], &1.5f64.to_le_bytes());
    assert_eq!(&b[8..], &[8, 7, 6, 5, 4, 3, 2, 1]);
}

#[test]
fn packed_pushes_match_record_pushes() {
    let fixes: Vec<GnssFix> = (1..=30).map(|i| fix(i as f64)).collect();
    let counts: Vec<StepSample> = (0..30).map(|i| count(i as f64 + 0.5, 3 * i)).collect();

    let a = PaceTracker::with_defaults();
    let b = PaceTracker::with_defaults();
    let ra = a.push_step_samples(counts.clone());
    let rb = b
        .push_step_counts_packed(stridekit::packed::pack_step_counts(counts))
        .unwrap();
    assert_eq!(ra, rb);
    let ra = a.push_fixes(fixes.clone());
    let rb = b
        .push_fixes_packed(stridekit::packed::pack_fixes(fixes))
        .unwrap();
    assert_bit_identical(&to_core(&ra.estimates), &to_core(&rb.estimates));
    assert_eq!(a.snapshot(), b.snapshot());
}

#[test]
fn packed_errors() {
    let t = PaceTracker::with_defaults();
    let err = t.push_fixes_packed(vec![0u8; 55]).unwrap_err();
    assert!(matches!(err, PaceError::InvalidBuffer { .. }), "{err:?}");
    let err = t.push_step_counts_packed(vec![0u8; 17]).unwrap_err();
    assert!(matches!(err, PaceError::InvalidBuffer { .. }), "{err:?}");
    // A bad record inside a well-formed buffer is rejected by index, the rest pushed.
    let mut fixes: Vec<GnssFix> = (1..=3).map(|i| fix(i as f64)).collect();
    fixes[1].t_s = f64::NAN;
    let r = t
        .push_fixes_packed(stridekit::packed::pack_fixes(fixes))
        .unwrap();
    assert_eq!(r.estimates.len(), 2);
    assert_eq!(r.rejected.len(), 1);
    assert_eq!(r.rejected[0].index, 1);
}

// ---------------------------------------------------------------- snapshot, threads

#[test]
fn snapshot_restore_resumes_bit_identically() {
    let samples = short_run();
    let (half_a, half_b) = samples.split_at(samples.len() / 2);
    let original = PaceTracker::new(PaceConfig {
        initial_step_length_m: Some(1.0),
        ..default_pace_config()
    })
    .unwrap();
    original.push_samples(half_a.to_vec());
    let bytes = original.snapshot();
    let restored = PaceTracker::restore(bytes.clone()).unwrap();
    assert_eq!(restored.config(), original.config());
    assert_eq!(restored.estimate(), original.estimate());
    let ra = original.push_samples(half_b.to_vec());
    let rb = restored.push_samples(half_b.to_vec());
    assert_bit_identical(&to_core(&ra.estimates), &to_core(&rb.estimates));
    assert_eq!(original.snapshot(), restored.snapshot());
}

#[test]
fn concurrent_pushes_do_not_crash() {
    let t = PaceTracker::with_defaults();
    let handles: Vec<_> = (0..4)
        .map(|k| {
            let t = Arc::clone(&t);
            std::thread::spawn(move || {
                for i in 0..200 {
                    let time = (i * 4 + k) as f64;
                    // Interleaving makes some of these go back in time: errors, not crashes.
                    let _ = t.push_fixes(vec![fix(time)]);
                    let _ = t.push_steps(count(time, i as i64));
                    let _ = t.estimate();
                    if i % 50 == 0 {
                        let _ = t.snapshot();
                    }
                }
            })
        })
        .collect();
    for h in handles {
        h.join().unwrap();
    }
    assert!(PaceTracker::restore(t.snapshot()).is_ok());
}

// ---------------------------------------------------------------- simulated run

#[cfg(feature = "testing")]
#[test]
fn simulate_run_validates_duration() {
    assert!(matches!(
        simulate_run(1, f64::NAN),
        Err(PaceError::NonFinite { .. })
    ));
    assert!(matches!(
        simulate_run(1, 0.0),
        Err(PaceError::OutOfRange { .. })
    ));
    assert!(matches!(
        simulate_run(1, 1.0e9),
        Err(PaceError::OutOfRange { .. })
    ));
}

#[cfg(feature = "testing")]
#[test]
fn simulated_run_reference_matches_ffi_path() {
    let run = simulate_run(7, 300.0).unwrap();
    assert_eq!(run.samples.len(), run.fixes.len() + run.steps.len());
    let t = PaceTracker::with_defaults();
    let r = t.push_samples(run.samples.clone());
    assert_eq!(r.rejected.len() as i32, run.reference_rejected);
    assert_bit_identical(&to_core(&r.estimates), &to_core(&run.reference_estimates));
    assert_eq!(r.latest, run.reference_final);
    // Deterministic.
    assert_eq!(simulate_run(7, 300.0).unwrap(), run);
}

/// Fails while `stridekit_sim::simulate_run` is still a stub returning no data.
#[cfg(feature = "testing")]
#[test]
fn simulated_run_is_not_empty() {
    let run = simulate_run(7, 300.0).unwrap();
    assert!(run.fixes.len() > 100, "{} fixes", run.fixes.len());
    assert!(!run.steps.is_empty());
    assert_eq!(run.reference_rejected, 0);
    assert_eq!(run.reference_estimates.len(), run.fixes.len());
}
