//! Madgwick's gradient-descent orientation filter with Fusion-style robustness
//! ([`AhrsAlgorithm::Madgwick`](super::AhrsAlgorithm::Madgwick), the default before the
//! decoupled filter; [`AhrsSettings::madgwick`] gives its settings, [`AhrsSettings::plain`] the
//! paper's filter).
//!
//! # The filter
//! The orientation is a unit quaternion `q` (body → earth). Between samples it is
//! propagated by the gyroscope, `q̇ = ½ q ⊗ (0, ω)`. Gyroscopes drift, so each sample
//! also takes one gradient-descent step on the misfit between what the sensors
//! measure and what `q` predicts they should measure:
//! - accelerometer: the normalised specific force `â` should equal the earth's up
//!   direction seen from the body, `f_g(q) = q* ⊗ (0,0,0,1) ⊗ q − â` (true when the
//!   device does not accelerate);
//! - magnetometer: the normalised field `m̂` should equal the earth field seen from the
//!   body. The earth field reference `b = (|h_xy|, 0, h_z)` is rebuilt every sample
//!   from the measured field rotated into the earth frame, `h = q ⊗ m̂ ⊗ q*`, so the
//!   magnetometer only ever pulls on heading (its dip and magnitude are not assumed).
//!
//! With the stacked misfit `f` and its Jacobian `J`, the step is `∇ = Jᵀ f`, and
//! `q̇ = ½ q ⊗ ω − β ∇/|∇|`, integrated over the sample interval and renormalised.
//! β (the gain, rad/s) bounds how fast the correction turns the estimate: large β
//! trusts accelerometer / magnetometer, small β the gyroscope. The filter runs in
//! Madgwick's own North-West-Up frame (gravity reference `(0,0,1)`, field reference
//! in the x-z plane) and the outputs are rotated into ENU or NED by a constant
//! quaternion ([`super::frame`]). With [`AhrsSettings::plain`] it is the filter of
//! the paper and of the `ahrs` crate (`tests/ahrs.rs` checks agreement to ≤ 1e-6 rad;
//! not bit-equal, see "Cost").
//!
//! # Robustness (the design of x-io's Fusion, on top of the gradient step)
//! - **Initialisation.** The first sample sets the orientation directly: roll and
//!   pitch from gravity, heading from the field (TRIAD) or yaw = 0 without one. The
//!   gain then ramps linearly from `initial_gain` down to `gain` over
//!   `initialisation_period_s`, so the first seconds converge fast; nothing is
//!   rejected meanwhile.
//! - **Acceleration rejection.** Walking, braking or a swinging arm add linear
//!   acceleration, and the accelerometer no longer points up. The correction is
//!   skipped while ||a| − g| > `accel_rejection_mps2` or the angle between measured
//!   and estimated up exceeds `accel_rejection_rad` (`|f_g|² = 2 − 2 cos θ`, no
//!   trigonometry per sample).
//! - **Magnetic rejection.** A magnet, a laptop or steel changes the field's magnitude
//!   and its dip angle (angle below the horizontal). The filter learns the local Earth
//!   field (dip direction and magnitude, time constant 20 s) and skips the
//!   correction while |m| differs from it by more than `mag_rejection_ut` or the dip by
//!   more than `mag_rejection_dip_rad`. A disturbance that only turns the field without
//!   changing its magnitude or dip cannot be told from a real turn and is not rejected.
//! - **Recovery.** Each rejection has a trigger: rejected time counts up, accepted time
//!   counts down nine times as fast. When it reaches `recovery_trigger_period_s`, the
//!   estimate (not the sensor) is assumed wrong — e.g. after a gyroscope glitch — and
//!   the sensor is trusted again until the trigger has counted back to zero; a
//!   magnetic recovery also resets the learned field to the current one (the user
//!   walked into a building with another field).
//! - **Angular rate recovery.** A gyroscope reading beyond 98 % of its range was
//!   clipped; the integrated orientation is then wrong, so the initialisation phase
//!   (high gain, no rejection) restarts from the current orientation.
//! - **Gyroscope bias** is learned while still ([`super::bias`]) and subtracted.
//!
//! # Cost
//! One update is a chain of dependent floating-point operations from one sample's
//! `q` to the next (the state is stored and loaded back by the next sample), so the
//! work is arranged to keep that chain short and the instruction count low: f64
//! scalar code on plain arrays, the step's common factor 2 dropped (it is normalised
//! anyway); the field reference from `b_z = up·m̂` and `b_x = √(1 − b_z²)` instead of
//! rotating `m̂`; the magnetometer gradient regrouped as `P + b_x·Q` with
//! `b_x² = 1 − b_z²` inside `P` and `Q`, so that root runs in parallel with the rest
//! (`mag_gradient`); `β·dt/|∇|` as `β·dt·|∇|/|∇|²` (root and division in
//! parallel); the renormalisation by a second-order series whose argument
//! `|q̃|² − 1 = (|p|² − 1 + (β·dt)²) − 2c·p·∇` is known up to one product before the
//! step size `c` is; rare paths (large turns, large renormalisations) out of line;
//! `min`/`max` without NaN fix-ups (the door already refused NaN); the orientation
//! stored as two halves that the next sample can load straight from the store buffer
//! (`quat::SplitQuat`). Derived outputs (Euler angles, heading, linear
//! acceleration) are computed only by [`Ahrs::output`](super::Ahrs::output). See
//! `benches/ahrs.rs` for the comparison with the `ahrs` crate.

