//! Online calibration of step-length models from 5-step GNSS samples.
//!
//! Every model is linear in three parameters θ = (A, B, C) over a model-specific
//! feature vector x, `L = θ·x`:
//!
//! | model | x | θ |
//! |---|---|---|
//! | constant | (0, 0, 1) | (·, ·, L) |
//! | linear | (F, SV, 1) | (A, B, C) |
//! | linear F only | (F, 0, 1) | (A, ·, C) |
//! | Weinberg | ((a_max − a_min)^¼, 0, 0) | (K, ·, ·) |
//!
//! (· = not used by the model: only its prior acts on it, and it never reaches the
//! prediction.) Features of a sample are the means over its 5 steps.
//!
//! **Robust calibration** ([`Regression`]): Bayesian least squares. The normal
//! equations of every accepted sample are accumulated on top of a Gaussian
//! population prior: Λ = Λ₀ + Σ x xᵀ/σ², η = Λ₀θ₀ + Σ x y/σ², θ = Λ⁻¹η. This is the
//! paper's least-squares fit of 20-step blocks with "successive fits averaged", done
//! properly: the posterior is the precision-weighted average of all block fits, and
//! the prior regularises it. When F or SV barely vary (steady walking: the paper's
//! 4-equation blocks are then nearly singular), the data only fix the step length at
//! the user's usual features; A and B stay at the population values and C absorbs
//! the user's level. The model then extrapolates to other paces with the population
//! slope instead of a wild one.
//!
//! **As-published calibration** ([`PublishedFit`]): each block of 4 samples is
//! solved on its own by unweighted least squares (the paper's indirect adjustment;
//! for a model linear in its parameters it is plain least squares, independent of
//! the approximate values A₀, B₀, C₀), blocks whose normal matrix is singular are
//! skipped (nothing else can be done with them), and the fits are averaged with equal
//! weights.

use nalgebra::{Matrix3, Vector3};

use crate::snapshot::{Reader, SnapshotError, Writer};

/// Reciprocal condition below which an as-published block fit is skipped.
const MIN_RCOND: f64 = 1e-12;
/// As-published convergence: the averaged model's prediction at the mean features
/// moved less than this share for `STABLE_FITS` fits in a row.
const PUBLISHED_STABLE_REL: f64 = 0.005;
const STABLE_FITS: u32 = 3;

/// Bayesian least squares in 3 parameters (robust calibration).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Regression {
    /// Information matrix Λ, row-major.
    info: [f64; 9],
    /// Information vector η.
    eta: [f64; 3],
    /// Current solution θ = Λ⁻¹η.
    pub theta: [f64; 3],
}

impl Regression {
    /// Start from a prior with means `mean` and 1-σ `sigma` (independent).
    pub fn new(mean: [f64; 3], sigma: [f64; 3]) -> Self {
        let mut info = [0.0; 9];
        let mut eta = [0.0; 3];
        for i in 0..3 {
            let p = 1.0 / (sigma[i] * sigma[i]);
            info[4 * i] = p;
            eta[i] = p * mean[i];
        }
        Self {
            info,
            eta,
            theta: mean,
        }
    }

