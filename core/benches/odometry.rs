//! Cost of the learned phone odometry: per IMU sample (AHRS, stabilisation,
//! resampling, smoothing, window ring, and every `hop` samples a window: features,
//! regressor, bias correction), and per window alone (features + regressor + bias
//! block solve). Baselines for comparison: naive double integration with AHRS
//! orientation.
//!
//! Input: a held-out simulated walk (100 Hz). `pipeline/block_of_2000` pushes 2 000
//! samples (20 s, 200 windows) into a clone of a warmed-up engine (clone not
//! timed); divide by 2 000 for ns per sample; `learned_auto` adds the embedded
//! placement classifier (`PlacementSource::Auto`). `window/features_regress` times one
//! window's features and regression; `window/bias_block` one bias-correction solve.
//!
//! Run: `cargo bench -p stridekit-core --bench odometry` (add `-- --quick`).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use stridekit_core::odometry::BiasCorrector;
use stridekit_core::odometry::FeatureWindow;
use stridekit_core::odometry::{
    ImuSample, OdometryConfig, OdometryModel, PhoneOdometry, PlacementSource,
};
use stridekit_lab::odometry::train::{sim_scenario, FIRST_EVAL_SEED};
use stridekit_sim::{simulate_phone, PhonePlacement};

const BLOCK: usize = 2_000;
const WARM: usize = 1_000;

fn data() -> Vec<ImuSample> {
    let sim = simulate_phone(&sim_scenario(FIRST_EVAL_SEED, PhonePlacement::InHand));
    sim.samples
        .iter()
        .take(WARM + BLOCK)
        .map(Into::into)
        .collect()
}

fn pipeline(c: &mut Criterion) {
    let data = data();
    let mut group = c.benchmark_group("odometry_pipeline");
    group.throughput(Throughput::Elements(BLOCK as u64));
    let in_hand = PlacementSource::Fixed(PhonePlacement::InHand.into());
    for (name, bias_correction, placement) in [
        ("learned", true, in_hand),
        ("learned_no_bias", false, in_hand),
        // The embedded placement classifier runs on every sample.
        ("learned_auto", true, PlacementSource::Auto),
    ] {
        let mut eng = PhoneOdometry::shipped(OdometryConfig {
            bias_correction,
            placement,
            ..OdometryConfig::default()
        })
        .unwrap();
        for s in &data[..WARM] {
            eng.push(s).unwrap();
        }
        group.bench_function(format!("{name}/block_of_{BLOCK}"), |b| {
            b.iter_batched_ref(
                || eng.clone(),
                |eng| {
                    for s in &data[WARM..] {
                        black_box(eng.push(s).ok());
                    }
                },
                BatchSize::SmallInput,
            )
        });
    }
    let mut naive = stridekit_lab::odometry::NaiveOdometry::new(
        stridekit_lab::odometry::NaiveMode::AhrsOrientation,
        OdometryConfig::default().ahrs,
        true,
    )
    .unwrap();
    for s in &data[..WARM] {
        naive.push(s).unwrap();
    }
    group.bench_function(format!("naive_ahrs/block_of_{BLOCK}"), |b| {
        b.iter_batched_ref(
            || naive.clone(),
            |n| {
                for s in &data[WARM..] {
                    black_box(n.push(s).ok());
                }
            },
            BatchSize::SmallInput,
        )
    });
    group.finish();
}

fn window(c: &mut Criterion) {
    let data = data();
    let model = OdometryModel::shipped();
    let mut eng = PhoneOdometry::new(OdometryConfig::default(), model.clone()).unwrap();
    let mut feats = Vec::new();
    for s in &data {
        if let Ok(Some(e)) = eng.push(s) {
            feats.push(e.features);
        }
    }
    let f = feats[feats.len() / 2];
    let reg = *model.regressor(Some(PhonePlacement::InHand.into()));
    let mut group = c.benchmark_group("odometry_window");
    let mut win = FeatureWindow::new(model.params.window);
    for (i, s) in data.iter().enumerate().take(400) {
        let a = s.accel_mps2;
        win.push(
            i as f64 * 0.01,
            &[
                s.gyro_rads[0],
                s.gyro_rads[1],
                s.gyro_rads[2],
                a[0],
                a[1],
                a[2] - 9.8,
            ],
        );
    }
    group.bench_function("features_of_200_samples", |b| {
        b.iter(|| black_box(win.features(black_box(0.3))))
    });
    group.bench_function("regressor_predict", |b| {
        b.iter(|| black_box(reg.predict(black_box(&f))))
    });
    let mut bias = BiasCorrector::new(model.params.lambda);
    for _ in 0..30 {
        bias.push([1.0, 0.0], [0.01, 0.0]);
    }
    group.bench_function("bias_block_solve", |b| {
        b.iter(|| black_box(bias.push(black_box([1.0, 0.1]), black_box([0.01, 0.0]))))
    });
    group.finish();
}

criterion_group!(benches, pipeline, window);
criterion_main!(benches);
