//! The smoothed path: fixed-lag smoothing over the particles' ancestry. Every step
//! keeps the particles' positions and which particle of the step before each came
//! from; a point of the path is the weighted mean, at that step, of the ancestors of
//! today's particles (those that survived the walls since). When the window is full
//! its older half is traced once and fixed; the newer half stays open to correction.

use super::particles::Cloud;

/// One point of the smoothed path: where the walker was after a step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothedPoint {
    /// Time of the step (heel strike), s.
    pub t_s: f64,
    pub x_m: f64,
    pub y_m: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct History {
    /// Slots (steps) the window holds, particles per slot.
    pub(crate) lag: usize,
    pub(crate) n: usize,
    /// Ring of slots: oldest at `head`, `len` filled.
    pub(crate) head: usize,
    pub(crate) len: usize,
    pub(crate) t_s: Vec<f64>,
    /// Positions (f32: millimetres on a plan of kilometres) and parent indices into the
    /// slot before, per slot × particle.
    pub(crate) xy: Vec<[f32; 2]>,
    pub(crate) parent: Vec<u32>,
    /// Today's particle → its ancestor in the newest slot (and scratch to compose it).
    pub(crate) link: Vec<u32>,
    scratch: Vec<u32>,
    /// The points fixed by the latest trace and how many were fixed in all.
    pub(crate) fixed: Vec<SmoothedPoint>,
    pub(crate) fixed_total: u64,
}

impl History {
    pub(crate) fn new(lag: usize, n: usize) -> Self {
        Self {
            lag,
            n,
            head: 0,
            len: 0,
            t_s: vec![0.0; lag],
            xy: vec![[0.0; 2]; lag * n],
            parent: vec![0; lag * n],
            link: (0..n as u32).collect(),
            scratch: vec![0; n],
            fixed: Vec::with_capacity(lag),
            fixed_total: 0,
        }
    }

    fn slot(&self, k: usize) -> usize {
        (self.head + k) % self.lag
    }

    /// Record the particles after a step (before any resampling of that step).
    pub(crate) fn push(&mut self, t_s: f64, cloud: &Cloud) {
        if self.len == self.lag {
            self.fix_oldest(self.lag.div_ceil(2), cloud);
        }
        let s = self.slot(self.len);
        self.t_s[s] = t_s;
        let base = s * self.n;
        for i in 0..self.n {
            self.xy[base + i] = [cloud.x[i] as f32, cloud.y[i] as f32];
            self.parent[base + i] = self.link[i];
        }
        self.link
            .iter_mut()
            .enumerate()
            .for_each(|(i, l)| *l = i as u32);
        self.len += 1;
    }

    /// The cloud was resampled: today's particle `i` copies `pick[i]`.
    pub(crate) fn resampled(&mut self, pick: &[u32]) {
        for (s, &p) in self.scratch.iter_mut().zip(pick) {
            *s = self.link[p as usize];
        }
        std::mem::swap(&mut self.link, &mut self.scratch);
    }

    /// Trace today's particles back through the window: calls `f(k, x, y)` with the
    /// weighted mean of their ancestors at every slot `k` (oldest 0) from `first` on.
    fn trace(&self, cloud: &Cloud, first: usize, mut f: impl FnMut(usize, f64, f64)) {
        let mut acc = [[0.0f64; 2]; super::config::MAX_SMOOTHING_LAG_STEPS];
        // Every particle was just ruled out (a recovery): their ancestors alike.
        let total: f64 = cloud.w.iter().sum();
        let uniform = if total > 0.0 {
            None
        } else {
            Some(1.0 / cloud.len() as f64)
        };
        for (i, &w) in cloud.w.iter().enumerate() {
            let w = uniform.unwrap_or(w);
            if w == 0.0 {
                continue;
            }
            let mut a = self.link[i] as usize;
            for k in (first..self.len).rev() {
                let j = self.slot(k) * self.n + a;
                let p = self.xy[j];
                acc[k][0] += w * f64::from(p[0]);
                acc[k][1] += w * f64::from(p[1]);
                a = self.parent[j] as usize;
            }
        }
        let k = if total > 0.0 { 1.0 / total } else { 1.0 };
        for (s, a) in acc.iter().enumerate().take(self.len).skip(first) {
            f(s, a[0] * k, a[1] * k);
        }
    }

    /// Fix the oldest `count` slots (they leave the window).
    pub(crate) fn fix_oldest(&mut self, count: usize, cloud: &Cloud) {
        let count = count.min(self.len);
        self.fixed.clear();
        let mut pts = [SmoothedPoint::default(); super::config::MAX_SMOOTHING_LAG_STEPS];
        self.trace(cloud, 0, |k, x, y| {
            pts[k] = SmoothedPoint {
                t_s: 0.0,
                x_m: x,
                y_m: y,
            }
        });
        for (k, p) in pts.iter().enumerate().take(count) {
            self.fixed.push(SmoothedPoint {
                t_s: self.t_s[self.slot(k)],
                ..*p
            });
        }
        self.fixed_total += count as u64;
        self.head = self.slot(count);
        self.len -= count;
    }

    /// Fix the whole window (before the cloud is spread anew).
    pub(crate) fn fix_all(&mut self, cloud: &Cloud) {
        if self.len > 0 {
            self.fix_oldest(self.len, cloud);
        }
        self.link
            .iter_mut()
            .enumerate()
            .for_each(|(i, l)| *l = i as u32);
    }

    /// The open part of the path (the window), oldest first.
    pub(crate) fn window(&self, cloud: &Cloud, mut f: impl FnMut(SmoothedPoint)) {
        self.trace(cloud, 0, |k, x, y| {
            f(SmoothedPoint {
                t_s: self.t_s[self.slot(k)],
                x_m: x,
                y_m: y,
            })
        });
    }
}
