//! The decoupled orientation filter: stridekit's default AHRS
//! ([`AhrsAlgorithm::Decoupled`](super::AhrsAlgorithm::Decoupled)).
//!
//! Designed from the physics of the three sensors, after studying why VQF (Laidig &
//! Seel 2023) is accurate and how x-io's Fusion rejects and recovers; stridekit's own
//! code. The orientation body → ENU is a product of three parts, each corrected by the
//! sensor that observes it and nothing else:
//!
//! ```text
//!   q = Rz(δ) ⊗ q_inc ⊗ q_gyr
//!        │       │       └─ gyroscope strapdown, bias-corrected   (tilt.rs, bias.rs)
//!        │       └─ inclination: accelerometer averaged in the
//!        │          almost-inertial frame of q_gyr                 (tilt.rs)
//!        └─ heading about the vertical: magnetometer, with
//!           disturbance rejection and recovery                     (heading.rs, magnetic.rs)
//! ```
//!
//! - **Inclination** ([`tilt`]): the specific force rotated into the gyroscope's
//!   frame averages to gravity (bounded velocity ⇒ zero-mean linear acceleration), so
//!   linear acceleration is filtered out without rejecting samples, and rotation does
//!   not smear the average.
//! - **Gyroscope bias** ([`bias`]): at rest ([`rest`]) from the gyroscope itself, in
//!   motion from the inclination corrections (what the residual bias does to the
//!   almost-inertial frame), optionally about the vertical from the heading
//!   corrections.
//! - **Heading** ([`heading`]): the magnetometer only ever turns the estimate about
//!   the vertical, so a disturbed field cannot tilt it; disturbances (magnitude or
//!   dip off the learned field) are rejected and the heading is held on the
//!   gyroscope, with recovery after a long disturbance ([`magnetic`]).
//!
//! One update is ~300 floating-point operations and allocates nothing.

mod bias;
mod heading;
mod magnetic;
mod rest;
mod settings;
mod tilt;

use self::bias::Bias;
use self::heading::Heading;
use self::magnetic::{gain, MagDisturbance, MagLimits};
use self::rest::{Rest, RestLimits};
use self::tilt::Tilt;
use super::flags::AhrsFlags;
use super::frame::EarthFrame;
use super::madgwick::GYRO_CLIP_SHARE;
use super::quat::{self, Quat};
use super::settings::AhrsSettings;
use crate::angle::wrap;
use crate::snapshot::{Reader, SnapshotError, Writer};

pub use self::settings::DecoupledSettings;
/// The named defaults of [`DecoupledSettings`].
pub use self::settings::{
    DEFAULT_ACCEL_TIME_CONSTANT_S, DEFAULT_BIAS_RANDOM_WALK, DEFAULT_HEADING_BIAS_TIME_CONSTANT_S,
    DEFAULT_MAG_DIP_THRESHOLD_RAD, DEFAULT_MAG_MAX_REJECTION_S, DEFAULT_MAG_MIN_UNDISTURBED_S,
    DEFAULT_MAG_NORM_THRESHOLD, DEFAULT_MAG_TIME_CONSTANT_S, DEFAULT_MAX_BIAS_RADS,
    DEFAULT_MOTION_BIAS_ACCURACY_RADS, DEFAULT_MOTION_BIAS_TIME_CONSTANT_S,
    DEFAULT_REST_ACCEL_MPS2, DEFAULT_REST_BIAS_TIME_CONSTANT_S, DEFAULT_REST_GYRO_RADS,
    DEFAULT_REST_TIME_S,
};

/// The slow loops (motion bias, magnetometer heading: time constants ≥ 10 s) run at
/// most this often, s (100 Hz).
pub const SLOW_PERIOD_S: f64 = 0.01;

/// The bias uncertainty at which the averaging time is the nominal one, rad/s
/// (0.3°/s): the lag such a bias causes over 3 s (≈1°) is then about what linear
/// acceleration leaves in a 3 s average of hand motion. With a worse-known bias
/// (after a start without rest), the average is shortened by (σ_b/0.3°/s)^(-1/2);
/// once rest or motion has taught the bias, it is the nominal one.
pub const BALANCE_BIAS_RADS: f64 = 0.3 * std::f64::consts::PI / 180.0;
const BALANCE_BIAS_VAR: f64 = BALANCE_BIAS_RADS * BALANCE_BIAS_RADS;

