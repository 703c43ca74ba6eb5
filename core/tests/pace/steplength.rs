//! Behaviour of the step-length estimator (`stridekit_core::steplength`).

use stridekit_core::input::InputError;
use stridekit_core::snapshot::SnapshotError;
use stridekit_core::stepdetect::{StepEvent, StepOrigin};
use stridekit_core::steplength::{
    StepLengthConfig, StepLengthError, StepLengthEstimator, StepLengthModel, GAIT_INITIATION,
};
use stridekit_core::{PaceConfig, PaceTracker};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario, SimulatedPhone};

fn event(t_s: f64, duration_s: f64, sv: f64) -> StepEvent {
    StepEvent {
        t_s,
        duration_s,
        accel_variance_m2ps4: sv,
        accel_max_mps2: 9.81 + sv.sqrt() * 1.5,
        accel_min_mps2: 9.81 - sv.sqrt(),
        vertical_displacement_m: f64::NAN,
        origin: StepOrigin::Detected,
    }
}

/// Feed fixes (before `t_gnss_end`) and steps of a simulated walk; returns lengths.
fn feed(est: &mut StepLengthEstimator, sim: &SimulatedPhone, t_gnss_end: f64) -> Vec<f64> {
    let mut fi = 0;
    let mut out = Vec::new();
    for e in sim.step_events() {
        while let Some(f) = sim.fixes.get(fi) {
            if f.t_s > e.t_s || f.t_s >= t_gnss_end {
                break;
            }
            est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m))
                .unwrap();
            fi += 1;
        }
        out.push(est.push_step(&e).unwrap());
    }
    out
}

#[test]
fn uncalibrated_gives_the_prior_and_bad_input_is_rejected_without_change() {
    let c = StepLengthConfig::default();
    for m in StepLengthModel::ALL {
        let mut est = StepLengthEstimator::new(m, c).unwrap();
        // The first step of a walk is read at its gait-initiation share of the prior.
        let l = est.push_step(&event(1.0, 0.55, 10.0)).unwrap() / GAIT_INITIATION[0];
        assert!((0.5..=0.95).contains(&l), "{m:?}: prior {l}");
        let before = est.snapshot();
        let bad = [
            event(f64::NAN, 0.5, 10.0),
            event(0.5, 0.5, 10.0),
            event(1.0, 0.5, 10.0),
            event(2.0, 0.0, 10.0),
            event(2.0, -1.0, 10.0),
            event(2.0, 0.5, -1.0),
            event(2.0, 0.5, f64::INFINITY),
            StepEvent {
                accel_max_mps2: 5.0,
                accel_min_mps2: 6.0,
                vertical_displacement_m: f64::NAN,
                ..event(2.0, 0.5, 1.0)
            },
        ];
        for b in bad {
            assert!(est.push_step(&b).is_err(), "{m:?}: {b:?} accepted");
        }
        assert!(matches!(
            est.push_step(&event(0.5, 0.5, 10.0)),
            Err(StepLengthError::Input(InputError::TimeNotIncreasing { .. }))
        ));
        est.push_gnss_fix(1.0, 0.0, 0.0, Some(4.0)).unwrap();
        let before_fix = est.snapshot();
        assert!(matches!(
            est.push_gnss_fix(1.0, 1.0, 0.0, None),
            Err(StepLengthError::Input(InputError::TimeNotIncreasing { .. }))
        ));
        assert!(matches!(
            est.push_gnss_fix(2.0, f64::NAN, 0.0, None),
            Err(StepLengthError::Input(InputError::NonFinite { .. }))
        ));
        assert!(matches!(
            est.push_gnss_fix(2.0, 1.0, 0.0, Some(-1.0)),
            Err(StepLengthError::Input(InputError::OutOfRange { .. }))
        ));
        assert_eq!(est.snapshot(), before_fix);
        assert_ne!(before, before_fix);
        // NaN duration (first step of a bout) is fine.
        assert!(est.push_step(&event(3.0, f64::NAN, 10.0)).is_ok());
    }
    let bad = StepLengthConfig {
        sample_sigma_m: 0.0,
        ..StepLengthConfig::default()
    };
    assert!(matches!(
        StepLengthEstimator::new(StepLengthModel::Linear, bad),
        Err(StepLengthError::InvalidConfig { .. })
    ));
}

