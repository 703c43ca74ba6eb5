//! PhoneNavigator: no heap allocation per IMU sample or GNSS fix after construction
//! (with and without a magnetometer, rejected inputs included).

use crate::common::allocations_in;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario};

enum Input {
    Imu(ImuSample),
    Fix(GnssFix),
}

fn inputs(placement: PhonePlacement, use_mag: bool) -> Vec<Input> {
    let mut sc = PhoneScenario::walk(11, placement, 1.4, 150.0);
    sc.gnss_outages = vec![(90.0, 151.0)];
    let sim = simulate_phone(&sc);
    let frame = LocalFrame::new(47.0, 8.0, 0.0);
    let mut out = Vec::with_capacity(sim.samples.len() + sim.fixes.len());
    let mut fi = 0;
    for s in &sim.samples {
        while fi < sim.fixes.len() && sim.fixes[fi].t_s <= s.t_s {
            let f = sim.fixes[fi];
            let (lat, lon) = frame.to_geodetic(f.east_m, f.north_m);
            out.push(Input::Fix(
                GnssFix::new(f.t_s, lat, lon).with_accuracy(f.accuracy_m),
            ));
            fi += 1;
        }
        out.push(Input::Imu(ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_radps,
            accel_mps2: s.accel_mps2,
            mag_ut: use_mag.then_some(s.mag_ut),
        }));
    }
    out
}

#[test]
fn navigator_does_not_allocate_per_sample() {
    for placement in [PhonePlacement::FrontPocket, PhonePlacement::InHand] {
        for use_mag in [true, false] {
            let xs = inputs(placement, use_mag);
            let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
            let (n, steps) = allocations_in(|| {
                for x in &xs {
                    match x {
                        Input::Imu(s) => nav.push_imu(s).unwrap(),
                        Input::Fix(f) => {
                            nav.push_fix(f).unwrap();
                        }
                    }
                    std::hint::black_box(nav.estimate().expect("an estimate after input"));
                }
                // Rejected inputs too.
                let t = nav.estimate().expect("an estimate after input").t_s;
                let bad = ImuSample {
                    t_s: t + 0.01,
                    gyro_rads: [0.0; 3],
                    accel_mps2: [0.0, 0.0, 9.8],
                    mag_ut: Some([f64::NAN, 0.0, 0.0]),
                };
                assert!(nav.push_imu(&bad).is_err());
                assert!(nav.push_fix(&GnssFix::new(t + 1.0, 95.0, 0.0)).is_err());
                nav.estimate().expect("an estimate after input").steps
            });
            assert!(steps > 100, "{placement:?}: {steps} steps");
            assert_eq!(
                n, 0,
                "{placement:?}, mag {use_mag}: allocations on the sample path"
            );
        }
    }
}

/// With a personal calibration loaded and through the external-attitude entry point
/// too: no allocation per sample.
#[test]
fn calibrated_and_external_attitude_paths_do_not_allocate() {
    use stridekit_core::pdr::PdrCalibration;
    use stridekit_core::steplength::StepLengthModel;
    let c = PdrCalibration {
        step_length_model: StepLengthModel::Weinberg,
        step_length_theta: [0.39, 0.0, 0.0],
        step_length_sigma: [0.004, 1.0, 1.0],
        carrying_body: Some([0.0, 1.0, 0.0]),
    };
    let mut sc = PhoneScenario::walk(12, PhonePlacement::InHand, 1.3, 90.0);
    sc.gnss = false;
    let sim = simulate_phone(&sc);
    let imu: Vec<(ImuSample, [f64; 4])> = sim
        .samples
        .iter()
        .map(|s| {
            (
                ImuSample {
                    t_s: s.t_s,
                    gyro_rads: s.gyro_radps,
                    accel_mps2: s.accel_mps2,
                    mag_ut: Some(s.mag_ut),
                },
                sim.truth_at(s.t_s).attitude_wxyz,
            )
        })
        .collect();
    for external in [false, true] {
        let mut nav = PhoneNavigator::with_calibration(NavigatorConfig::default(), &c).unwrap();
        let (n, steps) = allocations_in(|| {
            for (s, q) in &imu {
                if external {
                    nav.push_imu_with_attitude(s, *q).unwrap();
                } else {
                    nav.push_imu(s).unwrap();
                }
                std::hint::black_box(nav.estimate());
                std::hint::black_box(nav.recent_steps().1);
            }
            nav.estimate().expect("an estimate after input").steps
        });
        assert!(steps > 60, "external {external}: {steps} steps");
        assert_eq!(n, 0, "external {external}: allocations on the sample path");
    }
}

/// Separate sensor events (`push_event`), delivered in late 200 ms FIFO bursts: the
/// merger's queues are allocated at construction, nothing per event.
#[test]
fn navigator_does_not_allocate_per_sensor_event() {
    use stridekit_core::imu::{ImuEvent, SensorKind};
    let sim = simulate_phone(&PhoneScenario::walk(5, PhonePlacement::InHand, 1.4, 60.0));
    let mut events = Vec::with_capacity(sim.samples.len() * 3);
    for s in &sim.samples {
        for (kind, values, late) in [
            (SensorKind::Accelerometer, s.accel_mps2, 0),
            (SensorKind::Gyroscope, s.gyro_radps, 1),
            (SensorKind::Magnetometer, s.mag_ut, 1),
        ] {
            let burst = (s.t_s / 0.2).floor() as i64 + late;
            events.push((
                burst,
                ImuEvent {
                    t_s: s.t_s,
                    kind,
                    values,
                },
            ));
        }
    }
    events.sort_by_key(|e| e.0);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let (n, steps) = allocations_in(|| {
        for (_, e) in &events {
            nav.push_event(e).unwrap();
        }
        nav.flush_events();
        // A refused event too.
        assert!(nav.push_event(&events[0].1).is_err());
        nav.estimate().expect("an estimate").steps
    });
    assert!(steps > 50, "{steps} steps");
    assert_eq!(nav.merge_counts().samples, sim.samples.len() as u64);
    assert_eq!(n, 0, "allocations on the event path");
}
