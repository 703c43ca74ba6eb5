//! MapNavigator: no heap allocation per IMU sample or fix after construction — the
//! particles' steps, resampling, the smoothing window and its traces, fixes weighed,
//! held back and believed, recoveries on a plan every step crosses, rejected inputs.

use std::sync::Arc;

use crate::common::allocations_in;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::map::{FloorPlan, MapConfig, MapFix, MapNavigator};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario};

fn samples() -> Vec<ImuSample> {
    let mut sc = PhoneScenario::walk(5, PhonePlacement::InHand, 1.3, 60.0);
    sc.gnss = false;
    simulate_phone(&sc)
        .samples
        .iter()
        .map(ImuSample::from)
        .collect()
}

fn plans() -> Vec<Arc<FloorPlan>> {
    // An open hall with a few shops, and a comb of walls no step fits between.
    let hall = FloorPlan::rectangles(
        0,
        [-200.0, -200.0, 200.0, 200.0],
        &[
            [10.0, 10.0, 20.0, 20.0],
            [-30.0, 5.0, -20.0, 40.0],
            [5.0, -40.0, 40.0, -30.0],
        ],
    )
    .unwrap();
    let comb: Vec<[f64; 4]> = (0..100)
        .flat_map(|k| {
            let v = 0.3 * k as f64;
            [[v, 0.0, v + 0.02, 30.0], [0.0, v, 30.0, v + 0.02]]
        })
        .collect();
    let comb = FloorPlan::rectangles(1, [0.0, 0.0, 30.0, 30.0], &comb).unwrap();
    vec![Arc::new(hall), Arc::new(comb)]
}

#[test]
fn map_navigator_does_not_allocate_per_sample_or_fix() {
    let xs = samples();
    let config = MapConfig {
        particles: 300,
        smoothing_lag_steps: 16,
        ..MapConfig::default()
    };
    let mut m = MapNavigator::new(config, plans()).unwrap();
    m.start_at(0.0, 0.0, Some(1.0), Some(0)).unwrap();
    let n = xs.len();
    let (count, (steps, recoveries)) = allocations_in(|| {
        let mut fixed = 0u64;
        for (i, s) in xs.iter().enumerate() {
            let t = s.t_s;
            match i {
                // A fix that agrees, one far off, one that agrees with that, one on
                // the comb's floor (every step there crosses a wall).
                _ if i == n / 6 => {
                    let e = m.estimate().unwrap();
                    m.push_fix(&MapFix::plan(t, e.x_m + 1.0, e.y_m, 3.0))
                        .unwrap();
                }
                _ if i == n / 3 => {
                    m.push_fix(&MapFix::plan(t, 150.0, 150.0, 3.0)).unwrap();
                }
                _ if i == n / 3 + 300 => {
                    m.push_fix(&MapFix::plan(t, 151.0, 150.0, 3.0)).unwrap();
                }
                _ if i == 2 * n / 3 => {
                    let f = MapFix {
                        floor: Some(1),
                        ..MapFix::plan(t, 15.1, 15.1, 2.0)
                    };
                    m.push_fix(&f).unwrap();
                }
                _ => {}
            }
            std::hint::black_box(m.push(s).unwrap());
            fixed = m.smoothed_fixed().max(fixed);
            std::hint::black_box(m.smoothed_since(fixed.saturating_sub(3)).count());
            if i % 500 == 0 {
                m.smoothed_window(|p| {
                    std::hint::black_box(p);
                });
            }
        }
        // Rejected inputs.
        let t = m.estimate().unwrap().t_s;
        let mut bad = xs[0];
        bad.t_s = t + 0.01;
        bad.accel_mps2[1] = f64::NAN;
        assert!(m.push(&bad).is_err());
        assert!(m
            .push_fix(&MapFix::plan(t + 1.0, f64::NAN, 0.0, 3.0))
            .is_err());
        assert!(m.push_fix(&MapFix::plan(t - 100.0, 0.0, 0.0, 3.0)).is_err());
        let e = m.estimate().unwrap();
        (e.steps, e.recoveries)
    });
    assert!(steps > 80, "{steps} steps");
    assert!(
        recoveries > 5,
        "the comb's floor was reached: {recoveries} recoveries"
    );
    assert_eq!(count, 0, "allocations on the sample and fix path");
}
