//! The pace tracker fed raw accelerometer samples instead of platform step counts.

use stridekit_core::geo::LocalFrame;
use stridekit_core::input::InputError;
use stridekit_core::pace::{
    AccelStepModel, GnssFix, PaceCalibration, PaceConfig, PaceError, PaceTracker,
};
use stridekit_sim::phone::{simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario};

/// Accelerometer samples and fixes of a simulated walk, in time order.
enum In {
    Accel(f64, [f64; 3]),
    Fix(GnssFix),
}

fn walk(seconds: f64) -> Vec<In> {
    let sim = simulate_phone(&PhoneScenario::walk(
        5,
        PhonePlacement::BackPocket,
        1.5,
        seconds,
    ));
    sim.timeline(&LocalFrame::new(45.0, 7.0, 0.0))
        .into_iter()
        .map(|e| match e {
            PhoneEvent::Imu(s) => In::Accel(s.t_s, s.accel_mps2),
            PhoneEvent::Fix(f) => In::Fix(f),
        })
        .collect()
}

fn feed(tr: &mut PaceTracker, xs: &[In]) -> Vec<stridekit_core::PaceEstimate> {
    xs.iter()
        .map(|x| {
            match x {
                In::Accel(t, a) => tr.push_accel(*t, *a).unwrap(),
                In::Fix(f) => {
                    tr.push_fix(f).unwrap();
                }
            }
            tr.estimate().unwrap()
        })
        .collect()
}

#[test]
fn pace_and_cadence_from_raw_acceleration() {
    let xs = walk(240.0);
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let out = feed(&mut tr, &xs);
    let e = out.last().unwrap();
    assert!((e.speed_mps - 1.5).abs() < 0.25, "{e:?}");
    let c = e.cadence_spm.expect("cadence from detected steps");
    assert!((90.0..140.0).contains(&c), "{c}");
    assert!((e.distance_m - 360.0).abs() < 30.0, "{e:?}");
}

#[test]
fn g_units_are_rejected_and_leave_the_state_untouched() {
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let before = tr.snapshot();
    let err = tr.push_accel(0.0, [0.0, 0.0, 1.0]).unwrap_err();
    assert!(
        matches!(err, PaceError::Input(InputError::AccelerationInG { .. })),
        "{err:?}"
    );
    assert_eq!(tr.snapshot(), before);
    assert!(matches!(
        tr.push_accel(f64::NAN, [0.0, 0.0, 9.8]),
        Err(PaceError::Input(InputError::NonFinite { .. }))
    ));
    tr.push_accel(1.0, [0.0, 0.0, 9.8]).unwrap();
    assert!(matches!(
        tr.push_accel(0.5, [0.0, 0.0, 9.8]),
        Err(PaceError::Input(InputError::TimeNotIncreasing { .. }))
    ));
}

#[test]
fn split_and_restore_mid_accelerometer_stream() {
    let xs = walk(60.0);
    let mut whole = PaceTracker::new(PaceConfig::default()).unwrap();
    let reference = feed(&mut whole, &xs);
    for split in [1, 999, xs.len() / 2, xs.len() - 7] {
        let mut a = PaceTracker::new(PaceConfig::default()).unwrap();
        feed(&mut a, &xs[..split]);
        let mut b = PaceTracker::restore(&a.snapshot()).unwrap();
        assert!(
            feed(&mut b, &xs[split..]) == reference[split..],
            "split {split}"
        );
    }
}

/// A walker with steps 6 % longer than the population's: 1.2 m/s with GNSS for 8
/// minutes, then 3 minutes at 1.7 m/s without GNSS.
fn brisk_outage() -> (stridekit_sim::phone::SimulatedPhone, f64, f64) {
    use stridekit_sim::phone::{PhoneActivity, PhoneSegment};
    let walk = |v: f64, s: f64| PhoneSegment {
        activity: PhoneActivity::Walking { speed_mps: v },
        duration_s: s,
    };
    let (t0, t1) = (480.0, 660.0);
    let sim = simulate_phone(&PhoneScenario {
        segments: vec![walk(1.2, t0), walk(1.7, t1 - t0)],
        gnss_outages: vec![(t0, t1 + 1.0)],
        person_factor: Some(1.06),
        ..PhoneScenario::walk(3, PhonePlacement::FrontPocket, 1.2, 0.0)
    });
    (sim, t0, t1)
}

