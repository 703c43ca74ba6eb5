//! Garbage in, no panic out: the foot navigator fed adversarial input (NaN/∞,
//! values no IMU reports, time reversals and duplicates, huge gaps, saturated
//! samples, accelerations in g, random garbage) returns typed errors, leaves its state
//! byte-for-byte unchanged after a rejected sample, and never outputs a NaN.

use stridekit_core::foot::{
    AdaptiveThresholds, FixedThresholds, FootConfig, FootError, FootEstimate, FootNavigator,
    FootSample, ShoeDetector, SvmAdaptive, ZeroVelocityDetector,
};
use stridekit_core::input::InputError;
use stridekit_sim::{simulate_foot, FootScenario, Rng};

fn detectors() -> [ZeroVelocityDetector; 6] {
    [
        ZeroVelocityDetector::default(), // adaptive shoe
        ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ZeroVelocityDetector::Shoe(ShoeDetector::default()),
        ZeroVelocityDetector::Fixed(FixedThresholds::WALK),
        ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
        ZeroVelocityDetector::default_svm(),
    ]
}

fn finite_estimate(e: &FootEstimate) -> bool {
    e.is_finite()
        && e.position_std_m.iter().all(|v| *v >= 0.0)
        && (e.quaternion.iter().map(|q| q * q).sum::<f64>() - 1.0).abs() < 1e-6
}

/// Push one sample, checking the contract: an error leaves the state as it was, an
/// estimate is finite.
fn push_checked(
    nav: &mut FootNavigator,
    s: &FootSample,
) -> Result<Option<FootEstimate>, FootError> {
    // Only a sample that fails the door check is rejected: snapshot those.
    let before = nav.check(s).is_err().then(|| nav.snapshot());
    let r = nav.push(s);
    match &r {
        Err(e) => {
            let before = before.expect("check and push agree");
            assert_eq!(
                nav.snapshot(),
                before,
                "state changed by a rejected sample: {e}"
            );
        }
        Ok(Some(e)) => assert!(finite_estimate(e), "{s:?} → {e:?}"),
        Ok(None) => {}
    }
    if let Some(e) = nav.estimate() {
        assert!(finite_estimate(&e), "{e:?}");
    }
    r
}

fn pick(rng: &mut Rng, normal: f64) -> f64 {
    match rng.next_u64() % 16 {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => f64::NEG_INFINITY,
        3 => -1e12,
        4 => 0.0,
        5 => 1e-300,
        6 => rng.range(-1999.0, 1999.0),
        7 => 2000.0 * if rng.uniform() < 0.5 { -1.0 } else { 1.0 },
        _ => normal + 3.0 * rng.normal(),
    }
}

/// Mostly 50–1000 Hz spacing with reversals, duplicates, tiny steps and gaps. Gaps
/// longer than 1 s are rare: three such intervals in a row between accepted samples
/// are refused for good as a time-unit error (see stridekit_core::input).
fn next_t(rng: &mut Rng, t: &mut f64) -> f64 {
    *t += match rng.next_u64() % 400 {
        0..=9 => -rng.range(0.0, 0.5),
        10 => rng.range(0.0, 1e5),
        11..=20 => 0.0,
        21..=30 => 1e-12,
        31..=40 => rng.range(0.1, 0.9),
        _ => rng.range(0.001, 0.02),
    };
    *t
}