/// The decoupled filter's state; driven by [`Ahrs`](super::Ahrs), which owns the
/// door checks.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Decoupled {
    // Derived from the settings (not serialised).
    accel_tau_s: f64,
    /// Cut-off of the accelerometer average, rad/s (√2 / averaging time).
    accel_omega: f64,
    motion_bias_gain: f64,
    bias_q: f64,
    motion_accuracy_var: f64,
    heading_bias_gain: f64,
    inv_rest_bias_tau: f64,
    inv_mag_tau: f64,
    max_bias_rads: f64,
    gyro_clip_rads: f64,
    bias_estimation: bool,
    rest_limits: RestLimits,
    mag_limits: MagLimits,
    // State.
    tilt: Tilt,
    bias: Bias,
    rest: Rest,
    heading: Heading,
    mag: MagDisturbance,
    /// Time since the (re)start, s (capped at the averaging time): the averaging time
    /// grows with it, so the first seconds converge as fast as the data allow.
    accel_elapsed_s: f64,
    /// Inclination corrections summed since the last motion-bias update (E', rad),
    /// and the times since the last motion-bias and magnetometer updates, s.
    bias_corr: [f64; 3],
    bias_elapsed_s: f64,
    mag_elapsed_s: f64,
    /// The heading is still a running mean (initialising).
    heading_init: bool,
    /// Flags carried from sample to sample (angular-rate and magnetic recovery, the
    /// last magnetometer verdict).
    flags: AhrsFlags,
}

impl Decoupled {
    pub(crate) fn new(s: &AhrsSettings) -> Self {
        let d = &s.decoupled;
        Self {
            accel_tau_s: d.accel_time_constant_s,
            accel_omega: std::f64::consts::SQRT_2 / d.accel_time_constant_s,
            motion_bias_gain: 1.0 / d.motion_bias_time_constant_s,
            bias_q: d.bias_random_walk * d.bias_random_walk,
            motion_accuracy_var: d.motion_bias_accuracy_rads * d.motion_bias_accuracy_rads,
            heading_bias_gain: 1.0 / d.heading_bias_time_constant_s,
            inv_rest_bias_tau: 1.0 / d.rest_bias_time_constant_s,
            inv_mag_tau: 1.0 / d.mag_time_constant_s,
            max_bias_rads: d.max_bias_rads,
            gyro_clip_rads: GYRO_CLIP_SHARE * s.gyro_range_rads,
            bias_estimation: s.bias_estimation,
            rest_limits: RestLimits {
                gyro2: d.rest_gyro_rads * d.rest_gyro_rads,
                accel2: d.rest_accel_mps2 * d.rest_accel_mps2,
                max_bias: d.max_bias_rads,
                time_s: d.rest_time_s,
            },
            mag_limits: MagLimits {
                norm_rel: d.mag_norm_threshold,
                dip_rad: d.mag_dip_threshold_rad,
                min_undisturbed_s: d.mag_min_undisturbed_s,
                max_rejection_s: d.mag_max_rejection_s,
            },
            tilt: Tilt {
                q_gyr: [1.0, 0.0, 0.0, 0.0],
                q_inc: [1.0, 0.0, 0.0, 0.0],
                ..Tilt::default()
            },
            bias: Bias {
                b: [0.0; 3],
                var: d.max_bias_rads * d.max_bias_rads,
            },
            rest: Rest::default(),
            heading: Heading::default(),
            mag: MagDisturbance::default(),
            accel_elapsed_s: 0.0,
            bias_corr: [0.0; 3],
            bias_elapsed_s: 0.0,
            mag_elapsed_s: 0.0,
            heading_init: false,
            flags: AhrsFlags::default(),
        }
    }

    /// Orientation body → ENU (unit length to rounding).
    #[inline(always)]
    pub(crate) fn q_enu(&self) -> Quat {
        let q = self.tilt.q_body_to_e();
        let (s, c) = (0.5 * self.heading.delta_rad).sin_cos();
        // Rz(δ) ⊗ q with Rz(δ) = (cos δ/2, 0, 0, sin δ/2).
        [
            c * q[0] - s * q[3],
            c * q[1] - s * q[2],
            c * q[2] + s * q[1],
            c * q[3] + s * q[0],
        ]
    }

