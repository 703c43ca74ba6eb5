//! No heap allocation per sample once the foot navigator is aligned: the median
//! filter, every zero-velocity detector, the mechanisation and the Kalman filter run
//! on fixed-size state (counting allocator in `common`).

use crate::common::allocations_in;

use stridekit_core::foot::{
    AdaptiveThresholds, FixedThresholds, FootConfig, FootNavigator, FootSample, ShoeDetector,
    SvmAdaptive, ZeroVelocityDetector,
};
use stridekit_sim::{simulate_foot, FootScenario};

#[test]
fn pushing_samples_does_not_allocate() {
    let sim = simulate_foot(&FootScenario::walk(31, 1));
    for detector in [
        ZeroVelocityDetector::default(), // adaptive shoe
        ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ZeroVelocityDetector::Shoe(ShoeDetector::default()),
        ZeroVelocityDetector::Fixed(FixedThresholds::WALK),
        ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
        ZeroVelocityDetector::default_svm(),
    ] {
        for median_window in [1, 7] {
            let name = detector.name();
            let mut nav = FootNavigator::new(FootConfig {
                detector: detector.clone(),
                median_window,
                accel_range_mps2: Some(160.0),
                ..FootConfig::default()
            })
            .unwrap();
            let (warm, rest) = sim.samples.split_at(500);
            for s in warm {
                nav.push(s).unwrap();
            }
            assert!(nav.is_aligned());
            let (half_a, half_b) = rest.split_at(rest.len() / 2);
            let mut estimates = 0usize;
            let mut strides = 0usize;
            let (n, _) = allocations_in(|| {
                for s in half_a {
                    if let Some(e) = nav.push(s).unwrap() {
                        estimates += 1;
                        strides += e.stride.is_some() as usize;
                        std::hint::black_box(e);
                    }
                }
                // Rejected samples (typed errors) and a gap do not allocate either.
                let last = half_a.last().unwrap().t_s;
                let _ = nav.push(&FootSample {
                    t_s: f64::NAN,
                    ..half_b[0]
                });
                let _ = nav.push(&FootSample {
                    t_s: last,
                    ..half_b[0]
                });
                let _ = nav.push(&FootSample {
                    accel_mps2: [1e6, 0.0, 0.0],
                    ..half_b[0]
                });
                std::hint::black_box(nav.estimate());
                // A clean batch.
                let outcome = nav.push_batch_with(half_b, |e| {
                    std::hint::black_box(e);
                });
                estimates += outcome.estimates;
            });
            assert_eq!(
                n, 0,
                "{name} (median {median_window}): allocations on the per-sample path"
            );
            assert!(
                estimates > 5000 && strides > 10,
                "{name}: {estimates} {strides}"
            );
        }
    }
}

#[test]
fn the_gyroscope_ceiling_detector_does_not_allocate() {
    use stridekit_core::foot::GyroCeilingDetector;
    let sim = simulate_foot(&FootScenario::walk(31, 1));
    let mut d = GyroCeilingDetector::new();
    let (n, found) = allocations_in(|| {
        for s in &sim.samples {
            // Clipped at 4 rad/s, so that flat tops are found and grouped too.
            d.push(s.gyro_rads.map(|w| w.clamp(-4.0, 4.0)));
        }
        d.push([f64::NAN, 0.0, 0.0]);
        d.ceiling()
    });
    assert_eq!(n, 0, "allocations in the ceiling detector");
    assert!(found.is_some(), "the clipped walk has a ceiling");
}
