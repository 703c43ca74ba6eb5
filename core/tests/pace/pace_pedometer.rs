//! Pace without GNSS: pedometer-only speed from the first steps (treadmill, indoor
//! track, a watch without GNSS), a calibration carried between sessions, and the
//! hand-over to GNSS when it appears.

use stridekit_core::{
    AccelStepModel, PaceCalibration, PaceConfig, PaceError, PaceSample, PaceSource, PaceTracker,
    StepSample,
};
use stridekit_sim::{simulate_run, RunScenario};

/// 170 steps/min for `seconds`, in one of the three step-data shapes.
fn steps(shape: usize, seconds: f64) -> Vec<StepSample> {
    let cadence = 170.0 / 60.0;
    match shape {
        0 => (1..=seconds as usize)
            .map(|i| StepSample::Count {
                t_s: i as f64,
                steps: (cadence * i as f64).floor() as u64,
            })
            .collect(),
        1 => (1..(seconds * cadence) as usize)
            .map(|i| StepSample::Event {
                t_s: i as f64 / cadence,
            })
            .collect(),
        _ => (1..=seconds as usize)
            .map(|i| StepSample::Cadence {
                t_s: i as f64,
                steps_per_min: 170.0,
            })
            .collect(),
    }
}

#[test]
fn steps_alone_give_pedometer_speed_from_the_first_steps() {
    for shape in 0..3 {
        let mut tr = PaceTracker::new(PaceConfig {
            initial_step_length_m: Some(1.1),
            ..PaceConfig::default()
        })
        .unwrap();
        let mut first_moving = None;
        for s in steps(shape, 30.0) {
            tr.push_steps(&s).unwrap();
            let e = tr.estimate().unwrap();
            if e.speed_mps > 0.0 && first_moving.is_none() {
                first_moving = Some(e.t_s);
            }
        }
        let e = tr.estimate().unwrap();
        assert_eq!(e.source, PaceSource::Pedometer, "shape {shape}");
        assert_eq!(e.gnss_weight, 0.0);
        // 1.1 m at 168 steps/min on the prior slope: ≈ 1.11 m at 170 → 3.14 m/s.
        let want = 170.0 / 60.0 * 1.1;
        assert!(
            (e.speed_mps - want).abs() < 0.05 * want,
            "shape {shape}: {} m/s, want ≈ {want:.2}",
            e.speed_mps
        );
        assert!(e.pace_s_per_km.is_some());
        // Distance ≈ speed × time since the first moving estimate (the cadence filter's
        // start from integer counts adds up to a few metres).
        let t0 = first_moving.expect("moving");
        assert!(t0 <= 3.0, "shape {shape}: first speed at {t0} s");
        let d = want * (e.t_s - t0);
        assert!(
            (e.distance_m - d).abs() < 0.08 * d,
            "shape {shape}: {} m, want ≈ {d:.0}",
            e.distance_m
        );
    }
}

#[test]
fn without_configuration_the_prior_step_length_is_used_and_stopping_reads_zero() {
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    for s in steps(0, 20.0) {
        tr.push_steps(&s).unwrap();
    }
    let e = tr.estimate().unwrap();
    assert_eq!(e.source, PaceSource::Pedometer);
    // Population prior: 1.0 m at 168 steps/min.
    assert!((e.speed_mps - 170.0 / 60.0).abs() < 0.2, "{}", e.speed_mps);
    let d = e.distance_m;
    // The counter stops moving: standing.
    let last = (170.0 / 60.0 * 20.0f64).floor() as u64;
    for i in 21..30 {
        tr.push_steps(&StepSample::Count {
            t_s: i as f64,
            steps: last,
        })
        .unwrap();
    }
    let e = tr.estimate().unwrap();
    assert_eq!(e.source, PaceSource::Stationary);
    assert_eq!(e.speed_mps, 0.0);
    // Standing is recognised 2 s after the last step (≈ 6 m at this pace).
    assert!(e.distance_m - d < 8.0, "{} → {}", d, e.distance_m);
}

