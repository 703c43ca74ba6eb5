//! Foot-mounted navigation on simulated walks (`sim::foot`): loop closure, strides,
//! static alignment, sample rates, jitter and dropped samples, sensor axes, and
//! snapshot/restore splitting a replay anywhere.

use std::sync::Arc;
use stridekit_core::foot::{
    AdaptiveShoe, AdaptiveThresholds, FixedThresholds, FootConfig, FootError, FootEstimate,
    FootNavigator, GyroCeilingDetector, ShoeDetector, SvmAdaptive, SvmModel, WindowStats,
    ZeroVelocityDetector, FLAT_SHARE,
};

use stridekit_core::snapshot::SnapshotError;
use stridekit_sim::{simulate_foot, FootScenario, SimulatedFoot};

fn replay(sim: &SimulatedFoot, config: FootConfig) -> (FootNavigator, Vec<FootEstimate>) {
    let mut nav = FootNavigator::new(config).expect("valid config");
    let outcome = nav.push_batch(&sim.samples);
    assert!(outcome.rejected.is_empty(), "{:?}", &outcome.rejected[..1]);
    assert_eq!(nav.divergence_resets(), 0);
    (nav, outcome.estimates)
}

fn with_detector(detector: ZeroVelocityDetector) -> FootConfig {
    FootConfig {
        detector,
        ..FootConfig::default()
    }
}

/// End error (horizontal, m) and its share of the path.
fn closure(sim: &SimulatedFoot, est: &[FootEstimate]) -> (f64, f64) {
    let e = est.last().expect("estimates");
    let end = e.position_m[0].hypot(e.position_m[1]);
    (end, end / sim.distance_m)
}

/// Checks stride count, each stride's length (matched by time) and the distance.
fn check_strides(sim: &SimulatedFoot, est: &[FootEstimate], tol: f64, label: &str) {
    let strides: Vec<_> = est.iter().filter_map(|e| e.stride).collect();
    assert_eq!(strides.len(), sim.strides.len(), "{label}: stride count");
    let last = est.last().unwrap();
    assert_eq!(last.strides as usize, sim.strides.len(), "{label}");
    for (s, t) in strides.iter().zip(&sim.strides) {
        assert!(
            (s.t_s - t.t_s).abs() < 0.2,
            "{label}: stride at {} vs true {}",
            s.t_s,
            t.t_s
        );
        assert!(
            (s.length_m - t.length_m).abs() < tol * t.length_m,
            "{label}: stride at {}: {} m vs {} m",
            t.t_s,
            s.length_m,
            t.length_m
        );
        assert!(s.duration_s > 0.0 && s.speed_mps.is_finite() && s.climb_m.abs() < 0.1);
    }
    assert!(
        (last.distance_m - sim.distance_m).abs() < 0.02 * sim.distance_m,
        "{label}: distance {} vs {}",
        last.distance_m,
        sim.distance_m
    );
}

fn assert_finite(est: &[FootEstimate]) {
    for e in est {
        assert!(e.is_finite(), "{e:?}");
    }
}

#[test]
fn simulated_walk_closes_its_loop_with_every_detector() {
    let sim = simulate_foot(&FootScenario::walk(1, 2));
    assert_eq!(sim.strides.len(), 84);
    for det in [
        ZeroVelocityDetector::default(), // adaptive shoe
        ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ZeroVelocityDetector::Shoe(ShoeDetector::default()),
        ZeroVelocityDetector::Fixed(FixedThresholds::WALK),
        ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
    ] {
        let name = det.name();
        let (nav, est) = replay(&sim, with_detector(det));
        assert_finite(&est);
        // 51 samples (0.25 s) align, the rest come out after the pipeline delay.
        assert_eq!(est.len() + nav.delay_samples() + 51, sim.samples.len());
        let (end, share) = closure(&sim, &est);
        eprintln!(
            "walk {name}: end {end:.3} m, {:.3} % of {} m",
            100.0 * share,
            sim.distance_m
        );
        assert!(share < 0.01, "{name}: end error {end} m");
        check_strides(&sim, &est, 0.05, name);
        // The stance flag follows the true foot-flat phases (the detector window
        // and the smooth motion onset make the edges differ by a few samples).
        let truth_at = |t: f64| {
            let i = sim.truth.partition_point(|x| x.t_s < t);
            sim.truth[i].stance
        };
        let agree = est.iter().filter(|e| e.stance == truth_at(e.t_s)).count();
        let share = agree as f64 / est.len() as f64;
        assert!(share > 0.9, "{name}: stance agreement {share}");
        // Heading and position follow the truth all along.
        let mut worst: f64 = 0.0;
        for e in est.iter().step_by(20) {
            let i = sim.truth.partition_point(|x| x.t_s < e.t_s);
            let p = sim.truth[i].position_m;
            worst = worst.max((e.position_m[0] - p[0]).hypot(e.position_m[1] - p[1]));
        }
        assert!(worst < 1.0, "{name}: worst position error {worst} m");
    }
}

