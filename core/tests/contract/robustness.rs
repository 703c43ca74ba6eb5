//! Regression tests of the robustness findings (bad input must never freeze, poison or
//! lose a session): each failed before its fix.
//!
//! - a hang on huge timestamps;
//! - times in the wrong unit accepted silently;
//! - finite but absurd values poisoning state, and sessions that could not be resumed
//!   after that;
//! - restore trusting fields it did not check;
//! - model parsing cost without bound;
//! - a fresh navigator's NaN time, truncated snapshots reported as corrupted.
//!
//! (The FIT decoder panic is tested in formats/src/fit.rs.)

use stridekit_core::ahrs::{Ahrs, AhrsSettings, ImuSample};
use stridekit_core::foot::{
    AdaptiveThresholds, FootConfig, FootNavigator, FootSample, SvmModel, ZeroVelocityDetector,
};
use stridekit_core::geo::LocalFrame;
use stridekit_core::input::{InputError, LikelyTimeUnit};
use stridekit_core::odometry::{OdometryConfig, PhoneOdometry};
use stridekit_core::pace::{GnssFix, PaceConfig, PaceError, PaceSample, PaceTracker, StepSample};
use stridekit_core::pdr::{NavError, NavigatorConfig, PhoneNavigator};
use stridekit_core::placement::PlacementClassifier;
use stridekit_core::snapshot::{crc32, SnapshotError};
use stridekit_core::stepdetect::{StepDetectError, StepDetector};
use stridekit_core::steplength::{StepLengthConfig, StepLengthEstimator, StepLengthModel};
use stridekit_sim::phone::{simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario};
use stridekit_sim::{simulate_foot, simulate_run, FootScenario, RunScenario};

fn is_time_unit(e: &InputError, unit: LikelyTimeUnit) -> bool {
    matches!(e, InputError::TimeUnit { likely, .. } if *likely == unit)
}

fn phone_imu(seconds: f64) -> (Vec<ImuSample>, Vec<GnssFix>) {
    let sim = simulate_phone(&PhoneScenario::walk(
        11,
        PhonePlacement::InHand,
        1.3,
        seconds,
    ));
    let mut imu = Vec::new();
    let mut fixes = Vec::new();
    for e in sim.timeline(&LocalFrame::new(47.0, 8.0, 0.0)) {
        match e {
            PhoneEvent::Imu(s) => imu.push(ImuSample {
                t_s: s.t_s,
                gyro_rads: s.gyro_radps,
                accel_mps2: s.accel_mps2,
                mag_ut: Some(s.mag_ut),
            }),
            PhoneEvent::Fix(f) => fixes.push(f),
        }
    }
    (imu, fixes)
}

// ------------------------------------------------------------------ 1. the hang

#[test]
fn nanosecond_timestamps_after_days_of_uptime_return_at_once() {
    // 1e15 "s" is what an app sends that forgets to divide SensorEvent.timestamp by
    // 1e9 after about 12 days of uptime; the step detector's grid loop never ended.
    let mut d = StepDetector::default();
    for t in [1e15, 1e15 + 0.25] {
        match d.push_accel(t, [0.0, 0.0, 9.81]) {
            Err(StepDetectError::Input(e)) => {
                assert!(is_time_unit(&e, LikelyTimeUnit::Nanoseconds), "{e}")
            }
            other => panic!("{other:?}"),
        }
    }
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    assert!(matches!(
        p.push_accel(1e15, [0.0, 0.0, 9.81]),
        Err(PaceError::Input(InputError::TimeUnit { .. }))
    ));
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let s = ImuSample {
        t_s: 1e15,
        gyro_rads: [0.0; 3],
        accel_mps2: [0.0, 0.0, 9.81],
        mag_ut: None,
    };
    assert!(matches!(
        nav.push_imu(&s),
        Err(NavError::Input(InputError::TimeUnit { .. }))
    ));
}

// ------------------------------------------------------------------ 2. time units

