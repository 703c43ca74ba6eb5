//! What the demo report's charts show, measured on the run: the figures every caption
//! states (speeds and step lengths through each outage, GNSS weights, pace errors in
//! s/km, the next session's fast and usual paces), so no caption claims more.

use crate::pace::{Replay, Scores};
use crate::stats::median;
use stridekit_sim::{SimulatedRun, ZoneKind};

/// Slowest speed counted as running, m/s (8:20 /km): pace errors are a runner's.
pub const RUN_MIN_MPS: f64 = 2.0;
/// Speeds below this count as this in pace errors, m/s (a stalled estimate is a pace
/// of 10 000 s/km, not an infinite one, so that medians count it).
const PACE_FLOOR_MPS: f64 = 0.1;
/// A fast interval of the next session: the truth at least this fast, m/s.
pub const FAST_MPS: f64 = 4.2;

/// One GNSS outage of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Outage {
    pub start_min: f64,
    pub end_min: f64,
    /// Mean speeds over the outage, m/s: truth, stridekit (default), AsPublished.
    pub truth_mps: f64,
    pub ours_mps: f64,
    pub published_mps: f64,
    /// Mean step lengths over the outage, m: truth, stridekit's.
    pub truth_step_m: f64,
    pub ours_step_m: f64,
    /// Largest distance between stridekit's position and the truth in it, m.
    pub worst_position_m: f64,
    /// The outage's top speed (the truth within [`TOP_SHARE`] of its fastest): the
    /// truth's and stridekit's means there, m/s.
    pub top_truth_mps: f64,
    pub top_ours_mps: f64,
}

/// Samples within this share of an outage's fastest truth speed are its top speed.
pub const TOP_SHARE: f64 = 0.05;

/// Means over the next session's samples of one kind: truth, with this run's
/// calibration, with the population prior, m/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Means {
    pub truth: f64,
    pub calibrated: f64,
    pub prior: f64,
}

/// The next session's speeds on its grid, m/s.
#[derive(Clone, Copy, Debug)]
pub struct NextSession<'a> {
    pub truth: &'a [f64],
    pub calibrated: &'a [f64],
    pub prior: &'a [f64],
}

#[derive(Clone, Debug, PartialEq)]
pub struct Facts {
    pub outages: Vec<Outage>,
    /// Speed RMSE in the disturbed stretches, m/s, per method (table order).
    pub disturbed_rmse: [f64; 4],
    /// Median GNSS weight while running with GNSS: AsPublished, stridekit.
    pub weight_running: [f64; 2],
    /// stridekit's median GNSS weight while stopped.
    pub weight_stopped: f64,
    /// Median GNSS weight in the outages: AsPublished, stridekit.
    pub weight_outage: [f64; 2],
    /// Median |pace error| where the runner runs, s/km, per method (table order) and
    /// column (where GNSS, disturbed GNSS, outages); NaN where not defined.
    pub pace_error: [[f64; 3]; 4],
    /// The next session: fast intervals and usual paces.
    pub fast: Option<Means>,
    pub usual: Option<Means>,
}

fn mean(v: impl IntoIterator<Item = f64>) -> f64 {
    let (s, n) = v
        .into_iter()
        .filter(|x| x.is_finite())
        .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        s / n as f64
    }
}

/// |pace error|, s/km, of an estimate against the truth.
fn pace_error(est_mps: f64, truth_mps: f64) -> f64 {
    (1000.0 / est_mps.max(PACE_FLOOR_MPS) - 1000.0 / truth_mps).abs()
}

/// The replay's grid and the run it samples, for the measures.
struct Grid<'a> {
    run: &'a SimulatedRun,
    r: &'a Replay,
    /// The truth speed on the grid, m/s.
    truth: &'a [f64],
}

