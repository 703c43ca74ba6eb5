//! The step lengths cross-checked against GNSS (issue 36): over each GNSS stretch the
//! navigator forms (≥ 15 m and 5–60 s between good fixes) the GNSS displacement is set
//! against the dead-reckoned one over the same time. A wrong personal calibration or
//! model is a factor on every step, which the navigator's position update hides at
//! each fix but not between them, nor in the distance.
//!
//! Two stretches in a row off by more than [`DISAGREE_RATIO`] the same way raise
//! [`StepScale::disagrees`] and scale every later step by their mean ratio; further
//! disagreeing stretches refine the scale (half their log-ratio each); a stretch within
//! [`AGREE_RATIO`] clears the flag and the scale stays. Heading errors do not enter:
//! only the lengths of the two displacements are compared, and the steps the detector
//! releases late miss at both ends of a stretch alike.

use crate::snapshot::{Reader, SnapshotError, Writer};

/// A stretch whose GNSS and dead-reckoned displacements differ by more than this factor
/// disagrees (a factor, not noise: 15 m between fixes of a few metres' accuracy, the
/// detector's lag, a step model's spread, all within ≈ 15 %).
pub const DISAGREE_RATIO: f64 = 1.35;
/// ... and one within this factor agrees.
pub const AGREE_RATIO: f64 = 1.15;
/// Disagreeing stretches in a row (the same way) that raise the flag.
const DISAGREE_STRETCHES: u32 = 2;
/// Share of a later stretch's log-ratio taken into the scale while disagreeing.
const REFINE_GAIN: f64 = 0.5;
/// The scale stays within these factors of the step model's lengths.
const SCALE_RANGE: (f64, f64) = (0.5, 2.0);

/// The scale of the step lengths that GNSS taught, and whether they disagree now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepScale {
    factor: f64,
    /// Disagreeing stretches in a row, their sign (+1: GNSS longer) and summed log-ratio.
    run: u32,
    sign: f64,
    run_ln: f64,
    disagrees: bool,
}

impl Default for StepScale {
    fn default() -> Self {
        Self::new()
    }
}

impl StepScale {
    pub const fn new() -> Self {
        Self {
            factor: 1.0,
            run: 0,
            sign: 0.0,
            run_ln: 0.0,
            disagrees: false,
        }
    }

    /// The factor every step length is multiplied by (1 until GNSS disagreed).
    pub fn factor(&self) -> f64 {
        self.factor
    }

    /// Whether GNSS and the step lengths disagree by a factor now.
    pub fn disagrees(&self) -> bool {
        self.disagrees
    }

    /// One GNSS stretch: `gnss_m` the GNSS displacement, `dead_reckoned_m` the
    /// dead-reckoned displacement over the same time (with the current scale).
    pub fn observe(&mut self, gnss_m: f64, dead_reckoned_m: f64) {
        if !(gnss_m > 0.0 && dead_reckoned_m > 0.0) {
            return;
        }
        let ln = (gnss_m / dead_reckoned_m).ln();
        if ln.abs() < AGREE_RATIO.ln() {
            self.run = 0;
            self.disagrees = false;
            return;
        }
        if ln.abs() <= DISAGREE_RATIO.ln() {
            self.run = 0;
            return;
        }
        let sign = ln.signum();
        if sign == self.sign && self.run > 0 {
            self.run = self.run.saturating_add(1);
            self.run_ln += ln;
        } else {
            self.run = 1;
            self.run_ln = ln;
        }
        self.sign = sign;
        if self.disagrees {
            self.rescale(REFINE_GAIN * ln);
        } else if self.run >= DISAGREE_STRETCHES {
            log::warn!(
                "GNSS and the step lengths disagree by a factor of {:.2}: step lengths scaled",
                (self.run_ln / self.run as f64).exp()
            );
            self.disagrees = true;
            self.rescale(self.run_ln / self.run as f64);
        }
    }

    fn rescale(&mut self, ln: f64) {
        let (lo, hi) = SCALE_RANGE;
        self.factor = (self.factor * ln.exp()).clamp(lo, hi);
    }

    pub fn write(&self, w: &mut Writer) {
        let Self {
            factor,
            run,
            sign,
            run_ln,
            disagrees,
        } = self;
        w.f64s(&[*factor, *sign, *run_ln]);
        w.u64(u64::from(*run));
        w.bool(*disagrees);
    }

    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 3];
        r.f64s(&mut v)?;
        let s = Self {
            factor: v[0],
            sign: v[1],
            run_ln: v[2],
            run: r.len(u32::MAX as usize)? as u32,
            disagrees: r.bool()?,
        };
        let (lo, hi) = SCALE_RANGE;
        if !(lo..=hi).contains(&s.factor)
            || ![-1.0, 0.0, 1.0].contains(&s.sign)
            || s.run_ln.abs() > 1e6
        {
            return Err(SnapshotError::Invalid("step scale"));
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_stretches_off_by_a_factor_scale_the_steps_one_in_agreement_clears() {
        let mut s = StepScale::new();
        s.observe(20.0, 21.0);
        assert!(!s.disagrees() && s.factor() == 1.0);
        // Steps 1.5× too long.
        s.observe(20.0, 30.0);
        assert!(!s.disagrees(), "one stretch is not persistent");
        s.observe(18.0, 27.0);
        assert!(s.disagrees());
        assert!((s.factor() - 2.0 / 3.0).abs() < 1e-9, "{}", s.factor());
        // Corrected: the next stretch agrees, the scale stays.
        s.observe(20.0, 20.0 * 1.02);
        assert!(!s.disagrees());
        assert!((s.factor() - 2.0 / 3.0).abs() < 1e-9);
        // Alternating signs are noise, not a factor.
        let mut s = StepScale::new();
        for k in 0..6 {
            s.observe(20.0, if k % 2 == 0 { 28.0 } else { 14.0 });
        }
        assert!(!s.disagrees() && s.factor() == 1.0);
    }
}
