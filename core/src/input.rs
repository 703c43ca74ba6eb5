//! The door every engine's input goes through: one set of physical limits, one set
//! of checks, one error type.
//!
//! Every engine checks each sample here before it changes any state, so one phone
//! stream passes or fails the same way in every engine, and no accepted sample can
//! carry a value that makes an engine's arithmetic overflow. What is checked:
//!
//! - **Finite numbers**: NaN and ±∞ are refused ([`InputError::NonFinite`]).
//! - **Physical ranges** ([`limits`]): per axis |a| ≤ 2 000 m/s² (≈ 200 g, beyond
//!   every phone, watch and shoe IMU), |ω| ≤ 200 rad/s (≈ 11 500 °/s), |m| ≤ 5 000 µT
//!   (a magnet on the sensor saturates below that); GNSS latitude, longitude,
//!   altitude, accuracies and speed in their ranges ([`InputError::OutOfRange`]).
//! - **Time order** per stream: a sample not later than the previous accepted one is
//!   refused ([`InputError::TimeNotIncreasing`]; [`InputError::is_duplicate_time`]
//!   tells an equal timestamp, common in batched logs, from one going backwards).
//!   The same policy in every engine: an equal timestamp is not merged, it is refused
//!   quietly (no log line) and the state is unchanged; replay tools count such
//!   samples by reason.
//! - **Time units** ([`InputError::TimeUnit`], [`InputError::TimeTooFine`],
//!   [`InputError::TimeJump`]): `t_s` is in seconds. Milliseconds and nanoseconds are
//!   common mistakes (Android's `SensorEvent.timestamp` is nanoseconds,
//!   `Location.getTime()` milliseconds). Refused are:
//!   - |t_s| > [`limits::MAX_ABS_T_S`] (10¹¹ s, 3 000 years: Unix time in seconds
//!     passes, Unix time in milliseconds and nanoseconds since boot after 100 s of
//!     uptime do not), from the first sample;
//!   - a forward jump of more than [`limits::MAX_TIME_JUMP_S`] (about a year: mixed
//!     clocks) from the previous sample of the stream;
//!   - a third interval in a row longer than the stream's slow limit: 1 s on
//!     high-rate streams (IMU, accelerometer: a 50–500 Hz stream in milliseconds has
//!     intervals of 2–20 "seconds"), 150 s on GNSS (a 1 Hz receiver in milliseconds
//!     reports every 1 000 "seconds"), and on step streams 150 s until the stream has
//!     shown one shorter interval (steps at 0.3–1 s are 300–1 000 "seconds" apart in
//!     milliseconds; later, a long stop is no unit mistake). The unit the error names
//!     is judged from the run's first slow interval, so every refusal of one stream
//!     names the same unit, however long ago the last accepted sample is;
//!   - a positive interval below [`limits::MIN_INTERVAL_S`] (1 µs) that is not the
//!     rounding of equal times, before the stream is established
//!     ([`InputError::TimeTooFine`]): no sensor samples at a MHz; milliseconds
//!     divided by 10⁹ as if nanoseconds give this. Once a stream has shown its rate,
//!     such an interval is a duplicate (jitter, a batch), as below.
//!
//!   **The first samples.** A unit cannot be told from one time alone (4 000 may be
//!   seconds since boot or milliseconds of a stream that started 4 s ago): it is
//!   known once the stream shows an interval within its limits, neither slow nor
//!   faster than its kind of sensor samples ([`TimeGuard::established`]). An engine that must not let a sample of a wrong
//!   unit change anything holds the stream's samples until then, and drops them when
//!   the stream is refused: the pace tracker does so for GNSS and steps (at most 3
//!   samples; with a normal first interval the first sample waits for the second).
//!   Every other engine uses its first samples at once: a stream in a wrong unit is
//!   refused from its fourth sample on, and the first three are all it ever used.
//! - **Accelerations in g** ([`InputError::AccelerationInG`]): engines that can tell
//!   (a mean |a| near 1 instead of near 9.8) refuse such streams; the heuristics
//!   belong to each engine, the error is this one.
//!
//! A rejected sample changes nothing. [`TimeGuard`] is the per-stream time state
//! (two numbers), kept in each engine's snapshot.

use crate::snapshot::{Reader, SnapshotError, Writer};

