//! Inclination: gyroscope strapdown into an almost-inertial frame, and the
//! accelerometer averaged in that frame.
//!
//! The gyroscope (bias-corrected) is integrated into `q_gyr`, body → I. Over seconds
//! `I` barely moves against the earth (only the residual bias turns it, hundredths of
//! a degree per second), so the accelerometer rotated into `I` is gravity plus the
//! device's linear acceleration — and that averages out: velocity is bounded, so the
//! mean acceleration over T seconds is Δv/T. A second-order low-pass with
//! Butterworth damping (ζ = 1/√2, cut-off ω_c = √2/T so that T is its delay at low
//! frequencies) averages `a_I` (the rotation is undone *before* averaging, so turning
//! the device does not smear gravity, unlike a low-pass in the body frame). Against two
//! first-order stages of the same delay it halves what passes at high frequencies. The inclination correction
//! `q_inc` (I → E', E' = the earth frame up to a rotation about the vertical) is the
//! smallest rotation that makes the averaged vector vertical, applied in full every
//! sample: the inclination follows the average without lag of its own.
//!
//! The correction is also what the residual gyroscope bias does to `I` (about
//! horizontal earth axes), which [`super::bias`] integrates.

use crate::ahrs::quat::{self, Quat};

/// Above this half-angle² per sample the gyroscope increment uses sin/cos (0.1 rad).
const SERIES_HALF_ANGLE2: f64 = 0.05 * 0.05;

/// Largest |component| of the low-passed acceleration, m/s²: the input limit.
pub(crate) const MAX_AVG_MPS2: f64 = crate::input::limits::MAX_ACCEL_NORM_MPS2;
/// Smallest |average|² with a direction, (m/s²)².
const MIN_DIRECTION_NORM2: f64 = 1e-12;
/// Largest |component| of its rate of change, m/s³.
pub(crate) const MAX_AVG_RATE_MPS3: f64 = 1e6 * MAX_AVG_MPS2;

/// How the accelerometer is averaged.
///
/// While its span still grows (after a start, a clipped reading or a gap the
/// gyroscope could not bridge) the average is a running mean over that span: it
/// forgets what it held before in proportion 1/t. The second-order low-pass with a
/// cut-off √2/t that grows with the span forgets its start only as 1/√t (its
/// equation t²x'' + 2tx' + 2x = 0 has the roots (−1 ± i√7)/2): measured on BROAD with
/// 10 % of the samples dropped in bursts, a 30° inclination error left by a missed
/// rotation was still 8–10° two seconds later.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Averaging {
    /// Running mean over the span so far, s.
    Growing { span_s: f64 },
    /// Second-order low-pass with this cut-off, rad/s (√2 / averaging time).
    LowPass { omega: f64 },
}

/// Strapdown orientation, the averaged accelerometer and the inclination correction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Tilt {
    /// Body → I (gyroscope only), [w, x, y, z].
    pub(crate) q_gyr: Quat,
    /// I → E' (inclination corrections).
    pub(crate) q_inc: Quat,
    /// Low-pass of the specific force in I, m/s², and its rate of change, m/s³.
    pub(crate) avg: [f64; 3],
    pub(crate) avg_rate: [f64; 3],
}

impl Tilt {
    /// Start from one accelerometer sample: I = the body frame now, the averages at
    /// this sample, the inclination from it alone.
    pub(crate) fn start(&mut self, a: &[f64; 3]) {
        self.q_gyr = [1.0, 0.0, 0.0, 0.0];
        self.avg = *a;
        self.avg_rate = [0.0; 3];
        self.q_inc = [1.0, 0.0, 0.0, 0.0];
        if let Some(c) = vertical_correction(a, norm2(a)) {
            self.q_inc = quat::normalised(c);
        }
    }