    pub(crate) fn gyro_bias_rads(&self) -> [f64; 3] {
        self.bias.b
    }

    /// (Re)start from one sample (the learned bias is kept).
    pub(crate) fn start(
        &mut self,
        s: &AhrsSettings,
        gyro: &[f64; 3],
        accel: &[f64; 3],
        mag: Option<&[f64; 3]>,
    ) -> AhrsFlags {
        self.tilt.start(accel);
        self.rest.start(gyro, accel);
        self.accel_elapsed_s = 0.0;
        self.mag.restart(&self.mag_limits);
        self.heading = Heading::default();
        self.bias_corr = [0.0; 3];
        self.bias_elapsed_s = 0.0;
        self.mag_elapsed_s = 0.0;
        let measured = mag.and_then(|m| measure(&self.tilt.q_body_to_e(), m));
        self.heading_init = measured.is_some();
        match measured {
            Some(f) => {
                self.heading.reset_to(f.heading_rad);
                self.mag.assess(f.norm_ut, f.dip_rad, 0.0, &self.mag_limits);
            }
            None => {
                // No field: the output frame's yaw starts at 0 (as the Madgwick filter).
                let q_out = quat::mul(&s.frame.enu_to_frame(), &self.tilt.q_body_to_e());
                let (_, _, yaw) = quat::to_euler(&q_out);
                self.heading.delta_rad = match s.frame {
                    EarthFrame::Enu => -yaw,
                    EarthFrame::Ned => yaw,
                };
            }
        }
        self.flags = AhrsFlags {
            reinitialised: true,
            initialising: true,
            ..AhrsFlags::default()
        };
        self.flags
    }

    /// One accepted sample after the first.
    #[inline(always)]
    pub(crate) fn step(
        &mut self,
        dt: f64,
        gyro: [f64; 3],
        a: &[f64; 3],
        mag: Option<&[f64; 3]>,
    ) -> AhrsFlags {
        let mut flags = AhrsFlags {
            angular_rate_recovery: self.flags.angular_rate_recovery,
            mag_recovery: self.flags.mag_recovery,
            ..AhrsFlags::default()
        };
        // Angular-rate recovery: a clipped reading makes the integration wrong; restart
        // the averages so that accelerometer and magnetometer take over at once.
        let clip = self.gyro_clip_rads;
        let clipped = (gyro[0].abs() > clip) | (gyro[1].abs() > clip) | (gyro[2].abs() > clip);
        flags = self.rest_and_bias(&gyro, a, dt, flags);
        let b = &self.bias.b;
        let w = [gyro[0] - b[0], gyro[1] - b[1], gyro[2] - b[2]];
        self.tilt.integrate(&w, dt);
        if clipped {
            flags.angular_rate_recovery = true;
            self.tilt.reset_average(a);
            self.accel_elapsed_s = 0.0;
            self.heading.restart_averaging();
        }
        let accel_init;
        (flags, accel_init) = self.inclination(a, dt, clipped, flags);
        flags = self.slow_loops(dt, mag, flags);
        if flags.angular_rate_recovery & !accel_init & !self.heading_init {
            flags.angular_rate_recovery = clipped;
        }
        flags.initialising = accel_init | self.heading_init;
        self.flags = flags;
        flags
    }

    /// Rest detection and the bias at rest (with bias estimation on).
    #[inline(always)]
    fn rest_and_bias(
        &mut self,
        gyro: &[f64; 3],
        a: &[f64; 3],
        dt: f64,
        mut flags: AhrsFlags,
    ) -> AhrsFlags {
        if self.bias_estimation {
            let max_var = self.max_bias_rads * self.max_bias_rads;
            self.bias.predict(self.bias_q * dt, max_var);
            let at_rest = self.rest.step(gyro, a, dt, &self.rest_limits);
            if at_rest {
                let k = gain(dt, self.inv_rest_bias_tau);
                self.bias.rest(gyro, k, self.max_bias_rads);
            }
            flags.at_rest = at_rest;
            flags.bias_learning = at_rest;
        }
        flags
    }

