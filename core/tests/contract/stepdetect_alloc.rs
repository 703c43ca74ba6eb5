//! The per-sample path of the step detector must not touch the heap: pushing samples
//! (valid or rejected), releasing a confirmed bout and draining it with `pop_step`
//! allocate nothing once the detector is built.
//!
//! A counting global allocator wraps `System`; counting is switched on per thread, so
//! tests running in parallel do not disturb each other (pattern of tests/alloc.rs).

use std::hint::black_box;

use stridekit_core::stepdetect::{DetectorMode, StepDetector, StepDetectorConfig};

use crate::common::allocations_in;

/// A walk at ~1.9 steps/s, 100 Hz with a little timestamp jitter, as (t_s, accel).
fn walk(n: usize) -> Vec<(f64, [f64; 3])> {
    let mut seed = 0x5eed_u64;
    let mut noise = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..n)
        .map(|k| {
            let t = k as f64 * 0.01 + 0.004 * noise();
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

fn check(mode: DetectorMode) {
    let samples = walk(40_000);
    let mut d = StepDetector::new(StepDetectorConfig {
        mode,
        ..Default::default()
    })
    .unwrap();
    for &(t, a) in &samples[..100] {
        d.push_accel(t, a).unwrap();
    }
    let last_t = samples.last().unwrap().0;
    let (allocs, steps) = allocations_in(|| {
        let mut steps = 0usize;
        for (i, &(t, a)) in samples[100..].iter().enumerate() {
            if d.push_accel(black_box(t), black_box(a)).unwrap().is_some() {
                steps += 1;
            }
            while d.pop_step().is_some() {
                steps += 1;
            }
            if i % 1000 == 0 {
                // Rejected samples build their errors without allocating too.
                black_box(d.push_accel(f64::NAN, a).unwrap_err());
                black_box(d.push_accel(t, a).unwrap_err());
                black_box(
                    d.push_accel(t + 0.001, [f64::INFINITY, 0.0, 0.0])
                        .unwrap_err(),
                );
            }
        }
        black_box(d.push_accel(last_t + 0.01, [0.0, 0.0, 1.0]).is_ok());
        steps
    });
    assert_eq!(
        allocs, 0,
        "{mode:?}: {allocs} heap allocations on the sample path"
    );
    if mode == DetectorMode::Default {
        assert!(steps > 600, "{mode:?}: only {steps} steps");
    }
}

#[test]
fn default_sample_path_does_not_allocate() {
    check(DetectorMode::Default);
}

#[test]
fn as_published_sample_path_does_not_allocate() {
    check(DetectorMode::AsPublished);
}

#[test]
fn counting_allocator_sees_allocations() {
    let (n, v) = allocations_in(|| black_box(Vec::<u8>::with_capacity(16)));
    assert_eq!(n, 1);
    drop(v);
}
