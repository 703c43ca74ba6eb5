//! The stabilised frame: the sample's angular rate and specific force rotated into
//! ENU by the AHRS attitude, gravity removed (linear acceleration), and the AHRS yaw
//! that defines the gravity-aligned, heading-following frame S of RIDI
//! (`R_WS = R_z(yaw)`).

/// Angular rate and linear acceleration in ENU, and the device yaw.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stabilised {
    pub t_s: f64,
    /// Angular rate in ENU, rad/s.
    pub gyro_enu_rads: [f64; 3],
    /// Linear acceleration (gravity removed) in ENU, m/s².
    pub accel_enu_mps2: [f64; 3],
    /// ZYX yaw of the attitude, rad (counter-clockwise from East).
    pub yaw_rad: f64,
}

/// Rotate a body vector into ENU by the body → ENU quaternion `[w, x, y, z]` (the
/// AHRS's own rotation).
#[inline]
pub fn rotate(q: &[f64; 4], v: &[f64; 3]) -> [f64; 3] {
    crate::ahrs::quat::rotate(q, v)
}

/// ZYX yaw of a body → ENU quaternion, rad.
#[inline]
pub fn yaw(q: &[f64; 4]) -> f64 {
    let [w, x, y, z] = *q;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// The stabilised sample of one body-frame reading under attitude `q`.
#[inline]
pub fn stabilise(
    t_s: f64,
    q: &[f64; 4],
    gyro_rads: &[f64; 3],
    accel_mps2: &[f64; 3],
    gravity_mps2: f64,
) -> Stabilised {
    let mut a = rotate(q, accel_mps2);
    a[2] -= gravity_mps2;
    Stabilised {
        t_s,
        gyro_enu_rads: rotate(q, gyro_rads),
        accel_enu_mps2: a,
        yaw_rad: yaw(q),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gravity_is_removed_in_any_attitude() {
        // 90° about x: body y → ENU z.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = [h, h, 0.0, 0.0];
        let s = stabilise(0.0, &q, &[0.0; 3], &[0.0, 9.8, 0.0], 9.8);
        for v in s.accel_enu_mps2 {
            assert!(v.abs() < 1e-12);
        }
        // 90° about z: yaw = π/2.
        let q = [h, 0.0, 0.0, h];
        assert!((yaw(&q) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
