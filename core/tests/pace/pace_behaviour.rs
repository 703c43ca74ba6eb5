//! What users expect from the pace tracker, beyond accuracy: standing still, GNSS
//! outages and recovery, trustworthy learning, bad input, and snapshot/restore.

use stridekit_core::geo::LocalFrame;
use stridekit_core::input::InputError;
use stridekit_core::{
    GnssFix, PaceConfig, PaceError, PaceEstimate, PaceMode, PaceSample, PaceSource, PaceTracker,
    StepSample,
};
use stridekit_sim::{simulate_run, Rng, RunScenario, SimulatedRun, StepReport, ZoneKind};

/// Recognises the expected error of a rejected sample.
type ErrorCheck = fn(&PaceError) -> bool;

fn configs() -> [PaceConfig; 2] {
    [PaceConfig::default(), PaceConfig::as_published()]
}

fn replay(tr: &mut PaceTracker, samples: &[PaceSample]) -> Vec<PaceEstimate> {
    samples
        .iter()
        .map(|s| {
            tr.push(s).expect("valid sample");
            tr.estimate().unwrap()
        })
        .collect()
}

/// Fixes of a receiver that does not move: white noise plus a slow drift, 1 Hz.
fn standing_fixes(seconds: usize, seed: u64) -> Vec<GnssFix> {
    let frame = LocalFrame::new(52.2, 0.12, 0.0);
    let mut rng = Rng::new(seed);
    let (mut be, mut bn) = (0.0, 0.0);
    (0..seconds)
        .map(|i| {
            be = 0.98 * be + 0.3 * rng.normal();
            bn = 0.98 * bn + 0.3 * rng.normal();
            let (lat, lon) = frame.to_geodetic(be + 1.5 * rng.normal(), bn + 1.5 * rng.normal());
            GnssFix::new(i as f64, lat, lon).with_accuracy(4.0)
        })
        .collect()
}

#[test]
fn standing_still_reads_zero_and_adds_no_distance() {
    let fixes = standing_fixes(600, 11);
    // With a step counter that does not move.
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    for f in &fixes {
        tr.push_steps(&StepSample::Count {
            t_s: f.t_s - 0.5,
            steps: 4242,
        })
        .unwrap();
        let e = tr.push_fix(f).unwrap();
        if f.t_s > 5.0 {
            assert_eq!(e.speed_mps, 0.0, "speed at {}", f.t_s);
            assert_eq!(e.source, PaceSource::Stationary);
            assert_eq!(e.pace_s_per_km, None);
        }
    }
    assert!(
        tr.estimate().unwrap().distance_m < 1.0,
        "{}",
        tr.estimate().unwrap().distance_m
    );

    // GNSS only (no step data at all): jitter must not become distance either.
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let mut still = 0;
    for f in &fixes {
        if tr.push_fix(f).unwrap().source == PaceSource::Stationary {
            still += 1;
        }
    }
    let d = tr.estimate().unwrap().distance_m;
    assert!(
        d < 30.0,
        "GNSS-only distance while standing 10 min: {d} m ({still} still)"
    );
    assert!(still > 500, "stationary epochs: {still} of 600");
}

fn outage_run() -> SimulatedRun {
    simulate_run(&RunScenario::demo(2))
}

