//! [`ImuMerger`]: the streaming merge of separate accelerometer, gyroscope and
//! magnetometer events into IMU samples (the rule is in the module docs of
//! [`crate::imu`]). Allocation-free per event; snapshot and restore in `snapshot.rs`.

use crate::ahrs::ImuSample;
use crate::input::{InputError, Stream, TimeGuard};
use crate::snapshot::SnapshotError;

use super::event::{ImuEvent, SensorKind};
use super::queue::{Queue, Timed};

/// How long an accelerometer event waits for the other streams, s of event time: a
/// sensor hub's FIFO burst delivered this late still merges exactly (200 ms bursts
/// are tested; Android's `maxReportLatencyUs` batches of one sensor after another).
pub const DEFAULT_MAX_DELAY_S: f64 = 0.5;
/// How far from its own time an event's value is held when it cannot be
/// interpolated, s (a few periods at 50–200 Hz: the Android-log reader's rule since
/// issue 13).
pub const DEFAULT_MAX_HOLD_S: f64 = 0.1;
/// Longest interval between two events interpolated across, s (twice the hold: a
/// longer interval is a gap in the stream, not a sample period).
pub const DEFAULT_MAX_SPAN_S: f64 = 0.2;
/// The highest event rate a queue is sized for, Hz (phone IMUs reach 400–500 Hz with
/// `HIGH_SAMPLING_RATE_SENSORS`).
pub const MAX_EVENT_RATE_HZ: f64 = 1_000.0;
/// Events kept beyond `max_delay_s` × [`MAX_EVENT_RATE_HZ`] per stream (the events
/// around the window's edges).
const QUEUE_SLACK: usize = 16;
/// Largest `max_delay_s` accepted, s (10 000 events per stream at 1 kHz).
const MAX_DELAY_LIMIT_S: f64 = 10.0;
/// Largest `max_hold_s` and `max_span_s` accepted, s.
const MAX_HOLD_LIMIT_S: f64 = 1.0;

/// The merge rule's tunables (defaults: the `DEFAULT_*` constants).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MergeConfig {
    /// How long (event time) an accelerometer event waits for the gyroscope and
    /// magnetometer events around it, s.
    pub max_delay_s: f64,
    /// How far from its event a value is held when not interpolated, s.
    pub max_hold_s: f64,
    /// Longest interval between two events that is interpolated across, s.
    pub max_span_s: f64,
}

impl Default for MergeConfig {
    fn default() -> Self {
        Self {
            max_delay_s: DEFAULT_MAX_DELAY_S,
            max_hold_s: DEFAULT_MAX_HOLD_S,
            max_span_s: DEFAULT_MAX_SPAN_S,
        }
    }
}

impl MergeConfig {
    /// Whether the settings are usable (the error names the setting).
    pub fn validate(&self) -> Result<(), MergeError> {
        let ok = |v: f64, max: f64| v.is_finite() && (0.0..=max).contains(&v);
        if !ok(self.max_delay_s, MAX_DELAY_LIMIT_S) {
            return Err(MergeError::Config("max_delay_s must be 0 to 10 s"));
        }
        if !ok(self.max_hold_s, MAX_HOLD_LIMIT_S) {
            return Err(MergeError::Config("max_hold_s must be 0 to 1 s"));
        }
        if !ok(self.max_span_s, MAX_HOLD_LIMIT_S) {
            return Err(MergeError::Config("max_span_s must be 0 to 1 s"));
        }
        Ok(())
    }

    /// Events kept per stream.
    pub(crate) fn capacity(&self) -> usize {
        // Bounded by validate(): at most 10 000 + slack.
        (self.max_delay_s * MAX_EVENT_RATE_HZ).ceil() as usize + QUEUE_SLACK
    }
}