    /// Inclination from the accelerometer averaged in the almost-inertial frame; its
    /// corrections summed for the motion bias; and whether the average is still starting.
    #[inline(always)]
    fn inclination(
        &mut self,
        a: &[f64; 3],
        dt: f64,
        clipped: bool,
        mut flags: AhrsFlags,
    ) -> (AhrsFlags, bool) {
        self.accel_elapsed_s += dt;
        let accel_init = self.accel_elapsed_s < self.accel_tau_s;
        let mut t_avg = if accel_init {
            self.accel_elapsed_s
        } else {
            self.accel_elapsed_s = self.accel_tau_s;
            self.accel_tau_s
        };
        // While the bias is poorly known, a shorter average: the lag an unknown bias
        // σ_b causes (σ_b·T) and the linear acceleration left in the average (∝ 1/T)
        // balance at T ∝ 1/√σ_b (see BALANCE_BIAS_RADS).
        let var = self.bias.var;
        let shorten = self.bias_estimation & (var > BALANCE_BIAS_VAR);
        let omega = if accel_init | shorten {
            if shorten {
                t_avg *= (BALANCE_BIAS_VAR / var).sqrt().sqrt();
            }
            std::f64::consts::SQRT_2 / t_avg
        } else {
            self.accel_omega
        };
        let learn_motion = self.bias_estimation & !flags.at_rest & !accel_init & !clipped;
        match self.tilt.correct(a, dt, omega) {
            Some(c) => {
                if learn_motion {
                    for (s, c) in self.bias_corr.iter_mut().zip(c) {
                        *s += c;
                    }
                    flags.bias_motion = self.motion_bias_gain > 0.0;
                }
            }
            None => flags.accel_rejected = true,
        }
        (flags, accel_init)
    }

    /// The slow loops (time constants of 10 s and more) run at most every
    /// SLOW_PERIOD_S: the motion bias from the corrections summed since, the heading
    /// from the magnetometer sample at hand.
    #[inline(always)]
    fn slow_loops(&mut self, dt: f64, mag: Option<&[f64; 3]>, mut flags: AhrsFlags) -> AhrsFlags {
        self.bias_elapsed_s += dt;
        self.mag_elapsed_s += dt;
        let mag_due = mag.is_some() & ((self.mag_elapsed_s >= SLOW_PERIOD_S) | !self.heading.valid);
        let bias_due = self.bias_elapsed_s >= SLOW_PERIOD_S;
        if mag_due | bias_due {
            let q_be = self.tilt.q_body_to_e();
            if bias_due {
                self.motion_bias(&q_be);
            }
            if let (true, Some(m)) = (mag_due, mag) {
                let dt_m = self.mag_elapsed_s;
                self.mag_elapsed_s = 0.0;
                let v = self.correct_heading(&q_be, m, dt_m);
                flags.mag_disturbed = v.disturbed;
                flags.mag_rejected = v.rejected;
                flags.heading_held = v.rejected;
                flags.mag_recovery = (flags.mag_recovery | v.recovered) & !v.converged;
            }
        } else if mag.is_some() {
            // Between magnetometer updates the verdict of the last one stands.
            flags.mag_disturbed = self.flags.mag_disturbed;
            flags.mag_rejected = self.flags.mag_rejected;
            flags.heading_held = self.flags.heading_held;
        }
        flags
    }

    /// The motion bias from the inclination corrections summed since the last update
    /// (`q_be`: body → E' now).
    #[inline(always)]
    fn motion_bias(&mut self, q_be: &Quat) {
        let dt_b = self.bias_elapsed_s;
        self.bias_elapsed_s = 0.0;
        let c = self.bias_corr;
        if (c[0] != 0.0) | (c[1] != 0.0) {
            self.bias_corr = [0.0; 3];
            let c_body = quat::rotate(&quat::conj(q_be), &c);
            let g = self.motion_bias_gain;
            self.bias.motion(
                &c_body,
                g,
                g * dt_b,
                self.motion_accuracy_var,
                self.max_bias_rads,
            );
        }
    }

