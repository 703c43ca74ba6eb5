//! Trajectory errors as defined by RoNIN (Herath, Yan, Furukawa, ICRA 2020, §V):
//! - ATE: RMSE of the position error over the whole trajectory;
//! - RTE: RMSE of the position error over a fixed interval (1 minute), each
//!   interval's estimate aligned to the truth at its start:
//!   `sqrt(mean_t ‖(p̂(t+Δ) − p̂(t)) − (p(t+Δ) − p(t))‖²)`; for a trajectory
//!   shorter than Δ the error at its end, scaled by Δ / duration (RoNIN's code).
//!
//! Both trajectories are `(t, east, north)` at the same times, the estimate already
//! started at the truth's position (see [`align_start`]).

/// A track point (t s, east m, north m).
pub type Point = (f64, f64, f64);

/// Shift `est` so that its first point coincides with `truth`'s first point.
pub fn align_start(est: &mut [Point], truth: &[Point]) {
    let (Some(e0), Some(t0)) = (est.first().copied(), truth.first()) else {
        return;
    };
    for p in est.iter_mut() {
        p.1 += t0.1 - e0.1;
        p.2 += t0.2 - e0.2;
    }
}

/// Absolute trajectory error, m.
pub fn ate(est: &[Point], truth: &[Point]) -> f64 {
    let n = est.len().min(truth.len());
    if n == 0 {
        return f64::NAN;
    }
    let s: f64 = (0..n)
        .map(|i| (est[i].1 - truth[i].1).powi(2) + (est[i].2 - truth[i].2).powi(2))
        .sum();
    (s / n as f64).sqrt()
}

/// Relative trajectory error over `interval_s`, m.
pub fn rte(est: &[Point], truth: &[Point], interval_s: f64) -> f64 {
    let n = est.len().min(truth.len());
    if n < 2 {
        return f64::NAN;
    }
    let duration = truth[n - 1].0 - truth[0].0;
    let d = |i: usize, j: usize| {
        let ee = est[j].1 - est[i].1 - (truth[j].1 - truth[i].1);
        let en = est[j].2 - est[i].2 - (truth[j].2 - truth[i].2);
        ee * ee + en * en
    };
    if duration < interval_s {
        return d(0, n - 1).sqrt() * interval_s / duration.max(1e-9);
    }
    let (mut sum, mut count) = (0.0, 0usize);
    let mut j = 0;
    for i in 0..n {
        while j < n && truth[j].0 < truth[i].0 + interval_s {
            j += 1;
        }
        if j >= n {
            break;
        }
        sum += d(i, j);
        count += 1;
    }
    (sum / count.max(1) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_of_a_constant_drift() {
        let truth: Vec<Point> = (0..=1200).map(|i| (i as f64 * 0.1, 0.0, 0.0)).collect();
        let est: Vec<Point> = truth.iter().map(|p| (p.0, 0.01 * p.0, 0.0)).collect();
        assert!((rte(&est, &truth, 60.0) - 0.6).abs() < 1e-9);
        assert!(ate(&est, &truth) > 0.6);
    }
}
