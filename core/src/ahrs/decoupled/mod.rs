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
//! - **Magnetometer offset** ([`hard_iron`]): a constant offset in the body frame
//!   (hard iron) is learned online from how the field turns with the gyroscope, and
//!   removed from every reading before the heading and the disturbance checks see it.
//! - **Clipped readings and gaps** ([`angular_rate`]): the averages keep only the
//!   weight the rotation the gyroscope may have missed leaves them.
//!
//! [`measure`] reads a magnetometer sample in E', [`snapshot`] writes and checks
//! the state.
//!
//! One update is ~300 floating-point operations and allocates nothing.

mod angular_rate;
mod bias;
mod hard_iron;
mod heading;
mod magnetic;
mod measure;
mod rest;
mod settings;
mod snapshot;
mod tilt;

use self::angular_rate::RateCheck;
use self::bias::Bias;
use self::hard_iron::HardIron;
use self::heading::{Heading, MAG_HEADING_NOISE_RAD2_S};
use self::magnetic::{gain, MagDisturbance, MagLimits};
use self::measure::{measure, Field};
use self::rest::{Rest, RestLimits};
use self::tilt::{Averaging, Tilt};
use super::flags::{AhrsFlags, PackedFlags};
use super::frame::EarthFrame;
use super::madgwick::GYRO_CLIP_SHARE;
use super::quat::{self, Quat};
use super::settings::AhrsSettings;
use crate::angle::wrap;