#[test]
fn simulated_run_closes_its_loop() {
    let sim = simulate_foot(&FootScenario::run(2, 2));
    for det in [
        ZeroVelocityDetector::default(), // adaptive shoe
        ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ZeroVelocityDetector::Shoe(ShoeDetector::default()),
        ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
    ] {
        let name = det.name();
        let (_, est) = replay(&sim, with_detector(det));
        assert_finite(&est);
        let (end, share) = closure(&sim, &est);
        eprintln!(
            "run {name}: end {end:.3} m, {:.3} % of {} m",
            100.0 * share,
            sim.distance_m
        );
        assert!(share < 0.01, "{name}: end error {end} m");
        check_strides(&sim, &est, 0.05, name);
    }
}

#[test]
fn the_svm_detector_runs_on_a_walk() {
    // Whatever model ships, the pipeline with it stays finite and moves.
    let sim = simulate_foot(&FootScenario::walk(3, 1));
    let (nav, est) = replay(&sim, with_detector(ZeroVelocityDetector::default_svm()));
    assert_finite(&est);
    assert!(nav.is_aligned());
}

#[test]
fn sample_rates_100_200_500_hz() {
    for rate in [100.0, 200.0, 500.0] {
        let sim = simulate_foot(&FootScenario {
            sample_rate_hz: rate,
            ..FootScenario::walk(4, 1)
        });
        let (nav, est) = replay(&sim, FootConfig::default());
        assert!((nav.sample_rate_hz() - rate).abs() < 1e-6 * rate);
        // The detector window in samples: odd, 3..=31, from the measured rate.
        let mut expect = (FootConfig::default().detector_window_s * rate).round() as usize;
        if expect % 2 == 0 {
            expect += 1;
        }
        let expect = expect.clamp(3, 31);
        assert_eq!(nav.detector_window(), expect);
        assert_finite(&est);
        let (end, share) = closure(&sim, &est);
        eprintln!("{rate} Hz: end {end:.3} m ({:.3} %)", 100.0 * share);
        assert!(share < 0.01, "{rate} Hz: end error {end} m");
        check_strides(&sim, &est, 0.05, &format!("{rate} Hz"));
    }
}

#[test]
fn jittered_timestamps_and_dropped_samples() {
    let sim = simulate_foot(&FootScenario {
        timestamp_jitter_s: 0.0005,
        drop_probability: 0.05,
        ..FootScenario::walk(5, 2)
    });
    let dropped = 1.0 - sim.samples.len() as f64 / ((sim.truth.last().unwrap().t_s) * 200.0);
    assert!(dropped > 0.03, "{dropped}");
    let (nav, est) = replay(&sim, FootConfig::default());
    assert!(
        (nav.sample_rate_hz() - 190.0).abs() < 5.0,
        "{}",
        nav.sample_rate_hz()
    );
    assert_finite(&est);
    assert!(est.iter().all(|e| !e.gap));
    let (end, share) = closure(&sim, &est);
    eprintln!("jitter + drops: end {end:.3} m ({:.3} %)", 100.0 * share);
    assert!(share < 0.01, "end error {end} m");
    check_strides(&sim, &est, 0.05, "jitter + drops");

    // A half-second hole in the middle of a stance: flagged, and the walk goes on.
    let mut samples = sim.samples.clone();
    let mid = sim.strides[40].t_s + 0.05;
    samples.retain(|s| !(s.t_s > mid && s.t_s < mid + 0.3));
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    let outcome = nav.push_batch(&samples);
    assert!(outcome.rejected.is_empty());
    let est = outcome.estimates;
    assert_finite(&est);
    assert_eq!(est.iter().filter(|e| e.gap).count(), 1);
    let (end, share) = closure(&sim, &est);
    assert!(share < 0.02, "with a hole: end error {end} m");
}

/// Bursts of samples lost mid-swing (the foot turns fast there, so the attitude across
/// the hole is off by degrees): the next stances re-level the foot instead of letting
/// gravity leak through the tilt error stride after stride.
#[test]
fn holes_in_the_swing_are_bridged() {
    let sim = simulate_foot(&FootScenario::walk(5, 2));
    let mut samples = sim.samples.clone();
    for k in (5..sim.strides.len()).step_by(10) {
        // Strides end at a stance: 0.45 s before is mid-swing.
        let from = sim.strides[k].t_s - 0.45;
        samples.retain(|s| !(s.t_s > from && s.t_s < from + 0.12));
    }
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    let outcome = nav.push_batch(&samples);
    assert!(outcome.rejected.is_empty());
    let est = outcome.estimates;
    assert_finite(&est);
    let (end, share) = closure(&sim, &est);
    eprintln!(
        "holes in the swing: end {end:.3} m ({:.3} %)",
        100.0 * share
    );
    assert!(share < 0.03, "with holes in the swing: end error {end} m");
}

