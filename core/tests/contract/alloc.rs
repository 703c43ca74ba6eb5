//! The per-sample path of the pace engine must not touch the heap: pushing fixes and
//! step samples (valid or rejected) and reading estimates allocates nothing once the
//! tracker is built.
//!
//! A counting global allocator wraps `System`. Counting is switched on per thread
//! (a thread-local flag), so tests running in parallel threads do not disturb it.

use std::hint::black_box;
use stridekit_core::input::InputError;

use stridekit_core::pace::Stream;
use stridekit_core::{
    GnssFix, PaceConfig, PaceError, PaceMode, PaceSample, PaceTracker, StepSample,
};

use crate::common::allocations_in;

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

const LAT0: f64 = 52.2297;
const LON0: f64 = 21.0122;
const SPEED_MPS: f64 = 3.0;
const CADENCE_HZ: f64 = 2.9;

/// A fix of a straight run north-east at 3 m/s, with small noise.
fn fix_at(t_s: f64, noise: &mut Noise) -> GnssFix {
    let d = SPEED_MPS * t_s;
    let east = d * 0.6 + 1.5 * noise.next();
    let north = d * 0.8 + 1.5 * noise.next();
    // Small offsets: metres to degrees with local radii is plenty for a test.
    let lat = LAT0 + north / 111_320.0;
    let lon = LON0 + east / (111_320.0 * LAT0.to_radians().cos());
    GnssFix {
        t_s,
        lat_deg: lat,
        lon_deg: lon,
        alt_m: Some(100.0 + noise.next()),
        horizontal_accuracy_m: Some(4.0 + noise.next()),
        speed_mps: Some(SPEED_MPS + 0.1 * noise.next()),
        speed_accuracy_mps: Some(0.3),
    }
}

/// The kind of step data a device delivers (one kind per tracker, as on a real device).
#[derive(Clone, Copy, Debug)]
enum StepKind {
    /// Cumulative counts at 1 Hz.
    Count,
    /// One event per step, 2.9 Hz with jitter.
    Event,
    /// Cadence reports at 1 Hz.
    Cadence,
}

/// Fixes at 1 Hz and steps of one kind over `[t0, t1)`, each stream in time order.
fn stream(kind: StepKind, t0: f64, t1: f64, noise: &mut Noise) -> Vec<PaceSample> {
    let mut out = Vec::new();
    let mut t = t0;
    let mut next_event = t0 + 0.1;
    while t < t1 {
        out.push(PaceSample::Fix(fix_at(t, noise)));
        match kind {
            StepKind::Count => out.push(PaceSample::Steps(StepSample::Count {
                t_s: t + 0.25,
                steps: ((t + 0.25) * CADENCE_HZ) as u64 + 1000,
            })),
            StepKind::Event => {
                while next_event < t + 1.0 {
                    out.push(PaceSample::Steps(StepSample::Event { t_s: next_event }));
                    next_event += 1.0 / CADENCE_HZ + 0.01 * noise.next();
                }
            }
            StepKind::Cadence => out.push(PaceSample::Steps(StepSample::Cadence {
                t_s: t + 0.75,
                steps_per_min: 60.0 * CADENCE_HZ + 2.0 * noise.next(),
            })),
        }
        t += 1.0;
    }
    out
}

/// Tells whether an error is the expected one.
type IsExpected = fn(&PaceError) -> bool;

