//! The input checks every AHRS filter shares ("the door"): finite numbers, the axis
//! remap, strictly increasing time, accelerations in m/s² rather than g, and the
//! decision whether a sample (re)starts the filter. Nothing mutates until every
//! check passed: a rejected sample leaves the filter exactly as it was.
//!
//! # Units heuristic
//! Accelerations must be m/s². A common mistake is passing g (iOS Core Motion): a
//! filter would still find the tilt (it normalises `a`), but every threshold would be
//! off by 9.8×. (1) The sample that (re)initialises the filter is refused if |a| is in
//! 0.8..=1.2 while the gyroscope reads below 0.5 rad/s — a device at rest in g
//! units; in m/s² that would be near free fall at rest, which does not happen;
//! (2) afterwards the mean |a| over ~1 s (exponential, τ = 1 s) must stay above
//! 2.5 m/s²: in g units it sits near 1 even while running, in m/s² it falls that low
//! only after more than 1.3 s of free fall. Both return
//! [`AhrsError::AccelerationNotInMps2`]. Switching from m/s² to g mid-stream is
//! caught after ~1.8 s.
//!
//! # Absurd but finite values
//! Readings beyond ±[`GYRO_SATURATION_RADS`], ±[`ACCEL_SATURATION_MPS2`] and
//! ±[`MAG_SATURATION_UT`] per axis — orders of magnitude beyond any sensor's range —
//! are saturated there, so that no square or product in a filter can overflow: a
//! finite input never makes the orientation non-finite. (A gyroscope reading that
//! large is far beyond its range: the filters' clipping recovery takes over.)

use super::error::{finite3, AhrsError};
use super::frame::AxisRemap;
use super::quat::min;

/// Units heuristic (1): |a| band of a device at rest reporting in g.
const G_UNITS_LOW: f64 = 0.8;
const G_UNITS_HIGH: f64 = 1.2;
/// ... with the gyroscope below this, rad/s.
const G_UNITS_STILL_RADS: f64 = 0.5;
/// Units heuristic (2): time constant of the mean |a|, s, the time it must have run,
/// s, and the lowest mean |a| accepted, m/s².
const ACCEL_MEAN_TAU_S: f64 = 1.0;
const ACCEL_MEAN_SPAN_S: f64 = 1.0;
const ACCEL_MEAN_MIN_MPS2: f64 = 2.5;
/// Saturation of absurd readings (see the module docs): gyroscope, rad/s (~570 000°/s).
pub const GYRO_SATURATION_RADS: f64 = 1e4;
/// ... accelerometer, m/s² (~10 000 g).
pub const ACCEL_SATURATION_MPS2: f64 = 1e5;
/// ... magnetometer, µT (1 T).
pub const MAG_SATURATION_UT: f64 = 1e6;

#[inline(always)]
fn saturate(v: [f64; 3], limit: f64) -> [f64; 3] {
    v.map(|x| {
        if x > limit {
            limit
        } else if x < -limit {
            -limit
        } else {
            x
        }
    })
}

/// State of the door: time and the running mean |a| of the units check.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Door {
    pub(crate) started: bool,
    pub(crate) last_t_s: f64,
    /// Mean |a| (units heuristic), m/s², and how long it has run, s (capped).
    pub(crate) accel_mean_mps2: f64,
    pub(crate) accel_mean_span_s: f64,
}

/// A sample that passed the door, in body axes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Admitted {
    pub(crate) t_s: f64,
    pub(crate) gyro: [f64; 3],
    pub(crate) accel: [f64; 3],
    pub(crate) mag: Option<[f64; 3]>,
    /// |a|², |a|.
    pub(crate) a2: f64,
    pub(crate) a_norm: f64,
    /// Interval since the previous accepted sample, s (meaningless when `restart`).
    pub(crate) dt: f64,
    /// The filter starts (first sample) or restarts (gap longer than `max_gap_s`)
    /// from this sample.
    pub(crate) restart: bool,
    mean: f64,
    span: f64,
}

impl Door {
    /// Checks one sample; nothing changes. Call [`Door::commit`] to accept it.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn check(
        &self,
        remap: Option<&AxisRemap>,
        max_gap_s: f64,
        t_s: f64,
        gyro_rads: [f64; 3],
        accel_mps2: [f64; 3],
        mag_ut: Option<[f64; 3]>,
    ) -> Result<Admitted, AhrsError> {
        if !t_s.is_finite() {
            return Err(AhrsError::NonFinite { field: "t_s" });
        }
        finite3("gyro_rads", &gyro_rads)?;
        finite3("accel_mps2", &accel_mps2)?;
        if let Some(m) = &mag_ut {
            finite3("mag_ut", m)?;
        }
        let (gyro, accel, mag) = match remap {
            None => (gyro_rads, accel_mps2, mag_ut),
            Some(r) => (
                r.apply(gyro_rads),
                r.apply(accel_mps2),
                mag_ut.map(|m| r.apply(m)),
            ),
        };
        let (gyro, accel, mag) = (
            saturate(gyro, GYRO_SATURATION_RADS),
            saturate(accel, ACCEL_SATURATION_MPS2),
            mag.map(|m| saturate(m, MAG_SATURATION_UT)),
        );
        let a2 = accel[0] * accel[0] + accel[1] * accel[1] + accel[2] * accel[2];
        let a_norm = a2.sqrt();
        let dt = t_s - self.last_t_s;
        if self.started && dt <= 0.0 {
            return Err(AhrsError::TimeNotIncreasing {
                t_s,
                last_t_s: self.last_t_s,
            });
        }
        let restart = !self.started || dt > max_gap_s;
        let (mean, span) = if restart {
            let w2 = gyro[0] * gyro[0] + gyro[1] * gyro[1] + gyro[2] * gyro[2];
            if (G_UNITS_LOW..=G_UNITS_HIGH).contains(&a_norm)
                && w2 < G_UNITS_STILL_RADS * G_UNITS_STILL_RADS
            {
                return Err(AhrsError::AccelerationNotInMps2 { magnitude: a_norm });
            }
            (a_norm, 0.0)
        } else {
            let k = min(dt * (1.0 / ACCEL_MEAN_TAU_S), 1.0);
            let mean = self.accel_mean_mps2 + k * (a_norm - self.accel_mean_mps2);
            let span = self.accel_mean_span_s + dt;
            if span >= ACCEL_MEAN_SPAN_S && mean < ACCEL_MEAN_MIN_MPS2 {
                return Err(AhrsError::AccelerationNotInMps2 { magnitude: mean });
            }
            (mean, min(span, ACCEL_MEAN_SPAN_S))
        };
        Ok(Admitted {
            t_s,
            gyro,
            accel,
            mag,
            a2,
            a_norm,
            dt,
            restart,
            mean,
            span,
        })
    }

    /// Accepts a checked sample.
    #[inline(always)]
    pub(crate) fn commit(&mut self, s: &Admitted) {
        self.started = true;
        self.last_t_s = s.t_s;
        self.accel_mean_mps2 = s.mean;
        self.accel_mean_span_s = s.span;
    }
}
