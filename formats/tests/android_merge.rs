//! The one merge rule (`stridekit_core::imu`) on real Android logs of
//! `phone-indoor/`: the events as recorded, delivered in late 200 ms FIFO bursts,
//! with timestamp jitter and with dropped events; the merged samples and the phone
//! navigator's walk through them. Without `../shared/data` (or `STRIDEKIT_DATA`) the
//! test prints a skip message and passes.

use std::io::Read;
use std::path::PathBuf;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::imu::{ImuEvent, ImuMerger, MergeConfig, SensorKind};
use stridekit_core::pdr::{NavEstimate, NavigatorConfig, PhoneNavigator};
use stridekit_formats::{android_motion_events, data_dir, list_android_logs, parse_android_log};

/// Logs used: the first of each floor (sorted paths), a few thousand events each.
fn logs() -> Option<Vec<PathBuf>> {
    let Some(dir) = data_dir().map(|d| d.join("phone-indoor")) else {
        eprintln!("skipping: ../shared/data not found (set STRIDEKIT_DATA)");
        return None;
    };
    if !dir.is_dir() {
        eprintln!("skipping: {} not found", dir.display());
        return None;
    }
    let all = list_android_logs(&dir).unwrap();
    let mut out: Vec<PathBuf> = Vec::new();
    for p in all {
        if !out.iter().any(|q| q.parent() == p.parent()) {
            out.push(p);
        }
    }
    Some(out)
}

fn text(path: &PathBuf) -> String {
    let mut s = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap())
        .read_to_string(&mut s)
        .unwrap();
    s
}

fn merge(events: &[ImuEvent]) -> (Vec<ImuSample>, u64) {
    let mut m = ImuMerger::new(MergeConfig::default()).unwrap();
    let mut out = Vec::new();
    let mut refused = 0;
    for e in events {
        if m.push(e, |s| out.push(s)).is_err() {
            refused += 1;
        }
    }
    m.flush(|s| out.push(s));
    (out, refused)
}

/// The reader's samples as the engines' samples.
fn reader_samples(text: &str) -> Vec<ImuSample> {
    parse_android_log("x", text)
        .unwrap()
        .samples
        .iter()
        .map(|s| ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: s.mag_ut,
        })
        .collect()
}

fn walk(samples: &[ImuSample]) -> NavEstimate {
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    for s in samples {
        nav.push_imu(s).unwrap();
    }
    nav.estimate().unwrap()
}

/// A small deterministic generator (no dependency): uniform in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Each sensor's events in bursts of 200 ms; the gyroscope's and the magnetometer's
/// (or, `accel_late`, the accelerometer's) delivered one burst late.
fn fifo_bursts(events: &[ImuEvent], accel_late: bool) -> Vec<ImuEvent> {
    let t0 = events[0].t_s;
    let mut out = events.to_vec();
    out.sort_by_key(|e| {
        let late = (e.kind == SensorKind::Accelerometer) == accel_late;
        (((e.t_s - t0) / 0.2).floor() as i64 + i64::from(late), late)
    });
    out
}

#[test]
fn real_logs_merge_the_same_as_recorded_and_in_late_fifo_bursts() {
    let Some(logs) = logs() else { return };
    assert!(logs.len() >= 4, "{} floors", logs.len());
    for path in &logs {
        let text = text(path);
        let events = android_motion_events(&text);
        let reference = reader_samples(&text);
        let accel = events
            .iter()
            .filter(|e| e.kind == SensorKind::Accelerometer)
            .count();
        // As recorded: the reader's samples, one per accelerometer event.
        let (as_recorded, refused) = merge(&events);
        assert_eq!(as_recorded, reference, "{}", path.display());
        assert_eq!((refused, reference.len()), (0, accel), "{}", path.display());
        // Late FIFO bursts: exactly the same samples.
        for accel_late in [false, true] {
            let (late, refused) = merge(&fifo_bursts(&events, accel_late));
            assert_eq!(refused, 0);
            assert!(
                late == reference,
                "{}: bursts changed the samples",
                path.display()
            );
        }
    }
}

#[test]
fn real_logs_with_jitter_or_dropped_events_walk_nearly_the_same() {
    let Some(logs) = logs() else { return };
    let mut rng = Lcg(7);
    for path in &logs {
        let text = text(path);
        let events = android_motion_events(&text);
        let reference = walk(&reader_samples(&text));
        // Jitter: ±2 ms on every timestamp (each stream stays in its order: the
        // recording's 20 ms period is far larger).
        let jittered: Vec<ImuEvent> = events
            .iter()
            .map(|e| ImuEvent {
                t_s: e.t_s + (rng.next() - 0.5) * 0.004,
                ..*e
            })
            .collect();
        // Dropped: 10 % of the gyroscope and magnetometer events (what the merge
        // rule bridges), or 2 % of the accelerometer's (samples missing: the step
        // detector sees a sparser stream; looser bounds).
        let mut drop = |kind_dropped: fn(SensorKind) -> bool, p: f64| -> Vec<ImuEvent> {
            events
                .iter()
                .filter(|e| !kind_dropped(e.kind) || rng.next() >= p)
                .copied()
                .collect()
        };
        let no_gyro_mag = drop(|k| k != SensorKind::Accelerometer, 0.10);
        let no_accel = drop(|k| k == SensorKind::Accelerometer, 0.02);
        for (what, variant, tolerance) in [
            ("jitter ±2 ms", jittered, 1.0),
            (
                "10 % of gyroscope and magnetometer events dropped",
                no_gyro_mag,
                1.0,
            ),
            ("2 % of accelerometer events dropped", no_accel, 2.0),
        ] {
            let (samples, refused) = merge(&variant);
            assert_eq!(refused, 0, "{what}");
            let e = walk(&samples);
            let end = (e.east_m - reference.east_m).hypot(e.north_m - reference.north_m);
            let distance = (e.distance_m / reference.distance_m - 1.0).abs();
            eprintln!(
                "{}: {what}: steps {} / {}, distance {:+.2} %, end {:.2} m apart",
                path.file_name().unwrap().to_string_lossy(),
                e.steps,
                reference.steps,
                100.0 * (e.distance_m / reference.distance_m - 1.0),
                end
            );
            let steps = e.steps.abs_diff(reference.steps) as f64;
            assert!(
                steps <= tolerance * (2.0 + 0.01 * reference.steps as f64),
                "{what}: steps"
            );
            assert!(distance < tolerance * 0.03, "{what}: distance {distance}");
            assert!(
                end < tolerance * (0.05 * reference.distance_m + 0.5),
                "{what}: end {end} m"
            );
        }
    }
}

#[test]
fn the_navigator_fed_a_logs_events_walks_as_the_reader_and_the_cli() {
    let Some(logs) = logs() else { return };
    for path in &logs {
        let text = text(path);
        let mut direct = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
        for s in reader_samples(&text) {
            direct.push_imu(&s).unwrap();
        }
        let mut events = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
        for e in android_motion_events(&text) {
            events.push_event(&e).unwrap();
        }
        events.flush_events();
        assert_eq!(events.estimate(), direct.estimate(), "{}", path.display());
        assert_eq!(events.recent_steps().1, direct.recent_steps().1);
    }
}