use super::bias::{GyroBias, STILL_ACCEL_MPS2};
use super::flags::AhrsFlags;
use super::frame::EarthFrame;
use super::quat::{self, max, min, Quat};
use super::settings::AhrsSettings;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Longest interval the correction step is scaled by, s.
pub const MAX_CORRECTION_DT_S: f64 = 0.1;
/// Above this half-angle² per sample, gyroscope integration is exact (0.1 rad turn).
const EXACT_HALF_ANGLE2: f64 = 0.05 * 0.05;
/// Below this |ε| (|q|² − 1 before renormalising) the inverse norm is a series.
const SERIES_MAX_EPS: f64 = 1e-2;
/// A gyroscope axis beyond this share of the range has clipped.
pub(crate) const GYRO_CLIP_SHARE: f64 = 0.98;
/// Time constant of the learned Earth field, s, and during initialisation.
const MAG_REF_TAU_S: f64 = 20.0;
const MAG_REF_INIT_TAU_S: f64 = 0.5;
/// A field vector this close to gravity cannot give a heading (relative cross product).
const MIN_HEADING_SIN: f64 = 1e-3;
/// Accelerometer and magnetometer vectors shorter than this give no direction (a
/// free fall, a zeroed sensor): no correction from them (m/s², µT). Also keeps
/// 1/|v|² finite for tiny finite inputs.
const MIN_VECTOR_NORM: f64 = 1e-6;

/// Rejection trigger of one sensor (Fusion's recovery trigger, in seconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Recovery {
    trigger_s: f64,
    recovering: bool,
}

impl Recovery {
    /// Account one sample; returns (use the sensor, recovery started now).
    /// Branch-free (`&`, `|`, selects): whether a sample is rejected follows the
    /// data, so branches on it would be mispredicted.
    #[inline]
    fn step(&mut self, bad: bool, dt: f64, period: f64) -> (bool, bool) {
        let delta = if bad { dt } else { -9.0 * dt };
        self.trigger_s = min(max(self.trigger_s + delta, 0.0), period);
        let started = !self.recovering & (self.trigger_s >= period);
        let ended = self.recovering & (self.trigger_s <= 0.0);
        self.recovering = (self.recovering | started) & !ended;
        (!bad | self.recovering, started)
    }
}

/// Madgwick's filter state with Fusion's initialisation, rejection, recovery and bias
/// estimation; driven by [`Ahrs`](super::Ahrs), which owns the door checks.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Madgwick {
    // Derived from the settings (not serialised).
    /// |f_g|² above which the accelerometer is rejected (2 − 2 cos θ).
    accel_err2_limit: f64,
    /// cos of the dip deviation below which the magnetometer is rejected.
    mag_cos_dip_limit: f64,
    /// Clipping level of the gyroscope, rad/s.
    gyro_clip_rads: f64,
    /// Gain decrease per second while initialising (+∞: no initialisation phase).
    ramp_rate: f64,
    // State.
    /// Orientation body → North-West-Up, [w, x, y, z].
    q: quat::SplitQuat,
    /// Current (ramped) gain, rad/s.
    gain: f64,
    accel_rec: Recovery,
    mag_rec: Recovery,
    /// Learned Earth field: direction in the vertical plane (horizontal and up
    /// components of the unit field vector) and magnitude, µT (exponential means of
    /// accepted samples; the mean direction is within ~1e-4 of unit length, which
    /// moves the dip threshold by hundredths of a degree).
    mag_ref_ut: [f64; 3],
    mag_ref_valid: bool,
    bias: GyroBias,
    /// Flags of the latest sample (the initialising state carries over).
    flags: AhrsFlags,
}

