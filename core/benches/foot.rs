//! Cost of the whole foot-navigation pipeline per IMU sample (median pre-filter,
//! zero-velocity detector, strapdown mechanisation, 15-state error-state Kalman
//! filter with zero-velocity updates, estimate), per detector; and the time to
//! replay one hour of 200 Hz data. Project target: ≤ 1 µs per sample.
//!
//! Input: a simulated walk (`sim::foot`, 200 Hz, two laps of a 20 m × 10 m
//! rectangle), repeated with shifted timestamps (it starts and ends at rest, so the
//! repetitions join up). Each `pipeline` iteration pushes a block of 2 000 samples
//! (10 s: strides, stances, turns) into a clone of an aligned navigator (the clone is
//! not timed); divide the time by 2 000 for ns per sample (criterion also prints
//! elements/s). `replay_1h_200hz` pushes 720 000 samples through a new navigator
//! with `push_batch_with` (the estimates go to a callback, none is kept).
//!
//! Run: `cargo bench -p stridekit-core --bench foot` (add `-- --quick` for a short run).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use stridekit_core::foot::{
    AdaptiveThresholds, FixedThresholds, FootConfig, FootNavigator, FootSample, ShoeDetector,
    SvmAdaptive, ZeroVelocityDetector,
};
use stridekit_sim::{simulate_foot, FootScenario};

const BLOCK: usize = 2_000;
const WARM: usize = 1_000;

/// `n` samples: the simulated walk repeated with shifted timestamps.
fn samples(n: usize) -> Vec<FootSample> {
    simulate_foot(&FootScenario::walk(42, 2)).repeated_samples(n)
}

fn detectors() -> [(&'static str, ZeroVelocityDetector); 6] {
    [
        ("adaptive_shoe", ZeroVelocityDetector::default()),
        ("shoe", ZeroVelocityDetector::Shoe(ShoeDetector::default())),
        ("fixed", ZeroVelocityDetector::Fixed(FixedThresholds::WALK)),
        (
            "adaptive",
            ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
        ),
        ("svm", ZeroVelocityDetector::default_svm()),
        (
            "svm+adaptive",
            ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ),
    ]
}

fn pipeline(c: &mut Criterion) {
    let data = samples(WARM + BLOCK);
    let mut group = c.benchmark_group("foot_pipeline");
    group.throughput(Throughput::Elements(BLOCK as u64));
    for median_window in [1, 5] {
        for (name, detector) in detectors() {
            let mut nav = FootNavigator::new(FootConfig {
                detector,
                median_window,
                ..FootConfig::default()
            })
            .unwrap();
            for s in &data[..WARM] {
                nav.push(s).unwrap();
            }
            assert!(nav.is_aligned());
            let block = &data[WARM..];
            group.bench_function(
                format!("{name}/median_{median_window}/block_of_{BLOCK}"),
                |b| {
                    b.iter_batched_ref(
                        || nav.clone(),
                        |nav| {
                            let mut stance = 0u32;
                            for s in block {
                                if let Some(e) = nav.push(black_box(s)).unwrap() {
                                    stance += e.stance as u32;
                                }
                            }
                            stance
                        },
                        BatchSize::SmallInput,
                    )
                },
            );
        }
    }
    group.finish();
}

fn replay_hour(c: &mut Criterion) {
    let data = samples(720_000);
    let mut group = c.benchmark_group("foot_replay_1h_200hz");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Elements(data.len() as u64));
    for (name, detector) in detectors() {
        let config = FootConfig {
            detector,
            ..FootConfig::default()
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut nav = FootNavigator::new(config.clone()).unwrap();
                let mut strides = 0u64;
                let out = nav.push_batch_with(black_box(&data), |e| strides = e.strides);
                assert!(out.rejected.is_empty());
                strides
            })
        });
    }
    group.finish();
}

criterion_group!(benches, pipeline, replay_hour);
criterion_main!(benches);