#[test]
fn as_published_recovers_an_exact_linear_law() {
    // Noise-free GNSS at every step, F and SV varying independently: the paper's
    // per-block least squares is exact, and the robust fit gets close.
    let (a, b, c) = (0.3, 0.004, 0.15);
    for model in [StepLengthModel::LinearAsPublished, StepLengthModel::Linear] {
        let mut est = StepLengthEstimator::new(model, StepLengthConfig::default()).unwrap();
        let (mut t, mut x) = (0.0, 0.0);
        est.push_gnss_fix(t, x, 0.0, Some(3.0)).unwrap();
        est.push_step(&event(t, f64::NAN, 10.0)).unwrap();
        for i in 0..2000 {
            let f = 1.8 + 0.5 * (i as f64 * 0.05).sin();
            let sv = 20.0 + 15.0 * (i as f64 * 0.071).cos();
            let l = a * f + b * sv + c;
            t += 1.0 / f;
            x += l;
            est.push_gnss_fix(t, x, 0.0, Some(3.0)).unwrap();
            est.push_step(&event(t, 1.0 / f, sv)).unwrap();
        }
        let cal = est.calibration();
        // Exact data: the as-published average stops moving and freezes after the
        // minimum number of fits.
        assert!(cal.fits >= 10, "{model:?}: {cal:?}");
        if model == StepLengthModel::LinearAsPublished {
            assert!(cal.converged && cal.fits == 10, "{cal:?}");
        }
        let th = cal.theta;
        let tol = if model == StepLengthModel::LinearAsPublished {
            1e-6
        } else {
            0.02
        };
        assert!(
            (th[0] - a).abs() < tol
                && (th[1] - b).abs() < tol / 5.0
                && (th[2] - c).abs() < 2.0 * tol,
            "{model:?}: {th:?}"
        );
    }
}

#[test]
fn calibrates_from_a_simulated_walk() {
    let sim = simulate_phone(&PhoneScenario::walk(
        21,
        PhonePlacement::FrontPocket,
        1.4,
        480.0,
    ));
    let truth_mean = sim
        .steps
        .iter()
        .map(|s| s.length_m)
        .filter(|l| *l > 0.0)
        .sum::<f64>()
        / sim.steps.iter().filter(|s| s.length_m > 0.0).count() as f64;
    for m in [
        StepLengthModel::Constant,
        StepLengthModel::Linear,
        StepLengthModel::LinearFrequencyOnly,
        StepLengthModel::Weinberg,
    ] {
        let mut est = StepLengthEstimator::new(m, StepLengthConfig::default()).unwrap();
        feed(&mut est, &sim, f64::INFINITY);
        let cal = est.calibration();
        assert!(cal.fits > 30, "{m:?}: {cal:?}");
        let rel = cal.typical_step_length_m / truth_mean - 1.0;
        assert!(rel.abs() < 0.03, "{m:?}: {rel} {cal:?}");
    }
}

#[test]
fn bad_gnss_teaches_nothing() {
    let sim = simulate_phone(&PhoneScenario::walk(5, PhonePlacement::InHand, 1.3, 120.0));
    let events = sim.step_events();
    // Inaccurate fixes.
    let mut est =
        StepLengthEstimator::new(StepLengthModel::Linear, StepLengthConfig::default()).unwrap();
    let prior = est.calibration();
    let mut fi = 0;
    for e in &events {
        while fi < sim.fixes.len() && sim.fixes[fi].t_s <= e.t_s {
            let f = sim.fixes[fi];
            est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(25.0))
                .unwrap();
            fi += 1;
        }
        est.push_step(e).unwrap();
    }
    assert_eq!(est.calibration().samples, 0);
    assert_eq!(est.calibration().theta, prior.theta);
    // Fixes every 5 s (gaps too long), and fixes with jumps.
    for (every, jump) in [(5usize, 0.0), (1, 40.0)] {
        let mut est =
            StepLengthEstimator::new(StepLengthModel::Constant, StepLengthConfig::default())
                .unwrap();
        let mut fi = 0;
        for e in &events {
            while fi < sim.fixes.len() && sim.fixes[fi].t_s <= e.t_s {
                let f = sim.fixes[fi];
                if fi % every == 0 {
                    let j = if fi % 2 == 0 { jump } else { 0.0 };
                    est.push_gnss_fix(f.t_s, f.east_m + j, f.north_m, Some(f.accuracy_m))
                        .unwrap();
                }
                fi += 1;
            }
            est.push_step(e).unwrap();
        }
        assert_eq!(est.calibration().samples, 0, "every {every}, jump {jump}");
    }
}