impl Madgwick {
    /// A filter for validated settings; it starts at the first sample.
    pub(crate) fn new(s: &AhrsSettings) -> Self {
        let accel_err2_limit = if s.accel_rejection_rad < std::f64::consts::PI {
            2.0 - 2.0 * s.accel_rejection_rad.cos()
        } else {
            f64::INFINITY
        };
        let mag_cos_dip_limit = if s.mag_rejection_dip_rad < std::f64::consts::PI {
            s.mag_rejection_dip_rad.cos()
        } else {
            f64::NEG_INFINITY
        };
        let ramp_rate = if s.initialisation_period_s > 0.0 && s.initial_gain > s.gain {
            (s.initial_gain - s.gain) / s.initialisation_period_s
        } else {
            f64::INFINITY
        };
        Self {
            accel_err2_limit,
            mag_cos_dip_limit,
            gyro_clip_rads: GYRO_CLIP_SHARE * s.gyro_range_rads,
            ramp_rate,
            q: quat::SplitQuat::new([1.0, 0.0, 0.0, 0.0]),
            gain: s.gain,
            accel_rec: Recovery::default(),
            mag_rec: Recovery::default(),
            mag_ref_ut: [0.0; 3],
            mag_ref_valid: false,
            bias: GyroBias::default(),
            flags: AhrsFlags::default(),
        }
    }

    /// Estimated gyroscope bias, rad/s, body frame.
    pub(crate) fn gyro_bias_rads(&self) -> [f64; 3] {
        self.bias.bias_rads
    }

    /// Current filter gain β, rad/s.
    pub(crate) fn gain(&self) -> f64 {
        self.gain
    }

    /// Orientation body → North-West-Up (unit length to rounding).
    #[inline(always)]
    pub(crate) fn q_nwu(&self) -> Quat {
        self.q.get()
    }

    /// (Re)start the orientation from one sample.
    pub(crate) fn start(
        &mut self,
        s: &AhrsSettings,
        accel: &[f64; 3],
        a_norm: f64,
        mag: Option<&[f64; 3]>,
    ) -> AhrsFlags {
        self.q.set(initial_orientation(s.frame, accel, a_norm, mag));
        let init = self.ramp_rate.is_finite();
        self.gain = if init { s.initial_gain } else { s.gain };
        self.accel_rec = Recovery::default();
        self.mag_rec = Recovery::default();
        self.bias.still_s = 0.0;
        self.mag_ref_valid = false;
        if let Some(m) = mag {
            let h = quat::rotate(&self.q.get(), m);
            let n = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            if n > MIN_VECTOR_NORM {
                self.mag_ref_ut = [(h[0] * h[0] + h[1] * h[1]).sqrt() / n, h[2] / n, n];
                self.mag_ref_valid = true;
            }
        }
        self.flags = AhrsFlags {
            reinitialised: true,
            initialising: init,
            ..AhrsFlags::default()
        };
        self.flags
    }

