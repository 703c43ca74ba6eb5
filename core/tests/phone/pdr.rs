//! PhoneNavigator plumbing: it counts steps from raw IMU data, moves, takes GNSS,
//! rejects bad input without changing state, and resumes exactly from a snapshot.
//! (Accuracy is evaluated separately.)

use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::{NavEstimate, NavStep, NavigatorConfig, PhoneNavigator};
use stridekit_sim::phone::{
    simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario, SimulatedPhone,
};

enum Input {
    Imu(ImuSample),
    Fix(GnssFix),
}

fn inputs(seconds: f64) -> Vec<Input> {
    let sim = simulate_phone(&PhoneScenario::walk(
        3,
        PhonePlacement::FrontPocket,
        1.4,
        seconds,
    ));
    sim.timeline(&LocalFrame::new(47.0, 8.0, 0.0))
        .into_iter()
        .map(|e| match e {
            PhoneEvent::Imu(s) => Input::Imu(ImuSample {
                t_s: s.t_s,
                gyro_rads: s.gyro_radps,
                accel_mps2: s.accel_mps2,
                mag_ut: Some(s.mag_ut),
            }),
            PhoneEvent::Fix(f) => Input::Fix(f),
        })
        .collect()
}

/// A simulated walk's IMU samples through a default navigator: the navigator and
/// every step it placed, in order.
fn replay_placed_steps(sim: &SimulatedPhone) -> (PhoneNavigator, Vec<NavStep>) {
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let mut steps = Vec::new();
    for s in &sim.samples {
        let placed = nav.recent_steps().1;
        nav.push_imu(&ImuSample::from(s)).unwrap();
        steps.extend(nav.steps_since(placed));
    }
    (nav, steps)
}

fn feed(nav: &mut PhoneNavigator, xs: &[Input]) -> Vec<NavEstimate> {
    xs.iter()
        .map(|x| {
            match x {
                Input::Imu(s) => nav.push_imu(s).unwrap(),
                Input::Fix(f) => {
                    nav.push_fix(f).unwrap();
                }
            }
            nav.estimate().expect("an estimate after input")
        })
        .collect()
}

#[test]
fn walks_counts_steps_and_takes_gnss() {
    let xs = inputs(60.0);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let out = feed(&mut nav, &xs);
    let e = out.last().unwrap();
    assert!(e.steps > 50, "{e:?}");
    assert!(e.distance_m > 30.0, "{e:?}");
    assert!(e.lat_deg.is_some() && e.walking_azimuth_rad.is_some());
    assert!(out
        .iter()
        .all(|e| e.east_m.is_finite() && e.north_m.is_finite() && e.position_std_m.is_finite()));
}

#[test]
fn bad_input_leaves_state_untouched() {
    let xs = inputs(20.0);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    feed(&mut nav, &xs);
    let before = nav.snapshot();
    let t = nav.estimate().expect("an estimate after input").t_s;
    let bad = ImuSample {
        t_s: t + 0.01,
        gyro_rads: [0.0, f64::NAN, 0.0],
        accel_mps2: [0.0, 0.0, 9.8],
        mag_ut: None,
    };
    assert!(nav.push_imu(&bad).is_err());
    let late = ImuSample {
        t_s: t - 1.0,
        gyro_rads: [0.0; 3],
        accel_mps2: [0.0, 0.0, 9.8],
        mag_ut: None,
    };
    assert!(nav.push_imu(&late).is_err());
    assert!(nav.push_fix(&GnssFix::new(t + 1.0, 91.0, 0.0)).is_err());
    assert_eq!(nav.snapshot(), before);
}

#[test]
fn a_walk_split_and_restored_gives_the_same_output() {
    let xs = inputs(30.0);
    let mut whole = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let reference = feed(&mut whole, &xs);
    for split in [0, 1, 777, 1500, xs.len() / 2, xs.len() - 3] {
        let mut first = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
        feed(&mut first, &xs[..split]);
        let mut resumed = PhoneNavigator::restore(&first.snapshot()).unwrap();
        let rest = feed(&mut resumed, &xs[split..]);
        assert!(rest == reference[split..], "differs after split {split}");
    }
}

#[test]
fn a_raw_gyroscope_setting_survives_the_snapshot() {
    let xs = inputs(10.0);
    for gyro_calibrated in [true, false] {
        let config = NavigatorConfig {
            gyro_calibrated,
            ..NavigatorConfig::default()
        };
        let mut nav = PhoneNavigator::new(config).unwrap();
        let before = feed(&mut nav, &xs[..300]);
        let mut restored = PhoneNavigator::restore(&nav.snapshot()).unwrap();
        assert_eq!(*restored.config(), config);
        assert!(feed(&mut restored, &xs[300..]) == feed(&mut nav, &xs[300..]));
        assert!(!before.is_empty());
    }
}

/// A walk without GNSS (indoors): every detected step is placed on the track, those
/// of the first burst (released before the walking direction was known) included,
/// so the track's length is the distance walked.
#[test]
fn without_gnss_every_step_is_placed() {
    let sim = simulate_phone(&PhoneScenario {
        gnss: false,
        ..PhoneScenario::walk(4, PhonePlacement::InHand, 1.3, 40.0)
    });
    let (nav, steps) = replay_placed_steps(&sim);
    let mut path = 0.0;
    let mut last = (0.0, 0.0);
    for st in &steps {
        path += (st.east_m - last.0).hypot(st.north_m - last.1);
        last = (st.east_m, st.north_m);
    }
    let seen = nav.recent_steps().1;
    let e = nav.estimate().expect("an estimate after input");
    assert!(e.steps > 50 && e.lat_deg.is_none(), "{e:?}");
    assert_eq!(seen, e.steps, "every step placed");
    assert!(
        (path - e.distance_m).abs() < 1e-6 * e.distance_m,
        "{path} vs {}",
        e.distance_m
    );
}

