//! PhoneNavigator accuracy on the phone simulator, with margins (the figures come from
//! `stridekit eval pdr`): after GNSS calibrated the carrying, a 5-minute outage ends
//! within 10 % of the distance walked without GNSS, with the magnetometer, for
//! placements whose stride axis, yaw or attitude used to fail (pocket, neck pouch, bag).

use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::PhoneNavigator;
use stridekit_sim::phone::{navigator_config, simulate_phone, PhonePlacement, PhoneScenario};

/// End-point error as % of the distance walked after `outage_s`.
fn outage_error_pct(placement: PhonePlacement, seed: u64, walk_s: f64, outage_s: f64) -> f64 {
    let mut sc = PhoneScenario::walk(seed, placement, 1.4, walk_s);
    sc.gnss_outages = vec![(outage_s, walk_s + 1.0)];
    let sim = simulate_phone(&sc);
    let frame = LocalFrame::new(47.0, 8.0, 0.0);
    let mut nav = PhoneNavigator::new(navigator_config()).unwrap();
    let mut fi = 0;
    for s in &sim.samples {
        while fi < sim.fixes.len() && sim.fixes[fi].t_s <= s.t_s {
            let f = sim.fixes[fi];
            let (lat, lon) = frame.to_geodetic(f.east_m, f.north_m);
            nav.push_fix(&GnssFix::new(f.t_s, lat, lon).with_accuracy(f.accuracy_m))
                .unwrap();
            fi += 1;
        }
        nav.push_imu(&ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_radps,
            accel_mps2: s.accel_mps2,
            mag_ut: Some(s.mag_ut),
        })
        .unwrap();
    }
    let e = nav.estimate().expect("an estimate after input");
    let end = sim.truth.last().unwrap();
    let first = sim.fixes[0];
    let err =
        (e.east_m - (end.east_m - first.east_m)).hypot(e.north_m - (end.north_m - first.north_m));
    100.0 * err / (end.distance_m - sim.truth_at(outage_s).distance_m)
}

#[test]
fn a_five_minute_outage_ends_within_ten_percent() {
    for (placement, seed) in [
        (PhonePlacement::FrontPocket, 31),
        (PhonePlacement::NeckPouch, 32),
        (PhonePlacement::Bag, 33),
    ] {
        let e = outage_error_pct(placement, seed, 480.0, 180.0);
        assert!(e < 10.0, "{placement:?} seed {seed}: {e:.1} %");
    }
}
