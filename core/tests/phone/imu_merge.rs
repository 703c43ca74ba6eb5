//! The merge rule of separate sensor events (`stridekit_core::imu`): pairing,
//! late FIFO bursts, gaps, stopped streams, refusals and snapshots, on synthetic
//! streams (the real logs are in formats/tests/android_merge.rs).

use stridekit_core::ahrs::ImuSample;
use stridekit_core::imu::{ImuEvent, ImuMerger, MergeConfig, SensorKind};
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};

const A: SensorKind = SensorKind::Accelerometer;
const G: SensorKind = SensorKind::Gyroscope;
const M: SensorKind = SensorKind::Magnetometer;

/// A smooth signal per sensor, so interpolation can be checked against it.
fn signal(kind: SensorKind, t: f64) -> [f64; 3] {
    match kind {
        A => [0.5 * (3.0 * t).sin(), 0.2, 9.8 + (5.0 * t).cos()],
        G => [0.3 * (2.0 * t).sin(), 0.1 * t.cos(), 0.05],
        M => [20.0 + (t * 0.7).sin(), -5.0, -40.0],
    }
}

/// Events of one sensor: `rate_hz` from `offset_s` to `end_s`.
fn stream(kind: SensorKind, rate_hz: f64, offset_s: f64, end_s: f64) -> Vec<ImuEvent> {
    let n = ((end_s - offset_s) * rate_hz) as usize;
    (0..n)
        .map(|i| {
            let t_s = 100.0 + offset_s + i as f64 / rate_hz;
            ImuEvent {
                t_s,
                kind,
                values: signal(kind, t_s),
            }
        })
        .collect()
}

/// All events in time order (ties: accelerometer, gyroscope, magnetometer).
fn in_time_order(streams: &[Vec<ImuEvent>]) -> Vec<ImuEvent> {
    let mut all: Vec<ImuEvent> = streams.concat();
    all.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    all
}

fn merge(events: &[ImuEvent]) -> (Vec<ImuSample>, ImuMerger) {
    let mut m = ImuMerger::new(MergeConfig::default()).unwrap();
    let mut out = Vec::new();
    for e in events {
        m.push(e, |s| out.push(s)).unwrap();
    }
    m.flush(|s| out.push(s));
    (out, m)
}

fn walk() -> Vec<ImuEvent> {
    in_time_order(&[
        stream(A, 100.0, 0.0, 20.0),
        stream(G, 100.0, 0.003, 20.0),
        stream(M, 50.0, 0.007, 20.0),
    ])
}

#[test]
fn events_at_one_time_are_taken_as_they_are_and_others_interpolated() {
    let same = in_time_order(&[stream(A, 50.0, 0.0, 2.0), stream(G, 50.0, 0.0, 2.0)]);
    let (out, m) = merge(&same);
    assert_eq!(out.len(), 100);
    for s in &out {
        assert_eq!(s.gyro_rads, signal(G, s.t_s), "exact at the same time");
        assert!(s.mag_ut.is_none());
    }
    assert_eq!(m.counts().samples, 100);

    let (out, m) = merge(&walk());
    assert_eq!(out.len(), 2000);
    assert_eq!(m.counts().without_gyro, 0);
    for s in out.iter().skip(1).take(1990) {
        let g = signal(G, s.t_s);
        let mag = s.mag_ut.expect("a magnetometer");
        let true_mag = signal(M, s.t_s);
        for i in 0..3 {
            // Linear interpolation over 10 ms / 20 ms of smooth signals.
            assert!((s.gyro_rads[i] - g[i]).abs() < 1e-4, "{s:?}");
            assert!((mag[i] - true_mag[i]).abs() < 1e-3, "{s:?}");
        }
        assert_eq!(s.accel_mps2, signal(A, s.t_s));
    }
}