#[test]
fn garbage_after_a_clean_start_never_panics_or_goes_nan() {
    let sim = simulate_foot(&FootScenario::walk(21, 1));
    for (d, detector) in detectors().into_iter().enumerate() {
        for median_window in [1, 5] {
            let config = FootConfig {
                detector: detector.clone(),
                median_window,
                accel_range_mps2: Some(160.0),
                gyro_range_rads: Some(35.0),
                ..FootConfig::default()
            };
            let mut nav = FootNavigator::new(config).unwrap();
            let mut rng = Rng::new(100 + d as u64 * 2 + median_window as u64);
            let (mut ok, mut rejected, mut estimates) = (0, 0, 0);
            // A clean walk with corrupted samples mixed in, then pure garbage.
            let mut t = 0.0;
            for (i, clean) in sim.samples.iter().enumerate() {
                let s = if i > 600 && rng.next_u64() % 10 == 0 {
                    let mut s = *clean;
                    match rng.next_u64() % 5 {
                        0 => s.accel_mps2[(rng.next_u64() % 3) as usize] = pick(&mut rng, 0.0),
                        1 => s.gyro_rads[(rng.next_u64() % 3) as usize] = pick(&mut rng, 0.0),
                        2 => s.t_s = t - rng.range(0.0, 0.01),
                        3 => s.accel_mps2 = s.accel_mps2.map(|a| a / 9.80665),
                        _ => s.accel_mps2[2] = 200.0,
                    }
                    s
                } else {
                    *clean
                };
                match push_checked(&mut nav, &s) {
                    Ok(e) => {
                        ok += 1;
                        t = s.t_s;
                        estimates += e.is_some() as usize;
                    }
                    Err(_) => rejected += 1,
                }
            }
            assert!(nav.is_aligned());
            // The SVM's snapshot holds its model text: fewer rounds.
            let rounds = if d == 3 { 2_000 } else { 20_000 };
            for _ in 0..rounds {
                let g = if rng.next_u64() % 50 == 0 { 1.0 } else { 9.81 };
                let s = FootSample {
                    t_s: next_t(&mut rng, &mut t),
                    accel_mps2: [pick(&mut rng, 0.0), pick(&mut rng, 0.0), pick(&mut rng, g)],
                    gyro_rads: [
                        pick(&mut rng, 0.0),
                        pick(&mut rng, 0.0),
                        pick(&mut rng, 0.0),
                    ],
                };
                match push_checked(&mut nav, &s) {
                    Ok(e) => {
                        ok += 1;
                        estimates += e.is_some() as usize;
                    }
                    Err(_) => rejected += 1,
                }
            }
            eprintln!(
                "{} median {median_window}: {ok} accepted, {rejected} rejected, {estimates} \
                 estimates, {} divergence resets",
                nav.config().detector.name(),
                nav.divergence_resets()
            );
            assert!(estimates > rounds / 2);
            // The state still restores and continues.
            let restored = FootNavigator::restore(&nav.snapshot()).unwrap();
            assert_eq!(restored.snapshot(), nav.snapshot());
        }
    }
}

#[test]
fn garbage_from_the_first_sample() {
    for (d, detector) in detectors().into_iter().enumerate() {
        let mut nav = FootNavigator::new(FootConfig {
            detector,
            ..FootConfig::default()
        })
        .unwrap();
        let mut rng = Rng::new(7 + d as u64);
        let mut t = -1e6;
        for _ in 0..if d == 3 { 2_000 } else { 20_000 } {
            let s = FootSample {
                t_s: next_t(&mut rng, &mut t),
                accel_mps2: [
                    pick(&mut rng, 0.0),
                    pick(&mut rng, 0.0),
                    pick(&mut rng, 9.81),
                ],
                gyro_rads: [
                    pick(&mut rng, 0.0),
                    pick(&mut rng, 0.0),
                    pick(&mut rng, 0.0),
                ],
            };
            let _ = push_checked(&mut nav, &s);
        }
        let _ = FootNavigator::restore(&nav.snapshot()).unwrap();
    }
}

fn at_rest(t_s: f64) -> FootSample {
    FootSample {
        t_s,
        accel_mps2: [0.1, -0.2, 9.79],
        gyro_rads: [0.001, -0.002, 0.0005],
    }
}

fn aligned() -> FootNavigator {
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    for k in 0..200 {
        nav.push(&at_rest(k as f64 * 0.005)).unwrap();
    }
    assert!(nav.is_aligned());
    nav
}

/// Whether an error is the one expected.
type Expect = fn(&FootError) -> bool;