#[test]
fn snapshot_keeps_the_calibration_and_continues_identically() {
    let sim = simulate_phone(&PhoneScenario::walk(8, PhonePlacement::Armband, 1.3, 300.0));
    let events = sim.step_events();
    for m in StepLengthModel::ALL {
        let mut a = StepLengthEstimator::new(m, StepLengthConfig::default()).unwrap();
        let half = events.len() / 2;
        let mut fi = 0;
        let feed_one = |est: &mut StepLengthEstimator, e: &StepEvent, fi: &mut usize| {
            while *fi < sim.fixes.len() && sim.fixes[*fi].t_s <= e.t_s {
                let f = sim.fixes[*fi];
                est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m))
                    .unwrap();
                *fi += 1;
            }
            est.push_step(e).unwrap()
        };
        for e in &events[..half] {
            feed_one(&mut a, e, &mut fi);
        }
        let bytes = a.snapshot();
        let mut b = StepLengthEstimator::restore(&bytes).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.calibration(), b.calibration());
        assert!(a.calibration().fits > 0, "{m:?}");
        let fi0 = fi;
        let mut fb = fi0;
        for e in &events[half..] {
            let la = feed_one(&mut a, e, &mut fi);
            let lb = feed_one(&mut b, e, &mut fb);
            assert_eq!(la.to_bits(), lb.to_bits());
        }
        assert_eq!(a.snapshot(), b.snapshot());
        // Corruption, truncation and other engines' snapshots are refused.
        let mut bad = bytes.clone();
        bad[20] ^= 0x40;
        assert!(matches!(
            StepLengthEstimator::restore(&bad),
            Err(StepLengthError::Snapshot(SnapshotError::Checksum))
        ));
        assert!(StepLengthEstimator::restore(&bytes[..bytes.len() - 9]).is_err());
        let pace = PaceTracker::new(PaceConfig::default()).unwrap().snapshot();
        assert!(matches!(
            StepLengthEstimator::restore(&pace),
            Err(StepLengthError::Snapshot(SnapshotError::WrongKind { .. }))
        ));
    }
}

#[test]
fn converges_then_stops_refitting_unless_told_otherwise() {
    let sim = simulate_phone(&PhoneScenario::walk(
        3,
        PhonePlacement::NeckPouch,
        1.3,
        900.0,
    ));
    let config = StepLengthConfig {
        converged_rel_sigma: 0.02,
        ..StepLengthConfig::default()
    };
    let mut est = StepLengthEstimator::new(StepLengthModel::Linear, config).unwrap();
    feed(&mut est, &sim, f64::INFINITY);
    let cal = est.calibration();
    assert!(cal.converged, "{cal:?}");
    // Frozen: it stopped before using every block of the 15-minute walk.
    let mut learning = StepLengthEstimator::new(
        StepLengthModel::Linear,
        StepLengthConfig {
            freeze_when_converged: false,
            ..config
        },
    )
    .unwrap();
    feed(&mut learning, &sim, f64::INFINITY);
    assert!(learning.calibration().fits > cal.fits + 10, "{cal:?}");
    // As published: converges by the stability of the averaged fit (may or may not
    // happen on noisy data; it must not panic and must stay bounded).
    let mut p = StepLengthEstimator::new(StepLengthModel::LinearAsPublished, config).unwrap();
    for l in feed(&mut p, &sim, f64::INFINITY) {
        assert!((0.25..=2.5).contains(&l));
    }
}

#[test]
fn missed_detections_do_not_bias_the_calibration() {
    let sim = simulate_phone(&PhoneScenario::walk(
        12,
        PhonePlacement::BackPocket,
        1.3,
        480.0,
    ));
    let truth_mean = sim
        .steps
        .iter()
        .map(|s| s.length_m)
        .filter(|l| *l > 0.0)
        .sum::<f64>()
        / sim.steps.iter().filter(|s| s.length_m > 0.0).count() as f64;
    // Drop every 37th step: the next one then spans two steps (double duration).
    const DROP_EVERY: usize = 37;
    let mut events = Vec::new();
    let mut dropped_t: Option<f64> = None;
    for (i, e) in sim.step_events().into_iter().enumerate() {
        if i % DROP_EVERY == DROP_EVERY - 1 {
            dropped_t = Some(e.t_s - e.duration_s);
            continue;
        }
        let mut e = e;
        if let Some(t0) = dropped_t.take() {
            e.duration_s = e.t_s - t0;
        }
        events.push(e);
    }
    let mut est =
        StepLengthEstimator::new(StepLengthModel::Linear, StepLengthConfig::default()).unwrap();
    let mut fi = 0;
    for e in &events {
        while fi < sim.fixes.len() && sim.fixes[fi].t_s <= e.t_s {
            let f = sim.fixes[fi];
            est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m))
                .unwrap();
            fi += 1;
        }
        est.push_step(e).unwrap();
    }
    let cal = est.calibration();
    assert!(cal.rejected_blocks > 5, "{cal:?}");
    // Half the blocks are rejected, and the accepted ones no longer form one chain
    // (GNSS noise stops telescoping between them): noisier (±3 % over 8 seeds),
    // but unbiased; without the frequency check every dropped step would add a
    // 6-steps-in-5 sample (+20 %) to the fit.
    let rel = cal.typical_step_length_m / truth_mean - 1.0;
    assert!(rel.abs() < 0.04, "{rel} {cal:?}");
}