    /// One accepted sample after the first: bias, corrections, integration.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn step(
        &mut self,
        s: &AhrsSettings,
        dt: f64,
        gyro: [f64; 3],
        a: &[f64; 3],
        a2: f64,
        a_norm: f64,
        mag: Option<&[f64; 3]>,
    ) -> AhrsFlags {
        let mut flags = AhrsFlags {
            initialising: self.flags.initialising,
            angular_rate_recovery: self.flags.angular_rate_recovery,
            ..AhrsFlags::default()
        };
        // Flags go in and out by value: they stay in registers.
        flags = self.recover_angular_rate(s, &gyro, flags);
        flags = self.ramp_gain(s, dt, flags);
        let w;
        (w, flags) = self.unbiased_gyro(s, dt, gyro, a_norm, flags);
        let q = self.q.get();
        let up = up_in_body(&q);
        // ∇/2 of the accelerometer's and the magnetometer's misfits.
        let mut grad = [0.0; 4];
        if a_norm > MIN_VECTOR_NORM {
            (grad, flags) = self.accel_gradient(s, dt, &q, &up, a, a2, a_norm, grad, flags);
        } else {
            flags.accel_rejected = true;
        }
        if let Some(m) = mag {
            (grad, flags) = self.add_mag_gradient(s, dt, &q, &up, m, grad, flags);
        }
        let p = propagate(&q, &w, dt);
        self.q.set(gradient_step(
            &p,
            &grad,
            self.gain * min(dt, MAX_CORRECTION_DT_S),
        ));
        self.flags = flags;
        flags
    }

    /// Angular rate recovery: a clipped gyroscope restarts the initialisation phase.
    #[inline(always)]
    fn recover_angular_rate(
        &mut self,
        s: &AhrsSettings,
        gyro: &[f64; 3],
        mut flags: AhrsFlags,
    ) -> AhrsFlags {
        if (gyro[0].abs() > self.gyro_clip_rads)
            | (gyro[1].abs() > self.gyro_clip_rads)
            | (gyro[2].abs() > self.gyro_clip_rads)
        {
            flags.initialising = true;
            flags.angular_rate_recovery = true;
            self.gain = s.initial_gain.max(s.gain);
            self.accel_rec = Recovery::default();
            self.mag_rec = Recovery::default();
        }
        flags
    }

    /// While initialising, the gain ramps down to the nominal one.
    #[inline(always)]
    fn ramp_gain(&mut self, s: &AhrsSettings, dt: f64, mut flags: AhrsFlags) -> AhrsFlags {
        if flags.initialising {
            self.gain -= self.ramp_rate * dt;
            if self.gain <= s.gain {
                self.gain = s.gain;
                flags.initialising = false;
                flags.angular_rate_recovery = false;
            }
        }
        flags
    }

    /// The gyroscope minus its estimated bias (learned at rest).
    #[inline(always)]
    fn unbiased_gyro(
        &mut self,
        s: &AhrsSettings,
        dt: f64,
        gyro: [f64; 3],
        a_norm: f64,
        mut flags: AhrsFlags,
    ) -> ([f64; 3], AhrsFlags) {
        let mut w = gyro;
        if s.bias_estimation {
            let b = &self.bias.bias_rads;
            w = [w[0] - b[0], w[1] - b[1], w[2] - b[2]];
            let still = (a_norm - s.gravity_mps2).abs() < STILL_ACCEL_MPS2;
            flags.bias_learning = self.bias.update(&w, dt, still);
        }
        (w, flags)
    }

    /// Accelerometer: misfit between the estimated and the measured up direction; its
    /// gradient (½ J_gᵀ f_g; the step is normalised: common factors drop out) replaces
    /// `grad` when the sample is used.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn accel_gradient(
        &mut self,
        s: &AhrsSettings,
        dt: f64,
        q: &Quat,
        up: &[f64; 3],
        a: &[f64; 3],
        a2: f64,
        a_norm: f64,
        mut grad: Quat,
        mut flags: AhrsFlags,
    ) -> (Quat, AhrsFlags) {
        let [qw, qx, qy, qz] = *q;
        let [vx, vy, vz] = *up;
        // 1/|a| as |a|/|a|²: root and division in parallel.
        let inv = a_norm * (1.0 / a2);
        let f1 = vx - a[0] * inv;
        let f2 = vy - a[1] * inv;
        let f3 = vz - a[2] * inv;
        let bad = !flags.initialising
            & (((a_norm - s.gravity_mps2).abs() > s.accel_rejection_mps2)
                | (f1 * f1 + f2 * f2 + f3 * f3 > self.accel_err2_limit));
        let (use_it, _) = self.accel_rec.step(bad, dt, s.recovery_trigger_period_s);
        flags.accel_recovery = self.accel_rec.recovering;
        flags.accel_rejected = !use_it;
        if use_it {
            grad = [
                qx * f2 - qy * f1,
                qz * f1 + qw * f2 - 2.0 * qx * f3,
                qz * f2 - qw * f1 - 2.0 * qy * f3,
                qx * f1 + qy * f2,
            ];
        }
        (grad, flags)
    }

    /// Magnetometer: misfit between the estimated and the measured field direction,
    /// gated by the learned field; its gradient is added to `grad` when used.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn add_mag_gradient(
        &mut self,
        s: &AhrsSettings,
        dt: f64,
        q: &Quat,
        up: &[f64; 3],
        m: &[f64; 3],
        mut grad: Quat,
        mut flags: AhrsFlags,
    ) -> (Quat, AhrsFlags) {
        let m2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
        if m2 <= MIN_VECTOR_NORM * MIN_VECTOR_NORM {
            return (grad, flags);
        }
        let m_norm = m2.sqrt();
        let inv = m_norm * (1.0 / m2);
        let (mx, my, mz) = (m[0] * inv, m[1] * inv, m[2] * inv);
        let [vx, vy, vz] = *up;
        // The unit field in the earth frame, h = q ⊗ m̂ ⊗ q*, enters only as its up
        // component (up-in-body · m̂) and its horizontal magnitude, √(1 − h_z²) since
        // |h| = 1: the reference b = (b_x, 0, b_z) without rotating the whole vector.
        let bz = vx * mx + vy * my + vz * mz;
        let bx2 = 1.0 - bz * bz;
        let bx = max(bx2, 0.0).sqrt();
        let [rx, rz, rn] = self.mag_ref_ut;
        let bad = !flags.initialising
            & self.mag_ref_valid
            & (((m_norm - rn).abs() > s.mag_rejection_ut)
                | (bx * rx + bz * rz < self.mag_cos_dip_limit));
        let (use_it, started) = self.mag_rec.step(bad, dt, s.recovery_trigger_period_s);
        flags.mag_recovery = self.mag_rec.recovering;
        if started || !self.mag_ref_valid {
            self.mag_ref_ut = [bx, bz, m_norm];
            self.mag_ref_valid = true;
        }
        if !use_it {
            flags.mag_rejected = true;
            return (grad, flags);
        }
        let k = if flags.initialising {
            min(dt * (1.0 / MAG_REF_INIT_TAU_S), 1.0)
        } else {
            min(dt * (1.0 / MAG_REF_TAU_S), 1.0)
        };
        let r = &mut self.mag_ref_ut;
        r[0] += k * (bx - r[0]);
        r[1] += k * (bz - r[1]);
        r[2] += k * (m_norm - r[2]);
        // ∇/2 += ½ J_bᵀ f_b = P + b_x·Q: the root b_x enters last.
        let (gp, gq) = mag_gradient(q, up, &[mx, my, mz], bz, bx2);
        for i in 0..4 {
            grad[i] = (grad[i] + gp[i]) + bx * gq[i];
        }
        (grad, flags)
    }

    /// State after the settings, in the order of snapshot format 1 (q … still time).
    pub(crate) fn write_state(&self, w: &mut Writer) {
        w.f64s(&self.q.get());
        w.f64(self.gain);
        for r in [&self.accel_rec, &self.mag_rec] {
            w.f64(r.trigger_s);
            w.bool(r.recovering);
        }
        w.f64s(&self.mag_ref_ut);
        w.bool(self.mag_ref_valid);
        w.f64s(&self.bias.bias_rads);
        w.f64(self.bias.still_s);
    }

    /// Reads what [`Madgwick::write_state`] wrote and checks it against the
    /// settings: every number finite (the reader refused NaN and ±∞) and within what
    /// an update can produce.
    pub(crate) fn read_state(
        &mut self,
        r: &mut Reader,
        s: &AhrsSettings,
    ) -> Result<(), SnapshotError> {
        let mut q = [0.0; 4];
        r.f64s(&mut q)?;
        self.q.set(q);
        self.gain = r.f64()?;
        for rec in [&mut self.accel_rec, &mut self.mag_rec] {
            rec.trigger_s = r.f64()?;
            rec.recovering = r.bool()?;
        }
        r.f64s(&mut self.mag_ref_ut)?;
        self.mag_ref_valid = r.bool()?;
        r.f64s(&mut self.bias.bias_rads)?;
        self.bias.still_s = r.f64()?;
        let qn = q.iter().map(|c| c * c).sum::<f64>();
        if (qn - 1.0).abs() >= 1e-6 {
            return Err(SnapshotError::Invalid("quaternion not unit"));
        }
        if !(self.gain >= s.gain.min(s.initial_gain) && self.gain <= s.gain.max(s.initial_gain)) {
            return Err(SnapshotError::Invalid("gain outside the settings' range"));
        }
        for rec in [&self.accel_rec, &self.mag_rec] {
            // The trigger counts within 0..=period (0 when the period is +∞).
            if !(rec.trigger_s >= 0.0 && rec.trigger_s <= s.recovery_trigger_period_s) {
                return Err(SnapshotError::Invalid("recovery trigger"));
            }
        }
        let max_m = crate::input::limits::MAX_MAG_UT * 3f64.sqrt();
        let [rx, rz, rn] = self.mag_ref_ut;
        if !(rx.abs() <= 1.5 && rz.abs() <= 1.5 && (0.0..=max_m).contains(&rn)) {
            return Err(SnapshotError::Invalid("learned magnetic field"));
        }
        if self
            .bias
            .bias_rads
            .iter()
            .any(|b| b.abs() > crate::input::limits::MAX_GYRO_RADS)
            || !(0.0..=super::bias::STILL_TIMEOUT_S).contains(&self.bias.still_s)
        {
            return Err(SnapshotError::Invalid("gyroscope bias"));
        }
        Ok(())
    }

    /// The flags of the latest sample.
    #[inline(always)]
    pub(crate) fn flags(&self) -> AhrsFlags {
        self.flags
    }

    /// The flags carried from sample to sample (restored from a snapshot).
    pub(crate) fn set_flags(&mut self, flags: AhrsFlags) {
        self.flags = flags;
    }
}