impl Grid<'_> {
    /// The grid points `keep` accepts.
    fn select(&self, keep: &dyn Fn(usize) -> bool) -> Vec<usize> {
        (0..self.r.t_s.len()).filter(|&i| keep(i)).collect()
    }

    /// Grid point `i` lies in a zone of kind `k`.
    fn in_zone(&self, i: usize, k: ZoneKind) -> bool {
        let t = self.r.t_s[i];
        self.run
            .zones
            .iter()
            .any(|z| z.kind == k && t >= z.start_s && t < z.end_s)
    }

    /// The runner runs at grid point `i`.
    fn running(&self, i: usize) -> bool {
        self.truth[i] >= RUN_MIN_MPS
    }

    /// Every outage of the run, in time order.
    fn outages(&self, origin: (f64, f64)) -> Vec<Outage> {
        let mut outages: Vec<Outage> = self
            .run
            .zones
            .iter()
            .filter(|z| z.kind == ZoneKind::Outage)
            .map(|z| self.outage(z.start_s, z.end_s, origin))
            .collect();
        outages.sort_by(|a, b| a.start_min.total_cmp(&b.start_min));
        outages
    }

    /// The outage from `start_s` to `end_s`.
    fn outage(&self, start_s: f64, end_s: f64, origin: (f64, f64)) -> Outage {
        let (run, r, truth) = (self.run, self.r, self.truth);
        let idx = self.select(&|i| r.t_s[i] >= start_s && r.t_s[i] < end_s);
        let worst = idx
            .iter()
            .map(|&i| {
                let p = run.truth_at(r.t_s[i]);
                let (e, n) = r.position_enu_m[i];
                (origin.0 + e - p.east_m).hypot(origin.1 + n - p.north_m)
            })
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        let fastest = idx.iter().map(|&i| truth[i]).fold(f64::NAN, f64::max);
        let top: Vec<usize> = idx
            .iter()
            .copied()
            .filter(|&i| truth[i] >= (1.0 - TOP_SHARE) * fastest)
            .collect();
        Outage {
            start_min: start_s / 60.0,
            end_min: end_s / 60.0,
            truth_mps: mean(idx.iter().map(|&i| truth[i])),
            ours_mps: mean(idx.iter().map(|&i| r.speed[3][i])),
            published_mps: mean(idx.iter().map(|&i| r.speed[2][i])),
            truth_step_m: mean(idx.iter().map(|&i| run.truth_at(r.t_s[i]).step_length_m)),
            ours_step_m: mean(idx.iter().map(|&i| r.step_length[i])),
            worst_position_m: worst,
            top_truth_mps: mean(top.iter().map(|&i| truth[i])),
            top_ours_mps: mean(top.iter().map(|&i| r.speed[3][i])),
        }
    }

    /// Median GNSS weight of AsPublished (0) and stridekit (1) where `keep`.
    fn median_weight(&self, m: usize, keep: &dyn Fn(usize) -> bool) -> f64 {
        median(self.select(keep).into_iter().map(|i| self.r.weight[m][i]))
    }

    /// Median |pace error| where the runner runs, s/km, per method (table order) and
    /// column (where GNSS, disturbed GNSS, outages).
    fn pace_errors(&self) -> [[f64; 3]; 4] {
        let r = self.r;
        let columns: [&dyn Fn(usize) -> bool; 3] = [
            &|i| r.has_gnss[i],
            &|i| r.has_gnss[i] && self.in_zone(i, ZoneKind::Disturbance),
            &|i| self.in_zone(i, ZoneKind::Outage),
        ];
        let mut pace = [[f64::NAN; 3]; 4];
        for (m, row) in pace.iter_mut().enumerate() {
            for (c, keep) in columns.iter().enumerate() {
                // As the table: the GNSS-only methods have no speed in outages.
                if c == 2 && m < 2 {
                    continue;
                }
                row[c] = median(
                    self.select(&|i| keep(i) && self.running(i))
                        .into_iter()
                        .filter(|&i| r.speed[m][i].is_finite())
                        .map(|i| pace_error(r.speed[m][i], self.truth[i])),
                );
            }
        }
        pace
    }
}

impl NextSession<'_> {
    /// The means over the samples whose truth speed `keep` accepts; `None` without one.
    fn means(&self, keep: &dyn Fn(f64) -> bool) -> Option<Means> {
        let (tr, cal, pri) = (self.truth, self.calibrated, self.prior);
        let idx: Vec<usize> = (0..tr.len()).filter(|&i| keep(tr[i])).collect();
        (!idx.is_empty()).then(|| Means {
            truth: mean(idx.iter().map(|&i| tr[i])),
            calibrated: mean(idx.iter().map(|&i| cal[i])),
            prior: mean(idx.iter().map(|&i| pri[i])),
        })
    }
}

impl Facts {
    /// `truth`: the truth speed on the replay's grid; `origin`: the first fix, metres
    /// east / north of the scenario origin (the fused positions are relative to it);
    /// `next`: the next session without GNSS, if measured.
    pub fn measure(
        run: &SimulatedRun,
        r: &Replay,
        truth: &[f64],
        scores: &Scores,
        origin: (f64, f64),
        next: Option<NextSession>,
    ) -> Self {
        let g = Grid { run, r, truth };
        let weight_running = [0, 1].map(|m| g.median_weight(m, &|i| r.has_gnss[i] && g.running(i)));
        let weight_stopped = g.median_weight(1, &|i| g.in_zone(i, ZoneKind::Stop));
        let weight_outage = [0, 1].map(|m| g.median_weight(m, &|i| g.in_zone(i, ZoneKind::Outage)));
        let (fast, usual) = match next {
            Some(n) => (
                n.means(&|v| v >= FAST_MPS),
                n.means(&|v| (RUN_MIN_MPS..FAST_MPS).contains(&v)),
            ),
            None => (None, None),
        };
        Self {
            outages: g.outages(origin),
            disturbed_rmse: scores.disturbed,
            weight_running,
            weight_stopped,
            weight_outage,
            pace_error: g.pace_errors(),
            fast,
            usual,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pace_errors_are_in_seconds_per_km_and_finite_for_a_stalled_estimate() {
        // 3 m/s is 333.3 s/km, 3.3 m/s 303.0 s/km.
        assert!((pace_error(3.3, 3.0) - 30.3).abs() < 0.1);
        assert!(pace_error(0.0, 3.0).is_finite());
        assert!(pace_error(0.0, 3.0) > 9000.0);
    }
}