#[test]
fn gnss_fixes_in_milliseconds_or_nanoseconds_are_refused_with_the_unit() {
    // Unix time in milliseconds (Location.getTime()).
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    let e = p.push_fix(&GnssFix::new(1.7e12, 47.0, 8.0)).unwrap_err();
    assert!(
        matches!(&e, PaceError::Input(i) if is_time_unit(i, LikelyTimeUnit::Milliseconds)),
        "{e}"
    );
    assert!(e.to_string().contains("milliseconds"), "{e}");
    // Milliseconds since boot, 1 Hz: the third interval of 1 000 "s" is refused.
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    let t0 = 8.64e7;
    let mut refused = None;
    for k in 0..10 {
        let f = GnssFix::new(t0 + 1000.0 * k as f64, 47.0 + 1e-5 * k as f64, 8.0);
        if let Err(e) = p.push_fix(&f) {
            refused = Some((k, e));
            break;
        }
    }
    let (k, e) = refused.expect("millisecond fixes accepted");
    assert_eq!(k, 3);
    assert!(
        matches!(&e, PaceError::Input(i) if is_time_unit(i, LikelyTimeUnit::Milliseconds)),
        "{e}"
    );
    // Nanoseconds since boot: refused by their size after 100 s of uptime.
    let e = p.push_fix(&GnssFix::new(3.0e14, 47.0, 8.0)).unwrap_err();
    assert!(matches!(&e, PaceError::Input(i) if is_time_unit(i, LikelyTimeUnit::Nanoseconds)));
}

#[test]
fn a_fix_jumping_to_unix_milliseconds_is_refused() {
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    p.push_fix(&GnssFix::new(163.0, 47.0, 8.0)).unwrap();
    let e = p.push_fix(&GnssFix::new(1.7e12, 47.0, 8.0)).unwrap_err();
    assert!(
        matches!(e, PaceError::Input(InputError::TimeUnit { .. })),
        "{e}"
    );
    // A jump of decades within seconds-sized times is a clock change.
    let e = p
        .push_fix(&GnssFix::new(163.0 + 1.7e9, 47.0, 8.0))
        .unwrap_err();
    assert!(
        matches!(e, PaceError::Input(InputError::TimeJump { .. })),
        "{e}"
    );
}

#[test]
fn imu_samples_in_nanoseconds_are_refused_not_silently_stepless() {
    let (imu, _) = phone_imu(20.0);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let mut d = StepDetector::default();
    let mut refused = (0, 0);
    for s in &imu {
        // Nanoseconds since boot, 30 s of uptime (under the size limit).
        let ns = ImuSample {
            t_s: 30e9 + s.t_s * 1e9,
            ..*s
        };
        match nav.push_imu(&ns) {
            Err(NavError::Input(e)) if is_time_unit(&e, LikelyTimeUnit::Nanoseconds) => {
                refused.0 += 1
            }
            Err(e) => panic!("{e}"),
            Ok(()) => {}
        }
        match d.push_accel(ns.t_s, ns.accel_mps2) {
            Err(StepDetectError::Input(e)) if is_time_unit(&e, LikelyTimeUnit::Nanoseconds) => {
                refused.1 += 1
            }
            Err(e) => panic!("{e}"),
            Ok(_) => {}
        }
    }
    // Everything from the fourth sample on is refused, with the unit named.
    assert_eq!(refused, (imu.len() - 3, imu.len() - 3));
}

// ------------------------------------------------------------------ 3 + 4. absurd values