#[test]
fn outages_keep_pace_and_distance_and_recover_without_a_jump() {
    let run = outage_run();
    let samples = run.samples();
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let est = replay(&mut tr, &samples);
    let at = |t: f64| {
        let i = samples.partition_point(|s| s.t_s() <= t);
        est[i.saturating_sub(1)]
    };
    let outages: Vec<_> = run
        .zones
        .iter()
        .filter(|z| z.kind == ZoneKind::Outage)
        .collect();
    assert!(!outages.is_empty());
    for z in outages {
        // Distance keeps growing through the outage, close to the truth.
        let d_est = at(z.end_s - 0.5).distance_m - at(z.start_s).distance_m;
        let d_true = run.truth_at(z.end_s - 0.5).distance_m - run.truth_at(z.start_s).distance_m;
        let err = (d_est - d_true).abs() / d_true;
        assert!(err < 0.10, "outage {z:?}: {d_est:.0} m vs {d_true:.0} m");
        // Pace is there all along, from the pedometer.
        for k in 1..(z.end_s - z.start_s) as usize {
            let t = z.start_s + k as f64;
            let e = at(t);
            if run.truth_at(t).speed_mps > 1.0 {
                assert!(e.speed_mps > 0.5, "no pace at {t} s in an outage");
                assert!(
                    e.gnss_weight < 0.01,
                    "GNSS weight {} in an outage",
                    e.gnss_weight
                );
            }
        }
        // First fix after the outage: no jump in speed.
        let before = at(z.end_s - 0.5).speed_mps;
        let first_fix = run.fixes.iter().find(|f| f.t_s >= z.end_s).unwrap();
        let after = at(first_fix.t_s).speed_mps;
        let truth_change =
            (run.truth_at(first_fix.t_s).speed_mps - run.truth_at(z.end_s - 0.5).speed_mps).abs();
        assert!(
            (after - before).abs() < 0.5 + truth_change,
            "jump at {} s: {before:.2} -> {after:.2} m/s",
            first_fix.t_s
        );
    }
}

#[test]
fn step_length_is_not_learned_from_untrustworthy_gnss() {
    // After 10 minutes of clean GNSS, GNSS goes bad for 5 minutes (reported accuracy
    // 25 m, positions wandering by tens of metres). Bad GNSS must teach the step
    // length exactly as much as no GNSS at all: nothing.
    let mut scenario = RunScenario::clean(5);
    scenario.duration_s = 900.0;
    let run = simulate_run(&scenario);
    let frame = LocalFrame::new(scenario.origin_lat_deg, scenario.origin_lon_deg, 0.0);
    let mut rng = Rng::new(99);
    let (mut be, mut bn) = (0.0, 0.0);
    let mut bad = Vec::new();
    let mut none = Vec::new();
    for s in run.samples() {
        match s {
            PaceSample::Fix(f) if f.t_s > 600.0 => {
                be = 0.9 * be + 6.0 * rng.normal();
                bn = 0.9 * bn + 6.0 * rng.normal();
                let p = frame.to_enu(f.lat_deg, f.lon_deg, 0.0);
                let (lat, lon) = frame.to_geodetic(p[0] + be, p[1] + bn);
                bad.push(PaceSample::Fix(GnssFix {
                    lat_deg: lat,
                    lon_deg: lon,
                    horizontal_accuracy_m: Some(25.0),
                    ..f
                }));
            }
            other => {
                bad.push(other);
                none.push(other);
            }
        }
    }
    let end = |samples: &[PaceSample]| {
        let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
        replay(&mut tr, samples)
            .last()
            .unwrap()
            .step_length_m
            .unwrap()
    };
    let (with_bad, without) = (end(&bad), end(&none));
    assert!(
        (with_bad - without).abs() / without < 0.01,
        "bad GNSS moved the step length: {with_bad:.3} m vs {without:.3} m without GNSS"
    );
    let truth = run.truth_at(899.0).step_length_m;
    assert!(
        (without - truth).abs() / truth < 0.15,
        "{without} vs {truth}"
    );
}

