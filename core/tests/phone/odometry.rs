//! Learned phone inertial odometry: accuracy against the baselines on held-out
//! simulated walks, the model file, adversarial input, snapshots and allocation.

use crate::common::allocations_in;
use stridekit_core::input::InputError;

use stridekit_core::odometry::{
    ImuSample, OdometryConfig, OdometryError, OdometryModel, PhoneOdometry, PlacementSource,
    AUTO_MIN_CONFIDENCE,
};
use stridekit_core::placement::Placement;
use stridekit_lab::odometry::evaluate::run_methods;
use stridekit_lab::odometry::train::{sim_scenario, FIRST_EVAL_SEED};
use stridekit_sim::{simulate_phone, PhonePlacement, Rng};

fn fixed(p: PhonePlacement) -> PlacementSource {
    PlacementSource::Fixed(p.into())
}

fn walk(seed: u64, p: PhonePlacement) -> (stridekit_sim::SimulatedPhone, Vec<ImuSample>) {
    let sim = simulate_phone(&sim_scenario(seed, p));
    let samples = sim.samples.iter().map(Into::into).collect();
    (sim, samples)
}

/// A model with a regressor for every placement, trained on the simulator (the lab's
/// `lab/models/odometry_sim_v1.txt`): the simulated walks here test the pipeline on
/// the data it was trained for. The shipped model is trained on real hand-held walks
/// and has the general and in-hand regressors only.
fn simulator_model() -> OdometryModel {
    stridekit_lab::odometry::simulator_model()
}

#[test]
fn learned_pipeline_beats_both_baselines_by_a_wide_margin() {
    let model = simulator_model();
    for (seed, p) in [
        (FIRST_EVAL_SEED + 7, PhonePlacement::InHand),
        (FIRST_EVAL_SEED + 8, PhonePlacement::FrontPocket),
        (FIRST_EVAL_SEED + 9, PhonePlacement::Bag),
    ] {
        let (sim, samples) = walk(seed, p);
        let tracks = run_methods(&samples, &sim, &model, fixed(p));
        let s = tracks.scores();
        let walked = sim.truth.last().unwrap().distance_m;
        let (learned, nobias, fixed, ahrs) = (s[0], s[1], s[2], s[3]);
        eprintln!("{p:?}: walked {walked:.0} m, ATE/RTE {s:?}");
        assert!(learned.0.is_finite() && learned.1.is_finite());
        // Wide margin: at least 20× better than either naive integration.
        assert!(learned.0 * 20.0 < fixed.0.min(ahrs.0), "{p:?} ATE {s:?}");
        assert!(learned.1 * 20.0 < fixed.1.min(ahrs.1), "{p:?} RTE {s:?}");
        // And useful in absolute terms: RTE below 60 % of a minute's walk (the AHRS
        // heading error, 10–30° on the simulator, dominates; docs/odometry-pipeline.md).
        let per_minute = walked / sim.truth.last().unwrap().t_s * 60.0;
        assert!(
            learned.1 < 0.6 * per_minute,
            "{p:?}: RTE {} vs {per_minute}",
            learned.1
        );
        assert!(nobias.0.is_finite());
    }
}

#[test]
fn other_input_rates_are_resampled() {
    let model = OdometryModel::shipped();
    let mut sc = sim_scenario(FIRST_EVAL_SEED + 11, PhonePlacement::InHand);
    let mut ate = Vec::new();
    for rate in [100.0, 200.0, 50.0] {
        sc.sample_rate_hz = rate;
        let sim = simulate_phone(&sc);
        let samples: Vec<ImuSample> = sim.samples.iter().map(Into::into).collect();
        let s = run_methods(&samples, &sim, &model, fixed(PhonePlacement::InHand)).scores();
        ate.push(s[0].0);
    }
    eprintln!("ATE at 100, 200, 50 Hz: {ate:?}");
    assert!(ate.iter().all(|a| a.is_finite()));
    assert!(
        ate[1] < 2.0 * ate[0] + 10.0 && ate[2] < 2.0 * ate[0] + 10.0,
        "{ate:?}"
    );
}