#[test]
fn typed_errors_at_the_door() {
    let mut nav = aligned();
    let t = 1.0;
    let cases: Vec<(FootSample, Expect)> = vec![
        (
            FootSample {
                t_s: f64::NAN,
                ..at_rest(t)
            },
            |e| matches!(e, FootError::Input(InputError::NonFinite { field: "t_s" })),
        ),
        (
            FootSample {
                t_s: f64::INFINITY,
                ..at_rest(t)
            },
            |e| matches!(e, FootError::Input(InputError::NonFinite { field: "t_s" })),
        ),
        (
            FootSample {
                accel_mps2: [0.0, f64::NAN, 9.8],
                ..at_rest(t)
            },
            |e| {
                matches!(
                    e,
                    FootError::Input(InputError::NonFinite {
                        field: "accel_y_mps2"
                    })
                )
            },
        ),
        (
            FootSample {
                gyro_rads: [f64::NEG_INFINITY, 0.0, 0.0],
                ..at_rest(t)
            },
            |e| {
                matches!(
                    e,
                    FootError::Input(InputError::NonFinite {
                        field: "gyro_x_rads"
                    })
                )
            },
        ),
        (
            FootSample {
                accel_mps2: [0.0, 0.0, 2000.1],
                ..at_rest(t)
            },
            |e| {
                matches!(
                    e,
                    FootError::Input(InputError::OutOfRange {
                        field: "accel_z_mps2",
                        ..
                    })
                )
            },
        ),
        (
            FootSample {
                gyro_rads: [0.0, -200.5, 0.0],
                ..at_rest(t)
            },
            |e| {
                matches!(
                    e,
                    FootError::Input(InputError::OutOfRange {
                        field: "gyro_y_rads",
                        ..
                    })
                )
            },
        ),
        (at_rest(0.995), |e| {
            matches!(e, FootError::Input(InputError::TimeNotIncreasing { .. }))
        }),
        (at_rest(0.5), |e| {
            matches!(e, FootError::Input(InputError::TimeNotIncreasing { .. }))
        }),
    ];
    for (s, is_expected) in cases {
        let err = push_checked(&mut nav, &s).unwrap_err();
        assert!(is_expected(&err), "{s:?}: {err}");
        assert!(!err.to_string().is_empty());
    }
    // A duplicate of the last accepted time.
    let last = nav.estimate().unwrap();
    let s = at_rest(199.0 * 0.005);
    assert!(matches!(
        push_checked(&mut nav, &s),
        Err(FootError::Input(InputError::TimeNotIncreasing { .. }))
    ));
    assert_eq!(nav.estimate(), Some(last));
    // Still works afterwards.
    assert!(push_checked(&mut nav, &at_rest(1.0)).unwrap().is_some());
}

#[test]
fn accelerations_in_g_are_refused_before_alignment() {
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    let s = FootSample {
        t_s: 0.0,
        accel_mps2: [0.01, -0.02, 1.0],
        gyro_rads: [0.0; 3],
    };
    match push_checked(&mut nav, &s) {
        Err(FootError::Input(InputError::AccelerationInG { mean_magnitude })) => {
            assert!((mean_magnitude - 1.0).abs() < 0.01)
        }
        other => panic!("{other:?}"),
    }
    assert!(!nav.is_aligned());
    // A whole recording in g never aligns and never changes the state.
    let sim = simulate_foot(&FootScenario::walk(22, 1));
    let before = nav.snapshot();
    let g: Vec<FootSample> = sim
        .samples
        .iter()
        .map(|s| FootSample {
            accel_mps2: s.accel_mps2.map(|a| a / 9.80665),
            ..*s
        })
        .collect();
    let outcome = nav.push_batch(&g[..400]);
    assert!(outcome.estimates.is_empty());
    assert_eq!(outcome.rejected.len(), 400);
    assert!(outcome.rejected.iter().all(|r| matches!(
        r.error,
        FootError::Input(InputError::AccelerationInG { .. })
    )));
    assert_eq!(nav.snapshot(), before);
}

#[test]
fn huge_gaps_are_flagged_and_stay_finite() {
    // (A jump to t ≈ 1e12 s is a time-unit error: see stridekit_core::input.)
    for gap in [0.2, 10.0, 3600.0, 1e7] {
        let mut nav = aligned();
        let t0 = nav.estimate().unwrap().t_s + 0.05;
        let mut t = t0;
        for _ in 0..5 {
            push_checked(&mut nav, &at_rest(t)).unwrap();
            t += 0.005;
        }
        t += gap;
        let mut flagged = 0;
        for _ in 0..400 {
            if let Some(e) = push_checked(&mut nav, &at_rest(t)).unwrap() {
                flagged += e.gap as usize;
            }
            t += 0.005;
        }
        assert_eq!(flagged, 1, "gap {gap}");
        let e = nav.estimate().unwrap();
        assert!(finite_estimate(&e), "gap {gap}: {e:?}");
        // At rest across the gap: the position did not run away.
        assert!(
            e.position_m.iter().all(|p| p.abs() < 1.0),
            "gap {gap}: {e:?}"
        );
    }
}

