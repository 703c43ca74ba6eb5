//! Cost of one update of the pace engine (project target: ≤ 1 µs per update).
//!
//! Every measured call is a single `push_fix` / `push_steps` / `estimate` on a tracker
//! that was warmed up with a few hundred samples of a synthetic run (straight line at
//! 3 m/s, small deterministic noise, fixes at 1 Hz, step counts at 1 Hz or step events
//! at ~3 Hz, both streams interleaved in time order as a phone delivers them).
//!
//! Sample times must increase, so a call cannot simply be repeated on one tracker.
//! Instead the stream is replayed once and the tracker is cloned just before each of
//! `CHECKPOINTS` consecutive samples of the measured kind; criterion's
//! `iter_batched_ref` hands the routine a fresh clone (made outside the timing) and
//! the routine pushes that clone's next sample. Cycling through the checkpoints keeps
//! the filter state varied instead of timing one branch over and over.
//!
//! Run: `cargo bench -p stridekit-core --bench pace` (add `-- --quick` for a short run).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use stridekit_core::geo::LocalFrame;
use stridekit_core::{GnssFix, PaceConfig, PaceMode, PaceSample, PaceTracker, StepSample};

/// Samples pushed before the first checkpoint.
const WARM_UP_SAMPLES: usize = 400;
/// Distinct tracker states each benchmark cycles through.
const CHECKPOINTS: usize = 64;
/// Trackers cloned per timed batch (small, so the batch stays in cache).
const BATCH: u64 = 32;

const SPEED_MPS: f64 = 3.0;
const CADENCE_HZ: f64 = 2.9;
const HEADING_RAD: f64 = 0.6;

/// Deterministic xorshift noise in −1..1.
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

#[derive(Clone, Copy, Debug)]
enum StepKind {
    /// Cumulative step counts at 1 Hz.
    Count,
    /// One event per step at ~2.9 Hz with jitter.
    Event,
}

/// The run as a phone would deliver it, in time order, over `duration_s`.
fn synthetic_run(kind: StepKind, duration_s: f64) -> Vec<PaceSample> {
    let frame = LocalFrame::new(52.2297, 21.0122, 100.0);
    let mut noise = Noise(0x00c0_ffee_d00d_5eed);
    let (se, sn) = HEADING_RAD.sin_cos();
    let mut out = Vec::new();
    let mut next_event = 0.2;
    let mut t = 0.0;
    while t < duration_s {
        let d = SPEED_MPS * t;
        let (lat, lon) =
            frame.to_geodetic(d * se + 1.5 * noise.next(), d * sn + 1.5 * noise.next());
        out.push(PaceSample::Fix(GnssFix {
            t_s: t,
            lat_deg: lat,
            lon_deg: lon,
            alt_m: Some(100.0 + 0.5 * noise.next()),
            horizontal_accuracy_m: Some(4.0 + noise.next()),
            speed_mps: Some(SPEED_MPS + 0.1 * noise.next()),
            speed_accuracy_mps: Some(0.3),
        }));
        match kind {
            StepKind::Count => {
                let ts = t + 0.4;
                out.push(PaceSample::Steps(StepSample::Count {
                    t_s: ts,
                    steps: 12_000 + (ts * CADENCE_HZ) as u64,
                }));
            }
            StepKind::Event => {
                while next_event < t + 1.0 {
                    out.push(PaceSample::Steps(StepSample::Event { t_s: next_event }));
                    next_event += 1.0 / CADENCE_HZ + 0.01 * noise.next();
                }
            }
        }
        t += 1.0;
    }
    out
}

/// Tracker states right before consecutive samples that `want` selects, after a warm-up.
fn checkpoints(
    mode: PaceMode,
    kind: StepKind,
    want: impl Fn(&PaceSample) -> bool,
) -> Vec<(PaceTracker, PaceSample)> {
    let config = PaceConfig {
        mode,
        ..PaceConfig::default()
    };
    let mut tracker = PaceTracker::new(config).expect("valid config");
    // Long enough for the warm-up plus CHECKPOINTS samples of the sparser stream.
    let run = synthetic_run(kind, (WARM_UP_SAMPLES + 4 * CHECKPOINTS) as f64);
    let mut out = Vec::with_capacity(CHECKPOINTS);
    for (i, s) in run.iter().enumerate() {
        if i >= WARM_UP_SAMPLES && want(s) {
            out.push((tracker.clone(), *s));
            if out.len() == CHECKPOINTS {
                break;
            }
        }
        tracker.push(s).expect("synthetic sample accepted");
    }
    assert_eq!(out.len(), CHECKPOINTS, "synthetic run too short");
    out
}