/// The limits every engine applies at the door.
pub mod limits {
    /// Largest |acceleration| per axis, m/s² (≈ 204 g).
    pub const MAX_ACCEL_MPS2: f64 = 2_000.0;
    /// Largest |acceleration| as a vector, m/s² (the per-axis limit on all three
    /// axes, 2 000·√3, rounded up).
    pub const MAX_ACCEL_NORM_MPS2: f64 = 3_464.2;
    /// Largest |angular rate| per axis, rad/s (≈ 11 460 °/s).
    pub const MAX_GYRO_RADS: f64 = 200.0;
    /// Largest |magnetic field| per axis, µT (the Earth's is 25–65 µT).
    pub const MAX_MAG_UT: f64 = 5_000.0;
    /// Largest vertical displacement of a device over one step, m (a walker's body
    /// rises and falls by a few centimetres, a hand or a thigh by a few decimetres).
    pub const MAX_STEP_VERTICAL_M: f64 = 2.0;
    /// Largest |t_s|, s (about 3 000 years): Unix time in seconds passes.
    pub const MAX_ABS_T_S: f64 = 1.0e11;
    /// Shortest interval between two samples of one stream, s (1 µs: no sensor samples
    /// at a MHz). A closer sample is a duplicate; rates from a sub-µs interval would
    /// be numerically meaningless (1e-91 s gave angular rates of 1e91 rad/s).
    pub const MIN_INTERVAL_S: f64 = 1e-6;
    /// Largest forward jump between two samples of one stream, s (about a year).
    pub const MAX_TIME_JUMP_S: f64 = 3.2e7;
    /// An IMU/accelerometer interval longer than this is "slow", s; the third slow
    /// interval in a row is refused as a unit error.
    pub const SLOW_IMU_INTERVAL_S: f64 = 1.0;
    /// A GNSS interval longer than this is "slow", s; the third in a row is refused.
    pub const SLOW_GNSS_INTERVAL_S: f64 = 150.0;
    /// A step-stream interval longer than this before the stream showed a shorter one
    /// is "slow", s; the third in a row from the start is refused.
    pub const SLOW_STEPS_INTERVAL_S: f64 = 150.0;
    /// Intervals shorter than these do not show a stream's unit is seconds, s (an IMU
    /// at 10 kHz; GNSS or step data at 100 Hz): see [`super::TimeGuard::established`].
    pub const FAST_IMU_INTERVAL_S: f64 = 1e-4;
    pub const FAST_LOW_RATE_INTERVAL_S: f64 = 1e-2;
    /// Slow intervals in a row accepted before the next is refused.
    pub const SLOW_INTERVALS_ACCEPTED: u8 = 2;
    /// GNSS latitude, degrees.
    pub const MAX_LAT_DEG: f64 = 90.0;
    /// GNSS longitude, degrees.
    pub const MAX_LON_DEG: f64 = 180.0;
    /// GNSS altitude range, m.
    pub const MIN_ALT_M: f64 = -12_000.0;
    pub const MAX_ALT_M: f64 = 100_000.0;
    /// GNSS horizontal accuracy, m.
    pub const MAX_ACCURACY_M: f64 = 1.0e5;
    /// GNSS speed and speed accuracy, m/s.
    pub const MAX_SPEED_MPS: f64 = 100.0;
    /// Cadence, steps per minute (sprinters reach ~300).
    pub const MAX_CADENCE_SPM: f64 = 300.0;
    /// Fastest step rate a step counter can report, steps/s; a count rising faster
    /// is a counter discontinuity, not steps.
    pub const MAX_STEP_RATE_HZ: f64 = 10.0;
}

/// Which input stream a sample belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stream {
    /// GNSS position fixes.
    Gnss,
    /// Pedometer steps (counts, events, cadence).
    Steps,
    /// Raw accelerometer samples.
    Accelerometer,
    /// IMU samples (gyroscope + accelerometer, optionally magnetometer).
    Imu,
    /// Separate gyroscope events (merged into IMU samples by [`crate::imu`]).
    Gyroscope,
    /// Separate magnetometer events (merged into IMU samples by [`crate::imu`]).
    Magnetometer,
}

impl Stream {
    /// The slow limit of this stream's intervals (see the module docs), once the
    /// stream is `established` or before; `None`: no slow-interval check.
    fn slow_interval_s(self, established: bool) -> Option<f64> {
        match self {
            Stream::Accelerometer | Stream::Imu | Stream::Gyroscope | Stream::Magnetometer => {
                Some(limits::SLOW_IMU_INTERVAL_S)
            }
            Stream::Gnss => Some(limits::SLOW_GNSS_INTERVAL_S),
            // A stop of minutes is normal for steps, but not between the first ones.
            Stream::Steps => (!established).then_some(limits::SLOW_STEPS_INTERVAL_S),
        }
    }

    /// The shortest interval that shows this stream's unit is seconds, s: the
    /// fastest such sensors sample (an IMU at 10 kHz, a receiver or a pedometer at
    /// 100 Hz).
    fn fast_interval_s(self) -> f64 {
        match self {
            Stream::Accelerometer | Stream::Imu | Stream::Gyroscope | Stream::Magnetometer => {
                limits::FAST_IMU_INTERVAL_S
            }
            Stream::Gnss | Stream::Steps => limits::FAST_LOW_RATE_INTERVAL_S,
        }
    }

    /// The usual interval of this stream, s: what a wrong unit is judged against.
    fn nominal_interval_s(self) -> f64 {
        match self {
            Stream::Accelerometer | Stream::Imu | Stream::Gyroscope | Stream::Magnetometer => 0.01,
            Stream::Gnss | Stream::Steps => 1.0,
        }
    }
}

impl std::fmt::Display for Stream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stream::Gnss => "GNSS",
            Stream::Steps => "step",
            Stream::Accelerometer => "accelerometer",
            Stream::Imu => "IMU",
            Stream::Gyroscope => "gyroscope",
            Stream::Magnetometer => "magnetometer",
        })
    }
}

/// The unit a refused timestamp is most likely in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LikelyTimeUnit {
    Milliseconds,
    Microseconds,
    Nanoseconds,
}

impl LikelyTimeUnit {
    /// From how many "seconds" a value or an interval that should be about `nominal_s`
    /// seconds came out as.
    fn from_ratio(ratio: f64) -> Self {
        if ratio >= 3.0e7 {
            LikelyTimeUnit::Nanoseconds
        } else if ratio >= 3.0e4 {
            LikelyTimeUnit::Microseconds
        } else {
            LikelyTimeUnit::Milliseconds
        }
    }