#[test]
fn bad_input_is_rejected_with_typed_errors_and_leaves_state_untouched() {
    for config in configs() {
        let run = simulate_run(&RunScenario::demo(3));
        let samples = run.samples();
        let mut tr = PaceTracker::new(config).unwrap();
        replay(&mut tr, &samples[..400]);
        let last_fix = run
            .fixes
            .iter()
            .rfind(|f| f.t_s <= samples[399].t_s())
            .copied()
            .unwrap();
        let t = samples[399].t_s() + 0.5;
        let fix = GnssFix::new(t, last_fix.lat_deg, last_fix.lon_deg);
        let bad: Vec<(PaceSample, ErrorCheck)> = vec![
            (
                PaceSample::Fix(GnssFix {
                    lat_deg: f64::NAN,
                    ..fix
                }),
                |e| {
                    matches!(
                        e,
                        PaceError::Input(InputError::NonFinite { field: "lat_deg" })
                    )
                },
            ),
            (
                PaceSample::Fix(GnssFix {
                    lat_deg: 91.0,
                    ..fix
                }),
                |e| {
                    matches!(
                        e,
                        PaceError::Input(InputError::OutOfRange {
                            field: "lat_deg",
                            ..
                        })
                    )
                },
            ),
            (
                PaceSample::Fix(GnssFix {
                    lon_deg: -180.5,
                    ..fix
                }),
                |e| {
                    matches!(
                        e,
                        PaceError::Input(InputError::OutOfRange {
                            field: "lon_deg",
                            ..
                        })
                    )
                },
            ),
            (
                PaceSample::Fix(GnssFix {
                    t_s: f64::INFINITY,
                    ..fix
                }),
                |e| matches!(e, PaceError::Input(InputError::NonFinite { field: "t_s" })),
            ),
            (
                PaceSample::Fix(GnssFix {
                    horizontal_accuracy_m: Some(-1.0),
                    ..fix
                }),
                |e| matches!(e, PaceError::Input(InputError::OutOfRange { .. })),
            ),
            (
                PaceSample::Fix(GnssFix {
                    speed_mps: Some(f64::NAN),
                    ..fix
                }),
                |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
            ),
            (
                PaceSample::Fix(GnssFix {
                    t_s: last_fix.t_s,
                    ..fix
                }),
                |e| matches!(e, PaceError::Input(InputError::TimeNotIncreasing { .. })),
            ),
            (
                PaceSample::Fix(GnssFix {
                    t_s: last_fix.t_s - 30.0,
                    ..fix
                }),
                |e| matches!(e, PaceError::Input(InputError::TimeNotIncreasing { .. })),
            ),
            (
                PaceSample::Steps(StepSample::Event { t_s: f64::NAN }),
                |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
            ),
            (PaceSample::Steps(StepSample::Event { t_s: 1.0 }), |e| {
                matches!(e, PaceError::Input(InputError::TimeNotIncreasing { .. }))
            }),
            (
                PaceSample::Steps(StepSample::Cadence {
                    t_s: t,
                    steps_per_min: 1e6,
                }),
                |e| matches!(e, PaceError::Input(InputError::OutOfRange { .. })),
            ),
        ];
        for (sample, expected) in &bad {
            let before = tr.snapshot();
            let err = tr.push(sample).expect_err("bad sample accepted");
            assert!(expected(&err), "{sample:?} gave {err:?}");
            assert!(!err.to_string().is_empty());
            assert_eq!(
                tr.snapshot(),
                before,
                "state changed by rejected {sample:?}"
            );
        }
        // ... and the tracker keeps working.
        let out = replay(&mut tr, &samples[400..]);
        assert!(out
            .iter()
            .all(|e| e.speed_mps.is_finite() && e.distance_m.is_finite()));
        assert!(out.last().unwrap().distance_m > 1000.0);
    }
}

#[test]
fn step_counter_reset_is_handled() {
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    tr.push_steps(&StepSample::Count {
        t_s: 0.0,
        steps: 90_000,
    })
    .unwrap();
    tr.push_steps(&StepSample::Count {
        t_s: 1.0,
        steps: 90_003,
    })
    .unwrap();
    // Reboot: the platform counter restarts near zero.
    tr.push_steps(&StepSample::Count { t_s: 2.0, steps: 2 })
        .unwrap();
    tr.push_steps(&StepSample::Count { t_s: 3.0, steps: 5 })
        .unwrap();
    assert_eq!(tr.step_counter_resets(), 1);
}

