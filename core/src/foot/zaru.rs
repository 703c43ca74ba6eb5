//! Gyroscope bias jumps: the stillest window of each stance, if its rate scatters
//! less than the gyroscope's own noise, reads the bias; two consecutive such stances
//! that agree and the estimate cannot explain are a jump, and update the bias (zero rate).

use nalgebra::Vector3;

use super::config::MAX_DETECTOR_WINDOW;
use super::ekf::Strapdown;
use super::types::BodySample;
use crate::signal::Ring;

/// Length of the window whose rate is tested for stillness, s (10 samples at
/// 200 Hz: long enough that a foot rolling at a steady rate shows in the variance).
pub(crate) const ZARU_WINDOW_S: f64 = 0.05;
/// Fewest samples a stillness window holds: the variance of fewer is too noisy to
/// call a window still (at 50 Hz the window is 0.1 s).
pub(crate) const MIN_WINDOW: usize = 5;
/// A window is still when its per-axis rate variance, averaged over the axes, is at
/// most this share of the gyroscope's configured white-noise variance per sample
/// (density² × rate; the default density is set above data sheets on purpose): the
/// stillest stance windows of the UofT MicroStrain stand at 0.35–0.6 of it, the
/// stillest windows of its walks at 2–10 (the foot rolls;
/// docs/lab/2026-12-06-foot-bias.md).
pub(crate) const STILL_NOISE_FACTOR: f64 = 0.64;
/// 1-σ of a still window's mean rate beyond the sensor noise, rad/s: the foot's
/// residual pivot about the vertical, which the variance test does not see (within
/// ±0.005 rad/s per trial over the still windows of the UofT trials).
pub(crate) const ZARU_SIGMA_RADS: f64 = 0.005;
/// χ², 3 degrees of freedom, 99.9 %: a still stance whose rate the bias estimate
/// misses by more than this (normalised innovation squared) is unexplained; two
/// consecutive unexplained still stances whose rates agree within it (their
/// difference normalised by its variance, 2 r per axis) say the bias jumped by more
/// than its random walk allows, and the bias variance is widened so that the update
/// follows. One alone is taken as the foot's motion.
pub(crate) const BIAS_JUMP_NIS: f64 = 16.27;

/// The bias-jump check's state (snapshot format 9).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Zaru {
    /// The stillest still window of the current stance.
    pub window: Option<StillWindow>,
    /// The rate of the last still stance the bias estimate could not explain (body
    /// axes, rad/s), cleared by one it could.
    pub unexplained: Option<[f64; 3]>,
    /// Samples of the current stance so far: a window is a candidate only once it
    /// lies in the stance (with external labels a stance can be one sample long, and
    /// the window would hold the swing before it).
    pub stance_n: u64,
}

/// A still window: its mean per-axis rate variance, (rad/s)², its mean rate (body
/// axes, raw), rad/s, and its length, samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct StillWindow {
    pub var_rads2: f64,
    pub mean_rads: [f64; 3],
    pub n: usize,
}

/// The stillness window in samples at `rate_hz` (at least [`MIN_WINDOW`], at most the
/// ring).
pub(crate) fn window_len(rate_hz: f64) -> usize {
    ((ZARU_WINDOW_S * rate_hz).round() as usize).clamp(MIN_WINDOW, MAX_DETECTOR_WINDOW)
}