pub use self::settings::DecoupledSettings;
/// The named defaults of [`DecoupledSettings`].
pub use self::settings::{
    DEFAULT_ACCEL_TIME_CONSTANT_S, DEFAULT_BIAS_RANDOM_WALK, DEFAULT_HEADING_BIAS_TIME_CONSTANT_S,
    DEFAULT_MAG_DIP_THRESHOLD_RAD, DEFAULT_MAG_MAX_REJECTION_S, DEFAULT_MAG_MIN_UNDISTURBED_S,
    DEFAULT_MAG_NORM_THRESHOLD, DEFAULT_MAG_OFFSET_MAX_UT, DEFAULT_MAG_TIME_CONSTANT_S,
    DEFAULT_MAX_BIAS_RADS, DEFAULT_MOTION_BIAS_ACCURACY_RADS, DEFAULT_MOTION_BIAS_TIME_CONSTANT_S,
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

/// How wrong an accelerometer average over T seconds is in hand or body motion,
/// times T, rad·s: its linear acceleration averages to Δv/T, and |Δv| ≲ 0.5 m/s makes
/// ≈0.05/T rad (1° over 3 s). After the gyroscope missed up to θ, the average keeps
/// the weight of one that is θ off (T = this / θ), so it re-converges as fast as the
/// miss was large, without restarting from one sample.
pub const TILT_NOISE_RAD_S: f64 = 0.05;
/// A lost integration that may have missed this much or more, rad (a quarter turn),
/// leaves the accelerometer average nothing: gravity averaged in the old frame may lie
/// anywhere from along the new vertical to across it (or beyond: cos θ ≤ 0), so the
/// average restarts from the sample instead of keeping [`TILT_NOISE_RAD_S`] / θ of
/// weight. Measured on BROAD with 10 % of the samples dropped in bursts of 0.05–1 s:
/// over gaps of 0.4–1 s in fast motion the gyroscope's estimate misses 110–180° (rms),
/// and the old average's ≤ 32 ms of weight held the inclination for 0.1–0.3 s after
/// (mean error 14.10 → 13.24° with the restart).
pub const AVERAGE_LOST_RAD: f64 = std::f64::consts::FRAC_PI_2;
/// The inclination is taken as converged (its dip judged, its heading measurements
/// at full weight) once the accelerometer average spans this long, s (≈3° of error).
pub const TILT_KNOWN_S: f64 = 1.0;
/// A bound on a measurement's variance, rad² (a tilt nothing is known about, through a
/// field near the vertical).
const MAX_MEASUREMENT_VAR_RAD2: f64 = 1e12;
/// A heading the magnetometer keeps turning one way faster than this, rad/s
/// (1°/s, averaged over the heading's time constant), is turned by a gyroscope bias
/// about the vertical that the rest estimate no longer knows (a bias step: a
/// temperature jump, a knock), which leaves a steady lag of rate × τ_mag (20° at
/// 2°/s). Field noise averages out; what stays below is the field itself: a magnet
/// carried with the device (BROAD's attached-magnet trials) turns the heading
/// measurements with the device's attitude, up to ≈0.6°/s in this average.
pub const HEADING_DRIFT_ON_RADS: f64 = 1.0 * std::f64::consts::PI / 180.0;
/// Once learning, the bias about the vertical follows the heading corrections until
/// their mean rate falls below this, rad/s (0.25°/s: a lag of 2.5°).
pub const HEADING_DRIFT_OFF_RADS: f64 = 0.25 * std::f64::consts::PI / 180.0;
/// While it learns from a drift, the bias about the vertical is the integral term of
/// the heading loop (the magnetometer correction, gain 1/τ_mag, its proportional
/// term) with time constant this × τ_mag: the loop s² + s/τ + 1/(τ·τ_I) then has the
/// damping ½√(τ_I/τ) = 1/√2 (no ringing, the fastest such).
pub const HEADING_DRIFT_INTEGRAL_TAUS: f64 = 2.0;

/// The heading counts as converged (flag `initialising` off) once its gain is within
/// this factor of the steady-state dt/τ.
const HEADING_CONVERGED_GAINS: f64 = 2.0;
/// Once the magnetometer offset estimate has moved this far from the one the learned
/// field (magnitude, dip) was seen through, µT, that field is learned anew: it was
/// measured through the wrong offset (half the magnitude gate of a 45 µT field).
const OFFSET_RELEARN_UT: f64 = 2.0;
/// The offset estimate is removed from the readings only from this size on, µT: below
/// it the estimate's own error on real devices (soft iron, field gradients along the
/// path, timing between the sensors: 1–3 µT on BROAD's calibrated magnetometers) is
/// as large as the offset, and removing it costs more heading than it saves (measured:
/// with 0 µT the BROAD mean rises from 2.30° to 2.6–4.9°).
const MIN_OFFSET_UT: f64 = 5.0;

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
    /// Largest magnetometer offset, µT (0: not estimated).
    mag_offset_max_ut: f64,
    // State.
    tilt: Tilt,
    bias: Bias,
    rest: Rest,
    heading: Heading,
    mag: MagDisturbance,
    /// The magnetometer offset estimate; the offset removed from the readings (the
    /// estimate, from when it is first known on), and the one removed when the learned
    /// field was seen, µT.
    hard_iron: HardIron,
    offset_applied_ut: [f64; 3],
    offset_seen_ut: [f64; 3],
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
    /// Mean rate of the magnetometer's heading corrections, rad/s (low-pass over
    /// τ_mag, while the heading is converged), and whether the bias about the
    /// vertical is learning from it.
    heading_drift_rads: f64,
    drift_learning: bool,
    /// Typical interval between samples, s (0 before the second sample).
    dt_typ_s: f64,
    /// The previous raw gyroscope reading, rad/s, and how many samples in a row
    /// repeated it on a fast axis (the plateau of a clipped gyroscope).
    gyro_prev: [f64; 3],
    plateau_run: u8,
    /// What the clipped readings of the gyroscope may have missed and the
    /// accelerometer average still holds, rad (summed over a clip run, forgotten as
    /// the average forgets; see [`Self::heading_noise`]).
    clip_miss_rad: f64,
    /// Flags carried from sample to sample (angular-rate and magnetic recovery, the
    /// last magnetometer verdict), packed: the engine reads the latest sample's from here.
    flags: PackedFlags,
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
            mag_offset_max_ut: d.mag_offset_max_ut,
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
            hard_iron: HardIron::new(d.mag_offset_max_ut),
            offset_applied_ut: [0.0; 3],
            offset_seen_ut: [0.0; 3],
            accel_elapsed_s: 0.0,
            bias_corr: [0.0; 3],
            bias_elapsed_s: 0.0,
            mag_elapsed_s: 0.0,
            heading_init: false,
            heading_drift_rads: 0.0,
            drift_learning: false,
            dt_typ_s: 0.0,
            gyro_prev: [0.0; 3],
            plateau_run: 0,
            clip_miss_rad: 0.0,
            flags: PackedFlags::default(),
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

    /// The magnetometer offset estimate, µT, body frame, and whether it is still being
    /// learned (`None` when not estimated).
    pub(crate) fn mag_offset_ut(&self) -> Option<([f64; 3], bool)> {
        (self.mag_offset_max_ut > 0.0).then(|| (self.hard_iron.b, self.hard_iron.calibrating()))
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
        self.clip_miss_rad = 0.0;
        self.start_watch(gyro);
        // A restart after a gap keeps the learned field (see [`MagDisturbance::resume`]).
        let field_known = self.mag.ref_valid;
        if !field_known {
            self.mag.restart(&self.mag_limits);
        }
        self.heading = Heading::default();
        self.bias_corr = [0.0; 3];
        self.bias_elapsed_s = 0.0;
        self.mag_elapsed_s = 0.0;
        self.hard_iron.drop_anchor();
        self.offset_seen_ut = self.offset_applied_ut;
        self.heading_drift_rads = 0.0;
        self.drift_learning = false;
        let m_c = mag.map(|m| self.remove_offset(m));
        let measured = m_c.and_then(|m| measure(&quat::rotate(&self.tilt.q_body_to_e(), &m)));
        self.heading_init = measured.is_some();
        match measured {
            Some(f) => {
                self.heading.reset_to(f.heading_rad);
                if field_known {
                    self.mag.resume(f.norm_ut, f.dip_rad, &self.mag_limits);
                }
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
        let flags = AhrsFlags {
            reinitialised: true,
            initialising: true,
            // A restart after a gap lost the integration as a gap it could not bridge
            // does: the heading then keeps the inclination's error shared by its first
            // measurements (see [`Self::heading_noise`]).
            angular_rate_recovery: field_known,
            mag_calibrating: (self.mag_offset_max_ut > 0.0) & self.hard_iron.calibrating(),
            ..AhrsFlags::default()
        };
        self.flags = PackedFlags::pack(flags);
        flags
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
        let rate = self.check_rate(dt, &gyro);
        let at_rest = self.bias_at_rest(dt, &gyro, a);
        let a_i = self.tilt.integrate(&rate.rate(&gyro, &self.bias.b), dt, a);
        if rate.lost {
            self.recover(&rate, rate.missed_rad(&gyro, dt));
            self.hard_iron.drop_anchor();
        }
        // A gap holds no accelerometer samples: after a lost one, the sample weighs in
        // the average and its span as one typical interval (counting the whole gap
        // took a 1 s-old average for one the gap's length old, and the heading then
        // trusted its measurements through a tilt tens of degrees off).
        let dt_avg = if rate.lost & rate.gap {
            self.dt_typ_s
        } else {
            dt
        };
        let span = self.accel_span(dt_avg);
        if self.clip_miss_rad > 0.0 {
            self.forget_clip_miss(dt_avg, &span);
        }
        let learn_motion = self.bias_estimation & !at_rest & !span.init & !rate.lost;
        let recovering = rate.lost | self.flags.angular_rate_recovery();
        let (accel_rejected, bias_motion) =
            self.incline(&a_i, dt_avg, &span, recovering, learn_motion);
        let verdict = self.slow_loops(dt, mag, span.t_s);
        self.flags_after(&rate, at_rest, &span, accel_rejected, bias_motion, verdict)
    }

    /// Rest detection and the bias at rest (with bias estimation on); whether the
    /// device is at rest.
    #[inline(always)]
    fn bias_at_rest(&mut self, dt: f64, gyro: &[f64; 3], a: &[f64; 3]) -> bool {
        if !self.bias_estimation {
            return false;
        }
        let max_var = self.max_bias_rads * self.max_bias_rads;
        self.bias.predict(self.bias_q * dt, max_var);
        let at_rest = self.rest.step(gyro, a, dt, &self.rest_limits);
        if at_rest {
            let k = gain(dt, self.inv_rest_bias_tau);
            self.bias.rest(gyro, k, self.max_bias_rads);
        }
        at_rest
    }

    /// The span of the accelerometer average after `dt` more: it grows from a
    /// (re)start to the averaging time and, while the bias is poorly known, is
    /// shortened: the lag an unknown bias σ_b causes (σ_b·T) and the linear
    /// acceleration left in the average (∝ 1/T) balance at T ∝ 1/√σ_b (see
    /// [`BALANCE_BIAS_RADS`]).
    #[inline(always)]
    fn accel_span(&mut self, dt: f64) -> Span {
        self.accel_elapsed_s += dt;
        let init = self.accel_elapsed_s < self.accel_tau_s;
        let mut t_s = if init {
            self.accel_elapsed_s
        } else {
            self.accel_elapsed_s = self.accel_tau_s;
            self.accel_tau_s
        };
        let var = self.bias.var;
        let shorten = self.bias_estimation & (var > BALANCE_BIAS_VAR);
        let omega = if init | shorten {
            if shorten {
                t_s *= (BALANCE_BIAS_VAR / var).sqrt().sqrt();
            }
            std::f64::consts::SQRT_2 / t_s
        } else {
            self.accel_omega
        };
        Span { init, t_s, omega }
    }

    /// Inclination from the accelerometer averaged in the almost-inertial frame over
    /// `span` (a running mean while it still grows after a lost integration,
    /// `recovering`, see [`Averaging`]); the correction
    /// is summed for the motion bias when `learn_motion`. Returns whether the
    /// accelerometer was rejected (no direction) and whether the motion bias learns.
    #[inline(always)]
    fn incline(
        &mut self,
        a_i: &[f64; 3],
        dt: f64,
        span: &Span,
        recovering: bool,
        learn_motion: bool,
    ) -> (bool, bool) {
        // After a lost integration (not after a start: the average then starts from
        // the sample itself, nothing stale to forget).
        let averaging = if span.init & recovering {
            Averaging::Growing { span_s: span.t_s }
        } else {
            Averaging::LowPass { omega: span.omega }
        };
        match self.tilt.correct(a_i, dt, averaging) {
            Some(c) => {
                if learn_motion {
                    for (s, c) in self.bias_corr.iter_mut().zip(c) {
                        *s += c;
                    }
                }
                (false, learn_motion & (self.motion_bias_gain > 0.0))
            }
            None => (true, false),
        }
    }

    /// The slow loops (time constants of 10 s and more) run at most every
    /// [`SLOW_PERIOD_S`]: the motion bias from the corrections summed since, the
    /// heading from the magnetometer sample at hand (`t_avg`: the accelerometer
    /// average's span). Returns the magnetometer's verdict, if one came.
    #[inline(always)]
    fn slow_loops(&mut self, dt: f64, mag: Option<&[f64; 3]>, t_avg: f64) -> MagFlags {
        self.bias_elapsed_s += dt;
        self.mag_elapsed_s += dt;
        let mag_due = mag.is_some() & ((self.mag_elapsed_s >= SLOW_PERIOD_S) | !self.heading.valid);
        let bias_due = self.bias_elapsed_s >= SLOW_PERIOD_S;
        let carried = self.flags.unpack();
        let recovery = carried.mag_recovery;
        if !(mag_due | bias_due) {
            return match mag {
                // Between magnetometer updates the verdict of the last one stands.
                Some(_) => MagFlags {
                    disturbed: carried.mag_disturbed,
                    rejected: carried.mag_rejected,
                    held: carried.heading_held,
                    recovery,
                },
                None => MagFlags {
                    recovery,
                    ..MagFlags::default()
                },
            };
        }
        if bias_due {
            self.motion_bias();
        }
        match (mag_due, mag) {
            (true, Some(m)) => {
                let dt_m = self.mag_elapsed_s;
                self.mag_elapsed_s = 0.0;
                let m = self.learn_offset(m, dt_m);
                // Into I first (the gyroscope's frame, known early in the sample), then
                // E': only the last rotation waits for this sample's inclination.
                let e = quat::rotate(&self.tilt.q_inc, &quat::rotate(&self.tilt.q_gyr, &m));
                let v = self.correct_heading(&e, dt_m, t_avg);
                MagFlags {
                    disturbed: v.disturbed,
                    rejected: v.rejected,
                    held: v.rejected,
                    recovery: (recovery | v.recovered) & !v.converged,
                }
            }
            _ => MagFlags {
                recovery,
                ..MagFlags::default()
            },
        }
    }

    /// The raw reading `m` (`dt` s after the previous one) teaches the offset
    /// estimate, and the offset removed from the readings is updated from it once it
    /// is known (an estimate still converging can be far off along an axis the turns
    /// have not yet shown); the reading is returned without the offset removed.
    #[inline(always)]
    fn learn_offset(&mut self, m: &[f64; 3], dt: f64) -> [f64; 3] {
        if self.mag_offset_max_ut <= 0.0 {
            return *m;
        }
        let seen = self
            .hard_iron
            .observe(m, &self.tilt.q_gyr, dt, self.mag_offset_max_ut);
        if (seen.shift_ut > 0.0) & !self.hard_iron.calibrating() {
            self.apply_offset();
        }
        self.remove_offset(m)
    }

    #[inline(always)]
    fn remove_offset(&self, m: &[f64; 3]) -> [f64; 3] {
        let b = &self.offset_applied_ut;
        [m[0] - b[0], m[1] - b[1], m[2] - b[2]]
    }

    /// The known estimate becomes the offset removed if it is at least
    /// [`MIN_OFFSET_UT`] (none otherwise); once that has moved [`OFFSET_RELEARN_UT`]
    /// since the learned field (magnitude, dip) was seen, the field is learned anew.
    #[cold]
    fn apply_offset(&mut self) {
        let b = self.hard_iron.b;
        let norm2 = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
        self.offset_applied_ut = if norm2 >= MIN_OFFSET_UT * MIN_OFFSET_UT {
            b
        } else {
            [0.0; 3]
        };
        let a = &self.offset_applied_ut;
        let seen = &self.offset_seen_ut;
        let moved2: f64 = (0..3).map(|i| (a[i] - seen[i]) * (a[i] - seen[i])).sum();
        if moved2 > OFFSET_RELEARN_UT * OFFSET_RELEARN_UT {
            self.offset_seen_ut = *a;
            self.mag.restart(&self.mag_limits);
        }
    }

    /// The motion bias from the inclination corrections summed since the last
    /// update.
    #[inline(always)]
    fn motion_bias(&mut self) {
        let dt_b = self.bias_elapsed_s;
        self.bias_elapsed_s = 0.0;
        let c = self.bias_corr;
        if (c[0] == 0.0) & (c[1] == 0.0) {
            return;
        }
        self.bias_corr = [0.0; 3];
        // With the gain 0 (the default: motion-bias learning off) the update leaves
        // the bias and its variance as they are.
        let g = self.motion_bias_gain;
        if g > 0.0 {
            let c_body = quat::rotate(&quat::conj(&self.tilt.q_body_to_e()), &c);
            self.bias.motion(
                &c_body,
                g,
                g * dt_b,
                self.motion_accuracy_var,
                self.max_bias_rads,
            );
        }
    }

    /// The flags of this sample (kept for the next one too).
    #[inline(always)]
    fn flags_after(
        &mut self,
        rate: &RateCheck,
        at_rest: bool,
        span: &Span,
        accel_rejected: bool,
        bias_motion: bool,
        mag: MagFlags,
    ) -> AhrsFlags {
        let mut angular_rate_recovery = self.flags.unpack().angular_rate_recovery | rate.lost;
        if angular_rate_recovery & !span.init & !self.heading_init {
            angular_rate_recovery = rate.lost;
        }
        let flags = AhrsFlags {
            reinitialised: false,
            initialising: span.init | self.heading_init,
            angular_rate_recovery,
            accel_rejected,
            accel_recovery: false,
            mag_rejected: mag.rejected,
            mag_recovery: mag.recovery,
            bias_learning: at_rest,
            at_rest,
            bias_motion,
            mag_disturbed: mag.disturbed,
            heading_held: mag.held,
            mag_calibrating: (self.mag_offset_max_ut > 0.0) & self.hard_iron.calibrating(),
        };
        self.flags = PackedFlags::pack(flags);
        flags
    }

    /// The gyroscope's integration was lost by up to `missed` rad (a clipped reading,
    /// a gap it cannot bridge, as `rate` says): the accelerometer average keeps only
    /// the weight of an average as wrong as that ([`TILT_NOISE_RAD_S`] / missed, s;
    /// none from [`AVERAGE_LOST_RAD`] on) and the heading's variance grows by
    /// missed². A clipped reading's miss is also
    /// added to the clip run's: the readings of one run all miss the same way (the
    /// true rate is beyond the clip, with the clip's sign), so the average carries
    /// their sum, not one reading's (a gap's bound is already the whole gap's).
    #[cold]
    fn recover(&mut self, rate: &RateCheck, missed: f64) {
        let keep_s = if missed < AVERAGE_LOST_RAD {
            TILT_NOISE_RAD_S / missed
        } else {
            0.0
        };
        self.accel_elapsed_s = self.accel_elapsed_s.min(keep_s);
        self.heading.widen(missed * missed);
        if !rate.gap {
            self.clip_miss_rad += missed;
        }
    }

    /// The accelerometer average forgets a clip run's miss as it forgets any old
    /// sample: by dt / its span per sample (`dt`, `span`: this sample's).
    #[cold]
    fn forget_clip_miss(&mut self, dt: f64, span: &Span) {
        self.clip_miss_rad *= (1.0 - dt / span.t_s).max(0.0);
    }

    /// One magnetometer update of the heading (`dt` since the previous one) from the
    /// field `e` seen in E' (µT), with the accelerometer averaged over
    /// `t_avg` s.
    #[inline(always)]
    fn correct_heading(&mut self, e: &[f64; 3], dt: f64, t_avg: f64) -> HeadingUpdate {
        let Some(f) = measure(e) else {
            return HeadingUpdate::default();
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
        }
        if v.use_it {
            self.fuse_heading(&f, dt, t_avg);
        } else if self.heading.var_rad2 * dt > MAG_HEADING_NOISE_RAD2_S {
            // The heading is known worse than one undisturbed sample would tell (lost
            // over a gap or a clipped gyroscope): a disturbed field may still beat it.
            self.fuse_disturbed(&f, dt, t_avg, tilt_known);
        }
        HeadingUpdate {
            disturbed: v.disturbed,
            rejected: !v.use_it,
            recovered: v.recovered,
            converged: v.use_it & !self.heading_init,
        }
    }

    /// The variance of a heading measured by the field `f` (`dt` since the previous
    /// one, the accelerometer averaged over `t_avg` s), rad², and the part of it
    /// shared with the next measurements.
    #[inline(always)]
    fn heading_noise(&self, f: &Field, dt: f64, t_avg: f64) -> (f64, f64) {
        // The magnetometer's, and what the inclination's error beyond its converged
        // one turns it by through the dip.
        let inv_t = 1.0 / t_avg;
        let extra =
            TILT_NOISE_RAD_S * TILT_NOISE_RAD_S * (inv_t * inv_t - self.inv_accel_tau2).max(0.0);
        // A clip run's summed miss, while the average still holds it, is the larger
        // (measured on BROAD clipped at ±500 °/s: runs of up to 0.2 s miss 10–30°, the
        // inclination stays 10–20° off between them, and the heading had snapped to
        // fields seen through it).
        let miss = self.clip_miss_rad;
        let tilt_var = f.tan2_dip * extra.max(miss * miss);
        let r = MAG_HEADING_NOISE_RAD2_S / dt + tilt_var;
        // After a lost integration that error is the missed rotation's, shared by
        // the measurements until the inclination has converged (see
        // [`Heading::correct`]). After a start the heading has no prior to hold on
        // to: its running mean stays as it was.
        let common = if self.flags.angular_rate_recovery() {
            tilt_var
        } else {
            0.0
        };
        (r, common)
    }

    /// The Kalman update of the heading with the measured field `f` (`dt` since the
    /// previous one, the accelerometer averaged over `t_avg` s), and the heading bias.
    #[inline(always)]
    fn fuse_heading(&mut self, f: &Field, dt: f64, t_avg: f64) {
        let (r, common) = self.heading_noise(f, dt, t_avg);
        let q = self.heading_q * dt;
        let innovation = wrap(f.heading_rad - self.heading.delta_rad);
        let (d, k) = self
            .heading
            .correct(innovation, q, r.min(MAX_MEASUREMENT_VAR_RAD2), common);
        self.heading_init = k > HEADING_CONVERGED_GAINS * dt * self.inv_mag_tau;
        if self.bias_estimation & !self.heading_init {
            self.heading_bias(d, dt);
        }
    }

    /// A rejected field `f` corrects a heading known worse than it: with the heading
    /// error the disturbance may cause ([`MagDisturbance::heading_var`]) added to the
    /// measurement's variance, and only while the heading's variance exceeds the
    /// measurement's (a gain above ½). That error is common to the samples of one
    /// disturbance, so once one has corrected the heading the next ones of the same
    /// disturbance no longer pass; a smaller disturbance, or the undisturbed field,
    /// does. Measured on BROAD with 10 % of the samples dropped in bursts: after a
    /// lost gap near a magnet the heading stayed 30–120° off while the field was
    /// rejected; a disturbed field is off by 10–40°. Neither the heading bias nor the
    /// convergence flag learn from it.
    #[cold]
    fn fuse_disturbed(&mut self, f: &Field, dt: f64, t_avg: f64, tilt_known: bool) {
        let (r, common) = self.heading_noise(f, dt, t_avg);
        let r = r + self.mag.heading_var(self.mag.judges_dip(tilt_known));
        let q = self.heading_q * dt;
        if self.heading.var_rad2 + q > r {
            let innovation = wrap(f.heading_rad - self.heading.delta_rad);
            self.heading
                .correct(innovation, q, r.min(MAX_MEASUREMENT_VAR_RAD2), common);
        }
    }

    /// The bias about the vertical from a converged heading's correction `d` (rad,
    /// `dt` since the previous one): with the configured gain, and from when the
    /// corrections' mean rate exceeds [`HEADING_DRIFT_ON_RADS`] until it is back below
    /// [`HEADING_DRIFT_OFF_RADS`] with at least the integral gain of
    /// [`HEADING_DRIFT_INTEGRAL_TAUS`].
    #[inline(always)]
    fn heading_bias(&mut self, d: f64, dt: f64) {
        let k = gain(dt, self.inv_mag_tau);
        self.heading_drift_rads += k * (d / dt - self.heading_drift_rads);
        let rate = self.heading_drift_rads.abs();
        self.drift_learning = if self.drift_learning {
            rate > HEADING_DRIFT_OFF_RADS
        } else {
            rate > HEADING_DRIFT_ON_RADS
        };
        let g = if self.drift_learning {
            self.heading_bias_gain
                .max(self.inv_mag_tau / HEADING_DRIFT_INTEGRAL_TAUS)
        } else {
            self.heading_bias_gain
        };
        if g > 0.0 {
            // A turn of d about the vertical, in the body frame.
            let up = quat::rotate(&quat::conj(&self.tilt.q_body_to_e()), &[0.0, 0.0, d]);
            self.bias.heading(&up, g, self.max_bias_rads);
        }
    }

    /// The flags of the latest sample.
    #[inline(always)]
    pub(crate) fn flags(&self) -> AhrsFlags {
        self.flags.unpack()
    }

    /// The flags carried from sample to sample (restored from a snapshot).
    pub(crate) fn set_flags(&mut self, flags: AhrsFlags) {
        self.flags = PackedFlags::pack(flags);
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

/// The span of the accelerometer average for one sample.
#[derive(Clone, Copy, Debug)]
struct Span {
    /// Still growing from a (re)start (initialising).
    init: bool,
    /// Its length, s, and the matching cut-off (√2 / length), rad/s.
    t_s: f64,
    omega: f64,
}

/// The magnetometer's flags for one sample.
#[derive(Clone, Copy, Debug, Default)]
struct MagFlags {
    disturbed: bool,
    rejected: bool,
    held: bool,
    recovery: bool,
}