#[test]
fn model_round_trip_and_typed_errors() {
    // The shipped model: trained on real hand-held walks, the general and in-hand
    // regressors; it says how in its comments.
    let shipped = OdometryModel::shipped();
    let back = OdometryModel::parse(&shipped.to_text()).unwrap();
    assert_eq!(back, shipped);
    assert!(shipped.has_regressor(Some(Placement::InHand)));
    assert!(shipped
        .comments
        .iter()
        .any(|c| c.starts_with("trained by: stridekit train odometry --android")));
    let m = simulator_model();
    let text = m.to_text();
    let back = OdometryModel::parse(&text).unwrap();
    assert_eq!(back, m);
    assert_eq!(back.to_text(), text);
    assert!(m.regressors.iter().all(Option::is_some));
    let bad = |t: &str| match OdometryModel::parse(t) {
        Err(OdometryError::InvalidModel { line, reason }) => (line, reason),
        other => panic!("expected InvalidModel, got {other:?}"),
    };
    assert_eq!(m.regressors.len(), 1 + Placement::ALL.len());
    // A version-1 file (regressors keyed by the simulator's placements) and any other
    // version: typed error.
    for v in [1, 3] {
        let old = text.replacen(
            "stridekit-odometry 2",
            &format!("stridekit-odometry {v}"),
            1,
        );
        assert_eq!(
            OdometryModel::parse(&old),
            Err(OdometryError::ModelVersion {
                found: v,
                supported: 2
            })
        );
    }
    let v1 = "stridekit-odometry 1\npipeline rate_hz 100 window 200 hop 10 sigma 2 lambda 1\n";
    assert!(matches!(
        OdometryModel::parse(v1),
        Err(OdometryError::ModelVersion { found: 1, .. })
    ));
    // Version-1 placement names are unknown in version 2.
    bad(&text.replace("regressor pocket", "regressor front_pocket"));
    // Not a model at all, empty.
    bad("hello\n");
    bad("");
    // Truncated: the regressor lines cut off.
    let cut = &text[..text.find("regressor general").unwrap() + 40];
    bad(cut);
    // Wrong dimensions: one number less in `speed`.
    let general = text
        .lines()
        .find(|l| l.starts_with("regressor general"))
        .unwrap();
    let mut toks: Vec<&str> = general.split_whitespace().collect();
    let sp = toks.iter().position(|t| *t == "speed").unwrap();
    toks.remove(sp + 1);
    let fewer = text.replace(general, &toks.join(" "));
    let (_, reason) = bad(&fewer);
    assert!(reason.contains("speed"), "{reason}");
    // Non-finite number, zero sd, missing general, unknown placement, duplicates.
    bad(&text.replacen(" speed ", " speed NaN ", 1));
    let sd = toks.iter().position(|t| *t == "sd").unwrap();
    let mut zero = general.split_whitespace().collect::<Vec<_>>();
    zero[sd + 1] = "0";
    bad(&text.replace(general, &zero.join(" ")));
    bad(&text.replace(general, ""));
    bad(&text.replace("regressor bag", "regressor pocket"));
    bad(&format!("{text}{general}\n"));
    bad(&text.replace("window 200", "window 4000"));
    bad(&text.replace("pipeline", "# pipeline"));
}