#[test]
fn static_tilt_alignment() {
    for (i, rpy) in [[0.0, 0.0, 0.0], [10.0, -7.0, 0.0], [-25.0, 15.0, 30.0]]
        .into_iter()
        .enumerate()
    {
        let rpy_rad: [f64; 3] = rpy.map(|d: f64| d.to_radians());
        let sim = simulate_foot(&FootScenario {
            mount_rpy_rad: rpy_rad,
            laps: 0,
            rest_start_s: 3.0,
            rest_end_s: 0.0,
            accel_bias_std_mps2: 0.0,
            ..FootScenario::walk(6 + i as u64, 0)
        });
        // A 2 s alignment averages the tremor out of the gyroscope bias.
        let (nav, est) = replay(
            &sim,
            FootConfig {
                alignment_s: 2.0,
                ..FootConfig::default()
            },
        );
        assert!(nav.is_aligned());
        let e = est.last().unwrap();
        // Truth: the mounting rotation (the foot rests flat, pointing East).
        let tol = 0.1_f64.to_radians();
        assert!(
            (e.roll_rad - rpy_rad[0]).abs() < tol,
            "{rpy:?}: roll {}",
            e.roll_rad.to_degrees()
        );
        assert!(
            (e.pitch_rad - rpy_rad[1]).abs() < tol,
            "{rpy:?}: pitch {}",
            e.pitch_rad.to_degrees()
        );
        // At rest the navigator stays put and calls every sample stance.
        assert!(est.iter().all(|e| e.stance));
        assert!(e.position_m.iter().all(|p| p.abs() < 1e-3), "{e:?}");
        // The gyroscope bias came from the alignment.
        for k in 0..3 {
            assert!(
                (e.gyro_bias_rads[k] - sim.gyro_bias_rads[k]).abs() < 5e-4,
                "{e:?} vs {:?}",
                sim.gyro_bias_rads
            );
        }
    }
}

#[test]
fn tilted_mount_and_pyshoe_axes_walk() {
    let sim = simulate_foot(&FootScenario {
        mount_rpy_rad: [0.15, -0.1, 0.0],
        ..FootScenario::walk(7, 1)
    });
    let (_, est) = replay(&sim, FootConfig::default());
    let (end, share) = closure(&sim, &est);
    assert!(share < 0.01, "tilted mount: end error {end} m");
    check_strides(&sim, &est, 0.05, "tilted mount");

    let sim = simulate_foot(&FootScenario {
        sensor_z_down: true,
        ..FootScenario::walk(7, 1)
    });
    let (_, est) = replay(
        &sim,
        FootConfig {
            axis_remap: FootConfig::pyshoe_axes(),
            ..FootConfig::default()
        },
    );
    let (end, share) = closure(&sim, &est);
    assert!(share < 0.01, "pyshoe axes: end error {end} m");
    check_strides(&sim, &est, 0.05, "pyshoe axes");
}

// ------------------------------------------------------------------ snapshot

/// Runs `samples` through `nav`, comparing with the reference estimates from `from`.
fn continue_and_compare(
    mut nav: FootNavigator,
    samples: &[stridekit_core::foot::FootSample],
    reference: &[Option<FootEstimate>],
    label: &str,
) -> FootNavigator {
    for (k, s) in samples.iter().enumerate() {
        let e = nav.push(s).expect("accepted");
        assert_eq!(
            e.map(|e| format!("{e:?}")),
            reference[k].map(|e| format!("{e:?}")),
            "{label}: sample {k} after the split"
        );
        if let (Some(a), Some(b)) = (e, reference[k]) {
            assert_eq!(
                a.position_m.map(f64::to_bits),
                b.position_m.map(f64::to_bits)
            );
            assert_eq!(
                a.quaternion.map(f64::to_bits),
                b.quaternion.map(f64::to_bits)
            );
        }
    }
    nav
}