#[test]
fn batch_push_equals_single_pushes_and_reports_rejections() {
    let run = simulate_run(&RunScenario::demo(4));
    let mut samples = run.samples();
    samples.truncate(600);
    let mut bad_batch = samples.clone();
    bad_batch.insert(100, PaceSample::Steps(StepSample::Event { t_s: f64::NAN }));
    bad_batch.insert(300, bad_batch[250]);
    for config in configs() {
        let mut a = PaceTracker::new(config).unwrap();
        let singles: Vec<PaceEstimate> =
            samples.iter().filter_map(|s| a.push(s).unwrap()).collect();
        let mut b = PaceTracker::new(config).unwrap();
        let out = b.push_batch(&bad_batch);
        assert_eq!(out.estimates, singles);
        let idx: Vec<usize> = out.rejected.iter().map(|r| r.index).collect();
        assert_eq!(idx, vec![100, 300]);
        assert_eq!(a.snapshot(), b.snapshot());
    }
}

#[test]
fn a_run_split_at_any_point_and_restored_gives_the_same_output() {
    for (mode, report) in [
        (PaceMode::Adaptive, StepReport::CountEverySecond),
        (PaceMode::Adaptive, StepReport::Events),
        (PaceMode::AsPublished, StepReport::CadenceEverySecond),
    ] {
        let mut scenario = RunScenario::demo(6);
        scenario.duration_s = 240.0;
        scenario.step_report = report;
        let samples = simulate_run(&scenario).samples();
        let config = PaceConfig {
            mode,
            ..PaceConfig::default()
        };
        let mut whole = PaceTracker::new(config).unwrap();
        let reference = replay(&mut whole, &samples);
        for split in 0..=samples.len() {
            let mut first = PaceTracker::new(config).unwrap();
            replay(&mut first, &samples[..split]);
            let bytes = first.snapshot();
            let mut resumed = PaceTracker::restore(&bytes).expect("restore");
            let rest = replay(&mut resumed, &samples[split..]);
            assert!(
                rest == reference[split..],
                "{mode:?}/{report:?}: output differs after a split at sample {split}"
            );
        }
    }
}

#[test]
fn corrupt_snapshots_are_rejected() {
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    replay(
        &mut tr,
        &simulate_run(&RunScenario::demo(7)).samples()[..200],
    );
    let bytes = tr.snapshot();
    assert!(PaceTracker::restore(&bytes).is_ok());
    for cut in [0, 3, 10, bytes.len() / 2, bytes.len() - 1] {
        assert!(matches!(
            PaceTracker::restore(&bytes[..cut]),
            Err(PaceError::Snapshot(_))
        ));
    }
    let mut rng = Rng::new(1);
    for _ in 0..200 {
        let mut b = bytes.clone();
        let i = (rng.next_u64() as usize) % b.len();
        b[i] ^= 1 << (rng.next_u64() % 8);
        assert!(
            PaceTracker::restore(&b).is_err(),
            "flipped byte {i} accepted"
        );
    }
}