/// Why the merger refused an event, a configuration or a snapshot.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MergeError {
    /// An event refused at the door (see [`crate::input`]); nothing changed.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A setting out of its range.
    #[error("invalid merge configuration: {0}")]
    Config(&'static str),
    /// A snapshot could not be restored.
    #[error("cannot restore merger snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

/// What the merger did so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MergeCounts {
    /// IMU samples released.
    pub samples: u64,
    /// Accelerometer events dropped: no gyroscope event within reach.
    pub without_gyro: u64,
    /// Events lost to a full queue (a stream more than `max_delay_s` behind at
    /// above [`MAX_EVENT_RATE_HZ`]); an accelerometer event released early counts too.
    pub overflow: u64,
    /// Released samples the engine behind the merger refused (an app that also
    /// pushed IMU samples directly, out of order with the events).
    pub refused: u64,
}

/// Stream indices of the time guards.
const ACCEL: usize = 0;
const GYRO: usize = 1;
const MAG: usize = 2;

/// Separate sensor events in, IMU samples out (see [`crate::imu`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ImuMerger {
    pub(super) config: MergeConfig,
    /// Accelerometer events waiting for the other streams.
    pub(super) accel: Queue,
    /// Gyroscope and magnetometer events still needed: the last one at or before
    /// the oldest time still to come, and every later one.
    pub(super) gyro: Queue,
    pub(super) mag: Queue,
    /// Per stream (accelerometer, gyroscope, magnetometer): time order and units.
    pub(super) times: [TimeGuard; 3],
    /// Time of the first event of any stream, s (NaN before any).
    pub(super) start_t_s: f64,
    pub(super) counts: MergeCounts,
}

impl Default for ImuMerger {
    /// An empty merger with the default rule but no queue memory: a placeholder
    /// (engines swap their merger out while it hands them samples). Use
    /// [`ImuMerger::new`].
    fn default() -> Self {
        Self::with_capacity(MergeConfig::default(), 0)
    }
}

impl ImuMerger {
    /// A merger with its queues allocated (the only allocation it makes).
    pub fn new(config: MergeConfig) -> Result<Self, MergeError> {
        config.validate()?;
        Ok(Self::with_capacity(config, config.capacity()))
    }

    pub(super) fn with_capacity(config: MergeConfig, capacity: usize) -> Self {
        Self {
            config,
            accel: Queue::with_capacity(capacity),
            gyro: Queue::with_capacity(capacity),
            mag: Queue::with_capacity(capacity),
            times: [
                TimeGuard::new(Stream::Accelerometer),
                TimeGuard::new(Stream::Gyroscope),
                TimeGuard::new(Stream::Magnetometer),
            ],
            start_t_s: f64::NAN,
            counts: MergeCounts::default(),
        }
    }

    pub fn config(&self) -> &MergeConfig {
        &self.config
    }

    pub fn counts(&self) -> MergeCounts {
        self.counts
    }

    /// Accelerometer events waiting for the other streams.
    pub fn pending(&self) -> usize {
        self.accel.len()
    }

    /// Count samples the engine behind the merger refused.
    pub fn count_refused(&mut self, n: u64) {
        self.counts.refused += n;
    }

    /// Whether `e` would be accepted; nothing changes.
    pub fn check(&self, e: &ImuEvent) -> Result<(), InputError> {
        e.check_values()?;
        self.times[index(e.kind)].check(e.t_s)?;
        Ok(())
    }

    /// One event; every sample it completes goes to `emit`, in time order. A
    /// refused event changes nothing.
    pub fn push(
        &mut self,
        e: &ImuEvent,
        mut emit: impl FnMut(ImuSample),
    ) -> Result<(), InputError> {
        self.check(e)?;
        self.times[index(e.kind)].accept(e.t_s);
        if self.start_t_s.is_nan() {
            self.start_t_s = e.t_s;
        }
        let event = (e.t_s, e.values);
        match e.kind {
            SensorKind::Accelerometer => {
                if self.accel.is_full() {
                    self.counts.overflow += 1;
                    self.release_oldest(&mut emit);
                }
                self.accel.push(event);
            }
            SensorKind::Gyroscope => self.keep(GYRO, event),
            SensorKind::Magnetometer => self.keep(MAG, event),
        }
        self.release(&mut emit, false);
        Ok(())
    }