#[test]
fn a_calibration_learned_with_gnss_carries_to_a_session_without_gnss() {
    // Session 1: a simulated run with good GNSS teaches the step length.
    let run = simulate_run(&RunScenario::demo(3));
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    assert_eq!(tr.calibration(), None, "nothing learned yet");
    for s in &run.samples() {
        let _ = tr.push(s);
    }
    let cal = tr.calibration().expect("learned from GNSS");
    cal.validate().unwrap();
    assert!((0.6..=1.6).contains(&cal.step_length_m), "{cal:?}");

    // Session 2: steps only, calibration imported.
    let config = PaceConfig {
        calibration: Some(cal),
        ..PaceConfig::default()
    };
    let mut tr2 = PaceTracker::new(config).unwrap();
    for s in steps(2, 20.0) {
        tr2.push_steps(&s).unwrap();
    }
    let e = tr2.estimate().unwrap();
    assert_eq!(e.source, PaceSource::Pedometer);
    let want = 170.0 / 60.0 * cal.step_length_at(170.0);
    assert!(
        (e.speed_mps - want).abs() < 0.03 * want,
        "{} m/s, want {want:.3}",
        e.speed_mps
    );
    // The calibration is part of the configuration: kept in the snapshot.
    let restored = PaceTracker::restore(&tr2.snapshot()).unwrap();
    assert_eq!(restored.config().calibration, Some(cal));
    assert_eq!(restored.estimate().unwrap(), tr2.estimate().unwrap());
    // Exported again, it is the imported line (nothing was learned without GNSS).
    let again = tr2.calibration().expect("given");
    assert!((again.step_length_at(170.0) - cal.step_length_at(170.0)).abs() < 1e-9);
}

#[test]
fn invalid_calibrations_are_rejected() {
    let good = PaceCalibration {
        step_length_m: 1.0,
        cadence_spm: 170.0,
        slope_m_per_spm: 0.008,
        step_length_std_m: 0.03,
        accel_model: None,
    };
    let model = AccelStepModel {
        a_m_s: 0.4,
        b_m_per_m2ps4: 0.0,
        c_m: -0.1,
        ref_frequency_hz: 1.8,
        ref_variance_m2ps4: 10.0,
        a_std_m_s: 0.05,
        b_std_m_per_m2ps4: 0.001,
        length_std_m: 0.02,
    };
    let with_model = |m: AccelStepModel| PaceCalibration {
        accel_model: Some(m),
        ..good
    };
    for bad in [
        with_model(AccelStepModel {
            a_m_s: f64::NAN,
            ..model
        }),
        with_model(AccelStepModel { c_m: 50.0, ..model }),
        with_model(AccelStepModel {
            b_std_m_per_m2ps4: 0.0,
            ..model
        }),
        with_model(AccelStepModel {
            a_std_m_s: f64::INFINITY,
            ..model
        }),
        with_model(AccelStepModel {
            ref_frequency_hz: 0.0,
            ..model
        }),
        with_model(AccelStepModel {
            ref_variance_m2ps4: -1.0,
            ..model
        }),
        PaceCalibration {
            step_length_m: f64::NAN,
            ..good
        },
        PaceCalibration {
            step_length_m: 5.0,
            ..good
        },
        PaceCalibration {
            cadence_spm: 0.0,
            ..good
        },
        PaceCalibration {
            slope_m_per_spm: 1.0,
            ..good
        },
        PaceCalibration {
            step_length_std_m: -1.0,
            ..good
        },
    ] {
        let r = PaceTracker::new(PaceConfig {
            calibration: Some(bad),
            ..PaceConfig::default()
        });
        assert!(matches!(r, Err(PaceError::InvalidConfig { .. })), "{bad:?}");
    }
    assert!(PaceTracker::new(PaceConfig {
        calibration: Some(with_model(model)),
        ..PaceConfig::default()
    })
    .is_ok());
}