#[test]
fn adversarial_input_never_panics_nor_produces_nan() {
    let mut rng = Rng::new(2024);
    for config in configs() {
        let mut tr = PaceTracker::new(config).unwrap();
        let mut t = 0.0;
        let mut steps = 0u64;
        for i in 0..20_000 {
            // Mostly plausible, sometimes extreme: poles, antimeridian, teleports,
            // huge time gaps, zero accuracy, garbage values.
            t += match rng.next_u64() % 20 {
                0 => rng.range(0.0, 1e6),
                1 => 1e-9,
                _ => rng.range(0.0, 2.0),
            };
            let pick = rng.next_u64() % 10;
            let sample = if pick < 5 {
                let (lat, lon) = match rng.next_u64() % 6 {
                    0 => (rng.range(-90.0, 90.0), rng.range(-180.0, 180.0)),
                    1 => (89.9999, rng.range(-180.0, 180.0)),
                    2 => (0.0, if i % 2 == 0 { 179.99999 } else { -179.99999 }),
                    3 => (f64::NAN, 0.0),
                    _ => (48.0 + 1e-5 * rng.normal(), 11.0 + 1e-5 * rng.normal()),
                };
                PaceSample::Fix(GnssFix {
                    t_s: t,
                    lat_deg: lat,
                    lon_deg: lon,
                    alt_m: Some(rng.range(-100.0, 5000.0)),
                    horizontal_accuracy_m: [None, Some(0.0), Some(3.0), Some(1e4)]
                        [(rng.next_u64() % 4) as usize],
                    speed_mps: Some(rng.range(0.0, 120.0)),
                    speed_accuracy_mps: Some(rng.range(0.0, 5.0)),
                })
            } else {
                steps = match rng.next_u64() % 10 {
                    0 => rng.next_u64() % 100,
                    1 => steps + 10_000,
                    _ => steps + rng.next_u64() % 5,
                };
                match pick {
                    5 | 6 => PaceSample::Steps(StepSample::Count { t_s: t, steps }),
                    7 => PaceSample::Steps(StepSample::Event { t_s: t }),
                    _ => PaceSample::Steps(StepSample::Cadence {
                        t_s: t,
                        steps_per_min: rng.range(-10.0, 400.0),
                    }),
                }
            };
            let _ = tr.push(&sample);
            // None while nothing was accepted yet.
            let Some(e) = tr.estimate() else {
                continue;
            };
            for v in [e.speed_mps, e.distance_m, e.gnss_weight, e.t_s] {
                assert!(v.is_finite(), "{config:?} sample {i}: {e:?}");
            }
            assert!(
                e.speed_mps >= 0.0 && (0.0..=1.0).contains(&e.gnss_weight),
                "{config:?} sample {i}: {sample:?} -> {e:?}"
            );
            assert!(e.step_length_m.is_none_or(|l| l.is_finite() && l > 0.0));
            assert!(e.cadence_spm.is_none_or(|c| c.is_finite() && c >= 0.0));
        }
        // The snapshot of whatever state that left restores.
        if let Err(e) = PaceTracker::restore(&tr.snapshot()) {
            panic!("{config:?}: {e}");
        }
    }
}

#[test]
fn invalid_configurations_are_rejected() {
    let mut c = PaceConfig::default();
    c.published.window_n = 2;
    assert!(matches!(
        PaceTracker::new(c),
        Err(PaceError::InvalidConfig { .. })
    ));
    let mut c = PaceConfig::default();
    c.adaptive.accel_noise_mps2 = f64::NAN;
    assert!(PaceTracker::new(c).is_err());
    let c = PaceConfig {
        initial_step_length_m: Some(7.0),
        ..PaceConfig::default()
    };
    assert!(PaceTracker::new(c).is_err());
}

/// The fused position: none before the first fix is used, then metres east/north of
/// it (the tracker's frame), near where the GNSS says the runner is while GNSS is
/// good; none at all for the published method, which estimates speed only. (The
/// first fix waits for the second, which shows the GNSS times are seconds: see
/// `pace/held.rs`.)
#[test]
fn the_fused_position_is_in_the_frame_of_the_first_fix() {
    let run = simulate_run(&RunScenario::demo(3));
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let mut published = PaceTracker::new(PaceConfig::as_published()).unwrap();
    assert_eq!(tr.position_enu_m(), None);
    let (mut n, mut near) = (0usize, 0usize);
    let mut fixes = 0usize;
    for s in run.samples() {
        tr.push(&s).unwrap();
        published.push(&s).unwrap();
        if matches!(s, PaceSample::Fix(_)) {
            fixes += 1;
        }
        if let (PaceSample::Fix(f), true) = (s, fixes >= 2) {
            let frame = *tr.frame().expect("a frame after the first fix");
            let p = tr.position_enu_m().expect("a position after the first fix");
            let g = frame.to_enu(f.lat_deg, f.lon_deg, 0.0);
            n += 1;
            if (p[0] - g[0]).hypot(p[1] - g[1]) < 25.0 {
                near += 1;
            }
        }
    }
    assert!(
        near as f64 > 0.9 * n as f64,
        "{near} of {n} fixes within 25 m"
    );
    assert_eq!(published.position_enu_m(), None);
    let _: Option<LocalFrame> = tr.frame().copied();
}
