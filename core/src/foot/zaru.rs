//! Gyroscope bias jumps: the stillest window of each stance, if its rate scatters
//! less than the gyroscope's own noise, reads the bias; two consecutive such stances
//! that agree, or one still for long, and the estimate cannot explain are a jump (zero rate).

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
/// A still run this long, s, reads the bias on its own: a foot that stands still (its
/// rate scatter at the sensor's noise throughout) for 0.25 s is standing, not rolling
/// through a stride (the flat part of a walking stance is shorter; none of the 42
/// UofT trials' walks or runs holds one, the stairs session's pauses do:
/// docs/lab/2026-12-06-foot-bias.md, round 2), so one unexplained such run is a jump
/// without waiting for a second stance.
pub(crate) const LONG_STILL_S: f64 = 0.25;
/// A still run goes on while the per-axis variance of all its rates is at most this
/// share of the configured white-noise variance per sample: the whole of it, as a
/// run's variance settles at the sensor's own (0.6 of the configured on the UofT
/// MicroStrain at rest) plus the foot's sway, and the stricter start bound
/// ([`STILL_NOISE_FACTOR`]) would end a standing foot's run at a random sample.
pub(crate) const RUN_NOISE_FACTOR: f64 = 1.0;
/// The heading a jump turned is given back over at most this long before the run
/// that read it, s: without an explained run before (a recording that starts with
/// the jump) or after a long walk, the jump's time is not known beyond it.
pub(crate) const MAX_GIVE_BACK_S: f64 = 10.0;

/// The bias-jump check's state (snapshot format 9; the still runs since format 12).
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
    /// The still run under way: consecutive stance samples from a still window on
    /// whose rates, together, still scatter within the bound.
    pub run: StillRun,
    /// The longest still run of the current stance.
    pub longest: StillRun,
    /// End of the last still run the bias estimate explained (or of a jump), s.
    pub explained_t_s: Option<f64>,
}

/// Consecutive still samples: their count, the times of the first and the last, s,
/// and the sums of their rates (body axes, raw, rad/s) and of their squared norms,
/// (rad/s)².
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct StillRun {
    pub n: u64,
    pub t0_s: f64,
    pub t1_s: f64,
    pub sum_rads: [f64; 3],
    pub sum_sq_rads2: f64,
}

impl StillRun {
    /// The run of a still window (mean `m`, mean per-axis variance `var` over `n`).
    fn of_window(m: [f64; 3], var: f64, n: usize, (t0_s, t1_s): (f64, f64)) -> Self {
        let nf = n as f64;
        StillRun {
            n: n as u64,
            t0_s,
            t1_s,
            sum_rads: m.map(|x| x * nf),
            sum_sq_rads2: var * 3.0 * nf + nf * Vector3::from(m).norm_squared(),
        }
    }

    /// The run with one more sample of rate `w`.
    fn with(&self, w: [f64; 3], t_s: f64) -> Self {
        StillRun {
            n: self.n + 1,
            t0_s: self.t0_s,
            t1_s: t_s,
            sum_rads: std::array::from_fn(|i| self.sum_rads[i] + w[i]),
            sum_sq_rads2: self.sum_sq_rads2 + Vector3::from(w).norm_squared(),
        }
    }

    pub fn mean_rads(&self) -> [f64; 3] {
        let n = self.n.max(1) as f64;
        self.sum_rads.map(|x| x / n)
    }