#[test]
fn gnss_arriving_after_pedometer_only_takes_over_without_a_drop_to_zero() {
    let run = simulate_run(&RunScenario::demo(5));
    let samples = run.samples();
    // The first 60 s without fixes (indoors, then out of the door).
    let mut tr = PaceTracker::new(PaceConfig {
        initial_step_length_m: Some(1.0),
        ..PaceConfig::default()
    })
    .unwrap();
    let mut moving = false;
    for s in &samples {
        if matches!(s, PaceSample::Fix(f) if f.t_s < 60.0) {
            continue;
        }
        let _ = tr.push(s);
        let e = tr.estimate().unwrap();
        if e.t_s > 10.0 && e.t_s < 200.0 && e.source != PaceSource::Stationary {
            let truth = run.truth_at(e.t_s).speed_mps;
            if truth > 1.5 {
                moving = true;
                assert!(
                    e.speed_mps > 0.5 * truth,
                    "t = {:.0}: {} m/s ({:?}), truth {truth}",
                    e.t_s,
                    e.speed_mps,
                    e.source
                );
            }
        }
    }
    assert!(moving);
    assert_ne!(tr.estimate().unwrap().source, PaceSource::Initializing);
}

/// `spm` steps/min reported as cadence once a second from `t0_s` for `seconds`.
fn cadence_reports(t0_s: f64, seconds: usize, spm: f64) -> Vec<StepSample> {
    (0..seconds)
        .map(|i| StepSample::Cadence {
            t_s: t0_s + i as f64,
            steps_per_min: spm,
        })
        .collect()
}

#[test]
fn a_walk_is_paced_with_a_walking_step_length_not_the_running_line() {
    // A runner's watch without GNSS, configured with the running step length: run at
    // 170 steps/min, then walk at 100 steps/min (a recovery, a cool-down).
    let mut tr = PaceTracker::new(PaceConfig {
        initial_step_length_m: Some(1.1),
        ..PaceConfig::default()
    })
    .unwrap();
    for s in cadence_reports(1.0, 60, 170.0) {
        tr.push_steps(&s).unwrap();
    }
    let run = tr.estimate().unwrap();
    assert!((run.speed_mps - 170.0 / 60.0 * 1.1).abs() < 0.05, "{run:?}");
    for s in cadence_reports(61.0, 60, 100.0) {
        tr.push_steps(&s).unwrap();
    }
    let walk = tr.estimate().unwrap();
    assert_eq!(walk.source, PaceSource::Pedometer);
    // The running line read at 100 steps/min says 0.53 m steps, 0.89 m/s; an adult
    // walks ≈ 1.0–1.2 m/s at that cadence (steps of ≈ 0.6–0.7 m).
    assert!((0.98..=1.25).contains(&walk.speed_mps), "{walk:?}");
    let l = walk.step_length_m.expect("a step length while walking");
    assert!((0.58..=0.75).contains(&l), "{l}");
    // Back to running: the running line again, untouched by the walk.
    for s in cadence_reports(121.0, 60, 170.0) {
        tr.push_steps(&s).unwrap();
    }
    let again = tr.estimate().unwrap();
    assert!((again.speed_mps - run.speed_mps).abs() < 0.05, "{again:?}");
}

#[test]
fn speed_has_no_jump_where_walking_turns_into_running() {
    // Cadence rising 1 step/min every 5 s from 120 to 145 steps/min (a walk becoming a
    // jog): the step length blends from the walking line into the running line.
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let mut speeds = Vec::new();
    for (k, spm) in (120..=145).enumerate() {
        for s in cadence_reports(1.0 + 5.0 * k as f64, 5, spm as f64) {
            tr.push_steps(&s).unwrap();
        }
        speeds.push(tr.estimate().unwrap().speed_mps);
    }
    for w in speeds.windows(2) {
        assert!((w[1] - w[0]).abs() < 0.08, "{speeds:?}");
    }
}