/// Orientation (body → NWU) from one sample: roll and pitch from gravity; heading
/// from the field when there is one (TRIAD: east = field × up, north = up × east),
/// else yaw = 0 in the output frame.
fn initial_orientation(
    frame: EarthFrame,
    a: &[f64; 3],
    a_norm: f64,
    mag: Option<&[f64; 3]>,
) -> Quat {
    let c = frame.nwu_to_frame();
    if a_norm <= MIN_VECTOR_NORM {
        return quat::conj(&c);
    }
    let up = [a[0] / a_norm, a[1] / a_norm, a[2] / a_norm];
    if let Some(m) = mag {
        let e = cross(m, &up);
        let en = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let mn = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        if en > MIN_HEADING_SIN * mn && mn > MIN_VECTOR_NORM {
            let east = [e[0] / en, e[1] / en, e[2] / en];
            let north = cross(&up, &east);
            let west = [-east[0], -east[1], -east[2]];
            return quat::from_rows(&[north, west, up]);
        }
    }
    let h = up[1].hypot(up[2]);
    let (roll, pitch) = match frame {
        EarthFrame::Enu => (up[1].atan2(up[2]), (-up[0]).atan2(h)),
        EarthFrame::Ned => ((-up[1]).atan2(-up[2]), up[0].atan2(h)),
    };
    let q_out = quat::from_euler(roll, pitch, 0.0);
    quat::mul(&quat::conj(&c), &q_out)
}

