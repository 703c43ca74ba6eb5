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
use self::heading::{wrap_pi, Heading, MAG_HEADING_NOISE_RAD2_S, UNKNOWN_VAR_RAD2};
use self::magnetic::{gain, MagDisturbance, MagLimits};
use self::rest::{Rest, RestLimits};
use self::tilt::Tilt;
use super::flags::AhrsFlags;
use super::frame::EarthFrame;
use super::madgwick::GYRO_CLIP_SHARE;
use super::quat::{self, Quat};
use super::settings::AhrsSettings;
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

/// An interval longer than this many typical intervals is a gap: samples were lost
/// (a Bluetooth burst, a busy phone) and the rotation meanwhile is unknown.
pub const GAP_INTERVALS: f64 = 3.0;
/// A gap is bridged by the gyroscope (the mean of the rates before and after it,
/// integrated over the gap) when the rotation that could hide in it, the larger rate
/// times the gap, is below this, rad (2°); beyond, the averages restart as after a
/// clipped gyroscope.
pub const GAP_BRIDGE_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;
/// How wrong an accelerometer average over T seconds is in hand or body motion,
/// times T, rad·s: its linear acceleration averages to Δv/T, and |Δv| ≲ 0.5 m/s makes
/// ≈0.05/T rad (1° over 3 s). After the gyroscope missed up to θ, the average keeps
/// the weight of one that is θ off (T = this / θ), so it re-converges as fast as the
/// miss was large, without restarting from one sample.
pub const TILT_NOISE_RAD_S: f64 = 0.05;
/// The inclination is taken as converged (its dip judged, its heading measurements
/// at full weight) once the accelerometer average spans this long, s (≈3° of error).
pub const TILT_KNOWN_S: f64 = 1.0;
/// A bound on a measurement's variance, rad² (a tilt nothing is known about, through a
/// field near the vertical).
const MAX_MEASUREMENT_VAR_RAD2: f64 = 1e12;
/// What one clipped gyroscope sample may have missed, rad (5°).
pub const CLIP_MISSED_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// The heading counts as converged (flag `initialising` off) once its gain is within
/// this factor of the steady-state dt/τ.
const HEADING_CONVERGED_GAINS: f64 = 2.0;
/// Gain per sample of the typical interval (a running mean over ~100 samples of the
/// intervals that are not gaps).
const TYPICAL_INTERVAL_GAIN: f64 = 0.01;
/// A gyroscope axis that reads exactly the same value on many consecutive samples at
/// a rate of at least this, rad/s (115°/s), is clipped: a sensor's output code
/// saturates, while a real rate that fast rarely holds one code. Catches the clipping
/// of a gyroscope whose range the settings do not know.
pub const CLIP_PLATEAU_MIN_RADS: f64 = 2.0;
/// Repeats (samples after the first) that make a plateau: the BROAD sensor's own
/// quantisation repeats a reading above 2 rad/s up to 5 times in 16 trials.
const CLIP_PLATEAU_REPEATS: u8 = 8;

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
    /// 1/τ_acc² and the heading's random-walk density (rad²/s) that makes the steady-
    /// state magnetometer gain dt/τ_mag.
    inv_accel_tau2: f64,
    heading_q: f64,
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
    /// Typical interval between samples, s (0 before the second sample).
    dt_typ_s: f64,
    /// The previous raw gyroscope reading, rad/s, and how many samples in a row
    /// repeated it on a fast axis (the plateau of a clipped gyroscope).
    gyro_prev: [f64; 3],
    plateau_run: u8,
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
            inv_accel_tau2: 1.0 / (d.accel_time_constant_s * d.accel_time_constant_s),
            heading_q: MAG_HEADING_NOISE_RAD2_S / (d.mag_time_constant_s * d.mag_time_constant_s),
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
            dt_typ_s: 0.0,
            gyro_prev: [0.0; 3],
            plateau_run: 0,
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
        self.gyro_prev = *gyro;
        self.plateau_run = 0;
        self.mag.restart(&self.mag_limits);
        self.heading = Heading::default();
        self.bias_corr = [0.0; 3];
        self.bias_elapsed_s = 0.0;
        self.mag_elapsed_s = 0.0;
        let measured = mag.and_then(|m| measure(&quat::rotate(&self.tilt.q_body_to_e(), m)));
        self.heading_init = measured.is_some();
        match measured {
            Some(f) => {
                self.heading.reset_to(f.heading_rad);
                self.mag
                    .assess(f.norm_ut, f.dip_rad, 0.0, false, &self.mag_limits);
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

        // Angular-rate recovery: a clipped reading, or a gap the held rate cannot
        // bridge, makes the integration wrong; restart the averages so that
        // accelerometer and magnetometer take over at once.
        let clip = self.gyro_clip_rads;
        let prev = self.gyro_prev;
        let clipped = (gyro[0].abs() > clip)
            | (gyro[1].abs() > clip)
            | (gyro[2].abs() > clip)
            | self.plateau(&gyro);
        let gap = self.gap(dt);
        let missed2 = if gap {
            bridge_angle2(&prev, &gyro, dt)
        } else {
            0.0
        };
        let bridged = missed2 <= GAP_BRIDGE_RAD * GAP_BRIDGE_RAD;
        let lost = clipped | !bridged;

        // Rest and the bias at rest.
        if self.bias_estimation {
            let max_var = self.max_bias_rads * self.max_bias_rads;
            self.bias.predict(self.bias_q * dt, max_var);
            let at_rest = self.rest.step(&gyro, a, dt, &self.rest_limits);
            if at_rest {
                let k = gain(dt, self.inv_rest_bias_tau);
                self.bias.rest(&gyro, k, self.max_bias_rads);
            }
            flags.at_rest = at_rest;
            flags.bias_learning = at_rest;
        }
        let b = &self.bias.b;
        let w = if gap {
            // Across a gap, the mean of the rates on either side.
            std::array::from_fn(|i| 0.5 * (gyro[i] + prev[i]) - b[i])
        } else {
            [gyro[0] - b[0], gyro[1] - b[1], gyro[2] - b[2]]
        };
        self.tilt.integrate(&w, dt);
        if lost {
            flags.angular_rate_recovery = true;
            // A clipped reading missed at least what it would have turned by.
            let missed = if bridged {
                let w2 = gyro[0] * gyro[0] + gyro[1] * gyro[1] + gyro[2] * gyro[2];
                CLIP_MISSED_RAD.max(w2.sqrt() * dt)
            } else {
                missed2.sqrt()
            };
            self.recover(missed);
        }

        // Inclination from the accelerometer averaged in the almost-inertial frame.
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
        let learn_motion = self.bias_estimation & !flags.at_rest & !accel_init & !lost;
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

        // The slow loops (time constants of 10 s and more) run at most every
        // SLOW_PERIOD_S: the motion bias from the corrections summed since, the
        // heading from the magnetometer sample at hand.
        self.bias_elapsed_s += dt;
        self.mag_elapsed_s += dt;
        let mag_due = mag.is_some() & ((self.mag_elapsed_s >= SLOW_PERIOD_S) | !self.heading.valid);
        let bias_due = self.bias_elapsed_s >= SLOW_PERIOD_S;
        if mag_due | bias_due {
            let q_be = self.tilt.q_body_to_e();
            if bias_due {
                let dt_b = self.bias_elapsed_s;
                self.bias_elapsed_s = 0.0;
                let c = self.bias_corr;
                if (c[0] != 0.0) | (c[1] != 0.0) {
                    self.bias_corr = [0.0; 3];
                    let c_body = quat::rotate(&quat::conj(&q_be), &c);
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
            if let (true, Some(m)) = (mag_due, mag) {
                let dt_m = self.mag_elapsed_s;
                self.mag_elapsed_s = 0.0;
                let e = quat::rotate(&q_be, m);
                let v = self.correct_heading(&q_be, &e, dt_m, t_avg);
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
        if flags.angular_rate_recovery & !accel_init & !self.heading_init {
            flags.angular_rate_recovery = lost;
        }
        flags.initialising = accel_init | self.heading_init;
        self.flags = flags;
        flags
    }

    /// The gyroscope's integration was lost by up to `missed` rad (a clipped reading,
    /// a gap it cannot bridge): the accelerometer average keeps only the weight of an
    /// average as wrong as that ([`TILT_NOISE_RAD_S`] / missed, s) and the heading's
    /// variance grows by missed².
    #[cold]
    fn recover(&mut self, missed: f64) {
        self.accel_elapsed_s = self.accel_elapsed_s.min(TILT_NOISE_RAD_S / missed);
        self.heading.widen(missed * missed);
    }

    /// Whether the gyroscope repeats a fast reading exactly (a clipped axis).
    #[inline(always)]
    fn plateau(&mut self, gyro: &[f64; 3]) -> bool {
        let p = &self.gyro_prev;
        let same = |i: usize| (gyro[i] == p[i]) & (gyro[i].abs() >= CLIP_PLATEAU_MIN_RADS);
        self.plateau_run = if same(0) | same(1) | same(2) {
            self.plateau_run.saturating_add(1)
        } else {
            0
        };
        self.gyro_prev = *gyro;
        self.plateau_run >= CLIP_PLATEAU_REPEATS
    }

    /// Whether `dt` is a gap (samples lost); learns the typical interval from the
    /// intervals that are not gaps.
    #[inline(always)]
    fn gap(&mut self, dt: f64) -> bool {
        if self.dt_typ_s <= 0.0 {
            self.dt_typ_s = dt;
            return false;
        }
        if dt <= GAP_INTERVALS * self.dt_typ_s {
            self.dt_typ_s += TYPICAL_INTERVAL_GAIN * (dt - self.dt_typ_s);
            return false;
        }
        true
    }

    /// One magnetometer update of the heading (`dt` since the previous one) from the
    /// field `e` seen in E' (µT), with the accelerometer averaged over
    /// `t_avg` s.
    #[inline(always)]
    fn correct_heading(&mut self, q_be: &Quat, e: &[f64; 3], dt: f64, t_avg: f64) -> HeadingUpdate {
        let mut out = HeadingUpdate::default();
        let Some(f) = measure(e) else {
            return out;
        };
        if !self.heading.valid {
            self.heading.reset_to(f.heading_rad);
            self.mag.restart(&self.mag_limits);
        }
        let tilt_known = t_avg >= TILT_KNOWN_S;
        let v = self
            .mag
            .assess(f.norm_ut, f.dip_rad, dt, tilt_known, &self.mag_limits);
        if v.recovered {
            self.heading.forget();
            out.recovered = true;
        }
        out.disturbed = v.disturbed;
        if v.use_it {
            // The measurement's variance: the magnetometer's, and what the
            // inclination's error beyond its converged one turns it by through the dip.
            let inv_t = 1.0 / t_avg;
            let extra = TILT_NOISE_RAD_S
                * TILT_NOISE_RAD_S
                * (inv_t * inv_t - self.inv_accel_tau2).max(0.0);
            let r = MAG_HEADING_NOISE_RAD2_S / dt + f.tan2_dip * extra;
            let q = self.heading_q * dt;
            let innovation = wrap_pi(f.heading_rad - self.heading.delta_rad);
            let (d, k) = self
                .heading
                .correct(innovation, q, r.min(MAX_MEASUREMENT_VAR_RAD2));
            self.heading_init = k > HEADING_CONVERGED_GAINS * dt * self.inv_mag_tau;
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
        let t = &self.tilt;
        w.f64s(&t.q_gyr);
        w.f64s(&t.q_inc);
        w.f64s(&t.avg);
        w.f64s(&t.avg_rate);
        w.f64s(&self.bias.b);
        w.f64(self.bias.var);
        w.f64s(&self.rest.gyro_mean);
        w.f64s(&self.rest.accel_mean);
        w.f64s(&self.rest.gyro_short);
        w.f64s(&self.rest.accel_short);
        w.f64s(&self.rest.gyro_short2);
        w.f64s(&self.rest.accel_short2);
        w.f64(self.rest.vibration2);
        w.f64(self.rest.still_s);
        w.f64(self.heading.delta_rad);
        w.bool(self.heading.valid);
        w.f64(self.heading.var_rad2);
        let m = &self.mag;
        w.f64s(&[m.ref_norm_ut, m.ref_dip_rad]);
        w.bool(m.ref_valid);
        w.bool(m.dip_trusted);
        w.f64s(&[m.norm_ut, m.dip_rad, m.undisturbed_s, m.rejected_s]);
        w.f64(self.accel_elapsed_s);
        w.f64s(&self.bias_corr);
        w.f64(self.bias_elapsed_s);
        w.f64(self.mag_elapsed_s);
        w.bool(self.heading_init);
        w.f64(self.dt_typ_s);
        w.f64s(&self.gyro_prev);
        w.u8(self.plateau_run);
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
        r.f64s(&mut self.rest.gyro_short)?;
        r.f64s(&mut self.rest.accel_short)?;
        r.f64s(&mut self.rest.gyro_short2)?;
        r.f64s(&mut self.rest.accel_short2)?;
        self.rest.vibration2 = r.f64()?;
        self.rest.still_s = r.f64()?;
        self.heading.delta_rad = r.f64()?;
        self.heading.valid = r.bool()?;
        self.heading.var_rad2 = r.f64()?;
        let m = &mut self.mag;
        let mut v = [0.0; 2];
        r.f64s(&mut v)?;
        [m.ref_norm_ut, m.ref_dip_rad] = v;
        m.ref_valid = r.bool()?;
        m.dip_trusted = r.bool()?;
        let mut v = [0.0; 4];
        r.f64s(&mut v)?;
        [m.norm_ut, m.dip_rad, m.undisturbed_s, m.rejected_s] = v;
        self.accel_elapsed_s = r.f64()?;
        r.f64s(&mut self.bias_corr)?;
        self.bias_elapsed_s = r.f64()?;
        self.mag_elapsed_s = r.f64()?;
        self.heading_init = r.bool()?;
        self.dt_typ_s = r.f64()?;
        r.f64s(&mut self.gyro_prev)?;
        self.plateau_run = r.u8()?;

        let t = &self.tilt;
        let finite = [
            t.avg,
            t.avg_rate,
            self.bias.b,
            self.rest.gyro_mean,
            self.rest.accel_mean,
            self.rest.gyro_short,
            self.rest.accel_short,
            self.rest.gyro_short2,
            self.rest.accel_short2,
            self.gyro_prev,
        ]
        .iter()
        .flatten()
        .chain(&[
            self.rest.still_s,
            self.heading.delta_rad,
            self.heading.var_rad2,
            m.ref_norm_ut,
            m.ref_dip_rad,
            m.norm_ut,
            m.dip_rad,
            m.undisturbed_s,
            m.rejected_s,
            self.accel_elapsed_s,
            self.bias.var,
            self.dt_typ_s,
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
            || !(0.0..=UNKNOWN_VAR_RAD2).contains(&self.heading.var_rad2)
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
            && within(&self.rest.gyro_short, w_max)
            && within(&self.rest.accel_short, A)
            && within(&self.rest.gyro_short2, w_max)
            && within(&self.rest.accel_short2, A)
            && (0.0..=4.0 * A * A).contains(&self.rest.vibration2)
            && within(&self.gyro_prev, MAX_GYRO_RADS)
            && self.dt_typ_s >= 0.0
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

/// The square of the rotation a gap of `dt` could hide: the larger of the rates on
/// either side of it, times the gap.
#[cold]
fn bridge_angle2(before: &[f64; 3], after: &[f64; 3], dt: f64) -> f64 {
    let n2 = |w: &[f64; 3]| w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    n2(before).max(n2(after)) * dt * dt
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
    /// tan² of the dip (how much a tilt error turns the measured heading, squared).
    tan2_dip: f64,
}

/// Magnitude, dip and measured heading offset of a field sample `e` seen in E'.
#[inline(always)]
fn measure(e: &[f64; 3]) -> Option<Field> {
    let h2 = e[0] * e[0] + e[1] * e[1];
    let n2 = h2 + e[2] * e[2];
    if n2 <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some(Field {
        norm_ut: n2.sqrt(),
        dip_rad: (-e[2]).atan2(h),
        tan2_dip: if h2 > 0.0 {
            e[2] * e[2] / h2
        } else {
            UNKNOWN_VAR_RAD2
        },
        // Rz(δ) must turn the horizontal field (azimuth ψ east of north) to north:
        // δ = ψ.
        heading_rad: e[0].atan2(e[1]),
    })
}
