//! The foot pipeline's cost per sample measured by the thread's own CPU time
//! (`CLOCK_THREAD_CPUTIME_ID` on Unix, wall time elsewhere), best and median of
//! 40 runs of 100 000 samples: on a shared VM the wall-clock criterion bench
//! (`--bench foot`) also measures the other tenants (±15–20 % between runs), the
//! thread's CPU time much less. Same input as `--bench foot` (the simulated 200 Hz
//! walk repeated); a new navigator per run (alignment included).
//!
//! Run: `cargo bench -p stridekit-core --bench foot_cpu`.

use std::hint::black_box;
use std::time::Instant;

use stridekit_core::foot::{
    FootConfig, FootNavigator, FootSample, SvmAdaptive, ZeroVelocityDetector,
};
use stridekit_sim::{simulate_foot, FootScenario};

#[path = "common/cpu_time.rs"]
mod cpu_time;
use cpu_time::cpu_s;

const N: usize = 100_000;
const RUNS: usize = 40;

/// `n` samples: the simulated walk repeated with shifted timestamps.
fn samples(n: usize) -> Vec<FootSample> {
    simulate_foot(&FootScenario::walk(42, 2)).repeated_samples(n)
}

fn main() {
    // `cargo test --benches` runs bench binaries with `--bench` absent: stay quick.
    let runs = if std::env::args().any(|a| a == "--bench") {
        RUNS
    } else {
        1
    };
    let data = samples(N);
    let origin = Instant::now();
    println!("foot pipeline, µs per sample of thread CPU time ({runs} runs of {N} samples)");
    for (name, detector) in [
        ("adaptive_shoe (default)", ZeroVelocityDetector::default()),
        (
            "svm+adaptive",
            ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ),
    ] {
        for median_window in [1, 5] {
            let config = FootConfig {
                detector: detector.clone(),
                median_window,
                ..FootConfig::default()
            };
            let mut per_sample: Vec<f64> = (0..runs)
                .map(|_| {
                    let mut nav = FootNavigator::new(config.clone()).unwrap();
                    let t0 = cpu_s(origin);
                    let mut stance = 0u32;
                    for s in &data {
                        if let Ok(Some(e)) = nav.push(black_box(s)) {
                            stance += e.stance as u32;
                        }
                    }
                    black_box(stance);
                    (cpu_s(origin) - t0) / N as f64 * 1e6
                })
                .collect();
            per_sample.sort_by(f64::total_cmp);
            println!(
                "{name:>24}, median filter {median_window}: best {:.3} µs, median {:.3} µs",
                per_sample[0],
                per_sample[runs / 2]
            );
        }
    }
}