/// Up in the body frame as the estimate `q` sees it (third row of R(q)).
#[inline(always)]
fn up_in_body(q: &Quat) -> [f64; 3] {
    let [qw, qx, qy, qz] = *q;
    [
        2.0 * (qx * qz - qw * qy),
        2.0 * (qw * qx + qy * qz),
        2.0 * (0.5 - qx * qx - qy * qy),
    ]
}

/// Gyroscope propagation of `q` by the rate `w` over `dt`, with the half-angle vector
/// ½ ω dt: first order (q + q ⊗ (0, ½ ω dt), as the paper) for small turns, exact
/// beyond.
#[inline(always)]
fn propagate(q: &Quat, w: &[f64; 3], dt: f64) -> Quat {
    let [qw, qx, qy, qz] = *q;
    let hdt = 0.5 * dt;
    let (hx, hy, hz) = (w[0] * hdt, w[1] * hdt, w[2] * hdt);
    let h2 = hx * hx + hy * hy + hz * hz;
    if h2 < EXACT_HALF_ANGLE2 {
        [
            qw - qx * hx - qy * hy - qz * hz,
            qx + qw * hx + qy * hz - qz * hy,
            qy + qw * hy - qx * hz + qz * hx,
            qz + qw * hz + qx * hy - qy * hx,
        ]
    } else {
        exact_propagation(q, hx, hy, hz, h2)
    }
}

