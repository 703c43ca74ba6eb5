//! The door of the AHRS, shared by both filters: the checks of the input layer
//! ([`crate::input`]: finite numbers within the IMU limits, time strictly increasing
//! and in seconds, accelerations in m/s² rather than g), the axis remap, and the
//! decision whether a sample (re)starts the filter. Nothing mutates until every check
//! passed: a rejected sample leaves the filter exactly as it was.
//!
//! The limits of the input layer (|a| ≤ 2 000 m/s², |ω| ≤ 200 rad/s, |m| ≤ 5 000 µT
//! per axis) keep every square and product in a filter far from overflow: no accepted
//! input can make the orientation non-finite.

use super::error::AhrsError;
use super::frame::AxisRemap;
use crate::input::{self, AccelUnits, Stream, TimeGuard};
use crate::snapshot::{Reader, SnapshotError, Writer};

/// State of the door: the stream's time and the g-units check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Door {
    pub(crate) time: TimeGuard,
    pub(crate) units: AccelUnits,
}

impl Default for Door {
    fn default() -> Self {
        Self {
            time: TimeGuard::new(Stream::Imu),
            units: AccelUnits::new(),
        }
    }
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
    /// The g-units check's mean |a| after this sample.
    mean: f64,
}

impl Door {
    /// Whether a sample was accepted yet.
    #[inline(always)]
    pub(crate) fn started(&self) -> bool {
        self.time.last_t_s().is_some()
    }

    /// Time of the newest accepted sample (0 before any).
    #[inline(always)]
    pub(crate) fn last_t_s(&self) -> f64 {
        self.time.last_t_s().unwrap_or(0.0)
    }

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
        let since = self.time.check(t_s)?;
        input::gyro(&gyro_rads)?;
        input::accel(&accel_mps2)?;
        if let Some(m) = &mag_ut {
            input::mag(m)?;
        }
        let (gyro, accel, mag) = match remap {
            None => (gyro_rads, accel_mps2, mag_ut),
            Some(r) => (
                r.apply(gyro_rads),
                r.apply(accel_mps2),
                mag_ut.map(|m| r.apply(m)),
            ),
        };
        let a2 = accel[0] * accel[0] + accel[1] * accel[1] + accel[2] * accel[2];
        let a_norm = a2.sqrt();
        let dt = since.unwrap_or(f64::INFINITY);
        let restart = dt > max_gap_s;
        // A (re)start takes the g-units check of a first sample.
        let mean = self.units.check((!restart).then_some(dt), a_norm)?;
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
        })
    }

    /// Accepts a checked sample.
    #[inline(always)]
    pub(crate) fn commit(&mut self, s: &Admitted) {
        self.time.accept(s.t_s);
        self.units.accept(s.mean);
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        self.time.write(w);
        self.units.write(w);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        Ok(Self {
            time: TimeGuard::read(r, Stream::Imu)?,
            units: AccelUnits::read(r)?,
        })
    }
}