/// Splits at every sample of the first `dense` and then every `every` samples.
fn split_everywhere(
    config: FootConfig,
    sim: &SimulatedFoot,
    every: usize,
    horizon: usize,
    dense: usize,
) {
    let label = config.detector.name();
    let mut reference_nav = FootNavigator::new(config.clone()).unwrap();
    let reference: Vec<Option<FootEstimate>> = sim
        .samples
        .iter()
        .map(|s| reference_nav.push(s).unwrap())
        .collect();
    let final_snapshot = reference_nav.snapshot();

    let mut nav = FootNavigator::new(config).unwrap();
    let n = sim.samples.len();
    for k in 0..n {
        if k < dense || k % every == 0 {
            let bytes = nav.snapshot();
            let restored = FootNavigator::restore(&bytes).expect("restores");
            assert_eq!(
                restored.snapshot(),
                bytes,
                "{label}: snapshot of the restored at {k}"
            );
            let end = (k + horizon).min(n);
            let after =
                continue_and_compare(restored, &sim.samples[k..end], &reference[k..end], label);
            if end == n {
                assert_eq!(after.snapshot(), final_snapshot, "{label}: split at {k}");
            }
        }
        nav.push(&sim.samples[k]).unwrap();
    }
    assert_eq!(nav.snapshot(), final_snapshot);
    // A split run to the very end matches bit for bit.
    let k = n / 3;
    let mut nav = FootNavigator::new(reference_nav.config().clone()).unwrap();
    for s in &sim.samples[..k] {
        nav.push(s).unwrap();
    }
    let restored = FootNavigator::restore(&nav.snapshot()).unwrap();
    let after = continue_and_compare(restored, &sim.samples[k..], &reference[k..], label);
    assert_eq!(after.snapshot(), final_snapshot);
    assert_eq!(after.estimate(), reference_nav.estimate());
}

#[test]
fn snapshot_restore_splits_anywhere() {
    let sim = simulate_foot(&FootScenario {
        sample_rate_hz: 100.0,
        rest_start_s: 0.5,
        rest_end_s: 0.5,
        loop_m: [6.0, 3.0],
        ..FootScenario::walk(8, 1)
    });
    let base = FootConfig {
        median_window: 5,
        accel_range_mps2: Some(60.0),
        gyro_range_rads: Some(20.0),
        ..FootConfig::default()
    };
    for det in [
        ZeroVelocityDetector::default(), // adaptive shoe
        ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ZeroVelocityDetector::Shoe(ShoeDetector::default()),
        ZeroVelocityDetector::Fixed(FixedThresholds::WALK),
        ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
        ZeroVelocityDetector::default_svm(),
    ] {
        // Restoring the SVM detector loads its model (builds the decision tables):
        // fewer split points.
        let svm = matches!(
            det,
            ZeroVelocityDetector::Svm(_) | ZeroVelocityDetector::SvmAdaptive(_)
        );
        split_everywhere(
            FootConfig {
                detector: det,
                ..base.clone()
            },
            &sim,
            if svm { 97 } else { 3 },
            120,
            if svm { 3 } else { 80 },
        );
    }
    // Defaults (no median), the calibrated-IMU profile (interval-mean gyro) and the
    // as-published correction.
    split_everywhere(FootConfig::default(), &sim, 7, 60, 80);
    split_everywhere(FootConfig::calibrated_imu(), &sim, 7, 60, 80);
    split_everywhere(
        FootConfig {
            correction: stridekit_core::foot::Correction::AsPublished,
            ..FootConfig::default()
        },
        &sim,
        7,
        60,
        80,
    );
}

#[test]
fn snapshot_rejects_garbage() {
    let sim = simulate_foot(&FootScenario::walk(9, 1));
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    for s in &sim.samples[..1000] {
        nav.push(s).unwrap();
    }
    let bytes = nav.snapshot();
    assert_eq!(bytes[4], 6, "engine kind byte");
    let mut bad = bytes.clone();
    bad[40] ^= 0x10;
    assert_eq!(
        FootNavigator::restore(&bad).unwrap_err(),
        FootError::Snapshot(SnapshotError::Checksum)
    );
    assert!(matches!(
        FootNavigator::restore(&bytes[..bytes.len() - 9]).unwrap_err(),
        FootError::Snapshot(_)
    ));
    assert!(matches!(
        FootNavigator::restore(b"not a snapshot at all").unwrap_err(),
        FootError::Snapshot(SnapshotError::BadMagic)
    ));
    let mut other = bytes.clone();
    other[4] = 5;
    assert!(FootNavigator::restore(&other).is_err());
    // Every truncation fails cleanly.
    for n in 0..bytes.len() {
        assert!(FootNavigator::restore(&bytes[..n]).is_err());
    }
}