#[test]
fn adversarial_input_never_panics_and_never_yields_nan() {
    let (_, samples) = walk(FIRST_EVAL_SEED + 3, PhonePlacement::SwingingArm);
    let mut rng = Rng::new(99);
    // Auto: the embedded placement classifier sees the garbage too.
    let mut eng = PhoneOdometry::shipped(OdometryConfig {
        placement: PlacementSource::Auto,
        ..OdometryConfig::default()
    })
    .unwrap();
    let mut t = 0.0;
    let mut estimates = 0;
    for (i, s) in samples.iter().take(20_000).enumerate() {
        t += 0.01;
        let mut x = ImuSample { t_s: t, ..*s };
        match i % 97 {
            1 => x.accel_mps2[0] = f64::NAN,
            2 => x.gyro_rads[2] = f64::INFINITY,
            3 => x.t_s = t - 5.0,
            4 => x.accel_mps2 = [1e300, -1e300, 1e300],
            5 => x.mag_ut = Some([f64::NAN; 3]),
            6 => x.accel_mps2 = [rng.range(-1500.0, 1500.0); 3],
            7 => x.gyro_rads = [rng.range(-150.0, 150.0); 3],
            8 if i % (97 * 20) == 8 => t += 3.0, // a gap now and then
            9 => x.t_s = -1e300,
            _ => {}
        }
        if i % (97 * 20) == 8 {
            x.t_s = t;
        }
        let before = eng.snapshot();
        match eng.push(&x) {
            Ok(Some(e)) => {
                estimates += 1;
                assert!(e.is_finite(), "{e:?}");
            }
            Ok(None) => {}
            Err(_) => assert_eq!(
                eng.snapshot(),
                before,
                "a rejected sample changed the state"
            ),
        }
        let p = eng.position_m();
        let v = eng.velocity_mps();
        assert!(p.iter().chain(v.iter()).all(|x| x.is_finite()));
    }
    assert!(estimates > 100, "{estimates}");
    // Typed errors.
    let mut eng = PhoneOdometry::shipped(OdometryConfig::default()).unwrap();
    let s = samples[0];
    assert!(matches!(
        eng.push(&ImuSample { t_s: f64::NAN, ..s }),
        Err(OdometryError::Input(InputError::NonFinite { field: "t_s" }))
    ));
    assert!(matches!(
        eng.push(&ImuSample {
            gyro_rads: [1e4, 0.0, 0.0],
            ..s
        }),
        Err(OdometryError::Input(InputError::OutOfRange { .. }))
    ));
    eng.push(&s).unwrap();
    assert!(matches!(
        eng.push(&s),
        Err(OdometryError::Input(InputError::TimeNotIncreasing { .. }))
    ));
    // Accelerations in g at rest.
    let mut eng = PhoneOdometry::shipped(OdometryConfig::default()).unwrap();
    let g = ImuSample {
        t_s: 0.0,
        accel_mps2: [0.0, 0.0, 1.0],
        gyro_rads: [0.0; 3],
        mag_ut: None,
    };
    assert!(matches!(
        eng.push(&g),
        Err(OdometryError::Input(InputError::AccelerationInG { .. }))
    ));
}

#[test]
fn snapshot_split_and_restore_gives_identical_output() {
    let (_, samples) = walk(FIRST_EVAL_SEED + 4, PhonePlacement::Armband);
    let samples = &samples[..8000];
    let run = |eng: &mut PhoneOdometry, s: &[ImuSample], out: &mut Vec<[u64; 7]>| {
        let code = |p: Option<Placement>| p.map_or(0, |p| 1 + p.index() as u64);
        for x in s {
            if let Ok(Some(e)) = eng.push(x) {
                out.push([
                    e.position_m[0].to_bits(),
                    e.position_m[1].to_bits(),
                    e.velocity_mps[0].to_bits(),
                    e.t_s.to_bits(),
                    e.placement_confidence.to_bits(),
                    code(e.regressor_placement),
                    code(e.detected_placement),
                ]);
            }
        }
    };
    for placement in [fixed(PhonePlacement::Armband), PlacementSource::Auto] {
        snapshot_case(samples, run, placement);
    }
    // Version-1 snapshots (no placement source and classifier) are typed errors.
    use stridekit_core::snapshot::{SnapshotError, Writer};
    // Engine kind 8: the phone odometry (docs/architecture.md).
    let mut w = Writer::new(8, 1);
    w.bytes(OdometryModel::shipped().to_text().as_bytes());
    assert_eq!(
        PhoneOdometry::restore(&w.finish()),
        Err(OdometryError::Snapshot(SnapshotError::UnsupportedVersion {
            found: 1,
            supported: 3
        }))
    );
}

type Run = fn(&mut PhoneOdometry, &[ImuSample], &mut Vec<[u64; 7]>);

