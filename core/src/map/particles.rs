//! The particle cloud: per hypothesis a position on the plan, a heading offset (what
//! the phone's heading is off from the plan's north) and a step-length scale, with a
//! weight. Structure of arrays, allocated once: spreading, moving by a step (a wall
//! crossing rules a particle out), weighting, systematic resampling, summaries.

use super::plan::FloorPlan;
use crate::angle::wrap;
use crate::rng::Rng;

/// Draws of a position before a particle is put at the centre itself.
const SPREAD_TRIES: usize = 16;
/// Resample when the effective sample size falls below this share of the particles.
const RESAMPLE_BELOW: f64 = 0.5;

/// The heading offsets a spread draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum OffsetPrior {
    /// Normal around a mean, rad.
    Normal { mean: f64, sigma: f64 },
    /// Any direction (no magnetometer: the heading is relative to where it started).
    Uniform,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Cloud {
    pub(crate) x: Vec<f64>,
    pub(crate) y: Vec<f64>,
    pub(crate) off: Vec<f64>,
    pub(crate) scale: Vec<f64>,
    /// Normalised weights (0: ruled out).
    pub(crate) w: Vec<f64>,
    /// Scratch of the resampling: the chosen indices, and one array to gather through.
    pub(crate) pick: Vec<u32>,
    tmp: Vec<f64>,
}

/// A summary of the cloud.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Summary {
    pub(crate) x: f64,
    pub(crate) y: f64,
    /// Per-axis 1-σ of the position (root of the mean of the two variances), m.
    pub(crate) std_m: f64,
    /// Circular mean and spread of the heading offset, rad.
    pub(crate) off: f64,
    pub(crate) off_std: f64,
    pub(crate) scale: f64,
    /// Share of the weight within `radius` of the mean.
    pub(crate) near_share: f64,
}

impl Cloud {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            x: vec![0.0; n],
            y: vec![0.0; n],
            off: vec![0.0; n],
            scale: vec![1.0; n],
            w: vec![1.0 / n as f64; n],
            pick: vec![0; n],
            tmp: vec![0.0; n],
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.x.len()
    }

    /// Draw offsets and scales for every particle.
    pub(crate) fn draw_states(&mut self, rng: &mut Rng, prior: OffsetPrior, scale_sigma: f64) {
        for i in 0..self.len() {
            self.off[i] = match prior {
                OffsetPrior::Normal { mean, sigma } => mean + sigma * rng.normal(),
                OffsetPrior::Uniform => std::f64::consts::TAU * (rng.uniform() - 0.5),
            };
            self.scale[i] = (1.0 + scale_sigma * rng.normal()).max(0.5);
        }
    }

    /// Positions around `c` (normal, per-axis σ), each walkable and in sight of `c`
    /// (not across a wall from it); equal weights.
    pub(crate) fn spread_around(
        &mut self,
        plan: &FloorPlan,
        rng: &mut Rng,
        c: [f64; 2],
        sigma: f64,
    ) {
        let n = self.len();
        for i in 0..n {
            let mut p = c;
            for _ in 0..SPREAD_TRIES {
                let q = [c[0] + sigma * rng.normal(), c[1] + sigma * rng.normal()];
                if plan.is_walkable(q) && !plan.crosses_wall(c, q) {
                    p = q;
                    break;
                }
            }
            self.x[i] = p[0];
            self.y[i] = p[1];
            self.w[i] = 1.0 / n as f64;
        }
    }

    /// Positions uniform over the walkable area; equal weights.
    pub(crate) fn spread_global(&mut self, plan: &FloorPlan, rng: &mut Rng) {
        let n = self.len();
        for i in 0..n {
            let p = plan.walkable_point(rng.uniform(), rng.uniform(), rng.uniform());
            self.x[i] = p[0];
            self.y[i] = p[1];
            self.w[i] = 1.0 / n as f64;
        }
    }

    /// Normalise the weights; returns their sum before (0: every particle ruled out).
    pub(crate) fn normalise(&mut self) -> f64 {
        let total: f64 = self.w.iter().sum();
        if total > 0.0 && total.is_finite() {
            let k = 1.0 / total;
            self.w.iter_mut().for_each(|w| *w *= k);
        }
        total
    }

    /// Effective sample size of the normalised weights.
    pub(crate) fn ess(&self) -> f64 {
        let s2: f64 = self.w.iter().map(|w| w * w).sum();
        if s2 > 0.0 {
            1.0 / s2
        } else {
            0.0
        }
    }

    pub(crate) fn needs_resampling(&self) -> bool {
        self.ess() < RESAMPLE_BELOW * self.len() as f64
    }

    /// Systematic resampling of the normalised weights: `pick[i]` is the particle the
    /// new particle `i` copies.
    pub(crate) fn resample(&mut self, rng: &mut Rng) {
        let n = self.len();
        let step = 1.0 / n as f64;
        let mut u = rng.uniform() * step;
        let (mut j, mut c) = (0usize, self.w[0]);
        for i in 0..n {
            while u > c && j + 1 < n {
                j += 1;
                c += self.w[j];
            }
            self.pick[i] = j as u32;
            u += step;
        }
        let Self {
            x,
            y,
            off,
            scale,
            w,
            pick,
            tmp,
        } = self;
        for a in [x, y, off, scale] {
            for (t, &p) in tmp.iter_mut().zip(pick.iter()) {
                *t = a[p as usize];
            }
            a.copy_from_slice(tmp);
        }
        w.iter_mut().for_each(|w| *w = step);
    }

    /// Mean, spread and the share of weight within `radius_m` of the mean; the
    /// heading offsets are averaged around `reference` (the last mean: they are
    /// angles, wrapped to within ±π of it).
    pub(crate) fn summary(&self, radius_m: f64, reference: f64) -> Summary {
        let dev = |o: f64| wrap(o - reference);
        let (mut sx, mut sy, mut ss, mut so) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..self.len() {
            let w = self.w[i];
            sx += w * self.x[i];
            sy += w * self.y[i];
            ss += w * self.scale[i];
            so += w * dev(self.off[i]);
        }
        let (mut vx, mut vy, mut vo, mut near) = (0.0, 0.0, 0.0, 0.0);
        let r2 = radius_m * radius_m;
        for i in 0..self.len() {
            let (dx, dy) = (self.x[i] - sx, self.y[i] - sy);
            let w = self.w[i];
            vx += w * dx * dx;
            vy += w * dy * dy;
            vo += w * (dev(self.off[i]) - so).powi(2);
            if dx * dx + dy * dy <= r2 {
                near += w;
            }
        }
        Summary {
            x: sx,
            y: sy,
            std_m: (0.5 * (vx + vy)).sqrt(),
            off: wrap(reference + so),
            off_std: vo.sqrt(),
            scale: ss,
            near_share: near,
        }
    }
}