/// A personal calibration sets the step length and the carrying, survives a snapshot,
/// and a refused one changes nothing.
#[test]
fn a_calibration_is_used_and_kept_in_the_snapshot() {
    use stridekit_core::pdr::PdrCalibration;
    use stridekit_core::steplength::StepLengthModel;
    let c = PdrCalibration {
        step_length_model: StepLengthModel::Constant,
        step_length_theta: [0.0, 0.0, 0.61],
        step_length_sigma: [1.0, 1.0, 0.001],
        carrying_body: Some([0.0, 1.0, 0.0]),
    };
    let xs = inputs(30.0);
    let imu: Vec<Input> = xs
        .into_iter()
        .filter(|x| matches!(x, Input::Imu(_)))
        .collect();
    let mut nav = PhoneNavigator::with_calibration(NavigatorConfig::default(), &c).unwrap();
    assert_eq!(nav.calibration(), Some(&c));
    let (a, b) = imu.split_at(imu.len() / 2);
    feed(&mut nav, a);
    let mut resumed = PhoneNavigator::restore(&nav.snapshot()).unwrap();
    assert_eq!(resumed.calibration(), Some(&c));
    let e1 = feed(&mut nav, b);
    let e2 = feed(&mut resumed, b);
    assert_eq!(e1, e2);
    let e = e1.last().unwrap();
    assert!((e.step_length_m.unwrap() - 0.61).abs() < 0.01, "{e:?}");
    let bad = PdrCalibration {
        step_length_sigma: [0.0, 1.0, 1.0],
        ..c
    };
    let before = nav.snapshot();
    assert!(nav.set_calibration(&bad).is_err());
    assert_eq!(before, nav.snapshot());
}

/// An external orientation (here the simulator's truth) drives the walking direction
/// instead of the AHRS; a quaternion that is not unit is refused without change.
#[test]
fn an_external_attitude_replaces_the_ahrs() {
    let sim = simulate_phone(&PhoneScenario {
        gnss: false,
        ..PhoneScenario::walk(6, PhonePlacement::InHand, 1.3, 30.0)
    });
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    for s in &sim.samples {
        let q = sim.truth_at(s.t_s).attitude_wxyz;
        nav.push_imu_with_attitude(
            &ImuSample {
                t_s: s.t_s,
                gyro_rads: s.gyro_radps,
                accel_mps2: s.accel_mps2,
                mag_ut: None,
            },
            q,
        )
        .unwrap();
    }
    let e = nav.estimate().expect("an estimate after input");
    assert!(e.steps > 30 && e.east_m.hypot(e.north_m) > 10.0, "{e:?}");
    assert!(nav.orientation().is_none(), "the internal AHRS did not run");
    let before = nav.snapshot();
    let t = e.t_s + 0.01;
    let s = ImuSample {
        t_s: t,
        gyro_rads: [0.0; 3],
        accel_mps2: [0.0, 0.0, 9.8],
        mag_ut: None,
    };
    assert!(nav
        .push_imu_with_attitude(&s, [2.0, 0.0, 0.0, 0.0])
        .is_err());
    assert_eq!(before, nav.snapshot());
}

/// The default step length is the inverted pendulum's: each placed step reports the
/// phone's vertical displacement, and without GNSS (prior K only) a walker taking
/// longer steps rises and falls more and is given longer steps, in proportion.
#[test]
fn longer_steps_lift_the_phone_more_and_are_read_longer() {
    let mean_step = |speed_mps: f64| {
        let sim = simulate_phone(&PhoneScenario {
            gnss: false,
            person_factor: Some(1.0),
            ..PhoneScenario::walk(6, PhonePlacement::InHand, speed_mps, 60.0)
        });
        let (_, steps) = replay_placed_steps(&sim);
        let (mut h, mut len, mut n) = (0.0, 0.0, 0.0);
        // Steady steps only (past the first seconds and the initiation shares).
        for st in steps.iter().filter(|st| st.t_s > sim.samples[0].t_s + 10.0) {
            assert!((0.005..0.5).contains(&st.vertical_displacement_m), "{st:?}");
            h += st.vertical_displacement_m;
            len += st.length_m;
            n += 1.0;
        }
        let true_len = sim.steps.iter().map(|s| s.length_m).sum::<f64>() / sim.steps.len() as f64;
        (h / n, len / n, true_len)
    };
    let (h_slow, l_slow, true_slow) = mean_step(1.0);
    let (h_fast, l_fast, true_fast) = mean_step(1.6);
    assert!(h_fast > 1.2 * h_slow, "h {h_slow} → {h_fast}");
    // The read length follows the true one's change (within a quarter of it).
    let (read, truth) = (l_fast / l_slow, true_fast / true_slow);
    assert!(
        truth > 1.1 && (read - truth).abs() < 0.25 * (truth - 1.0),
        "read ×{read}, true ×{truth}"
    );
}