    /// Release every waiting accelerometer event now, with what the other streams
    /// have (the end of a recording; a session that stops).
    pub fn flush(&mut self, mut emit: impl FnMut(ImuSample)) {
        self.release(&mut emit, true);
    }

    fn keep(&mut self, stream: usize, event: Timed) {
        let q = if stream == GYRO {
            &mut self.gyro
        } else {
            &mut self.mag
        };
        if q.push(event).is_some() {
            self.counts.overflow += 1;
        }
    }

    /// Release the waiting accelerometer events that are ready (all when `force`).
    fn release(&mut self, emit: &mut impl FnMut(ImuSample), force: bool) {
        while let Some((t, _)) = self.accel.front() {
            if !force && !self.ready(t) {
                break;
            }
            self.release_oldest(emit);
        }
    }

    fn release_oldest(&mut self, emit: &mut impl FnMut(ImuSample)) {
        let Some((t, accel)) = self.accel.pop_front() else {
            return;
        };
        match value_at(&self.gyro, t, &self.config) {
            Some(gyro_rads) => {
                self.counts.samples += 1;
                emit(ImuSample {
                    t_s: t,
                    gyro_rads,
                    accel_mps2: accel,
                    mag_ut: value_at(&self.mag, t, &self.config),
                });
            }
            None => self.counts.without_gyro += 1,
        }
        // Later accelerometer events are after `t`: older events are not needed.
        self.gyro.keep_from(t);
        self.mag.keep_from(t);
    }

    /// Whether a sample at `t` can go out: neither the gyroscope nor the
    /// magnetometer is still expected to report around it.
    fn ready(&self, t: f64) -> bool {
        !self.waits_for(GYRO, t) && !self.waits_for(MAG, t)
    }

    /// A stream is waited for at `t` while it has not reported at or after `t` and
    /// its last report (or the merger's start) is at most `max_delay_s` behind the
    /// newest event of any stream.
    fn waits_for(&self, stream: usize, t: f64) -> bool {
        let last = self.times[stream].last_t_s();
        if last.is_some_and(|l| l >= t) {
            return false;
        }
        let since = last.unwrap_or(self.start_t_s);
        self.newest_t_s() - since <= self.config.max_delay_s
    }

    /// The newest event time of any stream, s.
    fn newest_t_s(&self) -> f64 {
        self.times
            .iter()
            .filter_map(TimeGuard::last_t_s)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

fn index(kind: SensorKind) -> usize {
    match kind {
        SensorKind::Accelerometer => ACCEL,
        SensorKind::Gyroscope => GYRO,
        SensorKind::Magnetometer => MAG,
    }
}

/// A stream's value at `t`: its event at `t`; else linear interpolation between the
/// events around `t` at most `max_span_s` apart; else the nearer event held up to
/// `max_hold_s` from its time; else none.
fn value_at(q: &Queue, t: f64, c: &MergeConfig) -> Option<[f64; 3]> {
    let held = |e: Option<Timed>| e.filter(|(te, _)| (t - te).abs() <= c.max_hold_s);
    let Some(i) = q.last_at_or_before(t) else {
        return held(q.front()).map(|e| e.1);
    };
    let before = q.get(i)?;
    if before.0 == t {
        return Some(before.1);
    }
    match q.get(i + 1) {
        Some(after) if after.0 - before.0 <= c.max_span_s => Some(lerp(before, after, t)),
        Some(after) if after.0 - t < t - before.0 => held(Some(after)).map(|e| e.1),
        _ => held(Some(before)).map(|e| e.1),
    }
}

/// Linear interpolation at `t` between two events (`a.0 < t < b.0`).
fn lerp(a: Timed, b: Timed, t: f64) -> [f64; 3] {
    let k = (t - a.0) / (b.0 - a.0);
    [0, 1, 2].map(|i| a.1[i] + k * (b.1[i] - a.1[i]))
}