#[test]
fn svm_adaptive_switches_by_gait_and_snapshots_a_custom_model() {
    // Below the jog boundary the SVM decides, above it the jog / run thresholds.
    let d = SvmAdaptive::default();
    let mut s = WindowStats {
        acc_norm_mps2: 10.0,
        acc_dev_mps2: 3.5,
        gyro_norm_rads: 1.0,
        acc_std_mps2: [1.0; 3],
        gyro_std_rads: [0.4; 3],
        peak_acc_norm_mps2: 90.0,
        n: 5,
        ..Default::default()
    };
    assert!(d.is_stance(&s) && d.run.is_stance(&s) && !d.jog.is_stance(&s));
    s.peak_acc_norm_mps2 = 60.0;
    assert!(!d.is_stance(&s));
    for peak in [10.0, 20.0, 30.0, 45.0] {
        s.peak_acc_norm_mps2 = peak;
        for std in [0.01, 0.1, 1.0] {
            s.acc_std_mps2 = [std; 3];
            s.gyro_std_rads = [std; 3];
            assert_eq!(d.is_stance(&s), d.svm.is_stance(&s), "peak {peak}, σ {std}");
        }
    }

    // A model that is not the shipped one travels in the snapshot as its text.
    let shipped = SvmModel::shared_shipped().to_text();
    let (head, rest) = shipped.split_once('\n').unwrap();
    let text = format!("{head}\n# a user's copy\n{rest}");
    let model = Arc::new(SvmModel::parse(&text).unwrap());
    assert!(!model.is_shipped());
    let config = FootConfig {
        detector: ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::with_model(model)),
        ..FootConfig::default()
    };
    let sim = simulate_foot(&FootScenario::walk(12, 1));
    split_everywhere(config, &sim, 499, 120, 2);
}

#[test]
fn snapshots_of_another_format_version_are_typed_errors() {
    // One layout per build: a snapshot written by another version is refused, never
    // misread.
    let sim = simulate_foot(&FootScenario::walk(9, 1));
    let mut nav = FootNavigator::new(FootConfig::default()).unwrap();
    for s in &sim.samples[..800] {
        nav.push(s).unwrap();
    }
    let mut old = nav.snapshot();
    old[5..7].copy_from_slice(&2u16.to_le_bytes());
    let n = old.len() - 4;
    let crc = stridekit_core::snapshot::crc32(&old[..n]);
    old[n..].copy_from_slice(&crc.to_le_bytes());
    assert!(matches!(
        FootNavigator::restore(&old),
        Err(FootError::Snapshot(
            stridekit_core::snapshot::SnapshotError::UnsupportedVersion { found: 2, .. }
        ))
    ));
}

#[test]
fn adaptive_shoe_threshold_follows_the_gait() {
    let d = AdaptiveShoe::default();
    let at = |peak: f64| {
        d.threshold(&WindowStats {
            peak_acc_norm_mps2: peak,
            ..Default::default()
        })
    };
    assert_eq!(at(5.0), d.shoe.threshold);
    assert_eq!(at(d.ref_peak_mps2), d.shoe.threshold);
    let r = at(2.0 * d.ref_peak_mps2) / d.shoe.threshold;
    assert!((r - 2f64.powf(d.exponent)).abs() < 1e-9, "{r}");
    // A window that is SHOE stance at a slow gait stays stance when running; a
    // running swing is not stance at walking pace.
    let s = WindowStats {
        n: 5,
        shoe_acc_ss: 5.0 * (0.5 * d.shoe.acc_noise_mps2).powi(2) * d.shoe.threshold,
        peak_acc_norm_mps2: 12.0,
        ..Default::default()
    };
    assert!(d.is_stance(&s));
    let swing = WindowStats {
        shoe_acc_ss: 50.0 * s.shoe_acc_ss,
        ..s
    };
    assert!(!d.is_stance(&swing));
    assert!(d.is_stance(&WindowStats {
        peak_acc_norm_mps2: 80.0,
        ..swing
    }));
    for bad in [f64::NAN, -1.0, 11.0] {
        let c = FootConfig {
            detector: ZeroVelocityDetector::AdaptiveShoe(AdaptiveShoe { exponent: bad, ..d }),
            ..FootConfig::default()
        };
        assert!(FootNavigator::new(c).is_err(), "exponent {bad}");
    }
}

/// A stance called in the middle of a swing (a detector's glitch, a bad label) says
/// the foot is still while the filter's velocity and its uncertainty say it moves at
/// metres per second. Taken at face value, each such update stops the foot in the
/// air and shortens the stride; bounded by `zupt_gate_nis`, it pulls only a little,
/// while the true stances (small innovations) are untouched.
#[test]
fn a_stance_called_mid_swing_cannot_stop_the_foot() {
    let sim = simulate_foot(&FootScenario::walk(1, 2));
    // The true stance, and 6 samples (30 ms) called stance in the middle of each swing.
    let mut labels: Vec<bool> = sim.truth.iter().map(|t| t.stance).collect();
    let mut k = 0;
    while k < labels.len() {
        if labels[k] {
            k += 1;
            continue;
        }
        let start = k;
        while k < labels.len() && !labels[k] {
            k += 1;
        }
        let mid = (start + k) / 2;
        if k - start > 20 && k < labels.len() {
            labels[mid - 3..mid + 3].fill(true);
        }
    }
    let run = |gate: Option<f64>| {
        let mut nav = FootNavigator::new(FootConfig {
            zupt_gate_nis: gate,
            ..FootConfig::default()
        })
        .unwrap();
        let mut est = Vec::new();
        for (s, &stance) in sim.samples.iter().zip(&labels) {
            est.extend(nav.push_with_stance(s, stance).unwrap());
        }
        assert_finite(&est);
        est.last().map(|e| e.distance_m).unwrap()
    };
    let truth = sim.distance_m;
    let bounded = run(FootConfig::default().zupt_gate_nis);
    let face_value = run(None);
    eprintln!("distance {truth:.1} m: bounded {bounded:.1} m, at face value {face_value:.1} m");
    assert!(
        (bounded - truth).abs() < 0.03 * truth,
        "bounded: {bounded} m of {truth} m"
    );
    assert!(
        (face_value - truth).abs() > 3.0 * (bounded - truth).abs(),
        "at face value {face_value} m, bounded {bounded} m, true {truth} m"
    );
}

