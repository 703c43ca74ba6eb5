//! Garbage in, no panic out: the phone engines fed adversarial input (extreme values,
//! NaN, time jumps, reversals, units in g, huge gaps) keep returning typed errors or
//! finite outputs, and their snapshots restore.

use stridekit_core::ahrs::{Ahrs, AhrsSettings, ImuSample};
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};
use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig, StepEvent, StepOrigin};
use stridekit_core::steplength::{StepLengthConfig, StepLengthEstimator, StepLengthModel};
use stridekit_sim::Rng;

fn pick(rng: &mut Rng, normal: f64) -> f64 {
    match rng.next_u64() % 12 {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1e12,
        3 => 0.0,
        4 => 1e-300,
        5 => rng.range(-500.0, 500.0),
        _ => normal + rng.normal(),
    }
}

fn next_t(rng: &mut Rng, t: &mut f64) -> f64 {
    // Long jumps are rare: three long intervals in a row between accepted samples
    // are refused as a time-unit error for good (see stridekit_core::input).
    *t += match rng.next_u64() % 250 {
        0..=1 => -rng.range(0.0, 0.5),
        2 => rng.range(0.0, 1e5),
        3..=7 => 0.0,
        _ => rng.range(0.001, 0.02),
    };
    *t
}

fn imu(rng: &mut Rng, t: &mut f64) -> ImuSample {
    let g = if rng.next_u64() % 50 == 0 { 1.0 } else { 9.81 };
    ImuSample {
        t_s: next_t(rng, t),
        gyro_rads: [pick(rng, 0.0), pick(rng, 0.0), pick(rng, 0.0)],
        accel_mps2: [pick(rng, 0.0), pick(rng, 0.0), pick(rng, g)],
        mag_ut: (rng.next_u64() % 3 != 0)
            .then(|| [pick(rng, 20.0), pick(rng, 0.0), pick(rng, -40.0)]),
    }
}

#[test]
fn step_detector_and_ahrs_survive_garbage() {
    let mut rng = Rng::new(77);
    for config in [
        StepDetectorConfig::default(),
        StepDetectorConfig::as_published(),
    ] {
        let mut d = StepDetector::new(config).unwrap();
        let mut a = Ahrs::new(AhrsSettings::default()).unwrap();
        let mut t = 0.0;
        let (mut accepted_d, mut accepted_a) = (0, 0);
        for _ in 0..30_000 {
            let s = imu(&mut rng, &mut t);
            match d.push_accel(s.t_s, s.accel_mps2) {
                Ok(Some(e)) => {
                    accepted_d += 1;
                    assert!(e.t_s.is_finite());
                }
                Ok(None) => accepted_d += 1,
                Err(_) => {}
            }
            while let Some(e) = d.pop_step() {
                assert!(e.t_s.is_finite());
            }
            if a.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut).is_ok() {
                accepted_a += 1;
            }
            if let Some(o) = a.output() {
                assert!(o.quaternion.iter().all(|q| q.is_finite()), "{o:?}");
                assert!(o.heading_rad.is_finite());
            }
        }
        eprintln!(
            "{:?}: accepted {accepted_d} (detector), {accepted_a} (AHRS) of 30000",
            config.mode
        );
        // The AHRS refuses a sample when any of its nine values is out of range (gyro
        // beyond ±200 rad/s among them), so it accepts fewer than the detector.
        assert!(
            accepted_d > 3_000 && accepted_a > 1_500,
            "{accepted_d} {accepted_a}"
        );
        assert!(StepDetector::restore(&d.snapshot()).is_ok());
        assert!(Ahrs::restore(&a.snapshot()).is_ok());
    }
}

#[test]
fn step_length_estimator_survives_garbage() {
    let mut rng = Rng::new(78);
    for model in StepLengthModel::ALL {
        let mut est = StepLengthEstimator::new(model, StepLengthConfig::default()).unwrap();
        let mut t = 0.0;
        for _ in 0..20_000 {
            if rng.next_u64() % 3 == 0 {
                let tt = next_t(&mut rng, &mut t);
                let _ = est.push_gnss_fix(
                    tt,
                    pick(&mut rng, 0.0),
                    pick(&mut rng, 0.0),
                    Some(rng.range(-1.0, 50.0)),
                );
            } else {
                let e = StepEvent {
                    t_s: next_t(&mut rng, &mut t),
                    duration_s: pick(&mut rng, 0.55),
                    accel_variance_m2ps4: pick(&mut rng, 4.0),
                    accel_max_mps2: pick(&mut rng, 14.0),
                    accel_min_mps2: pick(&mut rng, 6.0),
                    vertical_displacement_m: pick(&mut rng, 0.07),
                    origin: StepOrigin::Detected,
                };
                if let Ok(l) = est.push_step(&e) {
                    assert!(l.is_finite() && l >= 0.0, "{model:?}: {l}");
                }
            }
        }
        if let Err(e) = StepLengthEstimator::restore(&est.snapshot()) {
            panic!("{model:?}: {e}");
        }
    }
}

#[test]
fn phone_navigator_survives_garbage() {
    let mut rng = Rng::new(79);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let mut t = 0.0;
    for i in 0..30_000 {
        if i % 97 == 0 {
            let f = GnssFix {
                t_s: t,
                lat_deg: pick(&mut rng, 45.0),
                lon_deg: pick(&mut rng, 7.0),
                alt_m: None,
                horizontal_accuracy_m: Some(rng.range(-1.0, 100.0)),
                speed_mps: None,
                speed_accuracy_mps: None,
            };
            let _ = nav.push_fix(&f);
        }
        let s = imu(&mut rng, &mut t);
        let _ = nav.push_imu(&s);
        if let Some(e) = nav.estimate() {
            assert!(
                e.east_m.is_finite() && e.north_m.is_finite() && e.distance_m.is_finite(),
                "{e:?}"
            );
        }
    }
    if let Err(e) = PhoneNavigator::restore(&nav.snapshot()) {
        panic!("{e}");
    }
}
