//! The yaw correction μ (AHRS azimuth − true azimuth) and its drift rate: with a
//! magnetometer a second-order loop on the tilt-compensated, hard-iron-corrected field,
//! gated by the learned field strength and dip; without one μ follows its drift rate
//! (which GNSS teaches, see `calibration`).

use nalgebra::{UnitQuaternion, Vector3};

use super::hard_iron::HardIron;
use crate::ahrs::field::FieldGate;
use crate::angle::wrap;

/// Loop time constants (offset, drift rate), s, for a raw gyroscope (~0.5°/s of bias
/// to follow) ...
const MAG_TAU_RAW_GYRO_S: f64 = 10.0;
const MAG_RATE_TAU_RAW_GYRO_S: f64 = 40.0;
/// ... and for one whose bias the platform removes (~0.01°/s: slow, so the field's
/// disturbances stay out of the heading; docs/lab/2026-12-06-phone-history.md gives the balance).
const MAG_TAU_CALIBRATED_GYRO_S: f64 = 120.0;
const MAG_RATE_TAU_CALIBRATED_GYRO_S: f64 = 480.0;
/// A field sample is rejected when its strength or dip departs from the learned ones
/// by more than this (µT, rad).
const MAG_GATE: FieldGate = FieldGate {
    strength_ut: 6.0,
    dip_rad: 0.14,
};
/// Time constant of the learned field strength and dip, s.
const MAG_REF_TAU_S: f64 = 60.0;
/// A corrected field weaker than this carries no direction, µT ...
const MIN_FIELD_UT: f64 = 1.0;
/// ... nor one whose horizontal part is weaker than this, µT.
const MIN_HORIZONTAL_FIELD_UT: f64 = 1.0;

/// The learned field strength and dip: what an undisturbed sample looks like.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct FieldReference {
    pub(super) strength_ut: f64,
    pub(super) dip_rad: f64,
    pub(super) known: bool,
}

impl FieldReference {
    /// Whether a sample of strength `n_ut` and dip `dip_rad` is undisturbed; the
    /// reference then follows it (accepted or not) with time constant `MAG_REF_TAU_S`.
    fn accept(&mut self, n_ut: f64, dip_rad: f64, dt: f64) -> bool {
        if !self.known {
            self.strength_ut = n_ut;
            self.dip_rad = dip_rad;
            self.known = true;
        }
        let ok = !MAG_GATE.departs(n_ut, dip_rad, self.strength_ut, self.dip_rad);
        let k = dt / MAG_REF_TAU_S;
        self.strength_ut += k * (n_ut - self.strength_ut);
        self.dip_rad += k * (dip_rad - self.dip_rad);
        ok
    }
}

/// μ, its drift rate and what the magnetometer taught.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct YawCorrection {
    /// AHRS azimuth − true azimuth, rad, and its drift rate, rad/s.
    pub(super) mu_rad: f64,
    pub(super) mu_rate_rads: f64,
    pub(super) mu_known: bool,
    /// A field sample has set μ (the magnetometer, not GNSS, holds the drift).
    pub(super) mag_seen: bool,
    /// The gyroscope's bias is removed by the platform (the loop is slow).
    pub(super) gyro_calibrated: bool,
    pub(super) field: FieldReference,
    pub(super) hard_iron: HardIron,
}

impl YawCorrection {
    pub(super) fn new(gyro_calibrated: bool) -> Self {
        Self {
            mu_rad: 0.0,
            mu_rate_rads: 0.0,
            mu_known: false,
            mag_seen: false,
            gyro_calibrated,
            field: FieldReference::default(),
            hard_iron: HardIron::default(),
        }
    }

    /// One sample `dt` after the previous: the corrected orientation (body → ENU),
    /// the body-frame up and the magnetometer reading, body frame, µT, if any.
    /// Returns the field's horizontal unit vector (east, north) in the AHRS frame
    /// when its strength passes the gate (for the bridge across gaps, `super::gap`).
    pub(super) fn push(
        &mut self,
        dt: f64,
        q_enu: &UnitQuaternion<f64>,
        up_body: &Vector3<f64>,
        mag_body_ut: Option<[f64; 3]>,
    ) -> Option<[f64; 2]> {
        let field = match mag_body_ut {
            Some(m) => self.measure(dt, q_enu, up_body, m),
            None => {
                if !self.mu_known {
                    self.mu_rad = 0.0;
                    self.mu_known = true;
                }
                None
            }
        };
        self.mu_rad = wrap(self.mu_rad + self.mu_rate_rads * dt);
        field
    }

