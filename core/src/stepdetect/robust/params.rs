//! Settings of the default step detector: one set for every placement, rate and user
//! (`stridekit eval steps --sensitivity` shows how each moves the count, with a
//! leave-one-user-out check on the Oxford traces).

use super::PENDING;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Parameters of the default detector (one set for every placement and rate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobustStepParams {
    /// Cut-off of the magnitude low-pass, Hz.
    pub lowpass_hz: f64,
    /// Smallest hysteresis of the peak detector, m/s².
    pub min_hysteresis_mps2: f64,
    /// Hysteresis relative to the RMS of the de-meaned magnitude.
    pub hysteresis_rel: f64,
    /// Smallest peak-to-valley amplitude of a step, m/s², except for the steps of a
    /// slow walk whose steps are all about as weak (see docs/phone.md).
    pub min_amplitude_mps2: f64,
    /// Largest peak-to-valley amplitude of a step, m/s² (beyond: violent shaking).
    pub max_amplitude_mps2: f64,
    /// Shortest interval between two steps, s (5 steps/s).
    pub min_step_interval_s: f64,
    /// Shortest median step interval that can start a bout, s.
    pub min_bout_interval_s: f64,
    /// Longest interval between steps of one bout, s.
    pub max_step_interval_s: f64,
    /// Consecutive regular candidates needed to confirm a bout.
    pub confirm_steps: usize,
    /// Allowed relative deviation of the intervals from their median when confirming.
    pub regularity: f64,
    /// Least normalised autocorrelation at the step or stride period.
    pub min_periodicity: f64,
    /// A bout is refused when the median impact ratio of its candidates is below this
    /// (RMS of the magnitude above 8 Hz over the step / step amplitude): smooth motion
    /// without heel impacts, such as pedalling.
    pub min_impact_ratio: f64,
    /// Step periods shorter than this are running cadences, s ...
    pub running_interval_s: f64,
    /// ... which need at least this median amplitude to start a bout, m/s² (running
    /// shakes the body by well over 1 g; at such a cadence small peaks are the
    /// secondary bumps of a slow walk), unless the cadence is a walk's (2.86 steps/s
    /// at most) and the signal repeats at every step (a fast walk: consecutive steps
    /// look alike, a bump does not look like a heel strike).
    pub running_min_amplitude_mps2: f64,
    /// Candidates smaller than this fraction of the typical recent step amplitude are
    /// secondary bumps, not steps.
    pub relative_amplitude: f64,
    /// In a bout, candidates sooner than this fraction of the period are double peaks.
    pub refractory: f64,
}

impl Default for RobustStepParams {
    fn default() -> Self {
        Self {
            lowpass_hz: 4.0,
            min_hysteresis_mps2: 0.3,
            hysteresis_rel: 0.5,
            min_amplitude_mps2: 1.0,
            max_amplitude_mps2: 60.0,
            min_step_interval_s: 0.2,
            min_bout_interval_s: 0.25,
            max_step_interval_s: 2.0,
            confirm_steps: 5,
            regularity: 0.3,
            min_periodicity: 0.4,
            min_impact_ratio: 0.008,
            refractory: 0.6,
            relative_amplitude: 0.45,
            running_interval_s: 0.45,
            running_min_amplitude_mps2: 4.0,
        }
    }
}

impl RobustStepParams {
    pub(crate) fn validate(&self) -> Result<(), String> {
        let all = self.as_array();
        if all.iter().any(|v| !v.is_finite()) {
            return Err("parameters must be finite".into());
        }
        if !(0.5..=20.0).contains(&self.lowpass_hz) {
            return Err("lowpass_hz must be 0.5..=20".into());
        }
        if self.min_hysteresis_mps2 <= 0.0 || self.hysteresis_rel < 0.0 {
            return Err("hysteresis must be positive".into());
        }
        if !(self.min_amplitude_mps2 >= 0.0 && self.max_amplitude_mps2 > self.min_amplitude_mps2) {
            return Err("need 0 ≤ min_amplitude_mps2 < max_amplitude_mps2".into());
        }
        if !(self.min_step_interval_s > 0.0
            && self.min_bout_interval_s >= self.min_step_interval_s
            && self.max_step_interval_s > self.min_bout_interval_s
            && self.max_step_interval_s <= 2.5)
        {
            return Err(
                "need 0 < min_step_interval_s ≤ min_bout_interval_s < max_step_interval_s ≤ 2.5"
                    .into(),
            );
        }
        if self.running_interval_s < 0.0 || self.running_min_amplitude_mps2 < 0.0 {
            return Err("running gate must not be negative".into());
        }
        if !(2..=PENDING).contains(&self.confirm_steps) {
            return Err(format!("confirm_steps must be 2..={PENDING}"));
        }
        if !(0.0..=1.0).contains(&self.regularity)
            || !(-1.0..=1.0).contains(&self.min_periodicity)
            || !(0.0..=1.0).contains(&self.min_impact_ratio)
            || !(0.0..1.0).contains(&self.refractory)
            || !(0.0..1.0).contains(&self.relative_amplitude)
        {
            return Err("regularity, periodicity, impact ratio, refractory or relative amplitude out of range".into());
        }
        Ok(())
    }

    /// Every numeric setting (the snapshot writes these and `confirm_steps`).
    fn as_array(&self) -> [f64; 15] {
        // Exhaustive on purpose: a new setting must be added here (and so to the
        // snapshot).
        let Self {
            lowpass_hz,
            min_hysteresis_mps2,
            hysteresis_rel,
            min_amplitude_mps2,
            max_amplitude_mps2,
            min_step_interval_s,
            min_bout_interval_s,
            max_step_interval_s,
            regularity,
            min_periodicity,
            min_impact_ratio,
            refractory,
            relative_amplitude,
            running_interval_s,
            running_min_amplitude_mps2,
            confirm_steps: _, // an integer, written on its own
        } = *self;
        [
            lowpass_hz,
            min_hysteresis_mps2,
            hysteresis_rel,
            min_amplitude_mps2,
            max_amplitude_mps2,
            min_step_interval_s,
            min_bout_interval_s,
            max_step_interval_s,
            regularity,
            min_periodicity,
            min_impact_ratio,
            refractory,
            relative_amplitude,
            running_interval_s,
            running_min_amplitude_mps2,
        ]
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.f64s(&self.as_array());
        w.u64(self.confirm_steps as u64);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 15];
        r.f64s(&mut v)?;
        let [lowpass_hz, min_hysteresis_mps2, hysteresis_rel, min_amplitude_mps2, max_amplitude_mps2, min_step_interval_s, min_bout_interval_s, max_step_interval_s, regularity, min_periodicity, min_impact_ratio, refractory, relative_amplitude, running_interval_s, running_min_amplitude_mps2] =
            v;
        let confirm_steps = r.len(PENDING)?;
        Ok(Self {
            lowpass_hz,
            min_hysteresis_mps2,
            hysteresis_rel,
            min_amplitude_mps2,
            max_amplitude_mps2,
            min_step_interval_s,
            min_bout_interval_s,
            max_step_interval_s,
            confirm_steps,
            regularity,
            min_periodicity,
            min_impact_ratio,
            refractory,
            relative_amplitude,
            running_interval_s,
            running_min_amplitude_mps2,
        })
    }
}
