//! Cost per IMU sample of the whole PDR pipeline: `PhoneNavigator::push_imu` (AHRS,
//! step detection, step length on each step, walking direction, position), with and
//! without the magnetometer.
//!
//! Input: the phone simulator (front pocket, walking 1.4 m/s, 100 Hz). The navigator
//! is warmed up on the first 120 s with GNSS (carrying calibrated, step length fitted,
//! hard-iron fit running); each iteration then pushes the next block of 2 000 samples
//! (20 s, ~37 steps, no GNSS) into a fresh clone, made outside the timing. Criterion
//! reports the time per block and, through the throughput setting, samples per second:
//! ns per sample = block time / 2 000.
//!
//! Run: `cargo bench -p stridekit-core --bench pdr` (add `-- --quick` for a short run).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario};

const BLOCK: usize = 2_000;
const WARM_UP_S: f64 = 120.0;

fn bench(c: &mut Criterion) {
    let mut sc = PhoneScenario::walk(7, PhonePlacement::FrontPocket, 1.4, WARM_UP_S + 25.0);
    sc.gnss_outages = vec![(WARM_UP_S, WARM_UP_S + 30.0)];
    let sim = simulate_phone(&sc);
    let frame = LocalFrame::new(47.0, 8.0, 0.0);
    let mut group = c.benchmark_group("pdr");
    group.throughput(Throughput::Elements(BLOCK as u64));
    for (name, use_mag) in [("push_imu_mag", true), ("push_imu_no_mag", false)] {
        let imu: Vec<ImuSample> = sim
            .samples
            .iter()
            .map(|s| ImuSample {
                t_s: s.t_s,
                gyro_rads: s.gyro_radps,
                accel_mps2: s.accel_mps2,
                mag_ut: use_mag.then_some(s.mag_ut),
            })
            .collect();
        let warm = imu.iter().position(|s| s.t_s >= WARM_UP_S).unwrap();
        let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
        let mut fi = 0;
        for s in &imu[..warm] {
            while fi < sim.fixes.len() && sim.fixes[fi].t_s <= s.t_s {
                let f = sim.fixes[fi];
                let (lat, lon) = frame.to_geodetic(f.east_m, f.north_m);
                nav.push_fix(&GnssFix::new(f.t_s, lat, lon).with_accuracy(f.accuracy_m))
                    .unwrap();
                fi += 1;
            }
            nav.push_imu(s).unwrap();
        }
        let block = &imu[warm..warm + BLOCK];
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                || nav.clone(),
                |n| {
                    for s in block {
                        n.push_imu(black_box(s)).unwrap();
                    }
                    black_box(n.estimate())
                },
                BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