/// `v` turned by the rotation vector `a` (Rodrigues).
fn rotate(a: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    let r = nalgebra::Rotation3::new(nalgebra::Vector3::from(a));
    (r * nalgebra::Vector3::from(v)).into()
}

/// A walk whose accelerometer is turned against the gyroscope by `misalign` (rotation
/// vector, body axes).
fn misaligned_walk(misalign: [f64; 3]) -> SimulatedFoot {
    let mut sim = simulate_foot(&FootScenario::walk(11, 2));
    let back = [-misalign[0], -misalign[1], -misalign[2]];
    for s in &mut sim.samples {
        s.accel_mps2 = rotate(back, s.accel_mps2);
    }
    sim
}

#[test]
fn the_accelerometer_alignment_undoes_a_misaligned_accelerometer() {
    let misalign = [0.004, 0.021, -0.006];
    let clean = simulate_foot(&FootScenario::walk(11, 2));
    let turned = misaligned_walk(misalign);
    // The filter's own height: the level floor would take the drift off.
    let unlevelled = FootConfig {
        level_stride_max_grade: None,
        ..FootConfig::default()
    };
    let (_, reference) = replay(&clean, unlevelled.clone());
    let (_, uncorrected) = replay(&turned, unlevelled.clone());
    let config = FootConfig {
        accel_alignment_rad: misalign,
        ..unlevelled
    };
    let (nav, corrected) = replay(&turned, config.clone());
    assert_eq!(nav.config().accel_alignment_rad, misalign);
    // The configured alignment gives back the aligned IMU's track (to rounding) ...
    assert_eq!(corrected.len(), reference.len());
    for (a, b) in corrected.iter().zip(&reference) {
        for k in 0..3 {
            assert!(
                (a.position_m[k] - b.position_m[k]).abs() < 1e-6,
                "{a:?} vs {b:?}"
            );
        }
        assert_eq!(a.stance, b.stance);
    }
    // ... where the misaligned one drifted in height (the swing's forward acceleration
    // read partly as vertical).
    let dz = |e: &[FootEstimate]| e.last().unwrap().position_m[2] - e[0].position_m[2];
    assert!(
        dz(&uncorrected).abs() > 5.0 * dz(&reference).abs().max(0.01),
        "height drift misaligned {} vs aligned {}",
        dz(&uncorrected),
        dz(&reference)
    );
    // The snapshot keeps it.
    let restored = FootNavigator::restore(&nav.snapshot()).unwrap();
    assert_eq!(restored.config(), &config);
}

/// An accelerometer range given in g instead of m/s² (4 for ±4 g) would take every
/// sample for clipped: refused with the field named; ±2 g and up are ranges.
#[test]
fn an_accelerometer_range_in_g_is_a_typed_error() {
    for r in [4.0, 9.0, 0.0, f64::NAN] {
        let e = FootNavigator::new(FootConfig {
            accel_range_mps2: Some(r),
            ..FootConfig::default()
        })
        .unwrap_err();
        assert!(
            matches!(
                e,
                FootError::InvalidConfig {
                    field: "accel_range_mps2",
                    ..
                }
            ),
            "{r}: {e:?}"
        );
    }
    for r in [2.0 * 9.80665, 4.0 * 9.80665, 16.0 * 9.80665] {
        let config = FootConfig {
            accel_range_mps2: Some(r),
            ..FootConfig::default()
        };
        assert!(FootNavigator::new(config).is_ok(), "{r}");
    }
}