/// Each sensor's events delivered in bursts of `burst_s`, the gyroscope's and the
/// magnetometer's one burst late (a sensor hub flushing its FIFOs one after another).
fn fifo_bursts(events: &[ImuEvent], burst_s: f64) -> Vec<ImuEvent> {
    let t0 = events[0].t_s;
    let burst = |e: &ImuEvent| ((e.t_s - t0) / burst_s).floor() as i64;
    let lateness = |k: SensorKind| match k {
        A => 0,
        G => 1,
        M => 1,
    };
    let mut out = events.to_vec();
    out.sort_by_key(|e| (burst(e) + lateness(e.kind), lateness(e.kind)));
    out
}

/// Equal sample lists (the first difference when not: the lists are long).
fn same(a: &[ImuSample], b: &[ImuSample]) {
    assert_eq!(a.len(), b.len());
    if let Some((x, y)) = a.iter().zip(b).find(|(x, y)| x != y) {
        panic!("first difference: {x:?} against {y:?}");
    }
}

#[test]
fn late_fifo_bursts_merge_exactly_as_events_in_time_order() {
    let events = walk();
    let (reference, _) = merge(&events);
    let bursts = fifo_bursts(&events, 0.2);
    assert_ne!(bursts, events);
    let (late, m) = merge(&bursts);
    same(&late, &reference);
    assert_eq!(m.counts().overflow, 0);
    // The accelerometer's own burst arriving last works too.
    let mut reversed = events.clone();
    reversed.sort_by_key(|e| {
        (
            ((e.t_s - events[0].t_s) / 0.2).floor() as i64 + i64::from(e.kind == A),
            e.kind == A,
        )
    });
    same(&merge(&reversed).0, &reference);
}

#[test]
fn a_gap_is_not_interpolated_across_and_a_stopped_stream_is_held_then_missing() {
    // Gyroscope silent from 5 to 6 s, magnetometer stops at 10 s.
    let gyro: Vec<ImuEvent> = stream(G, 100.0, 0.003, 20.0)
        .into_iter()
        .filter(|e| !(105.0..106.0).contains(&e.t_s))
        .collect();
    let mag: Vec<ImuEvent> = stream(M, 50.0, 0.007, 10.0);
    let last_mag = mag.last().unwrap().t_s;
    let events = in_time_order(&[stream(A, 100.0, 0.0, 20.0), gyro, mag]);
    let (out, m) = merge(&events);
    // Accelerometer samples further than 0.1 s from any gyroscope event are dropped.
    let dropped = m.counts().without_gyro;
    let kept: Vec<f64> = out
        .iter()
        .map(|s| s.t_s)
        .filter(|t| (105.0..106.1).contains(t))
        .collect();
    assert_eq!(
        kept.len() as u64 + dropped,
        110,
        "dropped {dropped}, kept {kept:?}"
    );
    // Held 0.1 s after the gyroscope's last event (105.00–105.09) and from 106 s on;
    // the 81 samples further than 0.1 s from both sides are dropped, and so are those
    // released before the gyroscope resumed (it counted as stopped after 0.5 s);
    // the one the magnetometer kept waiting until then is held from the next event.
    assert!((81..=90).contains(&dropped), "dropped {dropped}");
    assert_eq!(kept.iter().filter(|&&t| t < 105.095).count(), 10);
    assert_eq!(kept.iter().filter(|&&t| t > 105.995).count(), 10);
    assert_eq!(out.len() as u64 + dropped, 2000);
    let held = out
        .iter()
        .find(|s| s.t_s > 105.0 && s.t_s < 105.1)
        .expect("held near the gap's start");
    let last_before = signal(G, 104.993);
    assert!(held
        .gyro_rads
        .iter()
        .zip(last_before)
        .all(|(a, b)| (a - b).abs() < 1e-12));
    // The magnetometer: held 0.1 s past its last event, then absent.
    for s in &out {
        assert_eq!(
            s.mag_ut.is_some(),
            s.t_s <= last_mag + 0.1 + 1e-9,
            "{}",
            s.t_s
        );
    }
}

