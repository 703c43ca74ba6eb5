//! Online hard-iron estimate: the magnetometer's constant offset in the body frame,
//! from a least-squares sphere fit `|m − h|² = const`, i.e. `2 m·h + c = |m|²`, with
//! forgetting (re-solved once a stride) and a ridge towards zero.

use nalgebra::{Matrix4, Vector4};

/// Forgetting time constant of the fit, s.
pub(super) const HARD_IRON_TAU_S: f64 = 900.0;
/// Ridge towards zero, µT²: an offset along a direction the field never swept stays
/// near zero.
const HARD_IRON_RIDGE_UT2: f64 = 4.0;
/// Samples (forgetting included) of the fit before its solution is used.
const HARD_IRON_MIN_N: f64 = 1000.0;
/// Largest plausible offset per axis, µT: a solution beyond it is not taken.
const MAX_OFFSET_UT: f64 = 100.0;

/// The fit's sums and its latest solution.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct HardIron {
    /// Upper triangle of Σ x xᵀ for x = (2m, 1): 10 values, then Σ x |m|²: 4 values.
    pub(super) sums: [f64; 14],
    /// The offset, body frame, µT.
    pub(super) h_ut: [f64; 3],
}

impl HardIron {
    /// One accepted field sample, body frame, µT.
    pub(super) fn add(&mut self, m: &[f64; 3]) {
        let x = [2.0 * m[0], 2.0 * m[1], 2.0 * m[2], 1.0];
        let y = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
        let s = &mut self.sums;
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                s[k] += x[i] * x[j];
                k += 1;
            }
        }
        for i in 0..4 {
            s[10 + i] += x[i] * y;
        }
    }

    /// Forget (factor `decay`) and re-solve.
    pub(super) fn solve(&mut self, decay: f64) {
        for s in self.sums.iter_mut() {
            *s *= decay;
        }
        let s = &self.sums;
        let n = s[9];
        if n < HARD_IRON_MIN_N {
            return;
        }
        let mut a = Matrix4::zeros();
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                a[(i, j)] = s[k];
                a[(j, i)] = s[k];
                k += 1;
            }
        }
        // x = 2m: the ridge on h is 4 × the one on the offset.
        let ridge = 4.0 * n * HARD_IRON_RIDGE_UT2;
        for i in 0..3 {
            a[(i, i)] += ridge;
        }
        let b = Vector4::new(s[10], s[11], s[12], s[13]);
        if let Some(x) = a.cholesky().map(|c| c.solve(&b)) {
            let h = [x[0], x[1], x[2]];
            if h.iter().all(|v| v.is_finite() && v.abs() < MAX_OFFSET_UT) {
                self.h_ut = h;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Field samples of strength 45 µT in directions spread over the sphere, plus `h`.
    fn sphere(h: [f64; 3], n: usize) -> HardIron {
        let mut fit = HardIron::default();
        for i in 0..n {
            let (a, b) = (i as f64 * 0.37, i as f64 * 0.113);
            let d = [a.cos() * b.sin(), a.sin() * b.sin(), b.cos()];
            fit.add(&[45.0 * d[0] + h[0], 45.0 * d[1] + h[1], 45.0 * d[2] + h[2]]);
        }
        fit
    }

    #[test]
    fn recovers_an_offset_from_a_swept_field() {
        let h = [12.0, -7.0, 3.0];
        let mut fit = sphere(h, 5000);
        fit.solve(1.0);
        for (got, want) in fit.h_ut.iter().zip(h) {
            // The ridge pulls a little towards zero.
            assert!((got - want).abs() < 0.5, "{:?}", fit.h_ut);
        }
    }

    #[test]
    fn waits_for_enough_samples_and_forgets() {
        let mut fit = sphere([12.0, -7.0, 3.0], 900);
        fit.solve(1.0);
        assert_eq!(fit.h_ut, [0.0; 3]);
        let before = fit.sums[9];
        fit.solve(0.5);
        assert_eq!(fit.sums[9], 0.5 * before);
    }
}
