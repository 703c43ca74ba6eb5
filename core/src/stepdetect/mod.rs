//! Step detection on the acceleration magnitude of a phone carried anywhere (method 3 of
//! docs/architecture.md).
//!
//! [`StepDetector`] is the state machine apps feed with accelerometer samples
//! (`t_s`, acceleration in m/s², gravity included, any phone orientation). It checks
//! every sample at the door and runs one of two detectors chosen by [`DetectorMode`]:
//! - [`DetectorMode::AsPublished`]: the paper's windowed-variance detector
//!   (`published`), w = 15 samples, thresholds T1/T2, a 0.2–2 s rate gate;
//! - [`DetectorMode::Default`]: a detector that works in time at any rate, confirms
//!   walking/running bouts by their regularity and ignores shaking, vehicles and
//!   cycling (`robust`).
//!
//! A confirmed bout can release several buffered steps at once. They wait in a small
//! queue (no heap): [`StepDetector::push`] returns the oldest waiting step and
//! [`StepDetector::pop_step`] drains the rest.
//!
//! When a step is released (every [`StepEvent::t_s`] is the step's own time, on the
//! input's clock): inside a walk, about 0.15 s after it; the first steps of a walk, when
//! the bout is confirmed (a few steps later, 2–3 s); the gentle last step of a walk
//! (default detector), once no step has followed it for 1.2 step periods (about 0.7 s);
//! a step sooner than the cadence (default detector: perhaps a secondary bump), with the
//! next step or 1.2 step periods after it; a few steps before a stop, when the walk
//! after the stop is confirmed.
//!
//! Units at the door: the checks and limits of [`crate::input`] (finite, per axis
//! ≤ 2 000 m/s², time after the previous sample and in seconds, the g-units check
//! [`crate::input::AccelUnits`]).
//! A rejected sample leaves the state exactly as it was.

mod error;
mod event;
mod gait;
mod published;
mod robust;

pub use error::StepDetectError;
pub use event::{StepEvent, StepOrigin};
pub use published::PublishedStepParams;
pub use robust::RobustStepParams;

use crate::batch::{self, Batch};
use crate::input::{self, AccelUnits, Stream, TimeGuard};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Snapshot engine kind byte for the step detector.
const SNAPSHOT_KIND: u8 = 3;
/// Snapshot format version written by this build.
/// Version 12: each stored step event keeps its origin (detected or filled, [`StepOrigin`]).
/// Version 11: the default detector's steps held off the cadence. Version 10: each buffered candidate keeps the input time gaps hid before it, and
/// the autocorrelation's samples may be NaN (bridged across a gap). Version 9: the default detector's held last step of a bout. Version 8: the input
/// time the gaps hid since the last candidate, and the length of the latest gap. Version 7: the default detector's previous in-bout interval
/// (the period follows pairs of steps). Version 6: how the phone is held (the default detector's low-passed acceleration,
/// and its direction at each buffered candidate). Version 5: the default detector's
/// short walk before a stop. Version 4: the time
/// state of the input layer ([`TimeGuard`]) replaces the last time (version 3 added
/// the autocorrelation state of the default detector).
const SNAPSHOT_VERSION: u16 = 12;
/// Steps waiting to be popped.
const QUEUE: usize = 32;

/// Which detector runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DetectorMode {
    /// The paper's detector, faithfully (see `published`).
    AsPublished,
    /// The robust detector (see `robust`).
    #[default]
    Default,
}

/// Configuration of a [`StepDetector`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepDetectorConfig {
    pub mode: DetectorMode,
    pub published: PublishedStepParams,
    pub robust: RobustStepParams,
}

impl StepDetectorConfig {
    /// The paper's detector with its documented parameters.
    pub fn as_published() -> Self {
        Self {
            mode: DetectorMode::AsPublished,
            ..Self::default()
        }
    }

    pub fn validate(&self) -> Result<(), StepDetectError> {
        self.published
            .validate()
            .and_then(|_| self.robust.validate())
            .map_err(|reason| StepDetectError::InvalidConfig { reason })
    }
}

/// One accelerometer sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AccelSample {
    /// Time, seconds (monotonic clock).
    pub t_s: f64,
    /// Acceleration including gravity, m/s², any axes.
    pub accel_mps2: [f64; 3],
}