#[test]
fn finite_but_absurd_values_are_refused_or_harmless_and_the_state_resumes() {
    let (imu, fixes) = phone_imu(10.0);
    let mut a = Ahrs::new(AhrsSettings::default()).unwrap();
    for s in &imu[..300] {
        a.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)
            .unwrap();
    }
    let t = imu[300].t_s;
    let g = [0.0, 0.0, 9.81];
    let m = Some([20.0, 0.0, -40.0]);
    for (i, (gyro, accel, mag)) in [
        ([0.0; 3], [1e300, 0.0, 0.0], m),
        ([1e300, 0.0, 0.0], g, m),
        ([0.0; 3], g, Some([1e200, 0.0, 0.0])),
    ]
    .into_iter()
    .enumerate()
    {
        let e = a.update(t + i as f64 * 0.01, gyro, accel, mag).unwrap_err();
        assert!(
            matches!(
                e,
                stridekit_core::ahrs::AhrsError::Input(InputError::OutOfRange { .. })
            ),
            "{e}"
        );
    }
    // A vector too short to give a direction is accepted and ignored (free fall).
    a.update(
        t + 0.05,
        [0.0; 3],
        [0.0, 0.0, 1e-160],
        Some([0.0, 0.0, 1e-160]),
    )
    .unwrap();
    a.update(t + 0.06, [0.0; 3], g, m).unwrap();
    let q = a.quaternion().unwrap();
    assert!(q.iter().all(|c| c.is_finite()), "{q:?}");
    let again = Ahrs::restore(&a.snapshot()).unwrap();
    assert_eq!(again.snapshot(), a.snapshot());

    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    for s in &imu[..300] {
        nav.push_imu(s).unwrap();
    }
    let bad = ImuSample {
        t_s: t,
        gyro_rads: [1e300, 0.0, 0.0],
        ..imu[300]
    };
    assert!(matches!(
        nav.push_imu(&bad),
        Err(NavError::Input(InputError::OutOfRange { .. }))
    ));
    let again = PhoneNavigator::restore(&nav.snapshot()).unwrap();
    assert_eq!(again.snapshot(), nav.snapshot());

    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    p.push_fix(&fixes[0]).unwrap();
    assert!(p
        .push_steps(&StepSample::Count {
            t_s: 1e200,
            steps: 100
        })
        .is_err());
    let e = p.estimate().unwrap();
    assert!(e.speed_std_mps.is_none_or(f64::is_finite), "{e:?}");
    let again = PaceTracker::restore(&p.snapshot()).unwrap();
    assert_eq!(again.snapshot(), p.snapshot());
}

/// Found by the Kotlin stress test: counts a few seconds apart after a pause put all
/// their steps into one second (638 steps/min from 12 steps in 5 s; 120 641 steps/min
/// from 2500 steps in 1000 s), and the tracker's own snapshot was then refused.
#[test]
fn sparse_step_counts_give_a_human_cadence_and_a_restorable_session() {
    for (gap_s, steps) in [(5.0, 12), (1000.0, 2500), (3.0, 30)] {
        let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
        for (t, n) in [(1000.0, 0), (1000.0 + gap_s, steps)] {
            p.push_steps(&StepSample::Count { t_s: t, steps: n })
                .unwrap();
        }
        let est = p.estimate().unwrap();
        let spm = est.cadence_spm.unwrap_or(0.0);
        assert!(spm <= 300.0, "{gap_s} s, {steps} steps: {spm} steps/min");
        if gap_s == 5.0 {
            assert!(
                (120.0..=200.0).contains(&spm),
                "12 steps in 5 s: {spm} steps/min"
            );
        }
        let back = PaceTracker::restore(&p.snapshot())
            .unwrap_or_else(|e| panic!("{gap_s} s, {steps} steps: own snapshot refused: {e}"));
        assert_eq!(back.snapshot(), p.snapshot());
    }
}

/// Found by fuzzing (sequence_ahrs): samples 1e-91 s apart near t = 0 were accepted,
/// the filter's accelerometer average took a rate of 1e91 and the AHRS's own snapshot
/// was refused. A sample less than 1 µs after the previous one is refused now: a
/// duplicate when the two times are equal up to their rounding, else a unit mistake
/// (no sensor samples at a MHz: issue 36).
#[test]
fn sub_microsecond_intervals_are_refused_in_every_engine() {
    let g = [0.0, 0.0, 9.81];
    let mut a = Ahrs::new(AhrsSettings::default()).unwrap();
    a.update(-2.8e-91, [0.1; 3], g, None).unwrap();
    let e = a.update(2.3e-144, [0.1; 3], g, None).unwrap_err();
    assert!(e.to_string().contains("finer than any sensor"), "{e}");
    a.update(1e-6, [0.1; 3], g, None).unwrap();
    Ahrs::restore(&a.snapshot()).unwrap();
    let mut d = StepDetector::default();
    d.push_accel(5.0, g).unwrap();
    assert!(d.push_accel(5.0 + 1e-7, g).is_err());
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    p.push_fix(&GnssFix::new(10.0, 47.0, 8.0)).unwrap();
    assert!(p.push_fix(&GnssFix::new(10.0 + 5e-7, 47.0, 8.0)).is_err());
}

