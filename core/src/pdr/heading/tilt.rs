//! Tilt correction of the AHRS attitude: over strides the body's acceleration
//! averages out, so the mean specific force in the earth frame is vertical; the
//! AHRS's tilt error while walking (its accelerometer correction follows the median,
//! not the mean, of the asymmetric gait accelerations) tilts that mean, and is rotated away.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Time constant of the mean earth-frame specific force, s.
const TILT_TAU_S: f64 = 3.0;
/// Standard gravity, m/s² (the mean force before the first sample).
pub(super) const GRAVITY_MPS2: f64 = 9.80665;
/// A mean force weaker than this has no direction to correct towards, m/s².
const MIN_MEAN_FORCE_MPS2: f64 = 1.0;

/// The low-passed specific force in the AHRS's ENU frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TiltCorrection {
    /// Mean specific force in the AHRS earth frame, m/s²: its tilt from the vertical
    /// is the AHRS's mean tilt error while walking.
    pub(super) mean_force_enu: [f64; 3],
}

impl Default for TiltCorrection {
    fn default() -> Self {
        Self {
            mean_force_enu: [0.0, 0.0, GRAVITY_MPS2],
        }
    }
}

impl TiltCorrection {
    /// One sample `dt` after the previous: the AHRS orientation (body → ENU) and the
    /// specific force in its ENU frame, m/s², in; the corrected orientation and the
    /// linear acceleration in the corrected ENU frame, m/s², out.
    pub(super) fn correct(
        &mut self,
        dt: f64,
        q_enu: &UnitQuaternion<f64>,
        force_enu_mps2: [f64; 3],
    ) -> (UnitQuaternion<f64>, [f64; 3]) {
        let k_tilt = dt / TILT_TAU_S;
        for (m, f) in self.mean_force_enu.iter_mut().zip(force_enu_mps2) {
            *m += k_tilt * (f - *m);
        }
        // Shortest rotation taking the mean force's direction a to up:
        // q ∝ (1 + a_z, a × z) = (1 + a_z, a_y, −a_x, 0).
        let mf = Vector3::from(self.mean_force_enu);
        let g = mf.norm();
        let fix = if g > MIN_MEAN_FORCE_MPS2 && mf.z > 0.0 {
            let a = mf / g;
            UnitQuaternion::from_quaternion(Quaternion::new(1.0 + a.z, a.y, -a.x, 0.0))
        } else {
            UnitQuaternion::identity()
        };
        let lin = fix * Vector3::from(force_enu_mps2)
            - Vector3::new(0.0, 0.0, g.max(MIN_MEAN_FORCE_MPS2));
        (fix * q_enu, [lin.x, lin.y, lin.z])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_mean_force_is_rotated_to_the_vertical() {
        let mut tilt = TiltCorrection::default();
        // The AHRS is 0.05 rad off about east: gravity seen tilted towards north.
        let f = [0.0, 9.81 * 0.05f64.sin(), 9.81 * 0.05f64.cos()];
        let q = UnitQuaternion::identity();
        let mut out = (q, [0.0; 3]);
        for _ in 0..3000 {
            out = tilt.correct(0.01, &q, f);
        }
        let (fixed, lin) = out;
        assert!((fixed.angle() - 0.05).abs() < 1e-3, "{}", fixed.angle());
        assert!(lin.iter().all(|x| x.abs() < 1e-2), "{lin:?}");
    }

    #[test]
    fn a_level_mean_changes_nothing() {
        let mut tilt = TiltCorrection::default();
        let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.7);
        let (fixed, lin) = tilt.correct(0.01, &q, [0.0, 0.0, GRAVITY_MPS2]);
        assert!(fixed.angle_to(&q) < 1e-12);
        assert!(lin.iter().all(|x| x.abs() < 1e-12));
    }
}