    /// One magnetometer update of the heading (`dt` since the previous one).
    #[inline(always)]
    fn correct_heading(&mut self, q_be: &Quat, m: &[f64; 3], dt: f64) -> HeadingUpdate {
        let mut out = HeadingUpdate::default();
        let Some(f) = measure(q_be, m) else {
            return out;
        };
        if !self.heading.valid {
            self.heading.reset_to(f.heading_rad);
            self.mag.restart(&self.mag_limits);
        }
        let v = self.mag.assess(f.norm_ut, f.dip_rad, dt, &self.mag_limits);
        if v.recovered {
            self.heading.restart_averaging();
            out.recovered = true;
        }
        out.disturbed = v.disturbed;
        if v.use_it {
            let kh = gain(dt, self.inv_mag_tau);
            self.heading_init = self.heading.averaging(kh);
            let innovation = wrap(f.heading_rad - self.heading.delta_rad);
            let d = self.heading.correct(innovation, kh);
            if self.bias_estimation & !self.heading_init & (self.heading_bias_gain > 0.0) {
                // A turn of d about the vertical, in the body frame.
                let up = quat::rotate(&quat::conj(q_be), &[0.0, 0.0, d]);
                self.bias
                    .heading(&up, self.heading_bias_gain, self.max_bias_rads);
            }
            out.converged = !self.heading_init;
        } else {
            out.rejected = true;
        }
        out
    }

    pub(crate) fn write_state(&self, w: &mut Writer) {
        // Exhaustive on purpose, at every level: a new field must be written here (or
        // said to be derived from the settings), else this does not compile.
        let Decoupled {
            accel_tau_s: _,
            accel_omega: _,
            motion_bias_gain: _,
            bias_q: _,
            motion_accuracy_var: _,
            heading_bias_gain: _,
            inv_rest_bias_tau: _,
            inv_mag_tau: _,
            max_bias_rads: _,
            gyro_clip_rads: _,
            bias_estimation: _,
            rest_limits: _,
            mag_limits: _,
            tilt:
                Tilt {
                    q_gyr,
                    q_inc,
                    avg,
                    avg_rate,
                },
            bias: Bias { b, var },
            rest:
                Rest {
                    gyro_mean,
                    accel_mean,
                    still_s,
                },
            heading:
                Heading {
                    delta_rad,
                    valid,
                    averaged,
                },
            mag:
                MagDisturbance {
                    ref_norm_ut,
                    ref_dip_rad,
                    ref_valid,
                    norm_ut,
                    dip_rad,
                    undisturbed_s,
                    rejected_s,
                },
            accel_elapsed_s,
            bias_corr,
            bias_elapsed_s,
            mag_elapsed_s,
            heading_init,
            flags: _, // written by the engine with the output flags
        } = self;
        w.f64s(q_gyr);
        w.f64s(q_inc);
        w.f64s(avg);
        w.f64s(avg_rate);
        w.f64s(b);
        w.f64(*var);
        w.f64s(gyro_mean);
        w.f64s(accel_mean);
        w.f64(*still_s);
        w.f64(*delta_rad);
        w.bool(*valid);
        w.f64(*averaged);
        w.f64s(&[*ref_norm_ut, *ref_dip_rad]);
        w.bool(*ref_valid);
        w.f64s(&[*norm_ut, *dip_rad, *undisturbed_s, *rejected_s]);
        w.f64(*accel_elapsed_s);
        w.f64s(bias_corr);
        w.f64(*bias_elapsed_s);
        w.f64(*mag_elapsed_s);
        w.bool(*heading_init);
    }