/// Invalid samples, each rejected with the error variant given; pushed after time `t`.
fn invalid_samples(t: f64) -> Vec<(PaceSample, IsExpected)> {
    let good = fix_at(t + 10.0, &mut Noise(7));
    vec![
        (
            PaceSample::Fix(GnssFix {
                t_s: f64::NAN,
                ..good
            }),
            |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
        ),
        (
            PaceSample::Fix(GnssFix {
                lat_deg: f64::NAN,
                ..good
            }),
            |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
        ),
        (
            PaceSample::Fix(GnssFix {
                lon_deg: f64::INFINITY,
                ..good
            }),
            |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
        ),
        (
            PaceSample::Fix(GnssFix {
                lat_deg: 91.0,
                ..good
            }),
            |e| matches!(e, PaceError::Input(InputError::OutOfRange { .. })),
        ),
        (
            PaceSample::Fix(GnssFix {
                horizontal_accuracy_m: Some(-1.0),
                ..good
            }),
            |e| matches!(e, PaceError::Input(InputError::OutOfRange { .. })),
        ),
        (
            PaceSample::Fix(GnssFix {
                speed_mps: Some(f64::NAN),
                ..good
            }),
            |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
        ),
        (
            // Time reversal.
            PaceSample::Fix(GnssFix {
                t_s: t - 5.0,
                ..good
            }),
            |e| {
                matches!(
                    e,
                    PaceError::Input(InputError::TimeNotIncreasing {
                        stream: Stream::Gnss,
                        ..
                    })
                )
            },
        ),
        (
            PaceSample::Steps(StepSample::Event { t_s: f64::NAN }),
            |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
        ),
        (
            PaceSample::Steps(StepSample::Count {
                t_s: t - 5.0,
                steps: 1,
            }),
            |e| {
                matches!(
                    e,
                    PaceError::Input(InputError::TimeNotIncreasing {
                        stream: Stream::Steps,
                        ..
                    })
                )
            },
        ),
        (
            PaceSample::Steps(StepSample::Cadence {
                t_s: t + 10.0,
                steps_per_min: f64::NAN,
            }),
            |e| matches!(e, PaceError::Input(InputError::NonFinite { .. })),
        ),
        (
            PaceSample::Steps(StepSample::Cadence {
                t_s: t + 10.0,
                steps_per_min: 1000.0,
            }),
            |e| matches!(e, PaceError::Input(InputError::OutOfRange { .. })),
        ),
    ]
}

fn check(mode: PaceMode, kind: StepKind) {
    let config = PaceConfig {
        mode,
        ..PaceConfig::default()
    };
    let mut tracker = PaceTracker::new(config).expect("default config is valid");
    let mut noise = Noise(0x5eed_0000_1234_abcd);

    // Warm-up: ~100 samples, allocations allowed (first fix anchors the frame, ...).
    let warm = stream(kind, 0.0, 40.0, &mut noise);
    assert!(warm.len() >= 80, "{}", warm.len());
    for s in &warm {
        tracker.push(s).expect("warm-up sample accepted");
    }

    // Thousands of samples of both streams.
    let mut samples = stream(kind, 40.0, 2000.0, &mut noise);
    if let StepKind::Count = kind {
        // A step-counter reset (reboot) in the middle: from there on, counts restart
        // near 0 and keep increasing.
        let mid = (samples.len() / 2..samples.len())
            .find(|&i| matches!(samples[i], PaceSample::Steps(StepSample::Count { .. })))
            .expect("a count sample");
        let PaceSample::Steps(StepSample::Count {
            steps: at_reset, ..
        }) = samples[mid]
        else {
            unreachable!()
        };
        let offset = at_reset - 3;
        for s in &mut samples[mid..] {
            if let PaceSample::Steps(StepSample::Count { steps, .. }) = s {
                *steps -= offset;
            }
        }
    }
    let n_fix = samples
        .iter()
        .filter(|s| matches!(s, PaceSample::Fix(_)))
        .count();
    assert!(n_fix >= 1900, "{n_fix} fixes");
    assert!(samples.len() >= 3900, "{} samples", samples.len());

    let last_t = samples.last().unwrap().t_s() + 2.0;
    let invalid = invalid_samples(last_t);
    let mut errors = Vec::with_capacity(invalid.len());

    let (allocs, (accepted, estimates_seen)) = allocations_in(|| {
        let mut accepted = 0usize;
        let mut estimates_seen = 0usize;
        for (i, s) in samples.iter().enumerate() {
            // Both entry points: the typed ones and the sample enum.
            let r = match (i % 3, s) {
                (0, PaceSample::Fix(f)) => tracker.push_fix(black_box(f)).map(Some),
                (0, PaceSample::Steps(st)) => tracker.push_steps(black_box(st)).map(|_| None),
                _ => tracker.push(black_box(s)),
            };
            if let Ok(e) = r {
                accepted += 1;
                estimates_seen += usize::from(e.is_some());
            }
            if i % 7 == 0 {
                black_box(tracker.estimate());
            }
        }
        for (s, _) in &invalid {
            // The error is built (and kept, then dropped later) inside the counted region.
            errors.push(tracker.push(black_box(s)).err());
            black_box(tracker.estimate());
        }
        (accepted, estimates_seen)
    });

    assert_eq!(
        allocs, 0,
        "{mode:?}/{kind:?}: {allocs} heap allocations on the sample path"
    );
    assert_eq!(
        accepted,
        samples.len(),
        "{mode:?}/{kind:?}: valid samples rejected"
    );
    assert_eq!(estimates_seen, n_fix);
    if let StepKind::Count = kind {
        assert_eq!(tracker.step_counter_resets(), 1);
    }
    for ((s, expected), got) in invalid.iter().zip(&errors) {
        let e = got
            .as_ref()
            .unwrap_or_else(|| panic!("{mode:?}/{kind:?}: {s:?} was accepted"));
        assert!(expected(e), "{mode:?}/{kind:?}: {s:?} gave {e:?}");
    }
}