fn snapshot_case(samples: &[ImuSample], run: Run, placement: PlacementSource) {
    let cfg = OdometryConfig {
        placement,
        ..OdometryConfig::default()
    };
    let mut whole = Vec::new();
    run(
        &mut PhoneOdometry::shipped(cfg).unwrap(),
        samples,
        &mut whole,
    );
    assert!(whole.len() > 500);
    if placement == PlacementSource::Auto {
        // The classifier ran and its state is part of what is compared.
        assert!(whole.iter().any(|o| o[6] != 0), "no placement detected");
    }
    for split in (0..samples.len()).step_by(617).chain([1, 2, 250, 251]) {
        let mut eng = PhoneOdometry::shipped(cfg).unwrap();
        let mut out = Vec::new();
        run(&mut eng, &samples[..split], &mut out);
        let bytes = eng.snapshot();
        let mut restored = PhoneOdometry::restore(&bytes).unwrap();
        assert_eq!(restored.snapshot(), bytes, "split {split}");
        run(&mut restored, &samples[split..], &mut out);
        assert_eq!(out, whole, "split at {split}");
    }
    // Every sample a split point: snapshot and restore before each push.
    let mut eng = PhoneOdometry::shipped(cfg).unwrap();
    let mut out = Vec::new();
    for x in samples {
        eng = PhoneOdometry::restore(&eng.snapshot()).unwrap();
        run(&mut eng, std::slice::from_ref(x), &mut out);
    }
    assert_eq!(out, whole, "restored before every sample");
    // Corrupt snapshots are typed errors.
    let bytes = PhoneOdometry::shipped(cfg).unwrap().snapshot();
    let mut bad = bytes.clone();
    bad[20] ^= 0xff;
    assert!(matches!(
        PhoneOdometry::restore(&bad),
        Err(OdometryError::Snapshot(_))
    ));
    assert!(PhoneOdometry::restore(&bytes[..bytes.len() - 9]).is_err());
}

#[test]
fn pushing_samples_does_not_allocate() {
    let (_, samples) = walk(FIRST_EVAL_SEED + 5, PhonePlacement::BackPocket);
    for (bias_correction, placement) in [
        (true, PlacementSource::Auto),
        (false, PlacementSource::Auto),
        (true, PlacementSource::Unknown),
        (true, fixed(PhonePlacement::BackPocket)),
    ] {
        let mut eng = PhoneOdometry::shipped(OdometryConfig {
            bias_correction,
            placement,
            ..OdometryConfig::default()
        })
        .unwrap();
        let (warm, rest) = samples.split_at(1000);
        for s in warm {
            eng.push(s).unwrap();
        }
        let (a, b) = rest.split_at(rest.len() / 2);
        let mut estimates = 0;
        let (n, _) = allocations_in(|| {
            for s in a {
                if let Ok(Some(e)) = eng.push(s) {
                    estimates += 1;
                    std::hint::black_box(e);
                }
            }
            let _ = eng.push(&ImuSample {
                t_s: f64::NAN,
                ..b[0]
            });
            let out = eng.push_batch_with(b, |e| {
                std::hint::black_box(e);
            });
            estimates += out.estimates;
            std::hint::black_box(eng.estimate());
        });
        assert_eq!(n, 0, "allocations on the per-sample path");
        assert!(estimates > 1000, "{estimates}");
    }
}

#[test]
fn heading_alignment_undoes_a_frame_rotation() {
    use stridekit_lab::odometry::evaluate::Tracks;
    let truth: Vec<(f64, f64, f64)> = (0..300)
        .map(|i| (i as f64 * 0.1, i as f64 * 0.1, 0.0))
        .collect();
    // The same walk in a frame turned by 70°.
    let (s, c) = 70f64.to_radians().sin_cos();
    let turned: Vec<_> = truth.iter().map(|p| (p.0, c * p.1, s * p.1)).collect();
    let mut tracks = Tracks {
        truth: truth.clone(),
        methods: [turned.clone(), turned.clone(), turned.clone(), turned],
        ..Default::default()
    };
    assert!(tracks.scores()[0].0 > 5.0);
    tracks.align_heading(20.0);
    assert!(tracks.scores()[0].0 < 1e-9);
}

