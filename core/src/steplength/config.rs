//! Settings of the step-length estimator, with named defaults.

use super::error::StepLengthError;

/// Which step-length model the estimator runs (method 3 of docs/architecture.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StepLengthModel {
    /// One step length for every step: GNSS distance / steps over good-GNSS
    /// samples, held when GNSS is lost.
    Constant,
    /// `L = A·F + B·SV + C`, calibrated online by regularised, precision-weighted
    /// least squares over every good 5-step sample (stridekit's robust version).
    Linear,
    /// `L = A·F + B·SV + C` calibrated exactly as the paper describes: an unweighted
    /// least-squares fit of each 20-step block (4 samples), successive fits averaged,
    /// refitting stopped once the average stops moving. Sample distances are GNSS
    /// chords. No regularisation: ill-conditioned blocks give wild fits.
    LinearAsPublished,
    /// `L = A·F + C` (B fixed at 0): the linear model when only cadence is known
    /// (watches and foot pods without raw acceleration). Robust calibration.
    LinearFrequencyOnly,
    /// Weinberg: `L = K·(a_max − a_min)^¼`, K calibrated like the linear model.
    Weinberg,
    /// Inverted pendulum (Zijlstra & Hof 2003): the body vaults over the stance leg,
    /// so a step of length L raises and lowers it by h with L ≈ 2·√(2·l·h) for a leg
    /// of length l; here `L = K·√h`, h the device's peak-to-peak vertical
    /// displacement over the step ([`crate::stepdetect::StepEvent::vertical_displacement_m`],
    /// filled in by the phone navigator from its attitude), K calibrated like the
    /// linear model (prior: l = 0.9 m). A step whose h is unknown gets the prior step
    /// length and does not calibrate.
    Pendulum,
}

impl StepLengthModel {
    /// Every model, in report order.
    pub const ALL: [StepLengthModel; 6] = [
        StepLengthModel::Constant,
        StepLengthModel::Linear,
        StepLengthModel::LinearAsPublished,
        StepLengthModel::LinearFrequencyOnly,
        StepLengthModel::Weinberg,
        StepLengthModel::Pendulum,
    ];

    /// Short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            StepLengthModel::Constant => "constant",
            StepLengthModel::Linear => "linear (robust)",
            StepLengthModel::LinearAsPublished => "linear (as published)",
            StepLengthModel::LinearFrequencyOnly => "linear F only",
            StepLengthModel::Weinberg => "Weinberg",
            StepLengthModel::Pendulum => "inverted pendulum",
        }
    }

    pub(crate) fn code(self) -> u8 {
        match self {
            StepLengthModel::Constant => 0,
            StepLengthModel::Linear => 1,
            StepLengthModel::LinearAsPublished => 2,
            StepLengthModel::LinearFrequencyOnly => 3,
            StepLengthModel::Weinberg => 4,
            StepLengthModel::Pendulum => 5,
        }
    }

    pub(crate) fn from_code(c: u8) -> Option<Self> {
        Self::ALL.iter().copied().find(|m| m.code() == c)
    }
}

/// Leg length behind the pendulum model's prior K, metres (an adult's, about 0.53 of
/// a stature of 1.7 m).
pub const PRIOR_LEG_LENGTH_M: f64 = 0.9;
/// 2·√(2·l) for [`PRIOR_LEG_LENGTH_M`].
pub const PRIOR_PENDULUM_K: f64 = 2.683_281_572_999_747_7;

