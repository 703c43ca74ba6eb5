//! Cost of the phone-placement classifier.
//!
//! - `placement/push_block_*`: one block of 2 000 samples (a simulated walk with the
//!   phone in a front pocket, at 100 Hz and at 400 Hz) into a fresh clone of a
//!   classifier warmed up on the preceding 20 s (the clone is made outside the
//!   timing). Throughput is set in samples: ns per sample = block time / 2 000. It
//!   includes the window classifications that fall in the block (one per 1.28 s).
//! - `placement/window`: one window (features of 256 bins + the model).
//!
//! Run: `cargo bench -p stridekit-core --bench placement` (add `-- --quick` for a
//! short run).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use stridekit_core::placement::BinAverager;
use stridekit_core::placement::{window_features, FeatureTables};
use stridekit_core::placement::{AccelSample, PlacementClassifier, PlacementModel, WINDOW};
use stridekit_sim::{simulate_phone, PhonePlacement, PhoneScenario};

const BLOCK: usize = 2_000;
const WARM_UP_S: f64 = 20.0;

fn accel(t_s: f64, accel_mps2: [f64; 3]) -> AccelSample {
    AccelSample { t_s, accel_mps2 }
}

fn walk(rate_hz: f64) -> Vec<(f64, [f64; 3])> {
    let mut sc = PhoneScenario::walk(11, PhonePlacement::FrontPocket, 1.3, 60.0);
    sc.gnss = false;
    sc.sample_rate_hz = rate_hz;
    simulate_phone(&sc)
        .samples
        .iter()
        .map(|s| (s.t_s, s.accel_mps2))
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("placement");
    for rate in [100.0, 400.0] {
        let samples = walk(rate);
        let warm = (WARM_UP_S * rate) as usize;
        let mut base = PlacementClassifier::shipped();
        for &(t, a) in &samples[..warm] {
            let _ = base.push(&accel(t, a));
        }
        let block = &samples[warm..warm + BLOCK];
        g.throughput(Throughput::Elements(BLOCK as u64));
        g.bench_function(format!("push_block_{rate:.0}hz"), |b| {
            b.iter_batched_ref(
                || base.clone(),
                |c| {
                    for &(t, a) in block {
                        let _ = black_box(c.push(&accel(t, a)));
                    }
                },
                BatchSize::SmallInput,
            )
        });
    }
    let samples = walk(100.0);
    let mut bins = BinAverager::new();
    let mut w = [[0.0; 3]; WINDOW];
    let mut n = 0;
    for &(t, a) in &samples {
        let r = bins.push(t, a);
        for m in &r.means[..r.len] {
            if n < WINDOW {
                w[n] = *m;
                n += 1;
            }
        }
    }
    let tables = FeatureTables::default();
    let model = PlacementModel::shipped();
    g.throughput(Throughput::Elements(1));
    g.bench_function("window", |b| {
        b.iter(|| model.probabilities(&window_features(&tables, black_box(&w))))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