    /// Start from a prior with means `mean` and covariance `cov` (row-major 3×3,
    /// symmetric positive definite); `None` if it cannot be inverted.
    pub fn from_covariance(mean: [f64; 3], cov: [f64; 9]) -> Option<Self> {
        let inv = Matrix3::from_row_slice(&cov).try_inverse()?;
        let eta = inv * Vector3::from_column_slice(&mean);
        let mut info = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                // Symmetrised: the inverse of a symmetric matrix, up to rounding.
                info[3 * i + j] = 0.5 * (inv[(i, j)] + inv[(j, i)]);
            }
        }
        (info.iter().chain(eta.iter()).all(|v| v.is_finite())).then_some(Self {
            info,
            eta: [eta[0], eta[1], eta[2]],
            theta: mean,
        })
    }

    /// One diagonal entry of Λ (index into the row-major 3×3).
    pub fn info_diagonal(&self, i: usize) -> f64 {
        self.info[i]
    }

    /// Add one sample `y ≈ θ·x` with 1-σ `sigma` (no solve).
    pub fn add(&mut self, x: [f64; 3], y: f64, sigma: f64) {
        let w = 1.0 / (sigma * sigma);
        for i in 0..3 {
            for j in 0..3 {
                self.info[3 * i + j] += w * x[i] * x[j];
            }
            self.eta[i] += w * x[i] * y;
        }
    }

    fn matrix(&self) -> Matrix3<f64> {
        Matrix3::from_row_slice(&self.info)
    }

    /// Re-solve θ; keeps the old θ if Λ cannot be inverted (it always can: the
    /// prior makes it positive definite).
    pub fn solve(&mut self) {
        if let Some(inv) = self.matrix().try_inverse() {
            let t = inv * Vector3::from_column_slice(&self.eta);
            if t.iter().all(|v| v.is_finite()) {
                self.theta = [t[0], t[1], t[2]];
            }
        }
    }

    /// Marginal 1-σ of each parameter (√ of the diagonal of Λ⁻¹; the prior's σ if Λ
    /// could not be inverted, which the prior prevents).
    pub fn sigma(&self) -> [f64; 3] {
        match self.matrix().try_inverse() {
            Some(inv) => [0, 1, 2].map(|i| inv[(i, i)].max(0.0).sqrt()),
            None => [0, 4, 8].map(|i| 1.0 / self.info[i].sqrt()),
        }
    }

    /// 1-σ of the prediction θ·x.
    pub fn prediction_sigma(&self, x: [f64; 3]) -> f64 {
        match self.matrix().try_inverse() {
            Some(inv) => {
                let x = Vector3::from_column_slice(&x);
                (x.transpose() * inv * x)[(0, 0)].max(0.0).sqrt()
            }
            None => f64::INFINITY,
        }
    }

    pub fn write(&self, w: &mut Writer) {
        w.f64s(&self.info);
        w.f64s(&self.eta);
        w.f64s(&self.theta);
    }

    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut s = Self {
            info: [0.0; 9],
            eta: [0.0; 3],
            theta: [0.0; 3],
        };
        r.f64s(&mut s.info)?;
        r.f64s(&mut s.eta)?;
        r.f64s(&mut s.theta)?;
        if !s
            .info
            .iter()
            .chain(&s.eta)
            .chain(&s.theta)
            .all(|v| v.is_finite())
        {
            return Err(SnapshotError::Invalid("calibration"));
        }
        Ok(s)
    }
}

/// The paper's calibration: per-block least squares, fits averaged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PublishedFit {
    /// Sum of the block solutions.
    sum: [f64; 3],
    pub fits: u32,
    /// Successive fits that barely moved the average.
    stable: u32,
}

impl PublishedFit {
    pub const NEW: Self = Self {
        sum: [0.0; 3],
        fits: 0,
        stable: 0,
    };

    /// Average of the block fits so far (`None` before the first).
    pub fn theta(&self) -> Option<[f64; 3]> {
        (self.fits > 0).then(|| self.sum.map(|s| s / self.fits as f64))
    }

    /// Fit one block of samples (x, y) and fold it into the average. Returns whether
    /// the block could be solved. `x_mean` is where stability is judged.
    pub fn add_block(&mut self, xs: &[[f64; 3]], ys: &[f64], x_mean: [f64; 3]) -> bool {
        let mut n = Matrix3::<f64>::zeros();
        let mut b = Vector3::<f64>::zeros();
        for (x, &y) in xs.iter().zip(ys) {
            let v = Vector3::from_column_slice(x);
            n += v * v.transpose();
            b += v * y;
        }
        // Reciprocal condition estimate from the symmetric eigenvalues.
        let eig = n.symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &e| {
            (lo.min(e), hi.max(e))
        });
        if !(hi > 0.0 && lo / hi > MIN_RCOND) {
            return false;
        }
        let Some(inv) = n.try_inverse() else {
            return false;
        };
        let t = inv * b;
        if !t.iter().all(|v| v.is_finite()) {
            return false;
        }
        let before = self.theta();
        for i in 0..3 {
            self.sum[i] += t[i];
        }
        self.fits = self.fits.saturating_add(1);
        let after = self.theta().unwrap_or([0.0; 3]);
        let dot = |t: [f64; 3]| t[0] * x_mean[0] + t[1] * x_mean[1] + t[2] * x_mean[2];
        match before {
            Some(bf) => {
                let l = dot(after);
                if l.abs() > 0.0 && (l - dot(bf)).abs() < PUBLISHED_STABLE_REL * l.abs() {
                    self.stable = self.stable.saturating_add(1);
                } else {
                    self.stable = 0;
                }
            }
            None => self.stable = 0,
        }
        true
    }

    /// Converged: at least `min_fits` fits and the last few barely moved the average.
    pub fn converged(&self, min_fits: u32) -> bool {
        self.fits >= min_fits && self.stable >= STABLE_FITS
    }

    pub fn write(&self, w: &mut Writer) {
        w.f64s(&self.sum);
        w.u64(self.fits as u64);
        w.u64(self.stable as u64);
    }

    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut sum = [0.0; 3];
        r.f64s(&mut sum)?;
        let fits = r.len(u32::MAX as usize)? as u32;
        let stable = r.len(u32::MAX as usize)? as u32;
        if !sum.iter().all(|v| v.is_finite()) {
            return Err(SnapshotError::Invalid("published fit"));
        }
        Ok(Self { sum, fits, stable })
    }
}