#[test]
fn an_accelerometer_alignment_out_of_range_is_a_typed_error() {
    for a in [
        [0.0, 0.2, 0.0],
        [f64::NAN, 0.0, 0.0],
        [0.0, 0.0, -f64::INFINITY],
    ] {
        let e = FootNavigator::new(FootConfig {
            accel_alignment_rad: a,
            ..FootConfig::default()
        })
        .unwrap_err();
        assert!(
            matches!(
                e,
                FootError::InvalidConfig {
                    field: "accel_alignment_rad",
                    ..
                }
            ),
            "{e:?}"
        );
    }
    assert!(FootNavigator::new(FootConfig {
        accel_alignment_rad: [0.1, -0.1, 0.05],
        ..FootConfig::default()
    })
    .is_ok());
}

/// Height at the last estimate against the first, m.
fn height_gain(est: &[FootEstimate]) -> f64 {
    est.last().unwrap().position_m[2] - est[0].position_m[2]
}

#[test]
fn the_level_floor_takes_off_the_height_a_misaligned_accelerometer_gains() {
    // 1.2° about the lateral axis, as on x-io's NGIMU: every swing's forward
    // acceleration is read partly as vertical and the height climbs at every stride.
    let turned = misaligned_walk([0.0, 0.021, 0.0]);
    let off = FootConfig {
        level_stride_max_grade: None,
        ..FootConfig::default()
    };
    let (_, climbing) = replay(&turned, off);
    let (nav, level) = replay(&turned, FootConfig::default());
    assert_eq!(
        nav.config().level_stride_max_grade,
        Some(stridekit_core::foot::LEVEL_STRIDE_MAX_GRADE)
    );
    let strides: Vec<_> = level.iter().filter_map(|e| e.stride).collect();
    let levelled: Vec<_> = strides.iter().filter(|s| s.levelled_m != 0.0).collect();
    assert!(
        height_gain(&climbing) > 0.005 * turned.distance_m,
        "without the level floor the height climbs: {} m over {} m",
        height_gain(&climbing),
        turned.distance_m
    );
    // What is left is the turn after the first side: the filter's tilt and bias
    // estimates settle anew with the misaligned IMU turned (two strides climb 8 and
    // 20 cm, steeper than a level stride).
    assert!(
        height_gain(&level).abs() < 0.2 * height_gain(&climbing).abs(),
        "level floor: {} m, without it {} m",
        height_gain(&level),
        height_gain(&climbing)
    );
    assert!(
        levelled.len() * 10 >= strides.len() * 9,
        "{} of {}",
        levelled.len(),
        strides.len()
    );
    for s in &strides {
        // A levelled stride reports no climb; the height taken off is its own.
        assert!(s.levelled_m == 0.0 || s.climb_m == 0.0, "{s:?}");
        assert!(s.levelled_m.abs() <= 0.05 * s.length_m + 1e-12, "{s:?}");
    }
    // The horizontal track is the filter's either way (the nominal position feeds
    // nothing back).
    assert_eq!(level.len(), climbing.len());
    for (a, b) in level.iter().zip(&climbing) {
        assert_eq!(a.position_m[..2], b.position_m[..2]);
        assert_eq!(a.velocity_mps, b.velocity_mps);
        assert_eq!(a.quaternion, b.quaternion);
    }
}

#[test]
fn stairs_and_a_ramp_keep_their_height() {
    // A stair stride: 0.6 m on, two risers of 0.17 m up (57 %); a ramp of 1:10 on
    // 1.4 m strides. Both go round a spiral; both are steeper than the level floor's
    // grade, so nothing is taken off.
    for (stride_m, rise_m, label) in [(0.6, 0.34, "stairs"), (1.4, 0.14, "ramp 1:10")] {
        let mut sc = FootScenario::walk(5, 1);
        sc.gait.stride_length_m = stride_m;
        sc.loop_m = [8.0, 4.0];
        sc.rise_per_stride_m = rise_m;
        let sim = simulate_foot(&sc);
        let (_, est) = replay(&sim, FootConfig::default());
        let strides: Vec<_> = est.iter().filter_map(|e| e.stride).collect();
        assert_eq!(strides.len(), sim.strides.len(), "{label}");
        let truth = rise_m * sim.strides.len() as f64;
        let gain = height_gain(&est);
        assert!(
            (gain - truth).abs() < 0.03 * truth,
            "{label}: climbed {gain} m, truly {truth} m"
        );
        for s in &strides {
            assert_eq!(s.levelled_m, 0.0, "{label}: {s:?}");
            assert!((s.climb_m - rise_m).abs() < 0.3 * rise_m, "{label}: {s:?}");
        }
    }
}

#[test]
fn a_level_floor_grade_out_of_range_is_a_typed_error() {
    for g in [-0.01, 0.21, f64::NAN, f64::INFINITY] {
        let e = FootNavigator::new(FootConfig {
            level_stride_max_grade: Some(g),
            ..FootConfig::default()
        })
        .unwrap_err();
        assert!(
            matches!(
                e,
                FootError::InvalidConfig {
                    field: "level_stride_max_grade",
                    ..
                }
            ),
            "{g}: {e:?}"
        );
    }
    for g in [None, Some(0.0), Some(0.2)] {
        assert!(FootNavigator::new(FootConfig {
            level_stride_max_grade: g,
            ..FootConfig::default()
        })
        .is_ok());
    }
}