#[test]
fn without_a_magnetometer_samples_flow_after_the_first_delay() {
    let events = in_time_order(&[stream(A, 100.0, 0.0, 5.0), stream(G, 100.0, 0.0, 5.0)]);
    let mut m = ImuMerger::new(MergeConfig::default()).unwrap();
    let mut out = 0;
    for e in &events {
        m.push(e, |_| out += 1).unwrap();
    }
    // Only the first half second waited for a magnetometer that never came: by the
    // end every sample is out without one.
    assert_eq!((out, m.pending()), (500, 0));
}

#[test]
fn a_refused_event_changes_nothing() {
    let events = walk();
    let mut m = ImuMerger::new(MergeConfig::default()).unwrap();
    for e in &events[..300] {
        m.push(e, |_| {}).unwrap();
    }
    let before = m.snapshot();
    let last = events[299];
    let bad = [
        ImuEvent { ..last },
        ImuEvent {
            t_s: last.t_s - 0.5,
            ..last
        },
        ImuEvent {
            values: [f64::NAN, 0.0, 0.0],
            t_s: last.t_s + 1.0,
            ..last
        },
        ImuEvent {
            values: [1e9, 0.0, 0.0],
            t_s: last.t_s + 1.0,
            ..last
        },
    ];
    for e in &bad {
        assert!(m.push(e, |_| panic!("nothing released")).is_err(), "{e:?}");
        assert_eq!(m.snapshot(), before);
    }
}

#[test]
fn a_snapshot_at_any_event_continues_bit_exactly() {
    let events = fifo_bursts(&walk()[..1500], 0.2);
    let (reference, _) = merge(&events);
    for split in (0..events.len()).step_by(97) {
        let mut m = ImuMerger::new(MergeConfig::default()).unwrap();
        let mut out = Vec::new();
        for e in &events[..split] {
            m.push(e, |s| out.push(s)).unwrap();
        }
        let mut m = ImuMerger::restore(&m.snapshot()).unwrap();
        for e in &events[split..] {
            m.push(e, |s| out.push(s)).unwrap();
        }
        m.flush(|s| out.push(s));
        same(&out, &reference);
    }
    let mut bytes = ImuMerger::new(MergeConfig::default()).unwrap().snapshot();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 1;
    assert!(ImuMerger::restore(&bytes).is_err());
}

#[test]
fn the_navigator_merges_events_as_the_merged_samples_pushed_directly() {
    let events = fifo_bursts(&walk(), 0.2);
    let (samples, _) = merge(&in_time_order(&[
        stream(A, 100.0, 0.0, 20.0),
        stream(G, 100.0, 0.003, 20.0),
        stream(M, 50.0, 0.007, 20.0),
    ]));
    let mut direct = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    for s in &samples {
        direct.push_imu(s).unwrap();
    }
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    for (i, e) in events.iter().enumerate() {
        nav.push_event(e).unwrap();
        if i == events.len() / 2 {
            // Split through a snapshot: the waiting events are in it.
            nav = PhoneNavigator::restore(&nav.snapshot()).unwrap();
        }
    }
    nav.flush_events();
    assert_eq!(nav.estimate(), direct.estimate());
    assert_eq!(nav.merge_counts().samples, samples.len() as u64);
    // An accelerometer in g is refused at the door, state unchanged.
    let before = nav.snapshot();
    let t = events.iter().map(|e| e.t_s).fold(0.0, f64::max);
    let mut refused = 0;
    for i in 1..200 {
        let e = ImuEvent {
            t_s: t + f64::from(i) * 0.01,
            kind: A,
            values: [0.0, 0.0, 1.0],
        };
        if nav.push_event(&e).is_err() {
            refused += 1;
        }
    }
    assert!(refused > 0, "g units never refused");
    assert_ne!(nav.snapshot(), before);
}
