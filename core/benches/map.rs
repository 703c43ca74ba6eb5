//! Cost of the map engine: one step of the particles (`MapMatcher::step`: every
//! particle moved, its step checked against the walls, weights, resampling, the
//! smoothing window, the summary) at the default particle count, and building the
//! largest shared plan (`FloorPlan::new` on B1's 712 polygons; its heap size printed).
//!
//! Input: the real walk `site1/B1/5dda14979191710006b5720e` through the navigator
//! once, its steps replayed over B1's plan from its first waypoint, round and round
//! (a fresh clone of the started matcher each round, made outside the timing). Without
//! the shared data: a simulated walk in a hall with shops (said on stderr).
//!
//! After criterion's wall-clock figures, the same steps timed by the thread's own CPU
//! time (best and median of 30 rounds, `CLOCK_THREAD_CPUTIME_ID`): on a shared machine
//! the wall clock also measures the other tenants.
//!
//! Run: `cargo bench -p stridekit-core --bench map` (add `-- --quick` for a short run).

use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use stridekit_core::ahrs::ImuSample;
use stridekit_core::map::{FloorPlan, MapConfig, MapMatcher};
use stridekit_core::pdr::{NavStep, NavigatorConfig, PhoneNavigator};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario};

#[path = "common/cpu_time.rs"]
mod cpu_time;
use cpu_time::cpu_s;

/// The navigator's steps over `samples`.
fn steps_of(samples: &[ImuSample]) -> Vec<NavStep> {
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let mut out = Vec::new();
    for s in samples {
        let placed = nav.recent_steps().1;
        if nav.push_imu(s).is_ok() {
            out.extend(nav.steps_since(placed));
        }
    }
    out
}

/// (plan, geometry to rebuild it from, start, steps, what it is).
type Input = (
    Arc<FloorPlan>,
    Option<stridekit_formats::PlanFile>,
    [f64; 2],
    Vec<NavStep>,
    &'static str,
);

fn real() -> Option<Input> {
    let dir = stridekit_formats::data_dir()?.join("phone-indoor/site1/B1");
    let log = dir.join("5dda14979191710006b5720e.txt.gz");
    if !log.is_file() {
        return None;
    }
    let file = stridekit_formats::read_floor_plan(&dir).ok()?;
    let plan = Arc::new(file.build().ok()?);
    let rec = stridekit_formats::read_inertial(Path::new(&log)).ok()?;
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
    let start = [rec.truth[0].1, rec.truth[0].2];
    Some((
        plan,
        Some(file),
        start,
        steps_of(&samples),
        "B1, a real walk",
    ))
}

fn simulated() -> Input {
    let mut sc = PhoneScenario::walk(7, PhonePlacement::InHand, 1.3, 60.0);
    sc.gnss = false;
    let sim = simulate_phone(&sc);
    let samples: Vec<ImuSample> = sim.samples.iter().map(ImuSample::from).collect();
    let shops: Vec<[f64; 4]> = (0..20)
        .flat_map(|i| {
            let x = -100.0 + 10.0 * f64::from(i);
            [[x, 6.0, x + 8.0, 14.0], [x, -14.0, x + 8.0, -6.0]]
        })
        .collect();
    let plan = FloorPlan::rectangles(0, [-120.0, -120.0, 120.0, 120.0], &shops).unwrap();
    (
        Arc::new(plan),
        None,
        [0.0, 0.0],
        steps_of(&samples),
        "a simulated walk in a hall",
    )
}

fn bench(c: &mut Criterion) {
    let (plan, file, start, steps, what) = real().unwrap_or_else(|| {
        eprintln!("map bench: shared data absent, using a simulated walk in a hall");
        simulated()
    });
    eprintln!(
        "map bench: {what}: {} steps, plan of {} walls, {:.2} MB",
        steps.len(),
        plan.walls().len(),
        plan.heap_bytes() as f64 / 1e6
    );
    let config = MapConfig::default();
    let mut started = MapMatcher::new(config, vec![Arc::clone(&plan)]).unwrap();
    started.start_at(start[0], start[1], 1.0, None).unwrap();
    started.set_absolute_heading(true);
    let mut group = c.benchmark_group("map");
    group.bench_function("step_default_particles", |b| {
        b.iter_custom(|iters| {
            let mut spent = Duration::ZERO;
            let mut done = 0u64;
            while done < iters {
                let mut m = started.clone();
                let t = Instant::now();
                for s in steps.iter().take((iters - done) as usize) {
                    m.step(black_box(s), 0.0);
                    done += 1;
                }
                spent += t.elapsed();
                black_box(m.state());
            }
            spent
        })
    });
    if let Some(file) = file {
        group.bench_function("build_b1", |b| {
            b.iter(|| black_box(FloorPlan::new(&file.geometry, Some(file.geo)).unwrap()))
        });
    }
    group.finish();
}

/// CPU time per step over rounds of the walk: best and median, µs.
fn cpu_per_step(c: &mut Criterion) {
    let _ = c;
    let (plan, _, start, steps, what) = real().unwrap_or_else(simulated);
    let mut started = MapMatcher::new(MapConfig::default(), vec![plan]).unwrap();
    started.start_at(start[0], start[1], 1.0, None).unwrap();
    started.set_absolute_heading(true);
    let origin = Instant::now();
    let mut per_step: Vec<f64> = (0..30)
        .map(|_| {
            let mut m = started.clone();
            let t = cpu_s(origin);
            for s in &steps {
                m.step(black_box(s), 0.0);
            }
            black_box(m.state());
            (cpu_s(origin) - t) / steps.len().max(1) as f64 * 1e6
        })
        .collect();
    per_step.sort_by(f64::total_cmp);
    eprintln!(
        "map/step_default_particles, thread CPU time ({what}): best {:.1} µs, median {:.1} µs per step",
        per_step[0],
        per_step[per_step.len() / 2]
    );
}

criterion_group!(benches, bench, cpu_per_step);
criterion_main!(benches);
