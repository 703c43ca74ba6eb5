//! The demo's next session without GNSS (a treadmill): the run's steps alone, paced
//! with the calibration the GNSS session exported and with the population prior.

use stridekit_core::PaceConfig;

/// The run's steps replayed alone (a treadmill the next day), with the calibration
/// the GNSS session exported and with the population prior.
pub(super) struct Treadmill {
    pub(super) t_s: Vec<f64>,
    pub(super) truth: Vec<f64>,
    pub(super) calibrated: Vec<f64>,
    pub(super) prior: Vec<f64>,
}

impl Treadmill {
    /// The steps of `samples` with `calibration` (what the GNSS session exported) and
    /// with the prior; `None` without any step.
    pub(super) fn measure(
        run: &stridekit_sim::SimulatedRun,
        samples: &[stridekit_core::PaceSample],
        calibration: stridekit_core::PaceCalibration,
    ) -> Option<Self> {
        use crate::pace_device::steps_only;
        let (t_s, calibrated) = steps_only(
            samples,
            PaceConfig {
                calibration: Some(calibration),
                ..PaceConfig::default()
            },
        );
        if t_s.is_empty() {
            return None;
        }
        let (_, prior) = steps_only(samples, PaceConfig::default());
        let truth = t_s.iter().map(|&t| run.truth_at(t).speed_mps).collect();
        Some(Self {
            t_s,
            truth,
            calibrated,
            prior,
        })
    }

    /// Speed RMSE against the truth, m/s, and the distance error, %.
    fn score(&self, speed: &[f64]) -> (f64, f64) {
        let n = self.t_s.len().max(1) as f64;
        let se: f64 = speed
            .iter()
            .zip(&self.truth)
            .map(|(v, t)| (v - t).powi(2))
            .sum();
        let (d, dt): (f64, f64) = (speed.iter().sum(), self.truth.iter().sum());
        ((se / n).sqrt(), 100.0 * (d - dt) / dt)
    }

    pub(super) fn sentence(&self) -> String {
        let (rc, dc) = self.score(&self.calibrated);
        let (rp, dp) = self.score(&self.prior);
        format!(
            "**Next session without GNSS** (a treadmill: this run's steps alone, every fix left out): \
             with the calibration this run exported (`PaceTracker.calibration()`, imported through \
             `PaceConfig.calibration` in Kotlin and Swift) speed RMSE {rc:.3} m/s, distance {dc:+.1} %; \
             with the population prior {rp:.3} m/s, {dp:+.1} %."
        )
    }
}