fn check_mode(mode: PaceMode) {
    for kind in [StepKind::Count, StepKind::Event, StepKind::Cadence] {
        check(mode, kind);
    }
}

#[test]
fn adaptive_sample_path_does_not_allocate() {
    check_mode(PaceMode::Adaptive);
}

#[test]
fn as_published_sample_path_does_not_allocate() {
    check_mode(PaceMode::AsPublished);
}

#[test]
fn counting_allocator_sees_allocations() {
    // The harness itself works: a Vec on this thread is counted.
    let (n, v) = allocations_in(|| black_box(Vec::<u8>::with_capacity(16)));
    assert_eq!(n, 1);
    drop(v);
    assert!(crate::common::total_allocations() >= 1);
}

/// Raw accelerometer input (the tracker's own detector and feature step length) and
/// fixes, calibrated and then through an outage: no allocation per sample once the
/// tracker has seen its first accelerometer sample.
#[test]
fn accelerometer_path_does_not_allocate() {
    use stridekit_core::geo::LocalFrame;
    use stridekit_sim::phone::{simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario};
    let sim = simulate_phone(&PhoneScenario {
        gnss_outages: vec![(400.0, 500.0)],
        ..PhoneScenario::walk(11, PhonePlacement::InHand, 1.4, 500.0)
    });
    let events = sim.timeline(&LocalFrame::new(LAT0, LON0, 0.0));
    let mut tracker = PaceTracker::new(PaceConfig::default()).unwrap();
    // The first sample builds the accelerometer input (detector and model).
    let split = events
        .iter()
        .position(|e| matches!(e, PhoneEvent::Imu(_)))
        .unwrap()
        + 1;
    for e in &events[..split] {
        match e {
            PhoneEvent::Imu(s) => tracker.push_accel(s.t_s, s.accel_mps2).unwrap(),
            PhoneEvent::Fix(f) => {
                tracker.push_fix(f).unwrap();
            }
        }
    }
    let (allocs, pushed) = allocations_in(|| {
        let mut pushed = 0usize;
        for e in &events[split..] {
            match e {
                PhoneEvent::Imu(s) => tracker.push_accel(s.t_s, s.accel_mps2).unwrap(),
                PhoneEvent::Fix(f) => {
                    black_box(tracker.push_fix(f).unwrap());
                }
            }
            black_box(tracker.estimate());
            pushed += 1;
        }
        pushed
    });
    assert!(pushed > 50_000, "{pushed}");
    let cal = tracker.accel_step_length_calibration().unwrap();
    assert!(cal.fits >= 10, "the feature model was calibrated: {cal:?}");
    assert_eq!(allocs, 0, "{allocs} allocations over {pushed} samples");
}