    /// A field sample: the azimuth of magnetic north in the AHRS frame, if the
    /// sample passes the gate; its horizontal unit vector if its strength does.
    fn measure(
        &mut self,
        dt: f64,
        q_enu: &UnitQuaternion<f64>,
        up_body: &Vector3<f64>,
        m: [f64; 3],
    ) -> Option<[f64; 2]> {
        let h = self.hard_iron.h_ut;
        let mc = Vector3::new(m[0] - h[0], m[1] - h[1], m[2] - h[2]);
        let n = mc.norm();
        if n > MIN_FIELD_UT {
            let dip = (mc.dot(up_body) / n).clamp(-1.0, 1.0).asin();
            let ok = self.field.accept(n, dip, dt);
            let me = q_enu * mc;
            if ok {
                self.hard_iron.add(&m);
            }
            let horizontal = me.x.hypot(me.y);
            if horizontal > MIN_HORIZONTAL_FIELD_UT {
                if ok {
                    self.follow(me.x.atan2(me.y), dt);
                }
                // The bridge across gaps takes every sample: what it needs is the same
                // field on both sides of a gap (disturbed or not), and the dip departs
                // while the tilt re-converges after a lost gap, just when it is needed.
                return Some([me.x / horizontal, me.y / horizontal]);
            }
        }
        None
    }

    /// The loop: μ set by the first accepted measurement, then pulled towards each.
    fn follow(&mut self, meas_rad: f64, dt: f64) {
        if !self.mag_seen {
            self.mu_rad = meas_rad;
            self.mu_known = true;
        } else {
            let e = wrap(meas_rad - self.mu_rad);
            let (tau, rate_tau) = if self.gyro_calibrated {
                (MAG_TAU_CALIBRATED_GYRO_S, MAG_RATE_TAU_CALIBRATED_GYRO_S)
            } else {
                (MAG_TAU_RAW_GYRO_S, MAG_RATE_TAU_RAW_GYRO_S)
            };
            self.mu_rad += dt * e / tau;
            self.mu_rate_rads += dt * e / (rate_tau * rate_tau);
        }
        self.mag_seen = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Earth's field (20 µT north, 44 µT down) seen by a level phone turned so
    /// that the AHRS frame is `mu` clockwise of true north.
    fn field(mu: f64) -> [f64; 3] {
        [20.0 * mu.sin(), 20.0 * mu.cos(), -44.0]
    }

    #[test]
    fn the_loop_follows_the_field_and_the_gate_rejects_a_disturbance() {
        let q = UnitQuaternion::identity();
        let up = Vector3::z();
        let mut y = YawCorrection::new(false);
        y.push(0.01, &q, &up, Some(field(0.3)));
        assert!(y.mag_seen && (y.mu_rad - 0.3).abs() < 1e-12);
        // The field turns by 0.1 rad: μ follows with the raw gyroscope's 10 s.
        for _ in 0..6000 {
            y.push(0.01, &q, &up, Some(field(0.4)));
        }
        assert!((y.mu_rad - 0.4).abs() < 0.01, "{}", y.mu_rad);
        // Steel: +20 µT for a second, rejected (μ only drifts at its rate).
        let before = y;
        let strong = field(1.5).map(|x| 1.3 * x);
        y.push(0.01, &q, &up, Some(strong));
        assert!((y.mu_rad - wrap(before.mu_rad + before.mu_rate_rads * 0.01)).abs() < 1e-15);
        assert_eq!(y.hard_iron.sums, before.hard_iron.sums);
    }

    #[test]
    fn without_a_magnetometer_mu_starts_at_zero_and_drifts_at_its_rate() {
        let mut y = YawCorrection::new(true);
        y.mu_rate_rads = 0.01;
        y.push(0.5, &UnitQuaternion::identity(), &Vector3::z(), None);
        assert!(y.mu_known && !y.mag_seen);
        assert!((y.mu_rad - 0.005).abs() < 1e-15);
    }
}
