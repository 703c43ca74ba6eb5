//! Raw accelerometer input of the pace tracker: steps detected from it, and a step
//! length that follows the acceleration of each step.
//!
//! With platform step counts or a watch's cadence the tracker knows only how often
//! the feet land; through a GNSS outage it can only read its learned step-length line
//! at the cadence, so a runner who speeds up or slows down at the same cadence (longer
//! or shorter steps, the usual way runners change pace) is paced wrong. Raw
//! acceleration says more: a longer step at the same cadence lands harder and swings
//! the body more. When the app pushes raw acceleration
//! ([`super::PaceTracker::push_accel`]), every detected step also goes to a
//! [`StepLengthEstimator`] (the robust linear model `L = A·F + B·SV + C` of step
//! frequency and acceleration variance, method 3 of docs/architecture.md) that the
//! tracker's GNSS fixes calibrate while they are good. Once that calibration has
//! converged, the pedometer measurement uses the mean modelled length of the steps of
//! the last [`WINDOW_S`] whenever GNSS cannot teach the step length (an outage, a
//! disturbed stretch): speed = cadence × the step length of *these* steps, not the
//! line's value at the cadence. With good GNSS the filter's own line is used as
//! before; without raw acceleration nothing changes.
//!
//! The calibrated model is carried between sessions in
//! [`super::PaceCalibration::accel_model`]: imported, it counts as calibrated from the
//! first step (a treadmill run with raw acceleration is paced by its steps' features
//! from the start), and good GNSS keeps refining it.

use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stepdetect::{StepDetector, StepEvent};
use crate::steplength::{StepLengthConfig, StepLengthEstimator, StepLengthModel};

use super::AccelStepModel;

/// Steps whose modelled lengths are averaged, looking back this far from the
/// measurement time, seconds (the cadence window of the pedometer update).
pub const WINDOW_S: f64 = 4.0;
/// Fewest steps in the window for a feature step length.
const MIN_STEPS: usize = 3;
/// Recent step lengths kept (≥ 4 s of steps at 4 steps/s).
const RECENT: usize = 24;
/// The step-length model fed from the detected steps.
pub const MODEL: StepLengthModel = StepLengthModel::Linear;

/// One modelled step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Modelled {
    t_s: f64,
    length_m: f64,
}

/// Step detector and feature step length for raw accelerometer input.
#[derive(Clone, Debug, PartialEq)]
pub struct AccelSteps {
    detector: StepDetector,
    length: StepLengthEstimator,
    recent: Ring<Modelled, RECENT>,
    /// The imported model (calibrated from the start), `None` without one. Not in the
    /// snapshot: it follows from the configuration, which is.
    imported: Option<AccelStepModel>,
}

/// The estimator's settings here: the defaults, learning on after convergence (a
/// run's pace keeps changing; the tracker keeps following it while GNSS is good).
fn length_config() -> StepLengthConfig {
    StepLengthConfig {
        freeze_when_converged: false,
        ..StepLengthConfig::default()
    }
}

impl AccelSteps {
    /// Raw-accelerometer steps, starting from an imported model (validated with the
    /// configuration) or from the population prior.
    pub fn new(imported: Option<&AccelStepModel>) -> Self {
        let prior = || {
            StepLengthEstimator::new(MODEL, length_config())
                .expect("the default step-length configuration is valid")
        };
        // A validated model is always accepted; were it refused, the prior is not
        // taken for a calibration.
        let calibrated = imported.and_then(|m| {
            StepLengthEstimator::calibrated_at(
                MODEL,
                length_config(),
                m.theta(),
                m.reference(),
                [m.a_std_m_s, m.b_std_m_per_m2ps4],
                m.length_std_m,
            )
            .ok()
            .map(|e| (e, *m))
        });
        Self {
            detector: StepDetector::default(),
            imported: calibrated.as_ref().map(|(_, m)| *m),
            length: calibrated.map_or_else(prior, |(e, _)| e),
            recent: Ring::new(),
        }
    }

    pub fn detector(&self) -> &StepDetector {
        &self.detector
    }

    pub fn detector_mut(&mut self) -> &mut StepDetector {
        &mut self.detector
    }

    /// A detected step: modelled (and queued for calibration by the next fixes).
    pub fn on_step(&mut self, e: &StepEvent) {
        // Detected steps come in time order with checked features; a step the
        // estimator refuses all the same is left out of the window.
        if let Ok(length_m) = self.length.push_step(e) {
            if length_m.is_finite() {
                self.recent.push(Modelled {
                    t_s: e.t_s,
                    length_m,
                });
            }
        }
    }