/// Tunables of [`super::StepLengthEstimator`]. The paper's block structure (5 steps
/// per sample, 4 samples per fit) is fixed; these are the rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepLengthConfig {
    /// "Good GNSS": fixes reporting a worse 68 % horizontal accuracy are not used,
    /// metres. Fixes without an accuracy are accepted.
    pub max_accuracy_m: f64,
    /// Steps are only located between two good fixes at most this far apart, seconds.
    pub max_fix_gap_s: f64,
    /// Two fixes implying a faster motion are inconsistent (a jump), m/s.
    pub max_fix_speed_mps: f64,
    /// Steps further apart than this break a block (a stop), seconds.
    pub max_step_gap_s: f64,
    /// Robust models only: a block whose summed 5-step chords exceed its end-to-end
    /// chord by this factor is rejected (a turn or a GNSS jump inside the block;
    /// along-track projection would be biased short).
    pub max_detour_ratio: f64,
    /// Plausible range of a block's mean step length, metres (outside: rejected).
    pub min_step_length_m: f64,
    pub max_step_length_m: f64,
    /// Population prior of the linear model, `L = A·F + B·SV + C`: means and 1-σ.
    /// A in m per (step/s), B in m per (m/s²)², C in m.
    pub prior_a: f64,
    pub prior_a_sigma: f64,
    pub prior_b: f64,
    pub prior_b_sigma: f64,
    pub prior_c: f64,
    pub prior_c_sigma: f64,
    /// Prior of the constant model's step length and of the Weinberg K, with 1-σ.
    pub prior_step_length_m: f64,
    pub prior_step_length_sigma_m: f64,
    pub prior_weinberg_k: f64,
    pub prior_weinberg_k_sigma: f64,
    /// Prior K of the inverted-pendulum model `L = K·√h` (m^½), with 1-σ: 2·√(2·l)
    /// for a leg length l of 0.9 m (a population value, not fitted to any data).
    pub prior_pendulum_k: f64,
    pub prior_pendulum_k_sigma: f64,
    /// 1-σ of one 5-step sample's step length (GNSS noise over a few seconds and
    /// gait variability), metres: weighs samples against the prior.
    pub sample_sigma_m: f64,
    /// Calibration has converged when the 1-σ of the step length predicted at the
    /// user's mean features is below this share of it (after `min_fits` fits).
    pub converged_rel_sigma: f64,
    /// Fewest 20-step fits before convergence can be declared.
    pub min_fits: u32,
    /// Stop refitting once converged (the paper's rule). When false the calibration
    /// keeps learning from every good block.
    pub freeze_when_converged: bool,
}

impl Default for StepLengthConfig {
    fn default() -> Self {
        Self {
            max_accuracy_m: 10.0,
            max_fix_gap_s: 3.0,
            max_fix_speed_mps: 8.0,
            max_step_gap_s: 2.0,
            max_detour_ratio: 1.5,
            min_step_length_m: 0.25,
            max_step_length_m: 2.5,
            // Walking ~0.7 m at 1.8 steps/s, running ~1.1 m at 2.8 steps/s.
            prior_a: 0.4,
            prior_a_sigma: 0.15,
            prior_b: 0.0,
            prior_b_sigma: 0.002,
            prior_c: -0.02,
            prior_c_sigma: 1.0,
            prior_step_length_m: 0.75,
            prior_step_length_sigma_m: 0.5,
            prior_weinberg_k: 0.4,
            prior_weinberg_k_sigma: 0.3,
            prior_pendulum_k: PRIOR_PENDULUM_K,
            prior_pendulum_k_sigma: 2.0,
            sample_sigma_m: 0.2,
            converged_rel_sigma: 0.01,
            min_fits: 10,
            freeze_when_converged: true,
        }
    }
}

impl StepLengthConfig {
    /// Check every field; `InvalidConfig` names the first bad one.
    pub fn validate(&self) -> Result<(), StepLengthError> {
        let bad = |reason: &str| {
            Err(StepLengthError::InvalidConfig {
                reason: reason.to_string(),
            })
        };
        let positive = [
            ("max_accuracy_m", self.max_accuracy_m),
            ("max_fix_gap_s", self.max_fix_gap_s),
            ("max_fix_speed_mps", self.max_fix_speed_mps),
            ("max_step_gap_s", self.max_step_gap_s),
            ("min_step_length_m", self.min_step_length_m),
            ("prior_a_sigma", self.prior_a_sigma),
            ("prior_b_sigma", self.prior_b_sigma),
            ("prior_c_sigma", self.prior_c_sigma),
            ("prior_step_length_m", self.prior_step_length_m),
            ("prior_step_length_sigma_m", self.prior_step_length_sigma_m),
            ("prior_weinberg_k", self.prior_weinberg_k),
            ("prior_weinberg_k_sigma", self.prior_weinberg_k_sigma),
            ("prior_pendulum_k", self.prior_pendulum_k),
            ("prior_pendulum_k_sigma", self.prior_pendulum_k_sigma),
            ("sample_sigma_m", self.sample_sigma_m),
            ("converged_rel_sigma", self.converged_rel_sigma),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return bad(&format!("{name} must be a positive number, got {v}"));
            }
        }
        for (name, v) in [
            ("prior_a", self.prior_a),
            ("prior_b", self.prior_b),
            ("prior_c", self.prior_c),
        ] {
            if !v.is_finite() {
                return bad(&format!("{name} must be finite"));
            }
        }
        if !(self.max_detour_ratio.is_finite() && self.max_detour_ratio >= 1.0) {
            return bad("max_detour_ratio must be ≥ 1");
        }
        if !(self.max_step_length_m.is_finite() && self.max_step_length_m > self.min_step_length_m)
        {
            return bad("max_step_length_m must exceed min_step_length_m");
        }
        Ok(())
    }
}