/// The normalised gradient step of `step` (β·bounded dt) from the propagated `p`
/// along −∇ (`grad` = ∇/2), renormalised.
#[inline(always)]
fn gradient_step(p: &Quat, grad: &Quat, step: f64) -> Quat {
    let [p0, p1, p2, p3] = *p;
    let [sw, sx, sy, sz] = *grad;
    let n2 = sw * sw + sx * sx + sy * sy + sz * sz;
    // β·dt/|∇| written as β·dt·|∇|/|∇|²: the square root and the division then run in
    // parallel instead of one after the other (this is on the critical path from one
    // sample's q to the next).
    let (c, step2) = if n2 > 0.0 {
        ((step / n2) * n2.sqrt(), step * step)
    } else {
        (0.0, 0.0)
    };
    let nw = p0 - c * sw;
    let nx = p1 - c * sx;
    let ny = p2 - c * sy;
    let nz = p3 - c * sz;
    // Renormalise. |q|² stays close to 1: first-order integration adds (½|ω|dt)² and
    // the step, which has a radial part, changes it by ~2β·dt (≤ 1e-2 at β = 1,
    // 100 Hz). There the Taylor series of 1/√(1+ε) to second order,
    // 1 − ε/2 + 3ε²/8 (error ≤ 5/16·|ε|³ ≈ 3e-7, corrected again next sample), gives
    // the same direction without a square root and a division on the chain that
    // carries q from sample to sample. Larger deviations take the exact path.
    // ε = |p − c∇|² − 1 = (|p|² − 1 + c²|∇|²) − 2c·p·∇ with c²|∇|² = (β·dt)²:
    // everything but the last product is known before c.
    let pp = p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3;
    let ps = p0 * sw + p1 * sx + p2 * sy + p3 * sz;
    let eps = ((pp - 1.0) + step2) - 2.0 * c * ps;
    let inv = if eps.abs() < SERIES_MAX_EPS {
        (1.0 - 0.5 * eps) + 0.375 * (eps * eps)
    } else {
        exact_inverse_norm(eps)
    };
    [nw * inv, nx * inv, ny * inv, nz * inv]
}

/// Madgwick's algebraic magnetometer gradient ½ J_bᵀ f_b, regrouped as P + b_x·Q so
/// that the square root b_x = √(1 − b_z²) is needed only at the very end (it then runs
/// in parallel with P and Q instead of heading the chain).
///
/// With the reference b = (b_x, 0, b_z), N = first row of R(q) (north in the body
/// frame) and `v` the third (up), the misfit is f_b = b_x·N + b_z·v − m̂ = b_x·N + G.
/// Each row of ½ J_bᵀ is (α·b_x + b_z·γ) with α, γ from q alone:
/// α = (0, −qz, qy), (0, qy, qz), (−2qy, qx, qw), (−2qz, −qw, qx) and
/// γ = (−qy, qx, 0), (qz, qw, −2qx), (−qw, qz, −2qy), (qx, qy, 0) for w, x, y, z. So
///   ½ J_bᵀ f_b = b_x²·Σα N + b_z·Σγ G + b_x·(Σα G + b_z·Σγ N),
/// with b_x² = 1 − b_z² (`bx2`), and Σα N reduces to 2t·(qw, qx) for w, x and
/// 2(qw² + qx² − N₀)·(qy, qz) for y, z, where t = qy² + qz².
#[inline(always)]
fn mag_gradient(q: &Quat, v: &[f64; 3], m: &[f64; 3], bz: f64, bx2: f64) -> (Quat, Quat) {
    let [qw, qx, qy, qz] = *q;
    let t = qy * qy + qz * qz;
    let n0 = 1.0 - 2.0 * t;
    let n1 = 2.0 * (qx * qy - qw * qz);
    let n2 = 2.0 * (qw * qy + qx * qz);
    let g0 = bz * v[0] - m[0];
    let g1 = bz * v[1] - m[1];
    let g2 = bz * v[2] - m[2];
    let at = 2.0 * bx2 * t;
    let ac = 2.0 * bx2 * (qw * qw + qx * qx - n0);
    let (qx2, qy2, qz2) = (2.0 * qx, 2.0 * qy, 2.0 * qz);
    let p = [
        at * qw + bz * (qx * g1 - qy * g0),
        at * qx + bz * (qz * g0 + qw * g1 - qx2 * g2),
        ac * qy + bz * (qz * g1 - qw * g0 - qy2 * g2),
        ac * qz + bz * (qx * g0 + qy * g1),
    ];
    let r = [
        (qy * g2 - qz * g1) + bz * (qx * n1 - qy * n0),
        (qy * g1 + qz * g2) + bz * (qz * n0 + qw * n1 - qx2 * n2),
        (qx * g1 + qw * g2 - qy2 * g0) + bz * (qz * n1 - qw * n0 - qy2 * n2),
        (qx * g2 - qz2 * g0 - qw * g1) + bz * (qx * n0 + qy * n1),
    ];
    (p, r)
}