/// The accelerometer part of an IMU sample.
impl From<&crate::ahrs::ImuSample> for AccelSample {
    fn from(s: &crate::ahrs::ImuSample) -> Self {
        Self {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
        }
    }
}

/// A sample a batch push rejected, with its index in the batch.
pub type StepRejection = crate::batch::Rejected<StepDetectError>;

/// Where an engine releases its steps: the detector's queue and count.
pub(crate) struct Sink<'a> {
    queue: &'a mut Ring<StepEvent, QUEUE>,
    released: &'a mut u64,
}

impl Sink<'_> {
    pub(crate) fn push(&mut self, e: StepEvent) {
        *self.released = self.released.saturating_add(1);
        self.queue.push(e);
    }
}

/// Running moments of the magnitude over one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Moments {
    n: f64,
    sum: f64,
    sum_sq: f64,
    max: f64,
    min: f64,
}

impl Moments {
    pub(crate) const EMPTY: Moments = Moments {
        n: 0.0,
        sum: 0.0,
        sum_sq: 0.0,
        max: f64::NEG_INFINITY,
        min: f64::INFINITY,
    };

    pub(crate) fn add(&mut self, v: f64) {
        self.n += 1.0;
        self.sum += v;
        self.sum_sq += v * v;
        self.max = self.max.max(v);
        self.min = self.min.min(v);
    }

    pub(crate) fn event(&self, t_s: f64, duration_s: f64) -> StepEvent {
        let (var, max, min) = if self.n > 0.0 {
            let mean = self.sum / self.n;
            (
                (self.sum_sq / self.n - mean * mean).max(0.0),
                self.max,
                self.min,
            )
        } else {
            (f64::NAN, f64::NAN, f64::NAN)
        };
        StepEvent {
            t_s,
            duration_s,
            accel_variance_m2ps4: var,
            accel_max_mps2: max,
            accel_min_mps2: min,
            vertical_displacement_m: f64::NAN,
            origin: StepOrigin::Detected,
        }
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        let Moments {
            n,
            sum,
            sum_sq,
            max,
            min,
        } = *self;
        w.f64s(&[n, sum, sum_sq, max, min]);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        const A: f64 = crate::input::limits::MAX_ACCEL_NORM_MPS2;
        let mut v = [0.0; 3];
        r.f64s(&mut v)?;
        let [n, sum, sum_sq] = v;
        // max/min are ∓∞ while empty; otherwise magnitudes within the door's limit.
        let (max, min) = (r.f64_any()?, r.f64_any()?);
        let in_range = |x: f64| (0.0..=A).contains(&x);
        let ok = if n == 0.0 {
            max == f64::NEG_INFINITY && min == f64::INFINITY
        } else {
            in_range(max)
                && in_range(min)
                && (0.0..=n * A).contains(&sum)
                && (0.0..=n * A * A).contains(&sum_sq)
        };
        if n < 0.0 || !ok {
            return Err(SnapshotError::Invalid("step statistics"));
        }
        Ok(Self {
            n,
            sum,
            sum_sq,
            max,
            min,
        })
    }
}

pub(crate) use crate::signal::ema_gain;

pub(crate) fn write_event(w: &mut Writer, e: &StepEvent) {
    let StepEvent {
        t_s,
        duration_s,
        accel_variance_m2ps4,
        accel_max_mps2,
        accel_min_mps2,
        // The detector's own events never know it (NaN): not kept.
        vertical_displacement_m: _,
        origin,
    } = *e;
    w.f64s(&[
        t_s,
        duration_s,
        accel_variance_m2ps4,
        accel_max_mps2,
        accel_min_mps2,
    ]);
    origin.write(w);
}