#[test]
fn a_step_count_jump_no_runner_makes_is_a_counter_reset() {
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    for k in 0..20u64 {
        let t = k as f64;
        p.push_steps(&StepSample::Count {
            t_s: t,
            steps: 1000 + 3 * k,
        })
        .unwrap();
    }
    // 10^15 steps in one second.
    p.push_steps(&StepSample::Count {
        t_s: 20.0,
        steps: 1_000_000_000_000_000,
    })
    .unwrap();
    assert_eq!(p.step_counter_resets(), 1);
    let e = p.estimate().unwrap();
    assert!(e.speed_mps.is_finite() && e.distance_m < 1e3, "{e:?}");
}

// ------------------------------------------------------------------ 5. restore checks all

/// Writes `v` over the 8 bytes at `at` and recomputes the checksum, so the change
/// reaches the field decoding.
fn with_f64(snapshot: &[u8], at: usize, v: f64) -> Vec<u8> {
    let mut b = snapshot.to_vec();
    b[at..at + 8].copy_from_slice(&v.to_bits().to_le_bytes());
    let n = b.len() - 4;
    let crc = crc32(&b[..n]);
    b[n..].copy_from_slice(&crc.to_le_bytes());
    b
}

/// NaN and ±∞; beyond the reader's backstop; under it but beyond any physical
/// range; tiny.
const POISON: [f64; 5] = [f64::NAN, f64::INFINITY, -1e300, 1e29, 1e-300];

/// Every poison value at every byte offset of a snapshot: restore refuses it, or the
/// restored engine keeps giving finite output and its snapshot round-trips.
fn poison_everywhere<T>(
    what: &str,
    snapshot: &[u8],
    restore: impl Fn(&[u8]) -> Result<T, String>,
    run_on: impl Fn(&mut T) -> bool,
    snap: impl Fn(&T) -> Vec<u8>,
) {
    poison_from(what, snapshot, 11, 1, restore, run_on, snap)
}

/// Offset after the `n`-th length-prefixed blob (model texts, nested snapshots)
/// starting at `at`, with `gap` bytes of other fields between blobs.
fn after_blobs(snapshot: &[u8], mut at: usize, gaps: &[usize]) -> usize {
    for g in gaps {
        let len = u64::from_le_bytes(snapshot[at..at + 8].try_into().unwrap()) as usize;
        at += 8 + len + g;
    }
    at
}

/// As [`poison_everywhere`], from byte `start` on (past model texts, which their
/// parsers' own tests cover, and nested snapshots, which their engines' do), at
/// every `step`-th byte (large snapshots of slow engines).
fn poison_from<T>(
    what: &str,
    snapshot: &[u8],
    start: usize,
    step: usize,
    restore: impl Fn(&[u8]) -> Result<T, String>,
    run_on: impl Fn(&mut T) -> bool,
    snap: impl Fn(&T) -> Vec<u8>,
) {
    let (mut accepted, mut tried) = (0, 0);
    for at in (start..snapshot.len() - 12).step_by(step) {
        tried += POISON.len();
        for v in POISON {
            let bytes = with_f64(snapshot, at, v);
            let Ok(mut e) = restore(&bytes) else {
                continue;
            };
            accepted += 1;
            assert!(
                run_on(&mut e),
                "{what}: {v} at byte {at} gave non-finite output"
            );
            let s = snap(&e);
            let back = restore(&s).unwrap_or_else(|e| panic!("{what}: {v} at {at}: {e}"));
            assert_eq!(snap(&back), s, "{what}: {v} at byte {at}");
        }
    }
    eprintln!(
        "{what}: {tried} mutations of {} bytes, {accepted} restored",
        snapshot.len() - start
    );
}