    /// The unit as a small number (1–3) for [`TimeGuard`]'s snapshot byte.
    fn code(self) -> u8 {
        match self {
            LikelyTimeUnit::Milliseconds => 1,
            LikelyTimeUnit::Microseconds => 2,
            LikelyTimeUnit::Nanoseconds => 3,
        }
    }

    fn from_code(code: u8) -> Option<Self> {
        match code {
            1 => Some(LikelyTimeUnit::Milliseconds),
            2 => Some(LikelyTimeUnit::Microseconds),
            3 => Some(LikelyTimeUnit::Nanoseconds),
            _ => None,
        }
    }

    /// Divide by this to get seconds.
    pub fn per_second(self) -> f64 {
        match self {
            LikelyTimeUnit::Milliseconds => 1e3,
            LikelyTimeUnit::Microseconds => 1e6,
            LikelyTimeUnit::Nanoseconds => 1e9,
        }
    }
}

impl std::fmt::Display for LikelyTimeUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            LikelyTimeUnit::Milliseconds => "milliseconds",
            LikelyTimeUnit::Microseconds => "microseconds",
            LikelyTimeUnit::Nanoseconds => "nanoseconds",
        })
    }
}

/// Why a sample was refused at the door.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum InputError {
    /// A field is NaN or infinite.
    #[error("{field} is not a finite number")]
    NonFinite { field: &'static str },
    /// A field is outside its physical range `min` to `max` (in `unit`).
    #[error("{field} = {value} {unit} is out of range (allowed: {min} to {max} {unit})")]
    OutOfRange {
        field: &'static str,
        value: f64,
        min: f64,
        max: f64,
        unit: &'static str,
    },
    /// The sample is not later than the previous accepted one of its stream: equal
    /// or less than [`limits::MIN_INTERVAL_S`] after it (a duplicated timestamp), or
    /// earlier (time going backwards).
    #[error(
        "{stream} sample at t = {t_s} s is not after the previous one at {last_t_s} s{}",
        if (t_s - last_t_s).abs() < limits::MIN_INTERVAL_S { " (duplicate timestamp)" } else { "" }
    )]
    TimeNotIncreasing {
        stream: Stream,
        t_s: f64,
        last_t_s: f64,
    },
    /// The timestamps are not seconds: too large, or spaced as no stream of this
    /// kind is (see the module docs). `interval_s` is the spacing that gave it away,
    /// NaN when the value alone did.
    #[error(
        "{stream} timestamps look like {likely}, not seconds (t = {t_s}{}); \
         divide by {}",
        if interval_s.is_nan() { String::new() } else { format!(", {interval_s} after the previous sample") },
        likely.per_second()
    )]
    TimeUnit {
        stream: Stream,
        t_s: f64,
        interval_s: f64,
        likely: LikelyTimeUnit,
    },
    /// The timestamps advance by less than a microsecond per sample, yet are not
    /// equal: no sensor samples at a MHz, so they are not seconds but a smaller unit
    /// (milliseconds divided by 10⁹ as if they were nanoseconds give this). Named the
    /// same way however far the refused sample is from the last accepted one.
    #[error(
        "{stream} timestamps advance by {interval_s:e} s (t = {t_s}), finer than any sensor \
         samples: they are not seconds (milliseconds divided by 10⁹ as if nanoseconds give \
         this; multiply such times by 10⁶)"
    )]
    TimeTooFine {
        stream: Stream,
        t_s: f64,
        interval_s: f64,
    },
    /// The clock jumped forward by more than a year within one stream (mixed
    /// clocks, e.g. time since boot and Unix time): start a new engine.
    #[error(
        "{stream} sample at t = {t_s} s is {} s after the previous one at {last_t_s} s: \
         the clock changed (start a new session)",
        t_s - last_t_s
    )]
    TimeJump {
        stream: Stream,
        t_s: f64,
        last_t_s: f64,
    },
    /// The accelerometer reports in g, not m/s² (mean magnitude about 1, not 9.8).
    #[error(
        "acceleration magnitude averages {mean_magnitude:.2}: the samples look like g, \
         expected m/s² (about 9.8 at rest; multiply by 9.80665)"
    )]
    AccelerationInG { mean_magnitude: f64 },
}

impl InputError {
    /// A refusal of the stream's time unit ([`InputError::TimeUnit`],
    /// [`InputError::TimeTooFine`]): once one sample of a stream is refused so, the
    /// stream is in the wrong unit, and a replay should say so and fail.
    pub fn is_time_unit(&self) -> bool {
        matches!(
            self,
            InputError::TimeUnit { .. } | InputError::TimeTooFine { .. }
        )
    }

    /// A timestamp equal to the previous one (as opposed to one going backwards).
    pub fn is_duplicate_time(&self) -> bool {
        matches!(self, InputError::TimeNotIncreasing { t_s, last_t_s, .. }
            if (t_s - last_t_s).abs() < limits::MIN_INTERVAL_S)
    }

    /// A short stable name of the reason, for counting rejections (`"non_finite"`,
    /// `"out_of_range"`, `"duplicate_time"`, `"time_backwards"`, `"time_unit"` (also
    /// [`InputError::TimeTooFine`]), `"time_jump"`, `"accel_in_g"`).
    pub fn reason(&self) -> &'static str {
        match self {
            InputError::NonFinite { .. } => "non_finite",
            InputError::OutOfRange { .. } => "out_of_range",
            InputError::TimeNotIncreasing { .. } if self.is_duplicate_time() => "duplicate_time",
            InputError::TimeNotIncreasing { .. } => "time_backwards",
            InputError::TimeUnit { .. } | InputError::TimeTooFine { .. } => "time_unit",
            InputError::TimeJump { .. } => "time_jump",
            InputError::AccelerationInG { .. } => "accel_in_g",
        }
    }
}