pub(crate) fn read_event(r: &mut Reader) -> Result<StepEvent, SnapshotError> {
    // The time is always set; the duration is NaN for the first step of a bout and
    // the statistics for a step without samples (a filled-in step).
    const A: f64 = crate::input::limits::MAX_ACCEL_NORM_MPS2;
    /// Longest step duration a snapshot may hold, s.
    const MAX_DURATION_S: f64 = 3600.0;
    let t_s = r.f64()?;
    let duration_s = r.f64_or_nan()?;
    let accel_variance_m2ps4 = r.f64_or_nan()?;
    let accel_max_mps2 = r.f64_or_nan()?;
    let accel_min_mps2 = r.f64_or_nan()?;
    let origin = StepOrigin::read(r)?;
    let ok = |x: f64, hi: f64| x.is_nan() || (0.0..=hi).contains(&x);
    if !(ok(duration_s, MAX_DURATION_S)
        && ok(accel_variance_m2ps4, A * A)
        && ok(accel_max_mps2, A)
        && ok(accel_min_mps2, A))
    {
        return Err(SnapshotError::Invalid("step event"));
    }
    Ok(StepEvent {
        t_s,
        duration_s,
        accel_variance_m2ps4,
        accel_max_mps2,
        accel_min_mps2,
        vertical_displacement_m: f64::NAN,
        origin,
    })
}

/// The detector behind a [`StepDetector`]. Both variants live inline (no heap), so the
/// size difference is accepted: a detector is created once per session.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
enum Engine {
    Published(published::PublishedDetector),
    Robust(robust::RobustDetector),
}

/// Streaming step detector. Feed accelerometer samples in time order; read steps as
/// they are released.
#[derive(Clone, Debug, PartialEq)]
pub struct StepDetector {
    config: StepDetectorConfig,
    engine: Engine,
    time: TimeGuard,
    /// The g-units check.
    units: AccelUnits,
    queue: Ring<StepEvent, QUEUE>,
    step_count: u64,
}

impl Default for StepDetector {
    /// The default detector ([`StepDetectorConfig::default`]).
    fn default() -> Self {
        Self::new(StepDetectorConfig::default()).expect("the default configuration is valid")
    }
}

impl StepDetector {
    /// A detector with a validated configuration.
    pub fn new(config: StepDetectorConfig) -> Result<Self, StepDetectError> {
        config.validate()?;
        Ok(Self {
            engine: Self::make_engine(&config),
            config,
            time: TimeGuard::new(Stream::Accelerometer),
            units: AccelUnits::new(),
            queue: Ring::new(),
            step_count: 0,
        })
    }

    fn make_engine(c: &StepDetectorConfig) -> Engine {
        match c.mode {
            DetectorMode::AsPublished => {
                Engine::Published(published::PublishedDetector::new(c.published))
            }
            DetectorMode::Default => Engine::Robust(robust::RobustDetector::new(c.robust)),
        }
    }

    pub fn config(&self) -> &StepDetectorConfig {
        &self.config
    }

    /// Steps released so far (including those still waiting in the queue).
    pub fn step_count(&self) -> u64 {
        self.step_count
    }

    /// Time of the newest accepted sample, seconds.
    pub fn last_t_s(&self) -> Option<f64> {
        self.time.last_t_s()
    }

    /// Checks a sample without changing state; returns its magnitude and the updated
    /// units mean.
    /// Whether [`push`](Self::push) would accept this sample, without changing
    /// anything (callers that update several engines per sample check first).
    pub fn check_sample(&self, t_s: f64, accel_mps2: [f64; 3]) -> Result<(), StepDetectError> {
        self.check(t_s, accel_mps2).map(|_| ())
    }

    fn check(&self, t_s: f64, a: [f64; 3]) -> Result<(f64, f64), StepDetectError> {
        let dt = self.time.check(t_s)?;
        input::accel(&a)?;
        let mag = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let mean = self.units.check(dt, mag)?;
        Ok((mag, mean))
    }

    fn release(&mut self, e: StepEvent) {
        self.step_count = self.step_count.saturating_add(1);
        self.queue.push(e);
    }

    /// Push one sample. Returns the oldest released step waiting in the queue, if any;
    /// when a bout is confirmed several steps are released at once: call
    /// [`pop_step`](Self::pop_step) until `None` to drain them (or they come out with
    /// the next pushes). The queue holds 32 steps; older ones are dropped beyond that
    /// (they stay counted in [`step_count`](Self::step_count)).
    pub fn push(&mut self, s: &AccelSample) -> Result<Option<StepEvent>, StepDetectError> {
        self.push_accel(s.t_s, s.accel_mps2)
    }

