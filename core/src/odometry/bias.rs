//! The paper's low-frequency acceleration-bias correction over a sliding block of
//! windows.
//!
//! For the last `B` windows (`B` = [`BLOCK`]) with regressed velocities `v_R^f`
//! and raw velocity increments `d^f` (horizontal ENU linear acceleration integrated
//! over each hop, centred on the window's centre), find per-window bias increments
//! `x^f` minimising
//!
//! `Σ_f ‖v_C^f − v_R^f‖² + λ Σ_f ‖x^f‖²`,  `v_C^f = v_0 + Σ_{f' ≤ f} (d^{f'} + x^{f'})`,
//!
//! with `v_0` the corrected velocity of the window just before the block. With the
//! lower-triangular ones matrix `L` and `c_f = v_0 + Σ_{f'≤f} d^{f'} − v_R^f`, the
//! solution is `x = −(LᵀL + λI)⁻¹ Lᵀ c`, the same constant `B × B` matrix for east
//! and north (precomputed, fixed-size nalgebra). The corrected velocity of the newest
//! window is the output: the regressor sets the low frequencies, the integrated
//! acceleration the high ones; λ → ∞ is plain integration from `v_0`, λ → 0 is `v_R`.
//!
//! Deviation from the paper: the bias is solved in the horizontal ENU plane per hop
//! (2-D), not as a 3-D device-frame bias rotated by `R_SW R_WI`; over a few seconds
//! the two differ only by the device's rotation.

use nalgebra::{SMatrix, SVector};

use crate::signal::Ring;

/// Windows per block.
pub const BLOCK: usize = 20;

/// One window's entry: regressed velocity, raw increment, corrected output.
pub(crate) type Entry = ([f64; 2], [f64; 2], [f64; 2]);

/// Sliding-block bias correction.
#[derive(Clone, Debug, PartialEq)]
pub struct BiasCorrector {
    gain: SMatrix<f64, BLOCK, BLOCK>,
    pub(crate) hist: Ring<Entry, { BLOCK + 1 }>,
}

impl BiasCorrector {
    pub fn new(lambda: f64) -> Self {
        let l = SMatrix::<f64, BLOCK, BLOCK>::from_fn(|i, j| if j <= i { 1.0 } else { 0.0 });
        let a = l.transpose() * l + SMatrix::<f64, BLOCK, BLOCK>::identity() * lambda;
        // λ > 0 makes A symmetric positive definite.
        let inv = a
            .cholesky()
            .map(|c| c.inverse())
            .unwrap_or_else(SMatrix::identity);
        Self {
            gain: inv * l.transpose(),
            hist: Ring::new(),
        }
    }

    pub fn reset(&mut self) {
        self.hist.clear();
    }

    /// Add a window (`v_r` regressed velocity, `d` raw increment); returns the
    /// corrected velocity (`v_r` itself until a block and its anchor are held).
    pub fn push(&mut self, v_r: [f64; 2], d: [f64; 2]) -> [f64; 2] {
        if self.hist.len() < BLOCK {
            self.hist.push((v_r, d, v_r));
            return v_r;
        }
        // After this push the ring holds the anchor (0) and the block (1..=BLOCK).
        self.hist.push((v_r, d, v_r));
        let (_, _, v0) = self.hist.get(0).unwrap_or_default();
        let mut out = [0.0; 2];
        for (axis, o) in out.iter_mut().enumerate() {
            let mut c = SVector::<f64, BLOCK>::zeros();
            let mut cum = v0[axis];
            for j in 0..BLOCK {
                let (vr, dj, _) = self.hist.get(j + 1).unwrap_or_default();
                cum += dj[axis];
                c[j] = cum - vr[axis];
            }
            let x = -(self.gain * c);
            *o = cum + x.sum();
        }
        if let Some(e) = self.hist.newest_mut() {
            e.2 = out;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_the_regressor_when_increments_are_biased() {
        // True velocity 1 m/s east, increments carry a constant bias: the output
        // stays near v_R instead of drifting.
        let mut b = BiasCorrector::new(1.0);
        let mut last = [0.0; 2];
        for _ in 0..500 {
            last = b.push([1.0, 0.0], [0.05, 0.0]);
        }
        assert!((last[0] - 1.0).abs() < 0.2, "{last:?}");
        // Large λ: plain integration from the anchor drifts by the bias.
        let mut b = BiasCorrector::new(1e6);
        for _ in 0..100 {
            last = b.push([1.0, 0.0], [0.05, 0.0]);
        }
        assert!(last[0] > 2.0, "{last:?}");
    }
}
