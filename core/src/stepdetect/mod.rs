//! Step detection on the acceleration magnitude of a phone carried anywhere (method 3,
//! seed 004).
//!
//! [`StepDetector`] is the state machine apps feed with accelerometer samples
//! (`t_s`, acceleration in m/s², gravity included, any phone orientation). It checks
//! every sample at the door and runs one of two detectors chosen by [`DetectorMode`]:
//! - [`DetectorMode::AsPublished`]: the paper's windowed-variance detector
//!   ([`published`]), w = 15 samples, thresholds T1/T2, a 0.2–2 s rate gate;
//! - [`DetectorMode::Default`]: a detector that works in time at any rate, confirms
//!   walking/running bouts by their regularity and ignores shaking, vehicles and
//!   cycling ([`robust`]).
//!
//! A confirmed bout can release several buffered steps at once. They wait in a small
//! queue (no heap): [`StepDetector::push`] returns the oldest waiting step and
//! [`StepDetector::pop_step`] drains the rest.
//!
//! Units at the door: non-finite values, timestamps not after the previous one and
//! magnitudes above 50 g are rejected. Samples in g instead of m/s² are recognised by
//! their magnitude: while nothing was accepted yet, a first sample with magnitude in
//! 0.3..=3 (1 g in g units, while in m/s² that would be near free fall) is refused;
//! afterwards a slow mean of the magnitude (time constant 1 s) that would fall below
//! 3 m/s² is refused (a carried phone averages ≈ 9.8 m/s²; only a free fall of more than
//! a second gets that low). Both give [`StepDetectError::LooksLikeG`].
//! A rejected sample leaves the state exactly as it was.

mod error;
mod event;
mod gait;
pub mod published;
pub mod robust;

pub use error::StepDetectError;
pub use event::StepEvent;
pub use published::PublishedStepParams;
pub use robust::RobustStepParams;

use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Snapshot engine kind byte for the step detector.
const SNAPSHOT_KIND: u8 = 3;
/// Snapshot format version written by this build.
const SNAPSHOT_VERSION: u16 = 3;
/// Magnitudes above this are not an accelerometer reading, m/s² (50 g).
pub const MAX_ACCEL_MPS2: f64 = 50.0 * 9.80665;
/// Time constant of the magnitude mean used by the g-units check, s.
const UNITS_TAU_S: f64 = 1.0;
/// A mean magnitude below this is taken as data in g, m/s².
const UNITS_MIN_MEAN_MPS2: f64 = 3.0;
/// Steps waiting to be popped.
const QUEUE: usize = 32;

/// Which detector runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DetectorMode {
    /// The paper's detector, faithfully (see [`published`]).
    AsPublished,
    /// The robust detector (see [`robust`]).
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

/// A sample a batch push rejected, with its index in the batch.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRejection {
    pub index: usize,
    pub error: StepDetectError,
}

/// What a batch push produced.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepBatch {
    /// Steps released, in time order.
    pub steps: Vec<StepEvent>,
    /// Samples that were rejected (the rest of the batch was still processed).
    pub rejected: Vec<StepRejection>,
}

/// Where an engine releases its steps: the detector's queue and count.
pub(crate) struct Sink<'a> {
    queue: &'a mut Ring<StepEvent, QUEUE>,
    released: &'a mut u64,
}

impl Sink<'_> {
    pub(crate) fn push(&mut self, e: StepEvent) {
        *self.released += 1;
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
        }
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.f64s(&[self.n, self.sum, self.sum_sq, self.max, self.min]);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 5];
        r.f64s(&mut v)?;
        Ok(Self {
            n: v[0],
            sum: v[1],
            sum_sq: v[2],
            max: v[3],
            min: v[4],
        })
    }
}

/// Gain of a first-order low-pass over a step of `x` time constants: 1 − e^(−x), exact
/// discretisation for any sample spacing. Below x = 1 a Padé (2,2) form of e^(−x) is used
/// (relative error < 2e-4, no `exp` call on the per-sample path).
#[inline]
pub(crate) fn ema_gain(x: f64) -> f64 {
    if x < 1.0 {
        let (p, q) = (1.0 + x * x / 12.0, 0.5 * x);
        1.0 - (p - q) / (p + q)
    } else {
        1.0 - (-x).exp()
    }
}

pub(crate) fn write_event(w: &mut Writer, e: &StepEvent) {
    w.f64s(&[
        e.t_s,
        e.duration_s,
        e.accel_variance_m2ps4,
        e.accel_max_mps2,
        e.accel_min_mps2,
    ]);
}

