//! Small scalar quaternion helpers (w, x, y, z), f64, no allocation, and the scalar
//! `min`/`max` of the filter's hot path.
//!
//! A quaternion `q` here rotates body-frame vectors into the earth frame:
//! `v_earth = q ⊗ (0, v_body) ⊗ q*`.

pub(crate) type Quat = [f64; 4];

/// The smaller of two numbers that are not NaN: one `minsd` (`f64::min` adds a NaN
/// fix-up of four instructions).
#[inline(always)]
pub(crate) fn min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// The larger of two numbers that are not NaN (see [`min`]).
#[inline(always)]
pub(crate) fn max(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The filter's orientation as kept between samples: (w, x) and (y, z) in two
/// 16-byte halves with a gap between them. One sample stores the halves, the next
/// loads them back right away (the orientation is the chain from sample to sample);
/// a load spanning both stores (x and y together) cannot be forwarded from the store
/// buffer and waits for the previous sample to retire. The gap rules such a load out.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub(crate) struct SplitQuat {
    wx: [f64; 2],
    gap: f64,
    yz: [f64; 2],
}

impl SplitQuat {
    pub(crate) fn new(q: Quat) -> Self {
        Self {
            wx: [q[0], q[1]],
            gap: 0.0,
            yz: [q[2], q[3]],
        }
    }

    #[inline(always)]
    pub(crate) fn get(&self) -> Quat {
        [self.wx[0], self.wx[1], self.yz[0], self.yz[1]]
    }

    #[inline(always)]
    pub(crate) fn set(&mut self, q: Quat) {
        self.wx = [q[0], q[1]];
        self.yz = [q[2], q[3]];
    }
}

#[inline]
pub(crate) fn mul(a: &Quat, b: &Quat) -> Quat {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

#[inline]
pub(crate) fn conj(q: &Quat) -> Quat {
    [q[0], -q[1], -q[2], -q[3]]
}

pub(crate) fn normalised(q: Quat) -> Quat {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// Rotate a body vector into the earth frame (`R(q) v`).
#[inline]
pub(crate) fn rotate(q: &Quat, v: &[f64; 3]) -> [f64; 3] {
    let [w, x, y, z] = *q;
    [
        (1.0 - 2.0 * (y * y + z * z)) * v[0]
            + 2.0 * (x * y - w * z) * v[1]
            + 2.0 * (x * z + w * y) * v[2],
        2.0 * (x * y + w * z) * v[0]
            + (1.0 - 2.0 * (x * x + z * z)) * v[1]
            + 2.0 * (y * z - w * x) * v[2],
        2.0 * (x * z - w * y) * v[0]
            + 2.0 * (y * z + w * x) * v[1]
            + (1.0 - 2.0 * (x * x + y * y)) * v[2],
    ]
}

/// Quaternion of a rotation matrix given by rows (earth axes in body coordinates),
/// Shepperd's method (numerically safe for every rotation).
pub(crate) fn from_rows(m: &[[f64; 3]; 3]) -> Quat {
    let tr = m[0][0] + m[1][1] + m[2][2];
    let q = if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        [
            0.25 * s,
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
        [
            (m[2][1] - m[1][2]) / s,
            0.25 * s,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
        ]
    } else if m[1][1] > m[2][2] {
        let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
        [
            (m[0][2] - m[2][0]) / s,
            (m[0][1] + m[1][0]) / s,
            0.25 * s,
            (m[1][2] + m[2][1]) / s,
        ]
    } else {
        let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
        [
            (m[1][0] - m[0][1]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            0.25 * s,
        ]
    };
    normalised(q)
}

/// Quaternion from ZYX Euler angles (yaw about z, then pitch about y, then roll about x).
pub(crate) fn from_euler(roll: f64, pitch: f64, yaw: f64) -> Quat {
    let (sr, cr) = (0.5 * roll).sin_cos();
    let (sp, cp) = (0.5 * pitch).sin_cos();
    let (sy, cy) = (0.5 * yaw).sin_cos();
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}

/// ZYX Euler angles (roll, pitch, yaw), radians.
pub(crate) fn to_euler(q: &Quat) -> (f64, f64, f64) {
    let [w, x, y, z] = *q;
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    (roll, pitch, yaw)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_and_matrix_roundtrip() {
        let q = from_euler(0.3, -0.7, 2.5);
        let (r, p, y) = to_euler(&q);
        assert!((r - 0.3).abs() < 1e-12 && (p + 0.7).abs() < 1e-12 && (y - 2.5).abs() < 1e-12);
        // Rows of R: earth axes in body coordinates = R^T e_i.
        let qc = conj(&q);
        let rows = [
            rotate(&qc, &[1.0, 0.0, 0.0]),
            rotate(&qc, &[0.0, 1.0, 0.0]),
            rotate(&qc, &[0.0, 0.0, 1.0]),
        ];
        let q2 = from_rows(&rows);
        let d = (q[0] * q2[0] + q[1] * q2[1] + q[2] * q2[2] + q[3] * q2[3]).abs();
        assert!((d - 1.0).abs() < 1e-12);
        let v = rotate(&q, &[0.1, 0.2, 0.3]);
        let m = mul(&mul(&q, &[0.0, 0.1, 0.2, 0.3]), &qc);
        for i in 0..3 {
            assert!((v[i] - m[i + 1]).abs() < 1e-12);
        }
    }
}