/// `v` must be finite.
#[inline]
pub fn finite(field: &'static str, v: f64) -> Result<f64, InputError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(InputError::NonFinite { field })
    }
}

/// `v` must be finite and in `min..=max`.
#[inline]
pub fn in_range(
    field: &'static str,
    v: f64,
    min: f64,
    max: f64,
    unit: &'static str,
) -> Result<f64, InputError> {
    finite(field, v)?;
    if (min..=max).contains(&v) {
        Ok(v)
    } else {
        Err(InputError::OutOfRange {
            field,
            value: v,
            min,
            max,
            unit,
        })
    }
}

/// A 3-vector, each component finite and within ±`max`.
#[inline]
fn vec3(
    fields: [&'static str; 3],
    v: &[f64; 3],
    max: f64,
    unit: &'static str,
) -> Result<(), InputError> {
    for i in 0..3 {
        in_range(fields[i], v[i], -max, max, unit)?;
    }
    Ok(())
}

/// An accelerometer reading (specific force, m/s², gravity included).
#[inline]
pub fn accel(a_mps2: &[f64; 3]) -> Result<(), InputError> {
    vec3(
        ["accel_x_mps2", "accel_y_mps2", "accel_z_mps2"],
        a_mps2,
        limits::MAX_ACCEL_MPS2,
        "m/s²",
    )
}

/// A gyroscope reading, rad/s.
#[inline]
pub fn gyro(w_rads: &[f64; 3]) -> Result<(), InputError> {
    vec3(
        ["gyro_x_rads", "gyro_y_rads", "gyro_z_rads"],
        w_rads,
        limits::MAX_GYRO_RADS,
        "rad/s",
    )
}

/// A magnetometer reading, µT.
#[inline]
pub fn mag(m_ut: &[f64; 3]) -> Result<(), InputError> {
    vec3(
        ["mag_x_ut", "mag_y_ut", "mag_z_ut"],
        m_ut,
        limits::MAX_MAG_UT,
        "µT",
    )
}

/// The GNSS fields every engine that takes fixes checks.
pub fn gnss(
    lat_deg: f64,
    lon_deg: f64,
    alt_m: Option<f64>,
    horizontal_accuracy_m: Option<f64>,
    speed_mps: Option<f64>,
    speed_accuracy_mps: Option<f64>,
) -> Result<(), InputError> {
    use limits::*;
    in_range("lat_deg", lat_deg, -MAX_LAT_DEG, MAX_LAT_DEG, "°")?;
    in_range("lon_deg", lon_deg, -MAX_LON_DEG, MAX_LON_DEG, "°")?;
    if let Some(a) = alt_m {
        in_range("alt_m", a, MIN_ALT_M, MAX_ALT_M, "m")?;
    }
    if let Some(a) = horizontal_accuracy_m {
        in_range("horizontal_accuracy_m", a, 0.0, MAX_ACCURACY_M, "m")?;
    }
    if let Some(s) = speed_mps {
        in_range("speed_mps", s, 0.0, MAX_SPEED_MPS, "m/s")?;
    }
    if let Some(s) = speed_accuracy_mps {
        in_range("speed_accuracy_mps", s, 0.0, MAX_SPEED_MPS, "m/s")?;
    }
    Ok(())
}

/// [`gnss`] over the fields of a [`GnssFix`](crate::pace::GnssFix): the value checks
/// of every engine taking one (the engine's [`TimeGuard`] checks its time first).
pub(crate) fn gnss_fix(fix: &crate::pace::GnssFix) -> Result<(), InputError> {
    gnss(
        fix.lat_deg,
        fix.lon_deg,
        fix.alt_m,
        fix.horizontal_accuracy_m,
        fix.speed_mps,
        fix.speed_accuracy_mps,
    )
}

/// The stateless part of the time checks: `t_s` finite, in seconds by magnitude and
/// after `last_t_s`. Returns the interval (None for a first sample). [`time_after`]
/// adds the jump check, [`TimeGuard`] the slow-interval check of high-rate streams.
#[inline]
pub fn time_increasing(
    stream: Stream,
    t_s: f64,
    last_t_s: Option<f64>,
) -> Result<Option<f64>, InputError> {
    finite("t_s", t_s)?;
    if t_s.abs() > limits::MAX_ABS_T_S {
        return Err(InputError::TimeUnit {
            stream,
            t_s,
            interval_s: f64::NAN,
            // Unix time in ms is ~1.7e12, nanoseconds since boot pass 1e14 after a day.
            likely: if t_s.abs() >= 1.0e14 {
                LikelyTimeUnit::Nanoseconds
            } else {
                LikelyTimeUnit::Milliseconds
            },
        });
    }
    let Some(last) = last_t_s else {
        return Ok(None);
    };
    let dt = t_s - last;
    if dt < limits::MIN_INTERVAL_S {
        return Err(InputError::TimeNotIncreasing {
            stream,
            t_s,
            last_t_s: last,
        });
    }
    Ok(Some(dt))
}

/// Intervals within this many units in the last place of the times are equal times.
const ROUNDING_ULPS: f64 = 4.0;

/// [`time_increasing`] and no jump of years.
#[inline]
pub fn time_after(
    stream: Stream,
    t_s: f64,
    last_t_s: Option<f64>,
) -> Result<Option<f64>, InputError> {
    let dt = time_increasing(stream, t_s, last_t_s)?;
    if let (Some(dt), Some(last)) = (dt, last_t_s) {
        refuse_jump(stream, t_s, last, dt)?;
    }
    Ok(dt)
}

/// A forward jump of more than [`limits::MAX_TIME_JUMP_S`] is refused.
#[inline]
fn refuse_jump(stream: Stream, t_s: f64, last_t_s: f64, dt: f64) -> Result<(), InputError> {
    if dt > limits::MAX_TIME_JUMP_S {
        return Err(InputError::TimeJump {
            stream,
            t_s,
            last_t_s,
        });
    }
    Ok(())
}

/// The time state of one input stream: the last accepted time, how many slow
/// intervals in a row led to it (and the unit the first of them pointed to), and
/// whether the stream has shown an interval within its limits. `Copy`, a few bytes;
/// engines keep one per stream and write it into their snapshots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeGuard {
    stream: Stream,
    last_t_s: Option<f64>,
    slow_run: u8,
    /// The unit the first slow interval of the current run pointed to (`None` while
    /// the run is empty).
    slow_unit: Option<LikelyTimeUnit>,
    /// An interval within the stream's limits was accepted: its unit is seconds.
    established: bool,
}

