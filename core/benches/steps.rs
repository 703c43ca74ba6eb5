//! Cost per accelerometer sample of the step detectors (project target: ≤ 50 ns).
//!
//! Each iteration pushes one block of 2 000 samples (a synthetic walk at 100 Hz and at
//! 400 Hz, ~1.9 steps/s, small timestamp jitter) into a fresh clone of a detector warmed
//! up on the preceding 20 s; the clone is made outside the timing. Criterion reports the
//! time per block and, through the throughput setting, samples per second: ns per sample
//! = block time / 2 000.
//!
//! Run: `cargo bench -p stridekit-core --bench steps` (add `-- --quick` for a short run).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use stridekit_core::stepdetect::{DetectorMode, StepDetector, StepDetectorConfig};

const BLOCK: usize = 2_000;
const WARM_UP_S: f64 = 20.0;

/// A walk at `rate_hz` over `duration_s`, as (t_s, accel).
fn walk(rate_hz: f64, duration_s: f64) -> Vec<(f64, [f64; 3])> {
    let mut seed = 0x00c0_ffee_u64;
    let mut noise = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let n = (rate_hz * duration_s) as usize;
    (0..n)
        .map(|k| {
            let t = (k as f64 + 0.4 * noise()) / rate_hz;
            let w = std::f64::consts::TAU * 1.9 * t;
            let phase = (1.9 * t).fract();
            let m = 9.81
                + 1.5 * (w.cos() + 0.3 * (2.0 * w).cos())
                + 3.0 * (-(phase / 0.02).powi(2)).exp()
                + 0.05 * noise();
            (t, [0.3 * m, 0.2 * m, 0.93 * m])
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("steps");
    group.throughput(Throughput::Elements(BLOCK as u64));
    for rate_hz in [100.0, 400.0] {
        let samples = walk(rate_hz, WARM_UP_S + BLOCK as f64 / rate_hz);
        let warm = (WARM_UP_S * rate_hz) as usize;
        for (name, mode) in [
            ("default", DetectorMode::Default),
            ("as_published", DetectorMode::AsPublished),
        ] {
            let mut d = StepDetector::new(StepDetectorConfig {
                mode,
                ..Default::default()
            })
            .unwrap();
            for &(t, a) in &samples[..warm] {
                d.push_accel(t, a).unwrap();
                while d.pop_step().is_some() {}
            }
            let block = &samples[warm..warm + BLOCK];
            group.bench_function(format!("{name}/{rate_hz:.0}Hz/block_of_{BLOCK}"), |b| {
                b.iter_batched_ref(
                    || d.clone(),
                    |d| {
                        let mut n = 0u32;
                        for &(t, a) in block {
                            if d.push_accel(black_box(t), black_box(a)).unwrap().is_some() {
                                n += 1;
                            }
                            while d.pop_step().is_some() {
                                n += 1;
                            }
                        }
                        n
                    },
                    BatchSize::SmallInput,
                )
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
