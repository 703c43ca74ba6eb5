//! Snapshot and restore of the [`ImuMerger`]: its rule, the time state of each
//! stream, the events it still holds and its counts, versioned and checksummed.
//! `snapshot` destructures the merger, so a field that is not written is a compile error.

use crate::input::{Stream, TimeGuard};
use crate::snapshot::{Reader, SnapshotError, Writer};

use super::event::{ImuEvent, SensorKind};
use super::merge::{ImuMerger, MergeConfig, MergeCounts, MergeError};
use super::queue::Queue;

const SNAPSHOT_KIND: u8 = 10;
const SNAPSHOT_VERSION: u16 = 1;

impl ImuMerger {
    /// The whole state as bytes.
    pub fn snapshot(&self) -> Vec<u8> {
        let ImuMerger {
            config,
            accel,
            gyro,
            mag,
            times,
            start_t_s,
            counts,
        } = self;
        let MergeConfig {
            max_delay_s,
            max_hold_s,
            max_span_s,
        } = config;
        let MergeCounts {
            samples,
            without_gyro,
            overflow,
            refused,
        } = counts;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.f64s(&[*max_delay_s, *max_hold_s, *max_span_s, *start_t_s]);
        for t in times {
            t.write(&mut w);
        }
        for q in [accel, gyro, mag] {
            w.u64(q.len() as u64);
            for (t, v) in q.iter() {
                w.f64s(&[t, v[0], v[1], v[2]]);
            }
        }
        for n in [samples, without_gyro, overflow, refused] {
            w.u64(*n);
        }
        w.finish()
    }

    /// A merger continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, MergeError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let config = MergeConfig {
            max_delay_s: r.f64()?,
            max_hold_s: r.f64()?,
            max_span_s: r.f64()?,
        };
        config
            .validate()
            .map_err(|_| SnapshotError::Invalid("merge configuration"))?;
        // NaN before the first event.
        let start_t_s = r.f64_or_nan()?;
        let times = [
            TimeGuard::read(&mut r, Stream::Accelerometer)?,
            TimeGuard::read(&mut r, Stream::Gyroscope)?,
            TimeGuard::read(&mut r, Stream::Magnetometer)?,
        ];
        let capacity = config.capacity();
        let kinds = [
            SensorKind::Accelerometer,
            SensorKind::Gyroscope,
            SensorKind::Magnetometer,
        ];
        let mut queues = Vec::with_capacity(kinds.len());
        for (kind, guard) in kinds.into_iter().zip(&times) {
            queues.push(read_queue(&mut r, kind, guard, capacity)?);
        }
        let mut n = [0u64; 4];
        for v in &mut n {
            *v = r.u64()?;
        }
        r.end()?;
        let started = times.iter().any(|t| t.last_t_s().is_some());
        if started == start_t_s.is_nan() {
            return Err(SnapshotError::Invalid("merger start time").into());
        }
        let mut queues = queues.into_iter();
        let mut next = || queues.next().expect("three queues were read");
        Ok(Self {
            config,
            accel: next(),
            gyro: next(),
            mag: next(),
            times,
            start_t_s,
            counts: MergeCounts {
                samples: n[0],
                without_gyro: n[1],
                overflow: n[2],
                refused: n[3],
            },
        })
    }
}

/// One stream's queue: at most `capacity` events in strictly increasing time, none
/// after the stream's last accepted event, each within the input limits.
fn read_queue(
    r: &mut Reader,
    kind: SensorKind,
    guard: &TimeGuard,
    capacity: usize,
) -> Result<Queue, SnapshotError> {
    let mut q = Queue::with_capacity(capacity);
    let mut last = f64::NEG_INFINITY;
    for _ in 0..r.len(capacity)? {
        let mut v = [0.0; 4];
        r.f64s(&mut v)?;
        let e = ImuEvent {
            t_s: v[0],
            kind,
            values: [v[1], v[2], v[3]],
        };
        let in_time = e.t_s > last && guard.last_t_s().is_some_and(|l| e.t_s <= l);
        if !in_time || e.check_values().is_err() {
            return Err(SnapshotError::Invalid("merger event"));
        }
        last = e.t_s;
        q.push((e.t_s, e.values));
    }
    Ok(q)
}