/// Bits of [`TimeGuard`]'s snapshot byte: the slow run (0–2), the established flag,
/// the slow run's unit (0: none, 1–3: ms, µs, ns).
const GUARD_RUN_BITS: u8 = 0b11;
const GUARD_ESTABLISHED_BIT: u8 = 0b100;
const GUARD_UNIT_SHIFT: u8 = 3;

impl TimeGuard {
    pub const fn new(stream: Stream) -> Self {
        Self {
            stream,
            last_t_s: None,
            slow_run: 0,
            slow_unit: None,
            established: false,
        }
    }

    pub fn stream(&self) -> Stream {
        self.stream
    }

    /// Time of the newest accepted sample, s.
    pub fn last_t_s(&self) -> Option<f64> {
        self.last_t_s
    }

    /// Whether the stream has shown an interval within its limits (its unit is
    /// seconds): until then, a stream in a wrong unit cannot be told from one that
    /// started with pauses, and an engine that must not use such samples holds them
    /// (see the module docs).
    pub fn established(&self) -> bool {
        self.established
    }

    /// A sub-microsecond interval before the stream was established, not the rounding
    /// of equal times, is a unit mistake ([`InputError::TimeTooFine`]); once the
    /// stream has shown its rate, it is a duplicate (jitter, a batch), as `e` says.
    fn too_fine(&self, e: InputError, t_s: f64) -> InputError {
        let Some(last) = self.last_t_s else {
            return e;
        };
        let dt = t_s - last;
        let rounding = ROUNDING_ULPS * f64::EPSILON * t_s.abs().max(last.abs());
        if self.established || !(dt > rounding && dt < limits::MIN_INTERVAL_S) {
            return e;
        }
        InputError::TimeTooFine {
            stream: self.stream,
            t_s,
            interval_s: dt,
        }
    }

    /// The unit an interval `dt` (s) of this stream points to.
    fn unit_of(&self, dt: f64) -> LikelyTimeUnit {
        LikelyTimeUnit::from_ratio(dt / self.stream.nominal_interval_s())
    }

    /// Whether `t_s` may follow; nothing changes. On success returns the interval
    /// since the previous accepted sample (None for the first).
    #[inline]
    pub fn check(&self, t_s: f64) -> Result<Option<f64>, InputError> {
        let stream = self.stream;
        let Some(dt) =
            time_increasing(stream, t_s, self.last_t_s).map_err(|e| self.too_fine(e, t_s))?
        else {
            return Ok(None);
        };
        if let Some(slow) = stream.slow_interval_s(self.established) {
            if dt > slow && self.slow_run >= limits::SLOW_INTERVALS_ACCEPTED {
                // The run's first slow interval names the unit: later refusals, ever
                // further from the last accepted sample, name the same one.
                return Err(InputError::TimeUnit {
                    stream,
                    t_s,
                    interval_s: dt,
                    likely: self.slow_unit.unwrap_or_else(|| self.unit_of(dt)),
                });
            }
        }
        // `time_increasing` passed above, so only the jump is left to check.
        if let Some(last) = self.last_t_s {
            refuse_jump(stream, t_s, last, dt)?;
        }
        Ok(Some(dt))
    }

    /// Record an accepted sample (after [`check`](Self::check) passed).
    #[inline]
    pub fn accept(&mut self, t_s: f64) {
        if let Some(last) = self.last_t_s {
            let dt = t_s - last;
            match self.stream.slow_interval_s(self.established) {
                Some(slow) if dt > slow => {
                    if self.slow_run == 0 {
                        self.slow_unit = Some(self.unit_of(dt));
                    }
                    self.slow_run = self.slow_run.saturating_add(1);
                }
                _ => {
                    self.slow_run = 0;
                    self.slow_unit = None;
                    // Faster than the stream's kind ever samples (milliseconds read as
                    // nanoseconds reach a microsecond every few hundred samples)
                    // establishes nothing.
                    self.established |= dt >= self.stream.fast_interval_s();
                }
            }
        }
        self.last_t_s = Some(t_s);
    }