    /// A fix in the tracker's local frame (calibrates while GNSS is good).
    pub fn on_fix(&mut self, t_s: f64, east_m: f64, north_m: f64, accuracy_m: Option<f64>) {
        // Fixes were checked at the tracker's door and come in time order.
        let _ = self.length.push_gnss_fix(t_s, east_m, north_m, accuracy_m);
    }

    /// Whether GNSS has calibrated the step-length model: converged, or at least
    /// the estimator's `min_fits` 20-step fits (200 steps of good GNSS; its
    /// convergence test, 1 % of the step length, is for freezing the calibration).
    pub fn calibrated(&self) -> bool {
        let c = self.length.calibration();
        self.imported.is_some() || c.converged || c.fits >= self.length.config().min_fits
    }

    /// The model to carry to the next session, once calibrated (imported, or learned
    /// from GNSS); `None` before.
    pub fn export(&self) -> Option<AccelStepModel> {
        if !self.calibrated() {
            return None;
        }
        // Until GNSS has taught it something, an imported model goes out as it came;
        // then centred at the features of its calibration samples.
        let Some(x0) = self.length.typical_features() else {
            return self.imported;
        };
        let [a, b, c] = self.length.calibration().theta;
        let sigma = self.length.theta_sigma();
        let m = AccelStepModel {
            a_m_s: a,
            b_m_per_m2ps4: b,
            c_m: c,
            ref_frequency_hz: x0[0],
            ref_variance_m2ps4: x0[1],
            a_std_m_s: sigma[0],
            b_std_m_per_m2ps4: sigma[1],
            length_std_m: self.length.prediction_sigma(x0),
        };
        m.validate().is_ok().then_some(m)
    }

    /// Relative 1-σ of the modelled step length at the user's typical features (the
    /// calibration's uncertainty, not a step's scatter), once calibrated.
    pub fn rel_sigma(&self) -> Option<f64> {
        if !self.calibrated() {
            return None;
        }
        let (x0, l) = match self.length.typical_features() {
            Some(x) => (x, self.length.calibration().typical_step_length_m),
            None => {
                let m = self.imported?;
                (m.reference(), m.reference_length_m())
            }
        };
        (l > 0.0).then(|| self.length.prediction_sigma(x0) / l)
    }

    /// The step-length model's calibration state.
    pub fn calibration(&self) -> crate::steplength::Calibration {
        self.length.calibration()
    }

    /// Mean modelled length of the steps in `(t_s − WINDOW_S, t_s]`, metres, once
    /// calibrated and with at least [`MIN_STEPS`] of them.
    pub fn step_length_m(&self, t_s: f64) -> Option<f64> {
        if !self.calibrated() {
            return None;
        }
        let (mut sum, mut n) = (0.0, 0usize);
        for s in self.recent.iter().rev() {
            if s.t_s <= t_s - WINDOW_S {
                break;
            }
            if s.t_s <= t_s {
                sum += s.length_m;
                n += 1;
            }
        }
        (n >= MIN_STEPS).then(|| sum / n as f64)
    }

    pub fn write(&self, w: &mut Writer) {
        w.bytes(&self.detector.snapshot());
        w.bytes(&self.length.snapshot());
        w.u64(self.recent.len() as u64);
        for s in self.recent.iter() {
            w.f64s(&[s.t_s, s.length_m]);
        }
    }

    /// Read what [`Self::write`] wrote; `imported` from the restored configuration.
    pub fn read(r: &mut Reader, imported: Option<&AccelStepModel>) -> Result<Self, SnapshotError> {
        let imported = imported.copied();
        let detector = StepDetector::restore(r.bytes()?)
            .map_err(|_| SnapshotError::Invalid("accelerometer step detector"))?;
        let length = StepLengthEstimator::restore(r.bytes()?)
            .map_err(|_| SnapshotError::Invalid("accelerometer step length"))?;
        if length.model() != MODEL || *length.config() != length_config() {
            return Err(SnapshotError::Invalid("accelerometer step length"));
        }
        let n = r.len(RECENT)?;
        let mut recent = Ring::new();
        let mut prev = f64::NEG_INFINITY;
        for _ in 0..n {
            let mut v = [0.0; 2];
            r.f64s(&mut v)?;
            let [t_s, length_m] = v;
            if !(t_s.is_finite() && t_s >= prev && length_m.is_finite() && length_m > 0.0) {
                return Err(SnapshotError::Invalid("accelerometer step lengths"));
            }
            prev = t_s;
            recent.push(Modelled { t_s, length_m });
        }
        Ok(Self {
            detector,
            length,
            recent,
            imported,
        })
    }
}