#[test]
fn restore_refuses_poisoned_numbers_of_the_pace_tracker() {
    let samples = simulate_run(&RunScenario::demo(5)).samples();
    let (head, tail) = samples[..400].split_at(300);
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    for s in head {
        let _ = p.push(s);
    }
    let tail: Vec<PaceSample> = tail.to_vec();
    poison_everywhere(
        "pace",
        &p.snapshot(),
        |b| PaceTracker::restore(b).map_err(|e| e.to_string()),
        |p| {
            tail.iter().all(|s| match p.push(s) {
                Ok(Some(e)) => e.speed_mps.is_finite() && e.distance_m.is_finite(),
                _ => true,
            }) && p
                .estimate()
                .unwrap()
                .speed_std_mps
                .is_none_or(f64::is_finite)
        },
        |p| p.snapshot(),
    );
}

#[test]
fn restore_refuses_poisoned_numbers_of_the_phone_engines() {
    let (imu, _) = phone_imu(12.0);
    let (head, tail) = imu.split_at(500);
    let tail = &tail[..100];
    let mut a = Ahrs::new(AhrsSettings::default()).unwrap();
    let mut d = StepDetector::default();
    for s in head {
        a.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)
            .unwrap();
        d.push_accel(s.t_s, s.accel_mps2).unwrap();
    }
    poison_everywhere(
        "ahrs",
        &a.snapshot(),
        |b| Ahrs::restore(b).map_err(|e| e.to_string()),
        |a| {
            tail.iter().all(|s| {
                a.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)
                    .is_err()
                    || a.output().is_some_and(|o| {
                        o.quaternion.iter().all(|q| q.is_finite())
                            && o.linear_accel_earth_mps2.iter().all(|v| v.is_finite())
                    })
            })
        },
        |a| a.snapshot(),
    );
    poison_everywhere(
        "step detector",
        &d.snapshot(),
        |b| StepDetector::restore(b).map_err(|e| e.to_string()),
        |d| {
            tail.iter()
                .all(|s| match d.push_accel(s.t_s, s.accel_mps2) {
                    Ok(Some(e)) => e.t_s.is_finite(),
                    _ => true,
                })
        },
        |d| d.snapshot(),
    );
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    for s in head {
        nav.push_imu(s).unwrap();
    }
    poison_everywhere(
        "phone navigator",
        &nav.snapshot(),
        |b| PhoneNavigator::restore(b).map_err(|e| e.to_string()),
        |n| {
            tail.iter().all(|s| {
                let _ = n.push_imu(s);
                n.estimate().is_none_or(|e| {
                    e.east_m.is_finite() && e.north_m.is_finite() && e.distance_m.is_finite()
                })
            })
        },
        |n| n.snapshot(),
    );
}

#[test]
fn restore_refuses_poisoned_numbers_of_the_step_length_estimator() {
    let sim = simulate_phone(&PhoneScenario::walk(4, PhonePlacement::InHand, 1.3, 60.0));
    let steps = sim.step_events();
    let mut est =
        StepLengthEstimator::new(StepLengthModel::Linear, StepLengthConfig::default()).unwrap();
    let fixes = &sim.fixes;
    let mut fi = 0;
    let (head, tail) = steps.split_at(steps.len() - 10);
    for s in head {
        while fi < fixes.len() && fixes[fi].t_s <= s.t_s {
            let f = &fixes[fi];
            est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m))
                .unwrap();
            fi += 1;
        }
        est.push_step(s).unwrap();
    }
    poison_everywhere(
        "step length",
        &est.snapshot(),
        |b| StepLengthEstimator::restore(b).map_err(|e| e.to_string()),
        |e| {
            tail.iter()
                .all(|s| e.push_step(s).map_or(true, |l| l.is_finite() && l >= 0.0))
        },
        |e| e.snapshot(),
    );
}