/// q ⊗ exp(½ ω dt) for a large turn (cold: rare at phone sample rates).
#[cold]
#[inline(never)]
fn exact_propagation(q: &Quat, hx: f64, hy: f64, hz: f64, h2: f64) -> Quat {
    let ha = h2.sqrt();
    let (sn, cs) = ha.sin_cos();
    let k = sn / ha;
    quat::mul(q, &[cs, k * hx, k * hy, k * hz])
}

/// 1/√(1 + ε) when ε is too large for the series (cold).
#[cold]
#[inline(never)]
fn exact_inverse_norm(eps: f64) -> f64 {
    1.0 / (1.0 + eps).sqrt()
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The regrouped magnetometer gradient equals the direct ½ J_bᵀ f_b (Madgwick's
    /// formula, as written before the regrouping).
    #[test]
    fn mag_gradient_matches_the_direct_formula() {
        let mut seed = 12345u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..1000 {
            let q = quat::normalised([rnd(), rnd(), rnd(), rnd()]);
            let m = {
                let m = [rnd(), rnd(), rnd()];
                let n = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                [m[0] / n, m[1] / n, m[2] / n]
            };
            let [qw, qx, qy, qz] = q;
            let v = [
                2.0 * (qx * qz - qw * qy),
                2.0 * (qw * qx + qy * qz),
                2.0 * (0.5 - qx * qx - qy * qy),
            ];
            let bz = v[0] * m[0] + v[1] * m[1] + v[2] * m[2];
            let bx2 = 1.0 - bz * bz;
            let bx = bx2.max(0.0).sqrt();
            let (p, r) = mag_gradient(&q, &v, &m, bz, bx2);
            // Direct: f_b = b_x·N + b_z·v − m̂, then ½ J_bᵀ f_b.
            let n0 = 1.0 - 2.0 * (qy * qy + qz * qz);
            let n1 = 2.0 * (qx * qy - qw * qz);
            let n2 = 2.0 * (qw * qy + qx * qz);
            let f4 = bx * n0 + bz * v[0] - m[0];
            let f5 = bx * n1 + bz * v[1] - m[1];
            let f6 = bx * n2 + bz * v[2] - m[2];
            let direct = [
                (bz * qx - bx * qz) * f5 + bx * qy * f6 - bz * qy * f4,
                bz * qz * f4 + (bx * qy + bz * qw) * f5 + (bx * qz - 2.0 * bz * qx) * f6,
                (bx * qx + bz * qz) * f5 + (bx * qw - 2.0 * bz * qy) * f6
                    - (2.0 * bx * qy + bz * qw) * f4,
                (bz * qx - 2.0 * bx * qz) * f4 + (bz * qy - bx * qw) * f5 + bx * qx * f6,
            ];
            for i in 0..4 {
                let got = p[i] + bx * r[i];
                assert!(
                    (got - direct[i]).abs() < 1e-14,
                    "{i}: {got} vs {}",
                    direct[i]
                );
            }
        }
    }

    /// The first-order propagation agrees with the exact one for small turns, and the
    /// gradient step returns a unit quaternion moved against the gradient.
    #[test]
    fn propagation_and_gradient_step() {
        let q = quat::normalised([0.9, 0.1, -0.2, 0.3]);
        let w = [0.5, -0.3, 0.2];
        let small = propagate(&q, &w, 0.01);
        let (hx, hy, hz) = (0.0025, -0.0015, 0.001);
        let exact = exact_propagation(&q, hx, hy, hz, hx * hx + hy * hy + hz * hz);
        let n: f64 = exact.iter().map(|c| c * c).sum::<f64>().sqrt();
        for k in 0..4 {
            assert!(
                (small[k] - exact[k] * n).abs() < 1e-5,
                "{small:?} {exact:?}"
            );
        }
        let grad = [0.1, 0.0, 0.0, 0.0];
        let stepped = gradient_step(&q, &grad, 0.01);
        let n2: f64 = stepped.iter().map(|c| c * c).sum();
        assert!((n2 - 1.0).abs() < 1e-6, "{n2}");
        assert!(stepped[0] < q[0]);
        assert_eq!(gradient_step(&q, &[0.0; 4], 0.01), {
            let pp: f64 = q.iter().map(|c| c * c).sum();
            let eps = pp - 1.0;
            let inv = (1.0 - 0.5 * eps) + 0.375 * (eps * eps);
            q.map(|c| c * inv)
        });
    }
}