/// Horizontal RMSE of the estimates against the simulator's truth (both start at the
/// origin, same frame).
fn horizontal_rmse(sim: &SimulatedFoot, est: &[FootEstimate]) -> f64 {
    let mut se = 0.0;
    let mut n = 0.0;
    let mut j = 0;
    for e in est {
        while j + 1 < sim.truth.len() && sim.truth[j].t_s < e.t_s {
            j += 1;
        }
        let g = sim.truth[j].position_m;
        se += (e.position_m[0] - g[0]).powi(2) + (e.position_m[1] - g[1]).powi(2);
        n += 1.0;
    }
    (se / n).sqrt()
}

#[test]
fn a_clipped_gyroscope_gets_the_rotation_above_its_ceiling_back() {
    // A brisk walk whose swing pitch rate peaks 10 % above the gyroscope's ceiling:
    // every stride loses the rotation above it, which tips gravity into the rest of
    // the swing.
    let mut sc = FootScenario::walk(21, 1);
    sc.gait.pitch_peak_rad = 0.9;
    let clean = simulate_foot(&sc);
    let peak = clean
        .samples
        .iter()
        .map(|s| s.gyro_rads[1].abs())
        .fold(0.0, f64::max);
    let ceiling = 0.9 * peak;
    let mut clipped = clean.clone();
    let mut n_clipped = 0;
    for s in &mut clipped.samples {
        for w in &mut s.gyro_rads {
            if w.abs() > ceiling {
                *w = w.signum() * ceiling;
                n_clipped += 1;
            }
        }
    }
    assert!(n_clipped > 100, "{n_clipped} samples clipped");
    let with_range = |range: Option<f64>| FootConfig {
        gyro_range_rads: range,
        ..FootConfig::default()
    };
    let (_, reference) = replay(&clean, with_range(None));
    let (_, unrepaired) = replay(&clipped, with_range(None));
    // Range such that the ceiling is above 99 % of it.
    let (nav, repaired) = replay(&clipped, with_range(Some(ceiling / 0.995)));
    let (r0, r1, r2) = (
        horizontal_rmse(&clean, &reference),
        horizontal_rmse(&clipped, &unrepaired),
        horizontal_rmse(&clipped, &repaired),
    );
    assert!(
        r1 > 2.0 * r0,
        "clipping costs: clean {r0:.3} m, clipped {r1:.3} m"
    );
    // Measured: clean 0.18 m, clipped 3.5 m, repaired 0.11 m; since the standing
    // foot reads the gyroscope bias (issue 39, `zaru.rs`: the rests of this walk)
    // clean 0.028 m, clipped 0.28 m, repaired 0.056 m: a fifth of the clipped error,
    // within 5 cm of the clean walk.
    assert!(
        r2 < 0.25 * r1 && r2 < r0 + 0.05,
        "repair: clipped {r1:.3} m, repaired {r2:.3} m (clean {r0:.3} m)"
    );
    // A snapshot in the middle of a clipped run continues exactly.
    let k = clipped
        .samples
        .iter()
        .position(|s| s.gyro_rads[1].abs() >= ceiling)
        .expect("a clipped sample")
        + 1;
    let mut a = FootNavigator::new(with_range(Some(ceiling / 0.995))).unwrap();
    for s in &clipped.samples[..k] {
        a.push(s).unwrap();
    }
    let mut b = FootNavigator::restore(&a.snapshot()).unwrap();
    for s in &clipped.samples[k..] {
        assert_eq!(a.push(s).unwrap(), b.push(s).unwrap());
    }
    assert_eq!(nav.config().gyro_range_rads, Some(ceiling / 0.995));
    // The data say so themselves: the clipped walk has a ceiling (on the pitch axis,
    // at the clip), the clean one, whose smooth swing peaks go 10 % higher, has none.
    let detect = |sim: &SimulatedFoot| {
        let mut d = GyroCeilingDetector::new();
        for s in &sim.samples {
            d.push(s.gyro_rads);
        }
        d
    };
    let found = detect(&clipped).ceiling().expect("clipping detected");
    assert_eq!(found.axis, 1, "{found:?}");
    assert!(
        (found.ceiling_rads - ceiling).abs() <= FLAT_SHARE * ceiling,
        "{found:?} against {ceiling}"
    );
    let clean_detector = detect(&clean);
    assert_eq!(clean_detector.ceiling(), None);
    assert!(clean_detector.peak_rads() > found.range_rads());
}