#[test]
fn external_attitude_is_checked_and_used() {
    let (sim, samples) = walk(FIRST_EVAL_SEED + 12, PhonePlacement::InHand);
    let mut eng = PhoneOdometry::shipped(OdometryConfig::default()).unwrap();
    let before = eng.snapshot();
    assert!(matches!(
        eng.push_with_attitude(&samples[0], [f64::NAN, 0.0, 0.0, 0.0]),
        Err(OdometryError::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        eng.push_with_attitude(&samples[0], [0.0; 4]),
        Err(OdometryError::Input(InputError::OutOfRange { .. }))
    ));
    assert_eq!(eng.snapshot(), before);
    // The simulator's true attitude (10 Hz, nearest earlier) gives finite output.
    let mut n = 0;
    for s in &samples[..3000] {
        let q = sim.truth_at(s.t_s).attitude_wxyz;
        if let Some(e) = eng.push_with_attitude(s, q).unwrap() {
            assert!(e.is_finite());
            n += 1;
        }
    }
    assert!(n > 200);
}

/// Rotate a velocity in S by the window's yaw into ENU (as the engine does).
fn to_enu(v: [f64; 2], yaw: f64) -> [f64; 2] {
    let (s, c) = yaw.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

#[test]
fn fixed_and_unknown_sources_use_their_regressor() {
    let (_, samples) = walk(FIRST_EVAL_SEED + 13, PhonePlacement::FrontPocket);
    let samples = &samples[..6000];
    let model = simulator_model();
    let mut differs = 0;
    for source in Placement::ALL
        .into_iter()
        .map(PlacementSource::Fixed)
        .chain([PlacementSource::Unknown])
    {
        let want = match source {
            PlacementSource::Fixed(p) => Some(p),
            _ => None,
        };
        let cfg = OdometryConfig {
            placement: source,
            ..OdometryConfig::default()
        };
        let mut eng = PhoneOdometry::new(cfg, model.clone()).unwrap();
        let mut n = 0;
        eng.push_batch_with(samples, |e| {
            n += 1;
            assert_eq!(e.regressor_placement, want, "{source:?}");
            assert_eq!(e.detected_placement, None);
            let f = &e.features;
            let own = to_enu(model.regressor(want).predict(f), f.yaw_rad);
            assert_eq!(e.regressed_mps, own, "{source:?}");
            let general = to_enu(model.regressor(None).predict(f), f.yaw_rad);
            if want.is_some() && general != own {
                differs += 1;
            }
        });
        assert!(n > 400, "{n}");
        // The classifier never ran.
        assert_eq!(eng.placement_estimate(), None);
    }
    assert!(differs > 1000, "placement regressors equal the general one");
}

#[test]
fn auto_source_runs_the_classifier_and_stays_finite() {
    // Unknown is the default by measurement (see PlacementSource).
    assert_eq!(
        OdometryConfig::default().placement,
        PlacementSource::Unknown
    );
    let model = simulator_model();
    for (seed, p) in [
        (FIRST_EVAL_SEED + 14, PhonePlacement::InHand),
        (FIRST_EVAL_SEED + 15, PhonePlacement::BackPocket),
    ] {
        let (_, samples) = walk(seed, p);
        let auto = OdometryConfig {
            placement: PlacementSource::Auto,
            ..OdometryConfig::default()
        };
        let mut eng = PhoneOdometry::new(auto, model.clone()).unwrap();
        let (mut n, mut detected, mut own) = (0, 0, 0);
        for s in &samples {
            let Some(e) = eng.push(s).unwrap() else {
                continue;
            };
            n += 1;
            assert!(e.is_finite(), "{e:?}");
            assert!((0.0..=1.0).contains(&e.placement_confidence));
            let c = eng.placement_estimate();
            assert_eq!(e.detected_placement, c.map(|c| c.placement));
            match e.detected_placement {
                None => assert_eq!(e.regressor_placement, None),
                Some(d) => {
                    detected += 1;
                    let conf = c.unwrap().confidence;
                    assert_eq!(e.placement_confidence, conf);
                    let want = (conf >= AUTO_MIN_CONFIDENCE).then_some(d);
                    assert_eq!(e.regressor_placement, want);
                    own += usize::from(want.is_some());
                }
            }
            let f = &e.features;
            let reg = model.regressor(e.regressor_placement);
            assert_eq!(e.regressed_mps, to_enu(reg.predict(f), f.yaw_rad));
        }
        eprintln!("{p:?}: {n} estimates, {detected} with a placement, {own} with its regressor");
        assert!(n > 2000, "{n}");
        // The classifier's first window is 5.12 s in; after that every estimate has one.
        assert!(detected + 100 > n, "{detected} of {n}");
        assert!(eng.position_m().iter().all(|v| v.is_finite()));
    }
}