    /// Integrate the gyroscope over `dt`; returns the specific force `a` (body frame)
    /// seen in the new I.
    #[inline(always)]
    pub(crate) fn integrate(&mut self, w: &[f64; 3], dt: f64, a: &[f64; 3]) -> [f64; 3] {
        let h = [0.5 * w[0] * dt, 0.5 * w[1] * dt, 0.5 * w[2] * dt];
        let h2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
        let (c, s) = if h2 < SERIES_HALF_ANGLE2 {
            // cos |h| and sin |h| / |h| to fourth order (error < 3e-11 at the limit).
            (
                1.0 - h2 * (0.5 - h2 * (1.0 / 24.0)),
                1.0 - h2 * ((1.0 / 6.0) - h2 * (1.0 / 120.0)),
            )
        } else {
            exact_half_angle(h2)
        };
        let dq = [c, s * h[0], s * h[1], s * h[2]];
        // |q ⊗ dq|² = |q|²·|dq|²: neither waits for the product.
        let n2 = norm2_q(&self.q_gyr) * (c * c + s * s * h2);
        let p = quat::mul(&self.q_gyr, &dq);
        let inv = inverse_norm(n2);
        self.q_gyr = [p[0] * inv, p[1] * inv, p[2] * inv, p[3] * inv];
        // R(p/|p|)·a = R_h(p)·a/|p|² (R_h: the rotation's homogeneous quadratic form):
        // starts from the product, without waiting for its renormalisation.
        let s2 = inv * inv;
        let a_i = rotate_h(&p, a);
        [a_i[0] * s2, a_i[1] * s2, a_i[2] * s2]
    }

    /// Average the specific force `a_i` (in I, from [`Tilt::integrate`]) over `dt` as
    /// `averaging` says, then make the average vertical. Returns the correction as a
    /// rotation vector in E' (rad, horizontal), or `None` when the average is zero.
    #[inline(always)]
    pub(crate) fn correct(
        &mut self,
        a_i: &[f64; 3],
        dt: f64,
        averaging: Averaging,
    ) -> Option<[f64; 3]> {
        let a_i = *a_i;
        let w = match averaging {
            Averaging::LowPass { omega } => omega,
            Averaging::Growing { span_s } => {
                self.running_mean(&a_i, dt, span_s);
                return self.make_vertical();
            }
        };
        // x'' = ω²(u − x) − 2ζω x', ζ = 1/√2, ω = √2/T, by semi-implicit Euler; the step
        // is bounded to ω·dt ≤ 1/√2 (stable for any interval).
        let h = if w * dt < std::f64::consts::FRAC_1_SQRT_2 {
            dt
        } else {
            std::f64::consts::FRAC_1_SQRT_2 / w
        };
        let (w2h, damp) = (w * w * h, std::f64::consts::SQRT_2 * w * h);
        for ((x, r), u) in self.avg.iter_mut().zip(&mut self.avg_rate).zip(a_i) {
            let rate = *r + (w2h * (u - *x) - damp * *r);
            // Held within the ranges restore accepts (a no-op for any real input: an
            // average of accelerations cannot leave the accelerometer's range), so a
            // state restored at those limits cannot run past them.
            *r = rate.clamp(-MAX_AVG_RATE_MPS3, MAX_AVG_RATE_MPS3);
            *x = (*x + h * *r).clamp(-MAX_AVG_MPS2, MAX_AVG_MPS2);
        }
        self.make_vertical()
    }

    /// The average as a running mean of `a_i` over the `span_s` seconds since the
    /// (re)start (its rate of change held at 0 for the low-pass that follows).
    #[cold]
    fn running_mean(&mut self, a_i: &[f64; 3], dt: f64, span_s: f64) {
        let k = if dt < span_s { dt / span_s } else { 1.0 };
        for ((x, r), u) in self.avg.iter_mut().zip(&mut self.avg_rate).zip(a_i) {
            *x = (*x + k * (u - *x)).clamp(-MAX_AVG_MPS2, MAX_AVG_MPS2);
            *r = 0.0;
        }
    }

