//! Behaviour of the phone IMU simulator (`stridekit_sim::phone`).

use stridekit_sim::phone::{
    simulate_phone, PhoneActivity, PhonePlacement, PhoneScenario, PhoneSegment, TrueStep,
    GRAVITY_MPS2,
};

fn seg(activity: PhoneActivity, duration_s: f64) -> PhoneSegment {
    PhoneSegment {
        activity,
        duration_s,
    }
}

/// Steps compared bit for bit (`NaN` durations compare equal).
fn same_steps(a: &[TrueStep], b: &[TrueStep]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.t_s.to_bits() == y.t_s.to_bits()
                && x.length_m.to_bits() == y.length_m.to_bits()
                && x.duration_s.to_bits() == y.duration_s.to_bits()
                && x.segment == y.segment
        })
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[test]
fn deterministic_from_seed() {
    let sc = PhoneScenario::tour(5, PhonePlacement::FrontPocket);
    let a = simulate_phone(&sc);
    let b = simulate_phone(&sc);
    assert!(a.samples == b.samples && a.truth == b.truth && a.fixes == b.fixes);
    assert!(same_steps(&a.steps, &b.steps));
    let c = simulate_phone(&PhoneScenario::tour(6, PhonePlacement::FrontPocket));
    assert!(a.samples != c.samples && a.fixes != c.fixes);
    assert!(!same_steps(&a.steps, &c.steps));
}

#[test]
fn steps_only_while_walking_or_running_and_match_cadence() {
    for placement in PhonePlacement::ALL {
        let sim = simulate_phone(&PhoneScenario::tour(11, placement));
        assert!(!sim.steps.is_empty());
        for s in &sim.steps {
            let i = sim.segment_at(s.t_s).expect("step inside the scenario");
            assert!(
                sim.scenario.segments[i].activity.has_steps(),
                "{placement:?}: step at {} in {:?}",
                s.t_s,
                sim.scenario.segments[i].activity
            );
            let first_of_bout = s.duration_s.is_nan() && s.length_m == 0.0;
            assert!(
                first_of_bout || (s.duration_s > 0.0 && s.length_m > 0.2),
                "{s:?}"
            );
        }
        // Per walking/running segment: steps ≈ duration × speed / step length.
        for (i, sg) in sim.scenario.segments.iter().enumerate() {
            let (s0, s1) = sim.segment_times[i];
            let n = sim.steps.iter().filter(|s| s.segment == i).count() as f64;
            match sg.activity {
                PhoneActivity::Walking { speed_mps } | PhoneActivity::Running { speed_mps } => {
                    let lengths: Vec<f64> = sim
                        .steps
                        .iter()
                        .filter(|s| s.segment == i && s.length_m > 0.0)
                        .map(|s| s.length_m)
                        .collect();
                    let mean_l = lengths.iter().sum::<f64>() / n;
                    let expected = (s1 - s0) * speed_mps / mean_l;
                    assert!(
                        (n - expected).abs() <= 0.05 * expected + 2.0,
                        "{placement:?} seg {i}: {n} steps, expected {expected}"
                    );
                    let f = n / (s1 - s0);
                    if matches!(sg.activity, PhoneActivity::Walking { .. }) {
                        assert!((1.5..=2.2).contains(&f), "walking cadence {f}");
                        assert!((0.6..=0.85).contains(&mean_l), "walking step {mean_l}");
                    } else {
                        assert!((2.4..=3.2).contains(&f), "running cadence {f}");
                        assert!((0.95..=1.2).contains(&mean_l), "running step {mean_l}");
                    }
                }
                _ => assert_eq!(n, 0.0, "{placement:?}: steps in {:?}", sg.activity),
            }
        }
    }
}

#[test]
fn step_lengths_sum_to_walked_distance() {
    let sc = PhoneScenario {
        segments: vec![
            seg(PhoneActivity::Walking { speed_mps: 1.3 }, 120.0),
            seg(PhoneActivity::Standing, 10.0),
            seg(PhoneActivity::Running { speed_mps: 3.2 }, 120.0),
        ],
        ..PhoneScenario::walk(2, PhonePlacement::InHand, 1.3, 0.0)
    };
    let sim = simulate_phone(&sc);
    let sum: f64 = sim.steps.iter().map(|s| s.length_m).sum();
    let dist = sim.truth.last().unwrap().distance_m;
    assert!((sum - dist).abs() < 0.002 * dist, "{sum} vs {dist}");
    // Path length of the truth track equals the distance.
    let path: f64 = sim
        .truth
        .windows(2)
        .map(|w| (w[1].east_m - w[0].east_m).hypot(w[1].north_m - w[0].north_m))
        .sum();
    assert!((path - dist).abs() < 0.002 * dist, "{path} vs {dist}");
}