#[test]
fn restore_refuses_poisoned_numbers_of_the_foot_navigator() {
    let sim = simulate_foot(&FootScenario::walk(3, 1));
    // The adaptive detector: the SVM's snapshot carries its model text (checked by
    // the model parser's own tests) and makes every restore slow.
    let config = FootConfig {
        detector: ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
        ..FootConfig::default()
    };
    let mut n = FootNavigator::new(config).unwrap();
    let (head, tail) = sim.samples.split_at(1500);
    for s in head {
        n.push(s).unwrap();
    }
    let tail: Vec<FootSample> = tail[..60].to_vec();
    poison_everywhere(
        "foot",
        &n.snapshot(),
        |b| FootNavigator::restore(b).map_err(|e| e.to_string()),
        |n| {
            tail.iter().all(|s| match n.push(s) {
                Ok(Some(e)) => e.is_finite(),
                _ => true,
            }) && n.estimate().is_none_or(|e| e.is_finite())
        },
        |n| n.snapshot(),
    );
}

#[test]
fn restore_refuses_poisoned_numbers_of_the_placement_classifier_and_odometry() {
    let (imu, _) = phone_imu(12.0);
    let (head, tail) = imu.split_at(900);
    let tail = &tail[..40];
    let mut c = PlacementClassifier::shipped();
    for s in head {
        c.push(&s.into()).unwrap();
    }
    let snap = c.snapshot();
    poison_from(
        "placement",
        &snap,
        after_blobs(&snap, 11, &[0]),
        2,
        |b| PlacementClassifier::restore(b).map_err(|e| e.to_string()),
        |c| {
            tail.iter().all(|s| match c.push(&s.into()) {
                Ok(Some(e)) => e.probabilities.iter().all(|p| p.is_finite()),
                _ => true,
            })
        },
        |c| c.snapshot(),
    );
    let mut o = PhoneOdometry::shipped(OdometryConfig::default()).unwrap();
    let sample = |s: &ImuSample| ImuSample {
        t_s: s.t_s,
        accel_mps2: s.accel_mps2,
        gyro_rads: s.gyro_rads,
        mag_ut: s.mag_ut,
    };
    for s in head {
        o.push(&sample(s)).unwrap();
    }
    // Past the model text, the AHRS snapshot, two flags and the placement source, and
    // the classifier's snapshot.
    let snap = o.snapshot();
    poison_from(
        "odometry",
        &snap,
        after_blobs(&snap, 11, &[0, 3, 0]),
        7,
        |b| PhoneOdometry::restore(b).map_err(|e| e.to_string()),
        |o| {
            tail.iter().all(|s| match o.push(&sample(s)) {
                Ok(Some(e)) => e.position_m.iter().all(|v| v.is_finite()),
                _ => true,
            })
        },
        |o| o.snapshot(),
    );
}

// ------------------------------------------------------------------ 6. model cost

#[test]
fn oversized_svm_models_are_refused_before_any_work() {
    // 100 000 support vectors in one block took 16 s to load.
    let block = |n: usize| {
        let mut text = String::from("stridekit-zupt-svm 1\n");
        text.push_str(&format!(
            "svm acc_x gamma 0.5 rho 0 mean 0 0 sd 1 1 box -3 3 -3 3 n {n}\n"
        ));
        for _ in 0..n {
            text.push_str("0.1 0.2 0.3\n");
        }
        text
    };
    let e = SvmModel::parse(&block(100_000)).unwrap_err();
    assert!(e.to_string().contains("larger than"), "{e}");
    let e = SvmModel::parse(&block(10_000)).unwrap_err();
    assert!(e.to_string().contains("n must be"), "{e}");
    let huge = "#".repeat(2 << 20);
    assert!(SvmModel::parse(&format!("stridekit-zupt-svm 1\n{huge}")).is_err());
}

// ------------------------------------------------------------------ 8. smaller

#[test]
fn a_fresh_navigator_has_no_estimate_and_cut_snapshots_are_truncated() {
    let nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    assert!(nav.estimate().is_none());
    let snap = nav.snapshot();
    for cut in [snap.len() - 1, snap.len() / 2, 12] {
        assert!(
            matches!(
                PhoneNavigator::restore(&snap[..cut]),
                Err(NavError::Snapshot(SnapshotError::Truncated))
            ),
            "cut at {cut}"
        );
    }
    let p = PaceTracker::new(PaceConfig::default()).unwrap().snapshot();
    assert!(matches!(
        PaceTracker::restore(&p[..p.len() - 3]),
        Err(PaceError::Snapshot(SnapshotError::Truncated))
    ));
}
