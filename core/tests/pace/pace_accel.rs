//! The pace tracker fed raw accelerometer samples instead of platform step counts.

use stridekit_core::geo::LocalFrame;
use stridekit_core::input::InputError;
use stridekit_core::pace::{GnssFix, PaceConfig, PaceError, PaceTracker};
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