fn modes() -> [(PaceMode, &'static str); 2] {
    [
        (PaceMode::Adaptive, "adaptive"),
        (PaceMode::AsPublished, "as_published"),
    ]
}

/// A setup closure cycling through the checkpoints.
fn cycling<T: Clone>(states: &[T]) -> impl FnMut() -> T + '_ {
    let mut i = 0;
    move || {
        i = (i + 1) % states.len();
        states[i].clone()
    }
}

fn bench_push_fix(c: &mut Criterion) {
    let mut group = c.benchmark_group("push_fix");
    for (mode, name) in modes() {
        let states = checkpoints(mode, StepKind::Count, |s| matches!(s, PaceSample::Fix(_)));
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                cycling(&states),
                |(tracker, sample)| {
                    let PaceSample::Fix(fix) = sample else {
                        unreachable!()
                    };
                    tracker.push_fix(black_box(fix))
                },
                BatchSize::NumIterations(BATCH),
            )
        });
    }
    group.finish();
}

fn bench_push_steps(c: &mut Criterion) {
    for (kind, group_name) in [
        (StepKind::Count, "push_steps_count"),
        (StepKind::Event, "push_steps_event"),
    ] {
        let mut group = c.benchmark_group(group_name);
        for (mode, name) in modes() {
            let states = checkpoints(mode, kind, |s| matches!(s, PaceSample::Steps(_)));
            group.bench_function(name, |b| {
                b.iter_batched_ref(
                    cycling(&states),
                    |(tracker, sample)| {
                        let PaceSample::Steps(steps) = sample else {
                            unreachable!()
                        };
                        tracker.push_steps(black_box(steps))
                    },
                    BatchSize::NumIterations(BATCH),
                )
            });
        }
        group.finish();
    }
}

fn bench_estimate(c: &mut Criterion) {
    let mut group = c.benchmark_group("estimate");
    for (mode, name) in modes() {
        // A tracker between a fix and the next step sample: estimate() reads only.
        let (tracker, _) = checkpoints(mode, StepKind::Event, |s| matches!(s, PaceSample::Fix(_)))
            .pop()
            .expect("a checkpoint");
        group.bench_function(name, |b| b.iter(|| black_box(&tracker).estimate()));
    }
    group.finish();
}

/// Samples pushed per timed call of the accelerometer benchmark.
const ACCEL_BLOCK: usize = 1_000;

/// Raw accelerometer input (the tracker's own step detector and, once GNSS has
/// calibrated it, the feature step length; `core/src/pace/accel.rs`): blocks of
/// [`ACCEL_BLOCK`] samples of a simulated 100 Hz walk with 1 Hz fixes, pushed into a
/// clone of the tracker as it was before the block, after 6 minutes of calibration;
/// the GNSS of the last minute is cut (an outage, where the feature step length is
/// used). Reported per block: divide by 1 000 for the cost per sample (fixes
/// included, one per 100 samples).
fn bench_push_accel(c: &mut Criterion) {
    use stridekit_sim::phone::{simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario};
    let sim = simulate_phone(&PhoneScenario {
        gnss_outages: vec![(360.0, 421.0)],
        ..PhoneScenario::walk(7, PhonePlacement::FrontPocket, 1.4, 420.0)
    });
    let events = sim.timeline(&LocalFrame::new(48.2, 16.4, 0.0));
    let mut tracker = PaceTracker::new(PaceConfig::default()).expect("valid config");
    let push = |t: &mut PaceTracker, e: &PhoneEvent<'_>| match e {
        PhoneEvent::Imu(s) => t.push_accel(s.t_s, s.accel_mps2).expect("valid sample"),
        PhoneEvent::Fix(f) => {
            t.push_fix(f).expect("valid fix");
        }
    };
    // Blocks from 5 minutes in (calibrated) to the end: half with GNSS, half without.
    let first = events
        .iter()
        .position(|e| matches!(e, PhoneEvent::Imu(s) if s.t_s >= 300.0))
        .expect("a long enough walk");
    for e in &events[..first] {
        push(&mut tracker, e);
    }
    let mut states = Vec::new();
    let mut i = first;
    while i + ACCEL_BLOCK <= events.len() && states.len() < CHECKPOINTS {
        states.push((tracker.clone(), i));
        for e in &events[i..i + ACCEL_BLOCK] {
            push(&mut tracker, e);
        }
        i += ACCEL_BLOCK;
    }
    let mut group = c.benchmark_group("push_accel_block_1000");
    group.bench_function("adaptive", |b| {
        b.iter_batched_ref(
            cycling(&states),
            |(t, start)| {
                for e in &events[*start..*start + ACCEL_BLOCK] {
                    push(t, black_box(e));
                }
            },
            BatchSize::NumIterations(4),
        )
    });
    group.finish();
}

criterion_group!(
    benches,
    bench_push_fix,
    bench_push_steps,
    bench_estimate,
    bench_push_accel
);
criterion_main!(benches);