#[test]
fn magnitude_at_rest_is_gravity_and_motion_is_bigger() {
    for placement in PhonePlacement::ALL {
        let sc = PhoneScenario {
            segments: vec![
                seg(PhoneActivity::Standing, 30.0),
                seg(PhoneActivity::Walking { speed_mps: 1.4 }, 30.0),
                seg(PhoneActivity::Running { speed_mps: 3.2 }, 30.0),
                seg(PhoneActivity::Shaking, 10.0),
            ],
            ..PhoneScenario::walk(4, placement, 1.4, 0.0)
        };
        let sim = simulate_phone(&sc);
        let stats = |k: usize| {
            let (s0, s1) = sim.segment_times[k];
            let m: Vec<f64> = sim
                .samples
                .iter()
                .filter(|s| s.t_s >= s0 + 1.0 && s.t_s < s1 - 1.0)
                .map(|s| s.accel_norm_mps2())
                .collect();
            let mean = m.iter().sum::<f64>() / m.len() as f64;
            let var = m.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / m.len() as f64;
            (mean, var.sqrt())
        };
        let (rest, rest_sd) = stats(0);
        assert!((rest - GRAVITY_MPS2).abs() < 0.1, "{placement:?}: {rest}");
        assert!(rest_sd < 0.1, "{placement:?}: {rest_sd}");
        let (_, walk_sd) = stats(1);
        let (_, run_sd) = stats(2);
        let (_, shake_sd) = stats(3);
        assert!(walk_sd > 0.8, "{placement:?}: walking sd {walk_sd}");
        assert!(
            run_sd > 2.0 * walk_sd,
            "{placement:?}: {run_sd} vs {walk_sd}"
        );
        assert!(shake_sd > 2.0, "{placement:?}: shaking sd {shake_sd}");
        // Gyro and magnetometer plausible at rest.
        let (s0, s1) = sim.segment_times[0];
        for s in sim.samples.iter().filter(|s| s.t_s > s0 && s.t_s < s1) {
            assert!(norm(s.gyro_radps) < 0.2, "{:?}", s.gyro_radps);
            let m = norm(s.mag_ut);
            assert!((35.0..=65.0).contains(&m), "{m}");
        }
    }
}

#[test]
fn sample_rate_and_jitter_options() {
    for rate in [50.0, 200.0, 500.0] {
        let mut sc = PhoneScenario::walk(1, PhonePlacement::Armband, 1.3, 20.0);
        sc.sample_rate_hz = rate;
        let sim = simulate_phone(&sc);
        assert_eq!(sim.samples.len(), (20.0 * rate) as usize);
        let dts: Vec<f64> = sim
            .samples
            .windows(2)
            .map(|w| w[1].t_s - w[0].t_s)
            .collect();
        assert!(dts.iter().all(|d| (d - 1.0 / rate).abs() < 1e-9));
        sc.timestamp_jitter_s = 0.2 / rate;
        let jit = simulate_phone(&sc);
        assert_eq!(jit.samples.len(), sim.samples.len());
        assert!(jit.samples.windows(2).all(|w| w[1].t_s > w[0].t_s));
        let dev: f64 = jit
            .samples
            .iter()
            .enumerate()
            .map(|(i, s)| (s.t_s - i as f64 / rate).abs())
            .sum::<f64>()
            / jit.samples.len() as f64;
        assert!(dev > 0.05 / rate && dev < 0.3 / rate, "{dev}");
        // Same motion: same steps.
        assert!(same_steps(&jit.steps, &sim.steps));
    }
    // Out-of-range rates are clamped.
    let mut sc = PhoneScenario::walk(1, PhonePlacement::Armband, 1.3, 10.0);
    sc.sample_rate_hz = 5000.0;
    assert_eq!(simulate_phone(&sc).samples.len(), 5000);
}

#[test]
fn vehicle_and_cycling_move_without_steps_and_gnss_follows_truth() {
    let sc = PhoneScenario {
        segments: vec![
            seg(PhoneActivity::Vehicle { speed_mps: 12.0 }, 120.0),
            seg(PhoneActivity::Cycling { speed_mps: 5.0 }, 120.0),
        ],
        gnss_outages: vec![(100.0, 150.0)],
        ..PhoneScenario::walk(8, PhonePlacement::Bag, 1.3, 0.0)
    };
    let sim = simulate_phone(&sc);
    assert!(sim.steps.is_empty());
    let d = sim.truth.last().unwrap().distance_m;
    assert!(d > 0.8 * (120.0 * 12.0 + 120.0 * 5.0) * 0.9, "{d}");
    assert!(sim.fixes.iter().all(|f| !(100.0..150.0).contains(&f.t_s)));
    assert_eq!(sim.fixes.len(), 241 - 50);
    let mut e2 = 0.0;
    for f in &sim.fixes {
        let t = sim.truth_at(f.t_s);
        e2 += (f.east_m - t.east_m).powi(2) + (f.north_m - t.north_m).powi(2);
        assert!((3.0..=5.0).contains(&f.accuracy_m));
    }
    let rms = (e2 / sim.fixes.len() as f64).sqrt();
    assert!(rms > 0.5 && rms < 5.0, "{rms}");
    // Turns stay drivable: lateral acceleration (speed × heading rate) ≤ 3 m/s².
    for w in sim.truth.windows(2) {
        let dh = stridekit_core::angle::wrap(w[1].heading_rad - w[0].heading_rad);
        let lat = w[0].speed_mps * dh / 0.1;
        assert!(lat.abs() < 3.0, "t {}: {lat}", w[0].t_s);
    }
}

#[test]
fn step_events_carry_features_that_grow_with_speed() {
    let sc = PhoneScenario {
        segments: vec![
            seg(PhoneActivity::Walking { speed_mps: 1.0 }, 60.0),
            seg(PhoneActivity::Walking { speed_mps: 1.7 }, 60.0),
            seg(PhoneActivity::Running { speed_mps: 3.5 }, 60.0),
        ],
        ..PhoneScenario::walk(9, PhonePlacement::BackPocket, 1.0, 0.0)
    };
    let sim = simulate_phone(&sc);
    let ev = sim.step_events();
    assert_eq!(ev.len(), sim.steps.len());
    let mean_sv = |k: usize| {
        let v: Vec<f64> = ev
            .iter()
            .zip(&sim.steps)
            .filter(|(_, s)| s.segment == k)
            .map(|(e, _)| e.accel_variance_m2ps4)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    assert!(mean_sv(0) < mean_sv(1) && mean_sv(1) < mean_sv(2));
    for (e, s) in ev.iter().zip(&sim.steps) {
        assert_eq!(e.t_s, s.t_s);
        assert!(e.accel_max_mps2 > e.accel_min_mps2);
    }
}