    pub(crate) fn read_state(&mut self, r: &mut Reader) -> Result<(), SnapshotError> {
        let t = &mut self.tilt;
        r.f64s(&mut t.q_gyr)?;
        r.f64s(&mut t.q_inc)?;
        r.f64s(&mut t.avg)?;
        r.f64s(&mut t.avg_rate)?;
        r.f64s(&mut self.bias.b)?;
        self.bias.var = r.f64()?;
        r.f64s(&mut self.rest.gyro_mean)?;
        r.f64s(&mut self.rest.accel_mean)?;
        self.rest.still_s = r.f64()?;
        self.heading.delta_rad = r.f64()?;
        self.heading.valid = r.bool()?;
        self.heading.averaged = r.f64()?;
        let m = &mut self.mag;
        let mut v = [0.0; 2];
        r.f64s(&mut v)?;
        [m.ref_norm_ut, m.ref_dip_rad] = v;
        m.ref_valid = r.bool()?;
        let mut v = [0.0; 4];
        r.f64s(&mut v)?;
        [m.norm_ut, m.dip_rad, m.undisturbed_s, m.rejected_s] = v;
        self.accel_elapsed_s = r.f64()?;
        r.f64s(&mut self.bias_corr)?;
        self.bias_elapsed_s = r.f64()?;
        self.mag_elapsed_s = r.f64()?;
        self.heading_init = r.bool()?;
        let t = &self.tilt;
        let finite = [
            t.avg,
            t.avg_rate,
            self.bias.b,
            self.rest.gyro_mean,
            self.rest.accel_mean,
        ]
        .iter()
        .flatten()
        .chain(&[
            self.rest.still_s,
            self.heading.delta_rad,
            self.heading.averaged,
            m.ref_norm_ut,
            m.ref_dip_rad,
            m.norm_ut,
            m.dip_rad,
            m.undisturbed_s,
            m.rejected_s,
            self.accel_elapsed_s,
            self.bias.var,
        ])
        .all(|x| x.is_finite());
        if !finite {
            return Err(SnapshotError::Invalid("non-finite state"));
        }
        for q in [&t.q_gyr, &t.q_inc] {
            let n = q.iter().map(|c| c * c).sum::<f64>();
            if n.is_nan() || (n - 1.0).abs() >= 1e-6 {
                return Err(SnapshotError::Invalid("quaternion not unit"));
            }
        }
        if self.bias.b.iter().any(|b| b.abs() > self.max_bias_rads)
            || self.heading.delta_rad.abs() > std::f64::consts::PI
            || self.accel_elapsed_s < 0.0
            || self.bias.var < 0.0
            || self.heading.averaged < 0.0
        {
            return Err(SnapshotError::Invalid("state out of range"));
        }
        // Physical ranges: means of readings within the door's limits, a rate of the
        // averaged acceleration no faster than the door's largest change per short
        // sample, field magnitudes and dip angles, non-negative timers.
        use crate::input::limits::{MAX_ACCEL_NORM_MPS2 as A, MAX_GYRO_RADS, MAX_MAG_UT};
        let w_max = MAX_GYRO_RADS * 3f64.sqrt();
        let m_max = MAX_MAG_UT * 3f64.sqrt();
        let within = |v: &[f64], max: f64| v.iter().all(|x| x.abs() <= max);
        let m = &self.mag;
        let ok = within(&t.avg, tilt::MAX_AVG_MPS2)
            && within(&t.avg_rate, tilt::MAX_AVG_RATE_MPS3)
            && within(&self.rest.gyro_mean, w_max)
            && within(&self.rest.accel_mean, A)
            && within(&self.bias_corr, 1e6)
            && self.bias.var <= 1e6
            && self.rest.still_s >= 0.0
            && (0.0..=m_max).contains(&m.ref_norm_ut)
            && (0.0..=m_max).contains(&m.norm_ut)
            && m.ref_dip_rad.abs() <= std::f64::consts::PI
            && m.dip_rad.abs() <= std::f64::consts::PI
            && m.undisturbed_s >= 0.0
            && m.rejected_s >= 0.0
            && self.bias_elapsed_s >= 0.0
            && self.mag_elapsed_s >= 0.0;
        if !ok {
            return Err(SnapshotError::Invalid("state out of physical range"));
        }
        Ok(())
    }

    /// The flags carried from sample to sample (restored from a snapshot).
    pub(crate) fn set_flags(&mut self, flags: AhrsFlags) {
        self.flags = flags;
    }
}

/// What one magnetometer update did (returned by value: the flags stay in registers).
#[derive(Clone, Copy, Debug, Default)]
struct HeadingUpdate {
    disturbed: bool,
    rejected: bool,
    /// A recovery started now.
    recovered: bool,
    /// The heading is past its running mean (a recovery, if any, is over).
    converged: bool,
}

/// A field sample seen in E'.
#[derive(Clone, Copy, Debug)]
struct Field {
    norm_ut: f64,
    dip_rad: f64,
    heading_rad: f64,
}

/// Magnitude, dip and measured heading offset of a field sample `m` (body frame),
/// with `q` body → E'.
#[inline(always)]
fn measure(q: &Quat, m: &[f64; 3]) -> Option<Field> {
    let e = quat::rotate(q, m);
    let h2 = e[0] * e[0] + e[1] * e[1];
    let n2 = h2 + e[2] * e[2];
    if n2 <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some(Field {
        norm_ut: n2.sqrt(),
        dip_rad: (-e[2]).atan2(h),
        // Rz(δ) must turn the horizontal field (azimuth ψ east of north) to north:
        // δ = ψ.
        heading_rad: e[0].atan2(e[1]),
    })
}