#[test]
fn repeated_huge_gaps_while_walking() {
    // Hours-long holes again and again, in the middle of strides.
    let sim = simulate_foot(&FootScenario::walk(23, 1));
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    let mut shift = 0.0;
    for (i, s) in sim.samples.iter().enumerate() {
        if i > 500 && i % 97 == 0 {
            shift += 3600.0 * (1 + i % 5) as f64;
        }
        let s = FootSample {
            t_s: s.t_s + shift,
            ..*s
        };
        push_checked(&mut nav, &s).unwrap();
    }
    assert!(finite_estimate(&nav.estimate().unwrap()));
}

#[test]
fn saturated_samples_are_flagged_and_never_stance() {
    let sim = simulate_foot(&FootScenario::walk(24, 1));
    for detector in detectors() {
        let mut nav = FootNavigator::new(FootConfig {
            detector: detector.clone(),
            accel_range_mps2: Some(16.0 * 9.80665),
            gyro_range_rads: Some(2000_f64.to_radians()),
            ..FootConfig::default()
        })
        .unwrap();
        let mut saturated = 0;
        let mut times = Vec::new();
        for (i, s) in sim.samples.iter().enumerate() {
            let mut s = *s;
            if i > 1000 && i % 500 == 0 {
                // A clipped impact during the stance.
                s.accel_mps2[2] = 16.0 * 9.80665;
                times.push(s.t_s);
            }
            if let Some(e) = push_checked(&mut nav, &s).unwrap() {
                if e.saturated {
                    saturated += 1;
                    assert!(
                        !e.stance,
                        "{}: saturated window used for a ZUPT",
                        detector.name()
                    );
                    assert!(times.contains(&e.t_s));
                }
            }
        }
        let last = nav.estimate().unwrap().t_s;
        let expected = times.iter().filter(|&&t| t <= last).count();
        assert!(expected > 5);
        assert_eq!(saturated, expected, "{}", detector.name());
    }
}

#[test]
fn batches_skip_and_report_bad_samples() {
    let sim = simulate_foot(&FootScenario::walk(25, 1));
    let mut samples = sim.samples[..2000].to_vec();
    samples[700].gyro_rads[1] = f64::NAN;
    samples[900].t_s = samples[899].t_s;
    samples[1200].accel_mps2[0] = 1e9;
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    let outcome = nav.push_batch(&samples);
    assert!(outcome.estimates.iter().all(finite_estimate));
    assert_eq!(
        outcome.rejected.iter().map(|r| r.index).collect::<Vec<_>>(),
        vec![700, 900, 1200]
    );
    assert_eq!(outcome.accepted, samples.len() - 3);
    // Same result as pushing only the good samples.
    let good: Vec<FootSample> = samples
        .iter()
        .enumerate()
        .filter(|(i, _)| ![700, 900, 1200].contains(i))
        .map(|(_, s)| *s)
        .collect();
    let mut clean = FootNavigator::new(FootConfig::default()).unwrap();
    clean.push_batch(&good);
    assert_eq!(clean.snapshot(), nav.snapshot());
}

#[test]
fn restore_never_panics_on_corrupted_snapshots() {
    let sim = simulate_foot(&FootScenario::walk(26, 1));
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    nav.push_batch(&sim.samples[..1500]);
    let bytes = nav.snapshot();
    let mut rng = Rng::new(5);
    for _ in 0..3000 {
        let mut b = bytes.clone();
        for _ in 0..1 + rng.next_u64() % 4 {
            let i = (rng.next_u64() as usize) % b.len();
            b[i] = rng.next_u64() as u8;
        }
        let _ = FootNavigator::restore(&b);
        let n = (rng.next_u64() as usize) % (b.len() + 1);
        let _ = FootNavigator::restore(&b[..n]);
    }
}

#[test]
fn invalid_configurations_are_typed_errors() {
    let bad = [
        FootConfig {
            median_window: 4,
            ..FootConfig::default()
        },
        FootConfig {
            detector_window_s: f64::NAN,
            ..FootConfig::default()
        },
        FootConfig {
            alignment_s: 0.0,
            ..FootConfig::default()
        },
        FootConfig {
            accel_range_mps2: Some(-1.0),
            ..FootConfig::default()
        },
        FootConfig {
            max_gap_s: f64::INFINITY,
            ..FootConfig::default()
        },
        FootConfig {
            initial_yaw_rad: f64::NAN,
            ..FootConfig::default()
        },
    ];
    for c in bad {
        assert!(matches!(
            FootNavigator::new(c),
            Err(FootError::InvalidConfig { .. })
        ));
    }
}
