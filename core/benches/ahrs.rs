//! Cost of one AHRS update: stridekit's filters against the `ahrs` crate's `Madgwick`
//! on a synthetic loop (project target for Madgwick: ≤ 0.8× the crate's time per
//! update), and on a real trial (target for the default: ≤ 0.5× VQF's C++ core).
//!
//! Both filters consume the same 1024-sample loop of a synthetic hand-held motion at
//! 100 Hz (gyroscope, accelerometer, magnetometer consistent with one orientation
//! trajectory, plus gait-like linear acceleration), in order, one sample per
//! iteration. stridekit's filter needs increasing time, so each iteration advances
//! `t_s` by 10 ms; the state keeps evolving as in real use (no clones in the timing).
//!
//! - `stridekit_default`: the default (decoupled) filter, every feature on;
//! - `stridekit_madgwick`: `AhrsSettings::madgwick()` (door checks, initialisation,
//!   rejection and recovery, bias learning);
//! - `stridekit_plain`: `AhrsSettings::plain` (the paper's filter; door checks stay);
//! - `ahrs_crate`: `ahrs::Madgwick::update_imu` / `update` (fixed sample period).
//!
//! `update_*` returns flags only; the derived outputs (Euler angles, heading, linear
//! acceleration) cost an extra `output()` call, measured on its own.
//!
//! `broad_trial`: one whole pass over a real recording (BROAD trial 01, 56 940 samples
//! at 285.7 Hz with magnetometer, read from `../shared/data/orientation/broad/` or
//! `$STRIDEKIT_DATA`; skipped with a message when absent): a fresh filter fed every
//! sample in order, as in `stridekit eval orientation`. Time per update = time per
//! iteration / 56 940. `scripts/bench-vqf` runs this group and VQF's C++ core (PyPI
//! `vqf`, batch) on the same trial and prints the ratio.
//!
//! Run: `cargo bench -p stridekit-core --bench ahrs` (add `-- --quick` for a short run,
//! `-- broad_trial` for the real trial only).

use std::hint::black_box;

use ahrs::Ahrs as _;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::{UnitQuaternion, Vector3};
use stridekit_core::ahrs::{Ahrs, AhrsSettings, ImuSample};

/// The trial the real-data bench replays.
pub const BROAD_TRIAL: &str = "orientation/broad/01_undisturbed_slow_rotation_A.csv.gz";

const N: usize = 1024;
const DT: f64 = 0.01;
const BETA: f64 = 0.1;

struct Sample {
    gyro: [f64; 3],
    accel: [f64; 3],
    mag: [f64; 3],
}

/// Gyro rates integrated into a truth orientation; accelerometer and magnetometer
/// readings follow from it.
fn samples() -> Vec<Sample> {
    let mut q = UnitQuaternion::from_euler_angles(0.1, 0.5, 0.8);
    let field = Vector3::new(0.0, 20.0, -45.0);
    (0..N)
        .map(|i| {
            let t = i as f64 * DT;
            let ph = std::f64::consts::TAU * 1.9 * t;
            let w = Vector3::new(
                0.2 * ph.cos(),
                0.15 * (0.5 * ph).sin(),
                0.3 * (0.5 * ph).cos(),
            );
            let lin = Vector3::new(0.3 * ph.sin(), 0.8 * (ph + 1.0).sin(), 2.0 * ph.sin());
            let a = q.inverse() * (lin + Vector3::new(0.0, 0.0, 9.80665));
            let m = q.inverse() * field;
            q *= UnitQuaternion::from_scaled_axis(w * DT);
            Sample {
                gyro: w.into(),
                accel: a.into(),
                mag: m.into(),
            }
        })
        .collect()
}

fn imu(a: &mut Ahrs, t: f64, x: &Sample) -> bool {
    a.update_imu(t, black_box(x.gyro), black_box(x.accel))
        .is_ok()
}

fn marg(a: &mut Ahrs, t: f64, x: &Sample) -> bool {
    a.update_marg(t, black_box(x.gyro), black_box(x.accel), black_box(x.mag))
        .is_ok()
}

fn warmed(
    settings: AhrsSettings,
    s: &[Sample],
    update: impl Fn(&mut Ahrs, f64, &Sample) -> bool,
) -> (Ahrs, f64) {
    let mut a = Ahrs::new(settings).expect("valid settings");
    let mut t = 0.0;
    for x in s.iter().cycle().take(600) {
        t += DT;
        assert!(update(&mut a, t, x));
    }
    (a, t)
}