impl Zaru {
    /// A stance sample: the newest samples of `det`, once the stance is as long as
    /// they are, are a candidate window, kept if still (`noise_var`: the gyroscope's
    /// white-noise variance per sample) and stiller than the stance's best so far. `detector_var` is the mean per-axis
    /// variance of the newest `detector_n` samples (the detector's window): the
    /// candidate's variance is at least `detector_var · detector_n / n` when it holds
    /// them, which rules most stance samples out without reading the window.
    pub fn observe(
        &mut self,
        det: &Ring<BodySample, MAX_DETECTOR_WINDOW>,
        rate_hz: f64,
        noise_var: f64,
        (detector_var, detector_n): (f64, usize),
    ) {
        self.stance_n = self.stance_n.saturating_add(1);
        let n = window_len(rate_hz);
        // Neither still nor stiller than the best so far, by the lower bound alone.
        let bound = STILL_NOISE_FACTOR * noise_var;
        let best = self.window.map_or(f64::INFINITY, |w| w.var_rads2);
        let at_least = if detector_n <= n {
            detector_var * detector_n as f64 / n as f64
        } else {
            0.0
        };
        if det.len() < n || self.stance_n < n as u64 || at_least > bound || at_least >= best {
            return;
        }
        let (mean, var) = rate_stats(det, n);
        if var <= bound && var < best {
            self.window = Some(StillWindow {
                var_rads2: var,
                mean_rads: mean,
                n,
            });
        }
    }

    /// The stance ended: its stillest window (if any) is checked against the bias
    /// estimate, and updates it if it confirms a jump. Returns whether it did.
    pub fn stance_ended(&mut self, ins: &mut Strapdown, noise_var: f64) -> bool {
        self.stance_n = 0;
        let Some(w) = self.window.take() else {
            return false;
        };
        let r = ZARU_SIGMA_RADS * ZARU_SIGMA_RADS + noise_var / w.n.max(1) as f64;
        let m = Vector3::from(w.mean_rads);
        let Some(nis) = ins.zaru_nis(&m, r) else {
            return false;
        };
        self.jumped(nis, w.mean_rads, r) && ins.bias_jump(&m, r)
    }

    /// Whether a still stance reading `w` (innovation `nis`, variance `r` per axis)
    /// confirms a bias jump: it and the previous still stance are both unexplained
    /// and agree.
    fn jumped(&mut self, nis: f64, w: [f64; 3], r: f64) -> bool {
        if nis <= BIAS_JUMP_NIS {
            self.unexplained = None;
            return false;
        }
        let agree = self.unexplained.is_some_and(|p| {
            let d = Vector3::from(w) - Vector3::from(p);
            d.norm_squared() / (2.0 * r) <= BIAS_JUMP_NIS
        });
        self.unexplained = if agree { None } else { Some(w) };
        agree
    }
}

/// Mean rate (body axes) of the newest `n` samples and its per-axis variance
/// averaged over the axes.
fn rate_stats(det: &Ring<BodySample, MAX_DETECTOR_WINDOW>, n: usize) -> ([f64; 3], f64) {
    let mut m = Vector3::zeros();
    for k in 0..n {
        m += Vector3::from(det.back(k).unwrap_or_default().w);
    }
    m /= n as f64;
    let mut v = 0.0;
    for k in 0..n {
        v += (Vector3::from(det.back(k).unwrap_or_default().w) - m).norm_squared();
    }
    (m.into(), v / (3 * n) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_jump_needs_two_agreeing_unexplained_still_stances() {
        let r = 1e-4;
        let mut z = Zaru::default();
        // Explained: nothing pending.
        assert!(!z.jumped(1.0, [0.03, 0.0, 0.0], r));
        // One unexplained: pending, no jump.
        assert!(!z.jumped(20.0, [0.03, 0.0, 0.0], r));
        // A second that disagrees replaces it.
        assert!(!z.jumped(20.0, [-0.03, 0.0, 0.0], r));
        // A third that agrees with the second confirms.
        assert!(z.jumped(20.0, [-0.031, 0.0, 0.0], r));
        assert_eq!(z.unexplained, None);
        // An explained stance in between clears the pending one.
        assert!(!z.jumped(20.0, [0.03, 0.0, 0.0], r));
        assert!(!z.jumped(1.0, [0.0, 0.0, 0.0], r));
        assert!(!z.jumped(20.0, [0.03, 0.0, 0.0], r));
    }
}
