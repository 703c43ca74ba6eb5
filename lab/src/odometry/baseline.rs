//! The baselines: naive double integration of the linear acceleration, with the
//! orientation fixed at the initial attitude (the paper's baseline: the phone is
//! assumed not to rotate) or following the AHRS.
//!
//! `v += ½ (a_prev + a) Δt`, `p += ½ (v_prev + v) Δt` (trapezoids, horizontal ENU),
//! starting at rest at the origin. Gaps longer than the AHRS's `max_gap_s` are not
//! integrated (the velocity is kept).

use stridekit_core::ahrs::{Ahrs, AhrsSettings};
use stridekit_core::input;
use stridekit_core::odometry::rotate;
use stridekit_core::odometry::ImuSample;
use stridekit_core::odometry::OdometryError;

/// Which orientation rotates the acceleration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NaiveMode {
    /// The attitude at the first sample, kept for ever.
    FixedOrientation,
    /// The AHRS attitude of every sample.
    AhrsOrientation,
}

/// Naive double integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct NaiveOdometry {
    mode: NaiveMode,
    use_magnetometer: bool,
    ahrs: Ahrs,
    q_fixed: Option<[f64; 4]>,
    last: Option<(f64, [f64; 2])>,
    time: stridekit_core::input::TimeGuard,
    velocity_mps: [f64; 2],
    position_m: [f64; 2],
}

impl NaiveOdometry {
    pub fn new(
        mode: NaiveMode,
        ahrs: AhrsSettings,
        use_magnetometer: bool,
    ) -> Result<Self, OdometryError> {
        Ok(Self {
            mode,
            use_magnetometer,
            ahrs: Ahrs::new(ahrs)?,
            q_fixed: None,
            last: None,
            time: stridekit_core::input::TimeGuard::new(stridekit_core::input::Stream::Imu),
            velocity_mps: [0.0; 2],
            position_m: [0.0; 2],
        })
    }

    /// One sample; on error nothing changes.
    pub fn push(&mut self, s: &ImuSample) -> Result<(), OdometryError> {
        self.time.check(s.t_s)?;
        input::accel(&s.accel_mps2)?;
        input::gyro(&s.gyro_rads)?;
        if let Some(m) = &s.mag_ut {
            input::mag(m)?;
        }
        let mag = if self.use_magnetometer {
            s.mag_ut
        } else {
            None
        };
        self.ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, mag)?;
        let q_now = self.ahrs.quaternion().unwrap_or([1.0, 0.0, 0.0, 0.0]);
        let q = match self.mode {
            NaiveMode::FixedOrientation => *self.q_fixed.get_or_insert(q_now),
            NaiveMode::AhrsOrientation => q_now,
        };
        let a3 = rotate(&q, &s.accel_mps2);
        let a = [a3[0], a3[1]];
        if let Some((t0, a0)) = self.last {
            let dt = s.t_s - t0;
            if dt <= self.ahrs.settings().max_gap_s {
                let v0 = self.velocity_mps;
                for i in 0..2 {
                    self.velocity_mps[i] += 0.5 * (a0[i] + a[i]) * dt;
                    self.position_m[i] += 0.5 * (v0[i] + self.velocity_mps[i]) * dt;
                }
            }
        }
        self.last = Some((s.t_s, a));
        self.time.accept(s.t_s);
        Ok(())
    }

    pub fn position_m(&self) -> [f64; 2] {
        self.position_m
    }

    pub fn velocity_mps(&self) -> [f64; 2] {
        self.velocity_mps
    }
}