/// Distance the tracker adds over `[t0, t1]` against the truth's, percent; the
/// tracker is fed the raw accelerometer, or only the steps of the same detector.
fn outage_distance_error_pct(
    sim: &stridekit_sim::phone::SimulatedPhone,
    t0: f64,
    t1: f64,
    raw: bool,
) -> f64 {
    use stridekit_core::pace::StepSample;
    use stridekit_core::stepdetect::StepDetector;
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    let mut det = StepDetector::default();
    let (mut d0, mut d1) = (None, 0.0);
    for e in sim.timeline(&LocalFrame::new(45.0, 7.0, 0.0)) {
        match e {
            PhoneEvent::Fix(f) => {
                tr.push_fix(&f).unwrap();
            }
            PhoneEvent::Imu(s) => {
                if raw {
                    tr.push_accel(s.t_s, s.accel_mps2).unwrap();
                } else {
                    let first = det.push_accel(s.t_s, s.accel_mps2).unwrap();
                    for e in first
                        .into_iter()
                        .chain(std::iter::from_fn(|| det.pop_step()))
                    {
                        tr.push_steps(&StepSample::Event { t_s: e.t_s }).unwrap();
                    }
                }
                if s.t_s >= t0 && s.t_s <= t1 {
                    let d = tr.estimate().unwrap().distance_m;
                    d0.get_or_insert(d);
                    d1 = d;
                }
            }
        }
    }
    let truth = sim.truth_at(t1).distance_m - sim.truth_at(t0).distance_m;
    100.0 * ((d1 - d0.unwrap()) - truth) / truth
}

#[test]
fn raw_acceleration_paces_a_faster_outage_by_its_steps() {
    // Calibrated by GNSS at 1.2 m/s, the outage is walked at 1.7 m/s with longer,
    // harder steps: the feature step length, calibrated to this walker, follows them;
    // cadence × the population's walking line (walks do not teach the running line)
    // cannot know this walker's shorter steps.
    let (sim, t0, t1) = brisk_outage();
    let raw = outage_distance_error_pct(&sim, t0, t1, true);
    let events = outage_distance_error_pct(&sim, t0, t1, false);
    // (Measured: −2.0 % against −11.6 %; the linear model, calibrated at one pace,
    // extrapolates with the population's slope, hence not 0.)
    assert!(raw.abs() < 4.0, "raw acceleration: {raw:+.2} %");
    assert!(
        2.0 * raw.abs() < events.abs(),
        "raw {raw:+.2} % vs step events {events:+.2} %"
    );
}

#[test]
fn restore_mid_outage_keeps_the_feature_step_length() {
    let (sim, t0, _) = brisk_outage();
    let xs: Vec<In> = sim
        .timeline(&LocalFrame::new(45.0, 7.0, 0.0))
        .into_iter()
        .map(|e| match e {
            PhoneEvent::Imu(s) => In::Accel(s.t_s, s.accel_mps2),
            PhoneEvent::Fix(f) => In::Fix(f),
        })
        .collect();
    let split = xs
        .iter()
        .position(|x| matches!(x, In::Accel(t, _) if *t > t0 + 30.0))
        .unwrap();
    let mut whole = PaceTracker::new(PaceConfig::default()).unwrap();
    let reference = feed(&mut whole, &xs);
    let mut a = PaceTracker::new(PaceConfig::default()).unwrap();
    feed(&mut a, &xs[..split]);
    let cal = a.accel_step_length_calibration().unwrap();
    assert!(cal.fits >= 10, "{cal:?}");
    let mut b = PaceTracker::restore(&a.snapshot()).unwrap();
    assert!(feed(&mut b, &xs[split..]) == reference[split..]);
}

/// Session 2 of a carried calibration: a new tracker with `cal` gets only the raw
/// acceleration of `[t0, t1]` (no fix: a treadmill, an indoor track). Returns the
/// tracker and the distance error over `[t0 + 10 s, t1]` against the truth, percent
/// (the first seconds, before the detector confirms a bout, are the same either way).
fn carried_session(
    sim: &stridekit_sim::phone::SimulatedPhone,
    t0: f64,
    t1: f64,
    cal: stridekit_core::PaceCalibration,
) -> (PaceTracker, f64) {
    let mut tr = PaceTracker::new(PaceConfig {
        calibration: Some(cal),
        ..PaceConfig::default()
    })
    .unwrap();
    let t_start = t0 + 10.0;
    let (mut d0, mut d1) = (None, 0.0);
    for e in sim.timeline(&LocalFrame::new(45.0, 7.0, 0.0)) {
        if let PhoneEvent::Imu(s) = e {
            if s.t_s < t0 || s.t_s > t1 {
                continue;
            }
            tr.push_accel(s.t_s, s.accel_mps2).unwrap();
            if s.t_s >= t_start {
                let d = tr.estimate().unwrap().distance_m;
                d0.get_or_insert(d);
                d1 = d;
            }
        }
    }
    let truth = sim.truth_at(t1).distance_m - sim.truth_at(t_start).distance_m;
    (tr, 100.0 * ((d1 - d0.unwrap()) - truth) / truth)
}

