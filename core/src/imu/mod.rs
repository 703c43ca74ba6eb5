//! Separate sensor events to IMU samples: the one merge rule of stridekit.
//!
//! Phones deliver the accelerometer, the gyroscope and the magnetometer as separate
//! events, each with its own timestamp and rate, batched by the sensor hub. The
//! engines take IMU samples (`ahrs::ImuSample`: all three at one time). [`ImuMerger`]
//! turns the events into samples, streaming and allocation-free per event; the
//! phone navigator runs it behind `PhoneNavigator::push_event`, the CLI's Android-log
//! reader runs it over the file's events in file order, so an app and `stridekit pdr`
//! merge the same walk the same way.
//!
//! **The rule** (tunables in [`MergeConfig`], defaults `DEFAULT_*` in `merge`):
//! - The accelerometer paces the output: one sample per accelerometer event, at its
//!   time, in its order. Each stream must be in time order on its own (a repeated or
//!   earlier event of a stream is refused with the input layer's typed error); the
//!   streams may arrive interleaved in any order.
//! - Gyroscope and magnetometer are interpolated linearly between their two events
//!   around the accelerometer's time (an event at exactly that time is taken as is).
//!   Hold instead of interpolation would lag by half a period (2.5–10 ms at
//!   100–200 Hz) of rotation.
//! - One sample spans at most `max_span_s` (0.2 s) between the two events it
//!   interpolates: across a longer gap, and beyond a stream's first or last event,
//!   the nearer event is held up to `max_hold_s` (0.1 s) from its time. Beyond that
//!   the gyroscope is missing: the accelerometer event is dropped and counted
//!   ([`MergeCounts::without_gyro`]); a missing magnetometer gives a sample without
//!   one.
//! - Late events: an accelerometer event waits until the gyroscope and the
//!   magnetometer have reported at or after its time, so FIFO batches delivered late
//!   (one sensor's 200 ms burst after another's) merge exactly as events delivered
//!   in time order. It waits at most `max_delay_s` (0.5 s) of event time: once any
//!   stream is that far ahead of a stream's last event, that stream counts as
//!   stopped and the samples go out with what it has (held, or without it). A
//!   magnetometer that never reports delays the first samples by `max_delay_s` once.
//! - A stream that stops: its last event is held for `max_hold_s`, then the
//!   gyroscope's absence drops samples and the magnetometer's leaves them without
//!   one. [`ImuMerger::flush`] releases everything still waiting (the end of a
//!   recording, a session that stops); events after it merge as before.
//! - Memory: each stream keeps at most `max_delay_s` × 1 000 Hz events (allocated
//!   once, at construction); a stream that overflows that loses its oldest events
//!   (accelerometer: the oldest waiting one is released with what there is).

mod event;
mod merge;
mod queue;
mod snapshot;

pub use event::{ImuEvent, SensorKind};
pub use merge::{
    ImuMerger, MergeConfig, MergeCounts, MergeError, DEFAULT_MAX_DELAY_S, DEFAULT_MAX_HOLD_S,
    DEFAULT_MAX_SPAN_S, MAX_EVENT_RATE_HZ,
};