    /// [`check`](Self::check), then [`accept`](Self::accept) on success.
    #[inline]
    pub fn advance(&mut self, t_s: f64) -> Result<Option<f64>, InputError> {
        let dt = self.check(t_s)?;
        self.accept(t_s);
        Ok(dt)
    }

    /// Forget the stream's time (a new session on the same engine).
    pub fn reset(&mut self) {
        *self = Self::new(self.stream);
    }

    pub fn write(&self, w: &mut Writer) {
        // Exhaustive on purpose: a new field must be written.
        let Self {
            stream: _,
            last_t_s,
            slow_run,
            slow_unit,
            established,
        } = self;
        w.opt_f64(*last_t_s);
        // One byte, as before the flag and the unit were added: a snapshot of an
        // earlier build reads as "not established, no unit".
        let unit = slow_unit.map_or(0, LikelyTimeUnit::code);
        w.u8((*slow_run & GUARD_RUN_BITS)
            | if *established {
                GUARD_ESTABLISHED_BIT
            } else {
                0
            }
            | unit << GUARD_UNIT_SHIFT);
    }

    /// Reads what [`write`](Self::write) wrote; the time must be finite and within the
    /// limits.
    pub fn read(r: &mut Reader, stream: Stream) -> Result<Self, SnapshotError> {
        let last_t_s = r.opt_f64()?;
        if let Some(t) = last_t_s {
            if t.abs() > limits::MAX_ABS_T_S {
                return Err(SnapshotError::Invalid("last sample time"));
            }
        }
        let byte = r.u8()?;
        let slow_run = byte & GUARD_RUN_BITS;
        let unit = byte >> GUARD_UNIT_SHIFT;
        if slow_run > limits::SLOW_INTERVALS_ACCEPTED || unit > 3 {
            return Err(SnapshotError::Invalid("slow-interval count"));
        }
        Ok(Self {
            stream,
            last_t_s,
            slow_run,
            slow_unit: LikelyTimeUnit::from_code(unit),
            established: byte & GUARD_ESTABLISHED_BIT != 0,
        })
    }
}

/// The g-units check of an accelerometer stream, the same in every engine.
///
/// A phone, watch or shoe reporting in g (iOS Core Motion does) gives |a| ≈ 1 at
/// rest where m/s² gives ≈ 9.8. Refused as [`InputError::AccelerationInG`]: a first
/// sample (or the first after the engine restarted) with |a| in 0.3..=3 (a device
/// at rest in g units; in m/s² that would be near free fall), and any sample that
/// would bring the mean |a| (exponential, time constant 1 s) below 3 m/s² — a
/// carried device averages ≈ 9.8 m/s²; only a free fall of over a second gets that
/// low. A stream switching from m/s² to g mid-way is caught within about 1.5 s.
#[derive(Clone, Copy, Debug)]
pub struct AccelUnits {
    /// Mean |a|, m/s²; NaN before the first sample.
    mean_mps2: f64,
}

/// Equal when bit-identical (NaN, "no sample yet", equals itself), so engines
/// compare equal after a rejected sample.
impl PartialEq for AccelUnits {
    fn eq(&self, other: &Self) -> bool {
        self.mean_mps2.to_bits() == other.mean_mps2.to_bits()
    }
}

impl Default for AccelUnits {
    fn default() -> Self {
        Self::new()
    }
}

impl AccelUnits {
    /// |a| band of a first sample that reads as g.
    pub const FIRST_SAMPLE_G_MPS2: (f64, f64) = (0.3, 3.0);
    /// Time constant of the mean |a|, s.
    pub const MEAN_TAU_S: f64 = 1.0;
    /// Lowest mean |a| accepted, m/s².
    pub const MIN_MEAN_MPS2: f64 = 3.0;

    pub const fn new() -> Self {
        Self {
            mean_mps2: f64::NAN,
        }
    }

    /// Whether a sample of magnitude `norm_mps2`, `dt_s` after the previous one
    /// (`None`: the first, or the first after a restart), passes; returns the new mean
    /// for [`accept`](Self::accept). Nothing changes.
    #[inline]
    pub fn check(&self, dt_s: Option<f64>, norm_mps2: f64) -> Result<f64, InputError> {
        let (lo, hi) = Self::FIRST_SAMPLE_G_MPS2;
        match dt_s {
            Some(dt) if !self.mean_mps2.is_nan() => {
                let k = crate::signal::ema_gain(dt / Self::MEAN_TAU_S);
                let mean = self.mean_mps2 + k * (norm_mps2 - self.mean_mps2);
                if mean < Self::MIN_MEAN_MPS2 {
                    Err(InputError::AccelerationInG {
                        mean_magnitude: mean,
                    })
                } else {
                    Ok(mean)
                }
            }
            _ if (lo..=hi).contains(&norm_mps2) => Err(InputError::AccelerationInG {
                mean_magnitude: norm_mps2,
            }),
            _ => Ok(norm_mps2),
        }
    }

    #[inline]
    pub fn accept(&mut self, mean_mps2: f64) {
        self.mean_mps2 = mean_mps2;
    }

    /// Treat the next sample as a first one.
    pub fn restart(&mut self) {
        self.mean_mps2 = f64::NAN;
    }