pub(crate) fn read_event(r: &mut Reader) -> Result<StepEvent, SnapshotError> {
    let mut v = [0.0; 5];
    r.f64s(&mut v)?;
    Ok(StepEvent {
        t_s: v[0],
        duration_s: v[1],
        accel_variance_m2ps4: v[2],
        accel_max_mps2: v[3],
        accel_min_mps2: v[4],
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
    last_t_s: Option<f64>,
    /// Slow mean of the magnitude for the g-units check, m/s².
    units_mean_mps2: f64,
    queue: Ring<StepEvent, QUEUE>,
    step_count: u64,
}

impl StepDetector {
    /// A detector with a validated configuration.
    pub fn new(config: StepDetectorConfig) -> Result<Self, StepDetectError> {
        config.validate()?;
        Ok(Self {
            engine: Self::make_engine(&config),
            config,
            last_t_s: None,
            units_mean_mps2: f64::NAN,
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
        self.last_t_s
    }

    /// Checks a sample without changing state; returns its magnitude and the updated
    /// units mean.
    /// Whether [`push`](Self::push) would accept this sample, without changing
    /// anything (callers that update several engines per sample check first).
    pub fn check_sample(&self, t_s: f64, accel_mps2: [f64; 3]) -> Result<(), StepDetectError> {
        self.check(t_s, accel_mps2).map(|_| ())
    }

    fn check(&self, t_s: f64, a: [f64; 3]) -> Result<(f64, f64), StepDetectError> {
        if !t_s.is_finite() {
            return Err(StepDetectError::NonFinite { field: "t_s" });
        }
        for (v, field) in a
            .iter()
            .zip(["accel_x_mps2", "accel_y_mps2", "accel_z_mps2"])
        {
            if !v.is_finite() {
                return Err(StepDetectError::NonFinite { field });
            }
        }
        if let Some(last) = self.last_t_s {
            if t_s <= last {
                return Err(StepDetectError::TimeNotIncreasing {
                    t_s,
                    last_t_s: last,
                });
            }
        }
        let mag = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if mag > MAX_ACCEL_MPS2 {
            return Err(StepDetectError::OutOfRange {
                field: "acceleration magnitude",
                value: mag,
                expected: "≤ 50 g (490 m/s²)",
            });
        }
        let mean = match self.last_t_s {
            None => {
                if (0.3..=3.0).contains(&mag) {
                    return Err(StepDetectError::LooksLikeG {
                        mean_magnitude: mag,
                    });
                }
                mag
            }
            Some(last) => {
                let a = ema_gain((t_s - last) / UNITS_TAU_S);
                self.units_mean_mps2 + a * (mag - self.units_mean_mps2)
            }
        };
        if mean < UNITS_MIN_MEAN_MPS2 && self.last_t_s.is_some() {
            return Err(StepDetectError::LooksLikeG {
                mean_magnitude: mean,
            });
        }
        Ok((mag, mean))
    }

    fn release(&mut self, e: StepEvent) {
        self.step_count += 1;
        self.queue.push(e);
    }

    /// Push one sample. Returns the oldest released step waiting in the queue, if any;
    /// when a bout is confirmed several steps are released at once: call
    /// [`pop_step`](Self::pop_step) until `None` to drain them (or they come out with
    /// the next pushes). The queue holds 32 steps; older ones are dropped beyond that
    /// (they stay counted in [`step_count`](Self::step_count)).
    pub fn push(
        &mut self,
        t_s: f64,
        accel_mps2: [f64; 3],
    ) -> Result<Option<StepEvent>, StepDetectError> {
        let (mag, mean) = self.check(t_s, accel_mps2)?;
        self.last_t_s = Some(t_s);
        self.units_mean_mps2 = mean;
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
                d.push(t_s, mag, &mut sink);
            }
        }
        Ok(self.queue.pop_front())
    }

    /// Push one [`AccelSample`].
    pub fn push_sample(&mut self, s: &AccelSample) -> Result<Option<StepEvent>, StepDetectError> {
        self.push(s.t_s, s.accel_mps2)
    }

    /// The oldest released step not yet returned.
    pub fn pop_step(&mut self) -> Option<StepEvent> {
        self.queue.pop_front()
    }

    /// Push many samples in order. Invalid samples are skipped and reported; the others
    /// are processed as if pushed one by one. All released steps are returned.
    pub fn push_batch(&mut self, samples: &[AccelSample]) -> StepBatch {
        let mut out = StepBatch::default();
        for (index, s) in samples.iter().enumerate() {
            match self.push_sample(s) {
                Ok(Some(e)) => out.steps.push(e),
                Ok(None) => {}
                Err(error) => out.rejected.push(StepRejection { index, error }),
            }
            while let Some(e) = self.pop_step() {
                out.steps.push(e);
            }
        }
        out
    }

    /// The whole state as bytes (versioned, checksummed).
    pub fn snapshot(&self) -> Vec<u8> {
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.u8(match self.config.mode {
            DetectorMode::AsPublished => 0,
            DetectorMode::Default => 1,
        });
        self.config.published.write(&mut w);
        self.config.robust.write(&mut w);
        w.opt_f64(self.last_t_s);
        w.f64(self.units_mean_mps2);
        w.u64(self.queue.len() as u64);
        for e in self.queue.iter() {
            write_event(&mut w, &e);
        }
        w.u64(self.step_count);
        match &self.engine {
            Engine::Published(d) => d.write(&mut w),
            Engine::Robust(d) => d.write(&mut w),
        }
        w.finish()
    }

    /// A detector continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, StepDetectError> {
        let (mut r, version) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        if version < SNAPSHOT_VERSION {
            // Version 3 added the autocorrelation state of the default detector.
            return Err(SnapshotError::UnsupportedVersion {
                found: version,
                supported: SNAPSHOT_VERSION,
            }
            .into());
        }
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
        let last_t_s = r.opt_f64()?;
        let units_mean_mps2 = r.f64()?;
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
        Ok(Self {
            config,
            engine,
            last_t_s,
            units_mean_mps2,
            queue,
            step_count,
        })
    }
}