/// One group: our filter with both settings, then the crate, on the same samples.
/// The update functions are generic parameters (not function pointers), so both
/// filters are inlined into the timing loop alike.
fn group(
    c: &mut Criterion,
    name: &str,
    update: impl Fn(&mut Ahrs, f64, &Sample) -> bool + Copy,
    reference: impl Fn(&mut ahrs::Madgwick<f64>, &[Vector3<f64>; 3]) -> bool,
) {
    let s = samples();
    let v: Vec<[Vector3<f64>; 3]> = s
        .iter()
        .map(|x| [x.gyro.into(), x.accel.into(), x.mag.into()])
        .collect();
    let mut group = c.benchmark_group(name);
    for (name, settings) in [
        ("stridekit_default", AhrsSettings::default()),
        ("stridekit_madgwick", AhrsSettings::madgwick()),
        ("stridekit_plain", AhrsSettings::plain(BETA)),
    ] {
        let (mut a, mut t) = warmed(settings, &s, update);
        let mut i = 0usize;
        group.bench_function(name, |b| {
            b.iter(|| {
                let x = &s[i % N];
                i += 1;
                t += DT;
                black_box(update(&mut a, t, x))
            })
        });
    }
    let mut m =
        ahrs::Madgwick::new_with_quat(DT, BETA, UnitQuaternion::from_euler_angles(0.1, 0.5, 0.8));
    let mut i = 0usize;
    group.bench_function("ahrs_crate", |b| {
        b.iter(|| {
            let x = &v[i % N];
            i += 1;
            black_box(reference(&mut m, x))
        })
    });
    group.finish();
}

fn bench_imu(c: &mut Criterion) {
    group(c, "imu_update", imu, |m, x| {
        m.update_imu(black_box(&x[0]), black_box(&x[1])).is_ok()
    });
}

fn bench_marg(c: &mut Criterion) {
    group(c, "marg_update", marg, |m, x| {
        m.update(black_box(&x[0]), black_box(&x[1]), black_box(&x[2]))
            .is_ok()
    });
}

fn bench_output(c: &mut Criterion) {
    let s = samples();
    let (a, _) = warmed(AhrsSettings::default(), &s, marg);
    c.bench_function("output", |b| b.iter(|| black_box(&a).output()));
}

fn bench_broad(c: &mut Criterion) {
    let Some(dir) = stridekit_formats::data_dir() else {
        eprintln!("broad_trial: skipped (../shared/data not found; set STRIDEKIT_DATA)");
        return;
    };
    let path = dir.join(BROAD_TRIAL);
    let rec = match stridekit_formats::read_broad(&path) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("broad_trial: skipped ({}: {e})", path.display());
            return;
        }
    };
    let samples: Vec<ImuSample> = rec
        .samples
        .iter()
        .map(|s| ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: s.mag_ut,
        })
        .collect();
    let mut group = c.benchmark_group("broad_trial");
    group.throughput(Throughput::Elements(samples.len() as u64));
    group.sample_size(20);
    // CPU time of this thread, not wall clock: on a shared machine (the one these
    // figures come from runs several builds at once) wall-clock swings 2×, while the
    // CPU time a pass needs does not. `scripts/bench-vqf` times VQF the same way.
    for (name, settings, with_mag) in [
        ("default_marg", AhrsSettings::default(), true),
        ("default_imu", AhrsSettings::default(), false),
        ("madgwick_marg", AhrsSettings::madgwick(), true),
        ("plain_marg", AhrsSettings::plain(0.12), true),
    ] {
        group.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let start = thread_cpu_time();
                for _ in 0..iters {
                    let mut a = Ahrs::new(settings).expect("valid settings");
                    for s in &samples {
                        let mag = if with_mag { s.mag_ut } else { None };
                        let _ = black_box(a.update(s.t_s, s.gyro_rads, s.accel_mps2, mag));
                    }
                    black_box(a.quaternion());
                }
                thread_cpu_time().saturating_sub(start)
            })
        });
    }
    group.finish();
}

/// CPU time consumed by this thread (Linux: `/proc/thread-self/schedstat`, ns on
/// CPU); elsewhere the wall clock since the first call.
fn thread_cpu_time() -> std::time::Duration {
    if let Ok(s) = std::fs::read_to_string("/proc/thread-self/schedstat") {
        if let Some(ns) = s
            .split_whitespace()
            .next()
            .and_then(|v| v.parse::<u64>().ok())
        {
            return std::time::Duration::from_nanos(ns);
        }
    }
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    START.get_or_init(std::time::Instant::now).elapsed()
}

criterion_group!(benches, bench_imu, bench_marg, bench_output, bench_broad);
criterion_main!(benches);