    /// [`push`](Self::push) with the time and the acceleration as plain values.
    pub fn push_accel(
        &mut self,
        t_s: f64,
        accel_mps2: [f64; 3],
    ) -> Result<Option<StepEvent>, StepDetectError> {
        let (mag, mean) = self.check(t_s, accel_mps2)?;
        self.time.accept(t_s);
        self.units.accept(mean);
        match &mut self.engine {
            Engine::Published(d) => {
                if let Some(e) = d.push(t_s, mag) {
                    self.release(e);
                }
            }
            Engine::Robust(d) => {
                let mut sink = Sink {
                    queue: &mut self.queue,
                    released: &mut self.step_count,
                };
                d.push(t_s, accel_mps2, mag, &mut sink);
            }
        }
        Ok(self.queue.pop_front())
    }

    /// The oldest released step not yet returned.
    pub fn pop_step(&mut self) -> Option<StepEvent> {
        self.queue.pop_front()
    }

    /// Push many samples in order. Invalid samples are skipped and reported; the others
    /// are processed as if pushed one by one. The estimates are all released steps, in
    /// time order (the queue is drained after every sample, so none is left waiting).
    pub fn push_batch(&mut self, samples: &[AccelSample]) -> Batch<StepEvent, StepDetectError> {
        let mut b = Batch::default();
        b.accepted = batch::each_released(
            samples,
            |e| b.estimates.push(e),
            |r| b.rejected.push(r),
            |s, emit| {
                let first = self.push(s);
                if let Ok(Some(e)) = first {
                    emit(e);
                }
                while let Some(e) = self.pop_step() {
                    emit(e);
                }
                first.map(|_| ())
            },
        );
        b
    }

    /// The whole state as bytes (versioned, checksummed).
    pub fn snapshot(&self) -> Vec<u8> {
        // Exhaustive on purpose (and so are the nested writers): a new field that is
        // not written is a compile error.
        let StepDetector {
            config:
                StepDetectorConfig {
                    mode,
                    published,
                    robust,
                },
            engine,
            time,
            units,
            queue,
            step_count,
        } = self;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.u8(match mode {
            DetectorMode::AsPublished => 0,
            DetectorMode::Default => 1,
        });
        published.write(&mut w);
        robust.write(&mut w);
        time.write(&mut w);
        units.write(&mut w);
        w.u64(queue.len() as u64);
        for e in queue.iter() {
            write_event(&mut w, &e);
        }
        w.u64(*step_count);
        match engine {
            Engine::Published(d) => d.write(&mut w),
            Engine::Robust(d) => d.write(&mut w),
        }
        w.finish()
    }

    /// A detector continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, StepDetectError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let mode = match r.u8()? {
            0 => DetectorMode::AsPublished,
            1 => DetectorMode::Default,
            _ => return Err(SnapshotError::Invalid("mode").into()),
        };
        let config = StepDetectorConfig {
            mode,
            published: PublishedStepParams::read(&mut r)?,
            robust: RobustStepParams::read(&mut r)?,
        };
        config
            .validate()
            .map_err(|_| SnapshotError::Invalid("configuration"))?;
        let time = TimeGuard::read(&mut r, Stream::Accelerometer)?;
        let units = AccelUnits::read(&mut r)?;
        let mut queue = Ring::new();
        let n = r.len(QUEUE)?;
        for _ in 0..n {
            queue.push(read_event(&mut r)?);
        }
        let step_count = r.u64()?;
        let engine = match mode {
            DetectorMode::AsPublished => Engine::Published(published::PublishedDetector::read(
                &mut r,
                config.published,
            )?),
            DetectorMode::Default => {
                Engine::Robust(robust::RobustDetector::read(&mut r, config.robust)?)
            }
        };
        r.end()?;
        // The detector has seen no sample after the door's last accepted one.
        if let Engine::Robust(d) = &engine {
            if let Some(inner) = d.last_t_s() {
                if time.last_t_s().is_none_or(|outer| inner > outer) {
                    return Err(
                        SnapshotError::Invalid("step detector time after the input's").into(),
                    );
                }
            }
        }
        Ok(Self {
            config,
            engine,
            time,
            units,
            queue,
            step_count,
        })
    }
}