    /// Mean per-axis variance of the run's rates, (rad/s)².
    pub fn var_rads2(&self) -> f64 {
        let n = self.n.max(1) as f64;
        let m = Vector3::from(self.mean_rads());
        ((self.sum_sq_rads2 / n - m.norm_squared()) / 3.0).max(0.0)
    }
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
        self.extend_run(det, RUN_NOISE_FACTOR * noise_var);
        if det.len() < n || self.stance_n < n as u64 || at_least > bound {
            return;
        }
        if at_least >= best && self.run.n > 0 {
            return;
        }
        let (mean, var) = rate_stats(det, n);
        if var > bound {
            return;
        }
        if var < best {
            self.window = Some(StillWindow {
                var_rads2: var,
                mean_rads: mean,
                n,
            });
        }
        if self.run.n == 0 {
            let t = |k: usize| det.back(k).map_or(0.0, |s| s.t_s);
            self.run = StillRun::of_window(mean, var, n, (t(n - 1), t(0)));
        }
    }

    /// The run under way takes the newest sample while the run stays within `bound`;
    /// otherwise it ends (kept if the stance's longest).
    fn extend_run(&mut self, det: &Ring<BodySample, MAX_DETECTOR_WINDOW>, bound: f64) {
        if self.run.n == 0 {
            return;
        }
        let Some(s) = det.back(0) else { return };
        let run = self.run.with(s.w, s.t_s);
        if run.var_rads2() <= bound {
            self.run = run;
        } else {
            self.close_run();
        }
    }

    fn close_run(&mut self) {
        if self.run.n > self.longest.n {
            self.longest = self.run;
        }
        self.run = StillRun::default();
    }

    /// The stance ended (at `t_s`). If the foot stood (its longest still run lasted
    /// [`LONG_STILL_S`]), the run reads the bias: a zero-angular-rate update when the
    /// estimate explains it, a jump when not. Otherwise its stillest window (if any)
    /// is checked against the estimate, and updates it if it confirms a jump (two
    /// stances). Returns whether a jump was taken.
    pub fn stance_ended(
        &mut self,
        ins: &mut Strapdown,
        noise_var: f64,
        (rate_hz, t_s): (f64, f64),
    ) -> bool {
        self.stance_n = 0;
        self.close_run();
        let long = std::mem::take(&mut self.longest);
        let window = self.window.take();
        if long.n > 0 {
            let standing = long.n as f64 >= LONG_STILL_S * rate_hz;
            let r = ZARU_SIGMA_RADS * ZARU_SIGMA_RADS + noise_var / long.n as f64;
            let m = Vector3::from(long.mean_rads());
            match ins.zaru_nis(&m, r) {
                Some(nis) if nis <= BIAS_JUMP_NIS => {
                    self.explained_t_s = Some(long.t1_s);
                    if standing {
                        // The bias is read whether it moved or not (a failed update
                        // changes nothing).
                        ins.zaru(&m, r);
                    }
                }
                Some(_) if standing => {
                    self.unexplained = None;
                    return self.long_jump(ins, &m, r, &long);
                }
                _ => {}
            }
        }
        let Some(w) = window else {
            return false;
        };
        let r = ZARU_SIGMA_RADS * ZARU_SIGMA_RADS + noise_var / w.n.max(1) as f64;
        let m = Vector3::from(w.mean_rads);
        let Some(nis) = ins.zaru_nis(&m, r) else {
            return false;
        };
        if nis <= BIAS_JUMP_NIS {
            self.explained_t_s = Some(t_s);
        }
        let jump = self.jumped(nis, w.mean_rads, r) && ins.bias_jump(&m, r);
        if jump {
            self.explained_t_s = Some(t_s);
        }
        jump
    }

    /// A bias jump read by a long still run: the update, then the heading the jump
    /// turned from when it happened to the run's end given back. It happened after the
    /// last explained still run (at most [`MAX_GIVE_BACK_S`] before) and before this
    /// one began: taken at the middle, the rest of the interval added to the heading
    /// variance. The rate it added about the vertical is the bias change seen through
    /// the attitude now (the foot stands as it stood).
    #[cold]
    fn long_jump(&mut self, ins: &mut Strapdown, m: &Vector3<f64>, r: f64, run: &StillRun) -> bool {
        let before = ins.bg;
        if !ins.bias_jump(m, r) {
            return false;
        }
        let turned_rads = (ins.q * (ins.bg - before)).z;
        let earliest = self.explained_t_s.map_or(run.t0_s - MAX_GIVE_BACK_S, |t| {
            t.max(run.t0_s - MAX_GIVE_BACK_S)
        });
        let (mid, spread) = (0.5 * (earliest + run.t0_s), run.t0_s - earliest);
        ins.turn(-turned_rads * (run.t1_s - mid));
        ins.widen_heading((turned_rads * spread).powi(2) / 12.0);
        self.explained_t_s = Some(run.t1_s);
        true
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
