//! Settings of the pace engine, with named defaults.

use super::calibration::PaceCalibration;
use super::error::PaceError;

/// Which fusion filter the tracker runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PaceMode {
    /// The complementary filter of Skrzypczyk (method 1 of docs/architecture.md) as published, with the
    /// dimensional fixes documented in `super::published`.
    AsPublished,
    /// stridekit's default: an adaptive Kalman filter fusing GNSS positions (with a
    /// correlated-error model and robust weighting) with cadence × learned step length.
    Adaptive,
}

/// Parameters of the as-published complementary filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PublishedParams {
    /// Number of fixes in the polynomial fit and the variance window (paper: N = 5).
    pub window_n: usize,
    /// Cadence window in GNSS epochs (paper: H = 10).
    pub cadence_h: usize,
    /// Variance threshold σ²_THR of per-interval distances, m² (paper: 0.8).
    pub variance_threshold_m2: f64,
    /// Slope β of the weight sigmoid, 1/m² (not given by the paper).
    pub sigmoid_beta_per_m2: f64,
    /// EMA smoothing factor α of per-interval distances (not given by the paper).
    pub ema_alpha: f64,
}

impl Default for PublishedParams {
    fn default() -> Self {
        Self {
            window_n: 5,
            cadence_h: 10,
            variance_threshold_m2: 0.8,
            sigmoid_beta_per_m2: 5.0,
            ema_alpha: 0.5,
        }
    }
}

/// Parameters of the default adaptive Kalman filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveParams {
    /// Along-track acceleration noise of the runner, m/s² (1-σ): speed changes.
    pub accel_noise_mps2: f64,
    /// Cross-track acceleration noise, m/s² (1-σ): turns and corners.
    pub turn_accel_noise_mps2: f64,
    /// Per-axis 1-σ of GNSS white noise assumed when a fix has no accuracy, metres.
    pub default_gnss_sigma_m: f64,
    /// 1-σ of the slowly varying (correlated) GNSS error, metres.
    pub gnss_bias_sigma_m: f64,
    /// Correlation time of the GNSS error, seconds.
    pub gnss_bias_tau_s: f64,
    /// Relative 1-σ of cadence × step length against true speed (gait variability).
    pub pedometer_rel_sigma: f64,
    /// GNSS gap after which the position is re-anchored on the next fix, seconds.
    pub outage_reset_s: f64,
    /// Fixes with a worse horizontal accuracy are not used to learn step length, metres.
    pub learn_max_accuracy_m: f64,
    /// Random walk of the learned step length, m/√s: how fast it may follow changes
    /// of gait, terrain or fatigue while GNSS is good.
    pub step_length_rw_m_per_sqrt_s: f64,
}

impl Default for AdaptiveParams {
    fn default() -> Self {
        Self {
            accel_noise_mps2: 0.7,
            turn_accel_noise_mps2: 1.0,
            default_gnss_sigma_m: 3.0,
            gnss_bias_sigma_m: 2.0,
            gnss_bias_tau_s: 30.0,
            pedometer_rel_sigma: 0.03,
            outage_reset_s: 10.0,
            learn_max_accuracy_m: 12.0,
            step_length_rw_m_per_sqrt_s: 0.003,
        }
    }
}

/// Configuration of a [`PaceTracker`](super::PaceTracker).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaceConfig {
    pub mode: PaceMode,
    /// Step length at 168 steps/min used before any is learned, metres (`None`: a
    /// population prior of 1.0 m with a wide uncertainty, learned from GNSS). It is
    /// the running step length: below 132 steps/min (a walk) a population walking
    /// step length is used instead (`pace/walking.rs`).
    pub initial_step_length_m: Option<f64>,
    /// Without a step for this long while step data flows, the runner is stationary, seconds.
    pub stationary_after_s: f64,
    /// A step-length line learned in an earlier session (takes precedence over
    /// `initial_step_length_m`, unless its `step_length_std_m` is 0.2 m or more: such
    /// a line holds nothing learned and only its accelerometer model is used);
    /// `None`: learn from GNSS, starting at the prior.
    pub calibration: Option<PaceCalibration>,
    pub published: PublishedParams,
    pub adaptive: AdaptiveParams,
}