#[test]
fn the_accelerometer_model_carries_to_a_session_without_gnss() {
    // Session 1: the walk at 1.2 m/s with GNSS and raw acceleration.
    let (sim, t0, t1) = brisk_outage();
    let mut first = PaceTracker::new(PaceConfig::default()).unwrap();
    for e in sim.timeline(&LocalFrame::new(45.0, 7.0, 0.0)) {
        match e {
            PhoneEvent::Fix(f) if f.t_s < t0 => {
                first.push_fix(&f).unwrap();
            }
            PhoneEvent::Imu(s) if s.t_s < t0 => first.push_accel(s.t_s, s.accel_mps2).unwrap(),
            _ => {}
        }
    }
    let cal = first
        .calibration()
        .expect("the accelerometer model was learned");
    let model = cal.accel_model.expect("raw acceleration with good GNSS");
    model.validate().unwrap();
    // A walk teaches the running line nothing: exported as it stands, uncertain.
    assert!(cal.step_length_std_m > 0.08, "{cal:?}");

    // Session 2: the brisker walk with no fix at all, the calibration imported.
    let (tr, with_model) = carried_session(&sim, t0, t1, cal);
    let line_only = PaceCalibration {
        accel_model: None,
        ..cal
    };
    let (_, without) = carried_session(&sim, t0, t1, line_only);
    // (Measured: −1.2 % with the model against −11.0 % with the line alone, read
    // through the population's walking line.)
    assert!(with_model.abs() < 4.0, "with the model: {with_model:+.2} %");
    assert!(
        2.0 * with_model.abs() < without.abs(),
        "with the model {with_model:+.2} % vs the line alone {without:+.2} %"
    );
    let e = tr.estimate().unwrap();
    assert_eq!(e.source, stridekit_core::PaceSource::Pedometer);
    let l = e.step_length_m.expect("the steps' modelled length");
    assert!((0.5..1.3).contains(&l), "{l}");
    // Its uncertainty is the model's (about 2 % of the step length) with the
    // pedometer's 3 %, not the population walking line's 16 %.
    let rel = e.speed_std_mps.unwrap() / e.speed_mps;
    assert!((0.03..0.06).contains(&rel), "{rel}");
    // Nothing refined it without GNSS: exported again as imported (its uncertainty
    // too: carried centred at the user's features, it survives the round trip).
    let again = tr.calibration().unwrap().accel_model.unwrap();
    let parts = |m: &AccelStepModel| {
        [
            m.a_m_s,
            m.b_m_per_m2ps4,
            m.c_m,
            m.ref_frequency_hz,
            m.ref_variance_m2ps4,
            m.a_std_m_s,
            m.b_std_m_per_m2ps4,
            m.length_std_m,
        ]
    };
    for (a, b) in parts(&again).iter().zip(parts(&model).iter()) {
        assert!(
            (a - b).abs() <= 1e-6 * b.abs().max(1e-3),
            "{again:?} vs {model:?}"
        );
    }
    // The exported model is sure of the step length at the user's features (GNSS
    // calibrated it over 8 minutes) and its slopes are less certain.
    assert!(
        model.length_std_m < 0.05 * model.reference_length_m(),
        "{model:?}"
    );
    // Its line holds nothing learned: it does not override a configured step length.
    let mut counts = PaceTracker::new(PaceConfig {
        calibration: Some(cal),
        initial_step_length_m: Some(1.3),
        ..PaceConfig::default()
    })
    .unwrap();
    for i in 1..=20 {
        counts
            .push_steps(&stridekit_core::StepSample::Cadence {
                t_s: i as f64,
                steps_per_min: 170.0,
            })
            .unwrap();
    }
    let e = counts.estimate().unwrap();
    let want = 170.0 / 60.0 * 1.3;
    assert!((e.speed_mps - want).abs() < 0.05 * want, "{e:?}");
    // Kept in the snapshot, and the restored tracker goes on the same way.
    let restored = PaceTracker::restore(&tr.snapshot()).unwrap();
    assert_eq!(restored.config().calibration, Some(cal));
    assert_eq!(restored.calibration(), tr.calibration());
}