#[test]
fn steps_lagging_or_leading_gnss_are_located_alike() {
    let sim = simulate_phone(&PhoneScenario::walk(31, PhonePlacement::InHand, 1.3, 300.0));
    let events = sim.step_events();
    let mut results = Vec::new();
    // Fixes pushed up to `lead_s` ahead of the steps (negative: behind).
    for lead_s in [0.0, 4.0, -4.0] {
        let mut est =
            StepLengthEstimator::new(StepLengthModel::Linear, StepLengthConfig::default()).unwrap();
        let mut fi = 0;
        for e in events.iter().filter(|e| e.t_s < 285.0) {
            while fi < sim.fixes.len() && sim.fixes[fi].t_s <= e.t_s + lead_s {
                let f = sim.fixes[fi];
                est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m))
                    .unwrap();
                fi += 1;
            }
            est.push_step(e).unwrap();
        }
        // The remaining fixes locate the steps still waiting.
        for f in &sim.fixes[fi..] {
            est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m))
                .unwrap();
        }
        results.push(est.calibration());
    }
    assert!(results[0].fits > 20, "{:?}", results[0]);
    for c in &results[1..] {
        assert_eq!(c, &results[0]);
    }
}

#[test]
fn the_first_steps_from_standing_are_short_and_a_short_gap_is_not_a_stop() {
    let c = StepLengthConfig::default();
    let mut est = StepLengthEstimator::new(StepLengthModel::Weinberg, c).unwrap();
    let mut lengths = Vec::new();
    // Identical steps: a walk, a 3 s gap (steps lost in a turn), a 6 s stop, a walk.
    let times = [1.0, 1.5, 2.0, 2.5, 5.5, 6.0, 12.0, 12.5, 13.0];
    let mut snapshot_at_restart = None;
    for (i, &t) in times.iter().enumerate() {
        if i == 7 {
            snapshot_at_restart = Some(est.snapshot());
        }
        lengths.push(est.push_step(&event(t, 0.5, 10.0)).unwrap());
    }
    let steady = lengths[2];
    let shares: Vec<f64> = lengths.iter().map(|l| l / steady).collect();
    let want = [
        GAIT_INITIATION[0],
        GAIT_INITIATION[1],
        1.0,
        1.0,
        1.0,
        1.0,
        GAIT_INITIATION[0],
        GAIT_INITIATION[1],
        1.0,
    ];
    for (got, want) in shares.iter().zip(want) {
        assert!((got - want).abs() < 1e-12, "{shares:?}");
    }
    // A snapshot taken inside the initiation steps continues them.
    let mut restored = StepLengthEstimator::restore(&snapshot_at_restart.unwrap()).unwrap();
    let l7 = restored.push_step(&event(12.5, 0.5, 10.0)).unwrap();
    assert_eq!(l7, lengths[7]);
}

/// The pendulum model: L = K·√h with the prior K = 2·√(2·l) of a 0.9 m leg; a step
/// without h gets the prior step length, an impossible h is refused.
#[test]
fn the_pendulum_reads_the_vertical_displacement_and_needs_it() {
    use stridekit_core::steplength::{PRIOR_LEG_LENGTH_M, PRIOR_PENDULUM_K};
    assert_eq!(PRIOR_PENDULUM_K, 2.0 * (2.0 * PRIOR_LEG_LENGTH_M).sqrt());
    let c = StepLengthConfig::default();
    assert_eq!(c.prior_pendulum_k, PRIOR_PENDULUM_K);
    let mut est = StepLengthEstimator::new(StepLengthModel::Pendulum, c).unwrap();
    let with_h = |t: f64, h: f64| StepEvent {
        vertical_displacement_m: h,
        ..event(t, 0.55, 4.0)
    };
    // Past the gait initiation: steady steps.
    for i in 0..3 {
        est.push_step(&with_h(1.0 + 0.55 * f64::from(i), 0.07))
            .unwrap();
    }
    let l = est.push_step(&with_h(2.65, 0.07)).unwrap();
    assert!((l - PRIOR_PENDULUM_K * 0.07f64.sqrt()).abs() < 1e-12, "{l}");
    let l4 = est.push_step(&with_h(3.2, 0.28)).unwrap();
    assert!(
        (l4 / l - 2.0).abs() < 1e-12,
        "four times the rise, twice the step: {l4}"
    );
    let unknown = est.push_step(&with_h(3.75, f64::NAN)).unwrap();
    assert_eq!(unknown, c.prior_step_length_m);
    let before = est.snapshot();
    for h in [-0.01, 2.5, f64::INFINITY] {
        assert!(est.push_step(&with_h(4.3, h)).is_err(), "h = {h} accepted");
    }
    assert_eq!(est.snapshot(), before);
}
