//! PhoneNavigator plumbing: it counts steps from raw IMU data, moves, takes GNSS,
//! rejects bad input without changing state, and resumes exactly from a snapshot.
//! (Accuracy is evaluated separately.)

use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::{NavEstimate, NavigatorConfig, PhoneNavigator};
use stridekit_core::sim::phone::{simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario};

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