    /// Turn E' so that the average is vertical; the turn as a rotation vector.
    #[inline(always)]
    fn make_vertical(&mut self) -> Option<[f64; 3]> {
        let v = quat::rotate(&self.q_inc, &self.avg);
        let c = vertical_correction(&v, norm2(&self.avg))?;
        // |c|² = c_w (see [`vertical_correction`]), but for the turn of an average
        // pointing straight down (c_w = 0, |c| = 1).
        let c2 = if c[0] > 0.0 { c[0] } else { 1.0 };
        let n2 = c2 * norm2_q(&self.q_inc);
        self.q_inc = renormalise(quat::mul(&c, &self.q_inc), n2);
        // Rotation vector of c: (v_y, −v_x, 0)/n · θ/sin θ ≈ 2·(c_x, c_y, 0) for the
        // small angles of one sample.
        Some([2.0 * c[1], 2.0 * c[2], 0.0])
    }

    /// Body → E'.
    #[inline(always)]
    pub(crate) fn q_body_to_e(&self) -> Quat {
        quat::mul(&self.q_inc, &self.q_gyr)
    }
}

/// Smallest rotation taking `v` to the vertical (+z), or `None` for a zero vector;
/// `n2` = |v|², which the caller knows without `v` (a rotated vector keeps its
/// length). With n = |v|, cos θ = v_z/n and axis v × ẑ = (v_y, −v_x, 0): the
/// half-angle quaternion is ∝ (1 + cos θ, sin θ · axis) = (n + v_z, v_y, −v_x, 0)/n.
/// Scaled by 1/(2n) its norm is cos(θ/2): unit to second order in θ, which the
/// renormalisation after the product absorbs.
///
/// The square root and the division depend on `n2` alone: for the average, which
/// the gyroscope's frame carries, they are off the chain from one sample's
/// inclination correction to the next (rotate, these products, quaternion product,
/// renormalisation), which is what bounds the update's speed.
#[inline(always)]
pub(crate) fn vertical_correction(v: &[f64; 3], n2: f64) -> Option<Quat> {
    // Below 1 µm/s² (free fall) the average has no direction; near 1e-160 its squares
    // underflow and the correction would be NaN.
    if n2.is_nan() || n2 < MIN_DIRECTION_NORM2 {
        return None;
    }
    if v[2] > 0.0 {
        let f = 0.5 / n2.sqrt();
        return Some([0.5 + v[2] * f, v[1] * f, -v[0] * f, 0.0]);
    }
    vertical_correction_exact(v, norm2(v))
}

/// |v|².
#[inline(always)]
pub(crate) fn norm2(v: &[f64; 3]) -> f64 {
    v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
}

/// |q|².
#[inline(always)]
fn norm2_q(q: &Quat) -> f64 {
    q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
}

/// [`vertical_correction`] of an average pointing down (cold: upside down).
#[cold]
#[inline(never)]
fn vertical_correction_exact(v: &[f64; 3], n2: f64) -> Option<Quat> {
    if n2 <= 0.0 || !n2.is_finite() {
        return None;
    }
    let n = n2.sqrt();
    let w = n + v[2];
    Some(if w > 1e-6 * n {
        let f = 0.5 / n;
        [w * f, v[1] * f, -v[0] * f, 0.0]
    } else {
        // Upside down: any horizontal axis will do.
        [0.0, 1.0, 0.0, 0.0]
    })
}

/// q / |q| for |q| ≈ 1 (products of unit quaternions), `n2` = |q|² as the caller
/// knows it from the factors (so it is not computed after the product, on the chain
/// from one sample to the next): 1/√(1+ε) ≈ 1 − ε/2 + 3ε²/8.
#[inline(always)]
pub(crate) fn renormalise(q: Quat, n2: f64) -> Quat {
    let inv = inverse_norm(n2);
    [q[0] * inv, q[1] * inv, q[2] * inv, q[3] * inv]
}

/// 1/√`n2` for `n2` ≈ 1 (see [`renormalise`]).
#[inline(always)]
fn inverse_norm(n2: f64) -> f64 {
    let eps = n2 - 1.0;
    if eps.abs() < 1e-3 {
        1.0 - 0.5 * eps + 0.375 * eps * eps
    } else {
        exact_inverse_norm(eps)
    }
}