    pub fn write(&self, w: &mut Writer) {
        w.f64(self.mean_mps2);
    }

    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mean_mps2 = r.f64_or_nan()?;
        if mean_mps2 < 0.0 || mean_mps2 > limits::MAX_ACCEL_MPS2 * 3f64.sqrt() {
            return Err(SnapshotError::Invalid("acceleration mean"));
        }
        Ok(Self { mean_mps2 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gnss_fix_checks_every_field_as_gnss_does() {
        let ok = crate::pace::GnssFix::new(10.0, 48.1, 11.5);
        assert!(gnss_fix(&ok).is_ok());
        let bad = [
            crate::pace::GnssFix {
                lat_deg: 91.0,
                ..ok
            },
            crate::pace::GnssFix {
                lon_deg: f64::NAN,
                ..ok
            },
            crate::pace::GnssFix {
                alt_m: Some(1e9),
                ..ok
            },
            crate::pace::GnssFix {
                horizontal_accuracy_m: Some(-1.0),
                ..ok
            },
            crate::pace::GnssFix {
                speed_mps: Some(1e6),
                ..ok
            },
            crate::pace::GnssFix {
                speed_accuracy_mps: Some(f64::INFINITY),
                ..ok
            },
        ];
        for f in bad {
            let direct = gnss(
                f.lat_deg,
                f.lon_deg,
                f.alt_m,
                f.horizontal_accuracy_m,
                f.speed_mps,
                f.speed_accuracy_mps,
            );
            assert!(direct.is_err());
            assert_eq!(format!("{:?}", gnss_fix(&f)), format!("{direct:?}"));
        }
    }

    #[test]
    fn seconds_pass_and_unix_seconds_too() {
        let mut g = TimeGuard::new(Stream::Imu);
        for i in 0..1000 {
            g.advance(1.7e9 + i as f64 * 0.01).unwrap();
        }
        let mut g = TimeGuard::new(Stream::Gnss);
        for i in 0..10 {
            g.advance(100.0 + i as f64 * 60.0).unwrap(); // one fix a minute
        }
    }

    #[test]
    fn equal_time_is_a_duplicate_earlier_is_backwards() {
        let mut g = TimeGuard::new(Stream::Imu);
        g.advance(1.0).unwrap();
        let e = g.check(1.0).unwrap_err();
        assert!(e.is_duplicate_time());
        assert_eq!(e.reason(), "duplicate_time");
        let e = g.check(0.5).unwrap_err();
        assert!(!e.is_duplicate_time());
        assert_eq!(e.reason(), "time_backwards");
    }

    #[test]
    fn huge_times_are_milliseconds_or_nanoseconds() {
        let g = TimeGuard::new(Stream::Gnss);
        let e = g.check(1.7e12).unwrap_err();
        assert!(matches!(
            e,
            InputError::TimeUnit {
                likely: LikelyTimeUnit::Milliseconds,
                ..
            }
        ));
        let e = g.check(2.6e14).unwrap_err();
        assert!(matches!(
            e,
            InputError::TimeUnit {
                likely: LikelyTimeUnit::Nanoseconds,
                ..
            }
        ));
        assert!(e.to_string().contains("divide by 1000000000"), "{e}");
    }

    #[test]
    fn millisecond_imu_stream_is_refused_on_the_third_interval() {
        let mut g = TimeGuard::new(Stream::Imu);
        // 100 Hz in ms since boot (a day of uptime).
        let t0 = 8.64e7;
        g.advance(t0).unwrap();
        g.advance(t0 + 10.0).unwrap();
        g.advance(t0 + 20.0).unwrap();
        let e = g.check(t0 + 30.0).unwrap_err();
        assert!(
            matches!(
                e,
                InputError::TimeUnit {
                    likely: LikelyTimeUnit::Milliseconds,
                    ..
                }
            ),
            "{e:?}"
        );
    }

    #[test]
    fn nanosecond_imu_stream_is_refused_on_the_third_interval() {
        let mut g = TimeGuard::new(Stream::Imu);
        let t0 = 5.0e10; // 50 s of uptime in ns
        g.advance(t0).unwrap();
        g.advance(t0 + 1.0e7).unwrap();
        g.advance(t0 + 2.0e7).unwrap();
        let e = g.check(t0 + 3.0e7).unwrap_err();
        assert!(
            matches!(
                e,
                InputError::TimeUnit {
                    likely: LikelyTimeUnit::Nanoseconds,
                    ..
                }
            ),
            "{e:?}"
        );
    }

    #[test]
    fn every_refusal_of_a_stream_names_the_unit_of_its_first_slow_interval() {
        // 1 Hz GNSS in milliseconds: refused from the fourth fix on, and however far
        // the refused fixes get from the last accepted one (30 000 "s" would read as
        // microseconds), the unit named stays milliseconds.
        let mut g = TimeGuard::new(Stream::Gnss);
        for k in 0..3 {
            g.advance(1000.0 * k as f64).unwrap();
        }
        assert!(!g.established());
        for k in 3..100 {
            let e = g.check(1000.0 * k as f64).unwrap_err();
            assert!(
                matches!(
                    e,
                    InputError::TimeUnit {
                        likely: LikelyTimeUnit::Milliseconds,
                        ..
                    }
                ),
                "fix {k}: {e}"
            );
            assert!(e.is_time_unit());
        }
    }

    #[test]
    fn step_times_in_milliseconds_are_refused_until_a_normal_interval() {
        // Step events 0.4 s apart, in milliseconds.
        let mut g = TimeGuard::new(Stream::Steps);
        g.advance(0.0).unwrap();
        g.advance(400.0).unwrap();
        g.advance(800.0).unwrap();
        let e = g.check(1200.0).unwrap_err();
        assert!(matches!(
            e,
            InputError::TimeUnit {
                stream: Stream::Steps,
                likely: LikelyTimeUnit::Milliseconds,
                ..
            }
        ));
        // In seconds, once established, a stop of ten minutes is no unit mistake.
        let mut g = TimeGuard::new(Stream::Steps);
        g.advance(10.0).unwrap();
        g.advance(10.4).unwrap();
        assert!(g.established());
        for k in 1..10 {
            g.advance(10.4 + 600.0 * k as f64).unwrap();
        }
        // A first stop of minutes, then steps: established at the first short interval.
        let mut g = TimeGuard::new(Stream::Steps);
        g.advance(5.0).unwrap();
        g.advance(200.0).unwrap();
        assert!(!g.established());
        g.advance(200.5).unwrap();
        assert!(g.established());
    }

    #[test]
    fn intervals_under_a_microsecond_are_a_unit_not_a_duplicate() {
        // Milliseconds since boot divided by 10⁹ (as if nanoseconds): 5 ms → 5e-9 s.
        let mut g = TimeGuard::new(Stream::Accelerometer);
        g.advance(0.012).unwrap();
        let e = g.check(0.012 + 5e-9).unwrap_err();
        assert!(matches!(e, InputError::TimeTooFine { .. }), "{e:?}");
        assert_eq!(e.reason(), "time_unit");
        assert!(e.to_string().contains("milliseconds"), "{e}");
        // Equal times, and times equal to the rounding of Unix seconds, are duplicates.
        assert!(g.check(0.012).unwrap_err().is_duplicate_time());
        let mut g = TimeGuard::new(Stream::Imu);
        let t = 1.7e9;
        g.advance(t).unwrap();
        let next = t + 2.4e-7; // one unit in the last place
        assert!(g.check(next).unwrap_err().is_duplicate_time());
    }

    #[test]
    fn a_jump_of_years_is_a_clock_change() {
        let mut g = TimeGuard::new(Stream::Steps);
        g.advance(163.0).unwrap();
        let e = g.check(163.0 + 1.7e9).unwrap_err(); // boot time, then Unix time
        assert!(matches!(e, InputError::TimeJump { .. }), "{e:?}");
        assert_eq!(e.reason(), "time_jump");
    }

    #[test]
    fn one_pause_in_a_real_stream_passes() {
        let mut g = TimeGuard::new(Stream::Imu);
        let mut t = 10.0;
        for _ in 0..100 {
            t += 0.01;
            g.advance(t).unwrap();
        }
        t += 600.0; // sensors paused for ten minutes
        g.advance(t).unwrap();
        for _ in 0..100 {
            t += 0.01;
            g.advance(t).unwrap();
        }
        // Two pauses in a row are still fine.
        t += 5.0;
        g.advance(t).unwrap();
        t += 5.0;
        g.advance(t).unwrap();
        t += 0.01;
        g.advance(t).unwrap();
    }

    #[test]
    fn limits_are_inclusive_and_name_the_field() {
        accel(&[2000.0, -2000.0, 0.0]).unwrap();
        let e = accel(&[0.0, 2000.5, 0.0]).unwrap_err();
        assert!(matches!(
            e,
            InputError::OutOfRange {
                field: "accel_y_mps2",
                ..
            }
        ));
        assert!(gyro(&[1e300, 0.0, 0.0]).is_err());
        assert!(mag(&[1e200, 0.0, 0.0]).is_err());
        assert!(matches!(
            gyro(&[f64::NAN, 0.0, 0.0]),
            Err(InputError::NonFinite {
                field: "gyro_x_rads"
            })
        ));
    }

    #[test]
    fn accelerations_in_g_are_recognised() {
        let mut u = AccelUnits::new();
        assert!(matches!(
            u.check(None, 1.0),
            Err(InputError::AccelerationInG { .. })
        ));
        let m = u.check(None, 9.8).unwrap();
        u.accept(m);
        // Switching to g: refused within about 1.5 s at 100 Hz.
        let mut refused_after = None;
        for i in 0..300 {
            match u.check(Some(0.01), 1.0) {
                Ok(m) => u.accept(m),
                Err(_) => {
                    refused_after = Some(i);
                    break;
                }
            }
        }
        let n = refused_after.expect("never refused");
        assert!((100..=160).contains(&n), "{n}");
    }

    #[test]
    fn guard_snapshot_round_trip_and_validation() {
        let mut g = TimeGuard::new(Stream::Imu);
        g.advance(1.0).unwrap();
        g.advance(3.0).unwrap();
        let mut w = Writer::new(99, 1);
        g.write(&mut w);
        let bytes = w.finish();
        let (mut r, _) = Reader::new(&bytes, 99, 1).unwrap();
        assert_eq!(TimeGuard::read(&mut r, Stream::Imu).unwrap(), g);
        // An established stream in a slow run keeps its unit and its flag.
        let mut g = TimeGuard::new(Stream::Gnss);
        g.advance(1.0).unwrap();
        g.advance(2.0).unwrap();
        g.advance(2000.0).unwrap();
        assert!(g.established());
        let mut w = Writer::new(99, 1);
        g.write(&mut w);
        let bytes = w.finish();
        let (mut r, _) = Reader::new(&bytes, 99, 1).unwrap();
        assert_eq!(TimeGuard::read(&mut r, Stream::Gnss).unwrap(), g);
    }
}
