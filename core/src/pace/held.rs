//! Samples held until their stream's time unit is known (issue 36).
//!
//! One timestamp cannot say whether it is in seconds: a stream's unit is known once it
//! shows an interval within its limits (`crate::input::TimeGuard::established`), or
//! once its sample falls within [`SAME_CLOCK_S`] of the other stream's newest sample
//! whose unit is known (the tracker's two streams run on the app's one clock: a
//! stream in milliseconds is 1 000 times further from the start than one in seconds).
//! Until then the tracker holds the stream's samples (at most the first and two slow
//! intervals; the input layer refuses the third), applies them in order when the unit
//! is known, and never applies them when the stream is refused for its unit: a fix or
//! a step time in milliseconds changes nothing. With a normal first interval the first
//! sample waits for the second (the first fix gives no speed anyway).

use super::types::{GnssFix, StepSample};
use crate::input::limits::SLOW_INTERVALS_ACCEPTED;
use crate::input::TimeGuard;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Most samples of one stream held: the first and the slow intervals accepted.
pub(crate) const HELD: usize = SLOW_INTERVALS_ACCEPTED as usize + 1;

/// A sample this close to the other stream's newest one, whose unit is known, is on
/// the same clock in seconds, s (a step stream lags GNSS by a few seconds; a stream
/// in milliseconds is thousands of "seconds" off after the first second).
pub(crate) const SAME_CLOCK_S: f64 = 30.0;

/// Whether the unit of a sample at `t_s` of the stream `own` is known: `own` showed an
/// interval within its limits, or `other`'s unit is known and its newest sample is
/// within [`SAME_CLOCK_S`] of `t_s`.
pub(crate) fn unit_known(own: &TimeGuard, other: &TimeGuard, t_s: f64) -> bool {
    own.established()
        || other.established()
            && other
                .last_t_s()
                .is_some_and(|t| (t_s - t).abs() <= SAME_CLOCK_S)
}

/// Samples of the GNSS and the step stream waiting for their unit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Held {
    fixes: [Option<GnssFix>; HELD],
    steps: [Option<StepSample>; HELD],
}

/// Put `v` into the first free slot; `false` when all are taken.
fn hold<T>(slots: &mut [Option<T>; HELD], v: T) -> bool {
    match slots.iter_mut().find(|s| s.is_none()) {
        Some(s) => {
            *s = Some(v);
            true
        }
        None => false,
    }
}

impl Held {
    /// Hold a fix; `false` (nothing held) when full.
    pub fn hold_fix(&mut self, f: GnssFix) -> bool {
        hold(&mut self.fixes, f)
    }

    /// Hold a step sample; `false` (nothing held) when full.
    pub fn hold_steps(&mut self, s: StepSample) -> bool {
        hold(&mut self.steps, s)
    }

    /// Time of the newest held sample (−∞ when none is held).
    pub fn newest_t_s(&self) -> f64 {
        let fixes = self.fixes.iter().flatten().map(|f| f.t_s);
        let steps = self.steps.iter().flatten().map(|s| s.t_s());
        fixes.chain(steps).fold(f64::NEG_INFINITY, f64::max)
    }

    /// The held fixes in order.
    pub fn peek_fixes(&self) -> &[Option<GnssFix>; HELD] {
        &self.fixes
    }

    /// The held step samples in order.
    pub fn peek_steps(&self) -> &[Option<StepSample>; HELD] {
        &self.steps
    }

    /// The held fixes in order, emptying the slots.
    pub fn take_fixes(&mut self) -> [Option<GnssFix>; HELD] {
        std::mem::take(&mut self.fixes)
    }

    /// The held step samples in order, emptying the slots.
    pub fn take_steps(&mut self) -> [Option<StepSample>; HELD] {
        std::mem::take(&mut self.steps)
    }

    pub fn write(&self, w: &mut Writer) {
        let Self { fixes, steps } = self;
        for f in fixes {
            match f {
                Some(GnssFix {
                    t_s,
                    lat_deg,
                    lon_deg,
                    alt_m,
                    horizontal_accuracy_m,
                    speed_mps,
                    speed_accuracy_mps,
                }) => {
                    w.bool(true);
                    w.f64s(&[*t_s, *lat_deg, *lon_deg]);
                    for v in [alt_m, horizontal_accuracy_m, speed_mps, speed_accuracy_mps] {
                        w.opt_f64(*v);
                    }
                }
                None => w.bool(false),
            }
        }
        for s in steps {
            match s {
                Some(StepSample::Count { t_s, steps }) => {
                    w.u8(1);
                    w.f64(*t_s);
                    w.u64(*steps);
                }
                Some(StepSample::Event { t_s }) => {
                    w.u8(2);
                    w.f64(*t_s);
                }
                Some(StepSample::Cadence { t_s, steps_per_min }) => {
                    w.u8(3);
                    w.f64s(&[*t_s, *steps_per_min]);
                }
                None => w.u8(0),
            }
        }
    }

    /// Reads what [`write`](Self::write) wrote; every held sample must pass the
    /// input checks again (`check_fix`, `check_steps`), as it did when it was pushed,
    /// and come after the one before it.
    pub fn read(
        r: &mut Reader,
        check_fix: impl Fn(&GnssFix) -> bool,
        check_steps: impl Fn(&StepSample) -> bool,
    ) -> Result<Self, SnapshotError> {
        let mut held = Self::default();
        // Held samples are in time order, as they were pushed.
        let (mut last_fix_t, mut last_steps_t) = (None::<f64>, None::<f64>);
        for slot in &mut held.fixes {
            if !r.bool()? {
                continue;
            }
            let mut v = [0.0; 3];
            r.f64s(&mut v)?;
            let f = GnssFix {
                t_s: v[0],
                lat_deg: v[1],
                lon_deg: v[2],
                alt_m: r.opt_f64()?,
                horizontal_accuracy_m: r.opt_f64()?,
                speed_mps: r.opt_f64()?,
                speed_accuracy_mps: r.opt_f64()?,
            };
            if !check_fix(&f) || last_fix_t.is_some_and(|t| f.t_s <= t) {
                return Err(SnapshotError::Invalid("held fix"));
            }
            last_fix_t = Some(f.t_s);
            *slot = Some(f);
        }
        for slot in &mut held.steps {
            let s = match r.u8()? {
                0 => continue,
                1 => StepSample::Count {
                    t_s: r.f64()?,
                    steps: r.u64()?,
                },
                2 => StepSample::Event { t_s: r.f64()? },
                3 => StepSample::Cadence {
                    t_s: r.f64()?,
                    steps_per_min: r.f64()?,
                },
                _ => return Err(SnapshotError::Invalid("held step sample")),
            };
            if !check_steps(&s) || last_steps_t.is_some_and(|t| s.t_s() <= t) {
                return Err(SnapshotError::Invalid("held step sample"));
            }
            last_steps_t = Some(s.t_s());
            *slot = Some(s);
        }
        Ok(held)
    }
}