/// R(q/|q|)·v·|q|², the rotation by a quaternion of any length as the homogeneous
/// quadratic form of its components.
#[inline(always)]
fn rotate_h(q: &Quat, v: &[f64; 3]) -> [f64; 3] {
    let [w, x, y, z] = *q;
    let (ww, xx, yy, zz) = (w * w, x * x, y * y, z * z);
    [
        (ww + xx - yy - zz) * v[0] + 2.0 * (x * y - w * z) * v[1] + 2.0 * (x * z + w * y) * v[2],
        2.0 * (x * y + w * z) * v[0] + (ww - xx + yy - zz) * v[1] + 2.0 * (y * z - w * x) * v[2],
        2.0 * (x * z - w * y) * v[0] + 2.0 * (y * z + w * x) * v[1] + (ww - xx - yy + zz) * v[2],
    ]
}

#[cold]
#[inline(never)]
fn exact_half_angle(h2: f64) -> (f64, f64) {
    let a = h2.sqrt();
    let (s, c) = a.sin_cos();
    (c, s / a)
}

#[cold]
#[inline(never)]
fn exact_inverse_norm(eps: f64) -> f64 {
    let n2 = 1.0 + eps;
    if n2 > 0.0 && n2.is_finite() {
        1.0 / n2.sqrt()
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertical_correction_makes_vectors_vertical() {
        for v in [
            [0.3, -0.2, 9.0],
            [5.0, 5.0, -1.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
        ] {
            let q = quat::normalised(vertical_correction(&v, norm2(&v)).unwrap());
            let r = quat::rotate(&q, &v);
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!(r[0].abs() < 1e-12 && r[1].abs() < 1e-12, "{r:?}");
            assert!((r[2] - n).abs() < 1e-12);
            assert_eq!(q[3], 0.0, "no rotation about the vertical");
        }
        assert!(vertical_correction(&[0.0; 3], 0.0).is_none());
        let q = quat::normalised(vertical_correction(&[0.0, 0.0, -1.0], 1.0).unwrap());
        assert!((quat::rotate(&q, &[0.0, 0.0, -1.0])[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn homogeneous_rotation_is_the_rotation_scaled_by_the_norm_squared() {
        let q = quat::normalised([0.9, -0.2, 0.3, 0.25]);
        let v = [0.4, -9.7, 1.3];
        for s in [1.0, 1.0 + 1e-9, 0.5, 3.0] {
            let r = rotate_h(&q.map(|c| c * s), &v);
            let want = quat::rotate(&q, &v);
            for i in 0..3 {
                assert!(
                    (r[i] - s * s * want[i]).abs() < 1e-12 * s * s * 10.0,
                    "{r:?}"
                );
            }
        }
    }

    #[test]
    fn integrate_returns_the_specific_force_in_the_new_frame() {
        let mut t = Tilt::default();
        t.start(&[0.0, 0.0, 9.81]);
        let a = [0.3, -0.4, 9.7];
        for _ in 0..50 {
            let a_i = t.integrate(&[0.8, -0.3, 1.1], 0.01, &a);
            let want = quat::rotate(&t.q_gyr, &a);
            for i in 0..3 {
                assert!((a_i[i] - want[i]).abs() < 1e-12, "{a_i:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn strapdown_matches_the_exact_rotation() {
        let mut t = Tilt::default();
        t.start(&[0.0, 0.0, 9.81]);
        // 1 rad/s about (1, 2, 2)/3 for 2 s in 0.01 s steps, and a fast 30 rad/s turn.
        for (rate, n, dt) in [(1.0, 200, 0.01), (30.0, 10, 0.01)] {
            let mut t = t;
            let axis = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
            let w = axis.map(|c| c * rate);
            for _ in 0..n {
                t.integrate(&w, dt, &[0.0, 0.0, 9.81]);
            }
            let half = 0.5 * rate * dt * n as f64;
            let want = [
                half.cos(),
                axis[0] * half.sin(),
                axis[1] * half.sin(),
                axis[2] * half.sin(),
            ];
            for i in 0..4 {
                assert!(
                    (t.q_gyr[i] - want[i]).abs() < 1e-9,
                    "{:?} vs {want:?}",
                    t.q_gyr
                );
            }
        }
    }
}