impl Default for PaceConfig {
    fn default() -> Self {
        Self {
            mode: PaceMode::Adaptive,
            initial_step_length_m: None,
            stationary_after_s: 2.0,
            calibration: None,
            published: PublishedParams::default(),
            adaptive: AdaptiveParams::default(),
        }
    }
}

impl AdaptiveParams {
    /// Set a parameter by name (for evaluation sweeps and the CLI's `--set`).
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), PaceError> {
        let slot = match name {
            "accel_noise_mps2" => &mut self.accel_noise_mps2,
            "turn_accel_noise_mps2" => &mut self.turn_accel_noise_mps2,
            "default_gnss_sigma_m" => &mut self.default_gnss_sigma_m,
            "gnss_bias_sigma_m" => &mut self.gnss_bias_sigma_m,
            "gnss_bias_tau_s" => &mut self.gnss_bias_tau_s,
            "pedometer_rel_sigma" => &mut self.pedometer_rel_sigma,
            "outage_reset_s" => &mut self.outage_reset_s,
            "learn_max_accuracy_m" => &mut self.learn_max_accuracy_m,
            "step_length_rw_m_per_sqrt_s" => &mut self.step_length_rw_m_per_sqrt_s,
            _ => {
                return Err(PaceError::InvalidConfig {
                    reason: format!("unknown adaptive parameter {name}"),
                })
            }
        };
        *slot = value;
        Ok(())
    }
}

impl PaceConfig {
    /// The paper's filter with its published parameters.
    pub fn as_published() -> Self {
        Self {
            mode: PaceMode::AsPublished,
            ..Self::default()
        }
    }

    /// Check every field; a tracker is only built from a valid configuration.
    pub fn validate(&self) -> Result<(), PaceError> {
        let bad = |reason: &str| {
            Err(PaceError::InvalidConfig {
                reason: reason.to_string(),
            })
        };
        let p = &self.published;
        if !(3..=super::published::MAX_WINDOW).contains(&p.window_n) {
            return bad("published.window_n must be in 3..=32");
        }
        if !(1..=super::published::MAX_WINDOW).contains(&p.cadence_h) {
            return bad("published.cadence_h must be in 1..=32");
        }
        let positive = [
            ("published.variance_threshold_m2", p.variance_threshold_m2),
            ("published.sigmoid_beta_per_m2", p.sigmoid_beta_per_m2),
            ("adaptive.accel_noise_mps2", self.adaptive.accel_noise_mps2),
            (
                "adaptive.turn_accel_noise_mps2",
                self.adaptive.turn_accel_noise_mps2,
            ),
            (
                "adaptive.default_gnss_sigma_m",
                self.adaptive.default_gnss_sigma_m,
            ),
            (
                "adaptive.gnss_bias_sigma_m",
                self.adaptive.gnss_bias_sigma_m,
            ),
            ("adaptive.gnss_bias_tau_s", self.adaptive.gnss_bias_tau_s),
            (
                "adaptive.pedometer_rel_sigma",
                self.adaptive.pedometer_rel_sigma,
            ),
            ("adaptive.outage_reset_s", self.adaptive.outage_reset_s),
            (
                "adaptive.learn_max_accuracy_m",
                self.adaptive.learn_max_accuracy_m,
            ),
            (
                "adaptive.step_length_rw_m_per_sqrt_s",
                self.adaptive.step_length_rw_m_per_sqrt_s,
            ),
            ("stationary_after_s", self.stationary_after_s),
        ];
        // Every parameter is a noise, a time or a threshold: positive and at most 10⁶
        // of its unit, so no product in the filters can overflow.
        for (name, v) in positive {
            if !(v > 0.0 && v <= 1e6) {
                return Err(PaceError::InvalidConfig {
                    reason: format!("{name} must be in (0, 1e6], got {v}"),
                });
            }
        }
        if !(p.ema_alpha > 0.0 && p.ema_alpha <= 1.0) {
            return bad("published.ema_alpha must be in (0, 1]");
        }
        if let Some(c) = &self.calibration {
            c.validate()?;
        }
        if let Some(l) = self.initial_step_length_m {
            if !(l.is_finite() && (0.2..=3.0).contains(&l)) {
                return bad("initial_step_length_m must be in 0.2..=3.0 m");
            }
        }
        Ok(())
    }
}
