//! Scores in the plan's frame: per walk the RMSE over the waypoints after the first
//! and the error at the last (nothing forgiven), quantiles over walks, and the
//! rotation that best fits a start-pinned track (how far its north is off).

use crate::pdr::metrics::{track_at, TrackPoint};

/// A walk's score in the plan's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapScore {
    /// RMSE over the scored waypoints, m.
    pub rmse_m: f64,
    /// Error at the last scored waypoint, m.
    pub end_m: f64,
}

/// Score `track` against `waypoints` `(t, x, y)`: every waypoint after the first that
/// `excluded` does not mark.
pub fn map_score(
    track: &[TrackPoint],
    waypoints: &[(f64, f64, f64)],
    excluded: &[bool],
) -> Option<MapScore> {
    let errs: Vec<f64> = waypoints
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(i, _)| !excluded.get(*i).copied().unwrap_or(false))
        .map(|(_, w)| {
            let p = track_at(track, w.0);
            (p.0 - w.1).hypot(p.1 - w.2)
        })
        .collect();
    let end_m = *errs.last()?;
    let rmse_m = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
    Some(MapScore { rmse_m, end_m })
}

/// The `q`-quantile (0..=1, linear between order statistics) of the finite values.
pub fn quantile(values: impl IntoIterator<Item = f64>, q: f64) -> f64 {
    let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let pos = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let (i, k) = (pos.floor() as usize, pos.fract());
    if i + 1 < v.len() {
        v[i] + k * (v[i + 1] - v[i])
    } else {
        v[i]
    }
}

/// Per-walk scores of one method, with their floors.
pub type ByWalk = Vec<(String, MapScore)>;

/// One row: a score per walk (with its floor).
pub struct Row {
    pub name: String,
    pub by_walk: ByWalk,
}

impl Row {
    fn cells(scores: &[&MapScore]) -> String {
        if scores.is_empty() {
            return "0 | – | – | –".into();
        }
        format!(
            "{} | {:.2} m | {:.2} m | {:.2} m",
            scores.len(),
            quantile(scores.iter().map(|s| s.rmse_m), 0.5),
            quantile(scores.iter().map(|s| s.rmse_m), 0.9),
            quantile(scores.iter().map(|s| s.end_m), 0.5),
        )
    }

    pub fn overall(&self) -> String {
        Self::cells(&self.by_walk.iter().map(|s| &s.1).collect::<Vec<_>>())
    }

    pub fn floor(&self, f: &str) -> String {
        Self::cells(
            &self
                .by_walk
                .iter()
                .filter(|s| s.0 == f)
                .map(|s| &s.1)
                .collect::<Vec<_>>(),
        )
    }

    /// Median RMSE over the walks of the floors `keep` accepts.
    pub fn median_where(&self, keep: impl Fn(&str) -> bool) -> f64 {
        quantile(
            self.by_walk
                .iter()
                .filter(|s| keep(&s.0))
                .map(|s| s.1.rmse_m),
            0.5,
        )
    }
}

/// `track` moved so that it is at the first waypoint at its time, turned
/// anticlockwise by `theta` about it.
pub fn pinned(track: &[TrackPoint], truth: &[(f64, f64, f64)], theta: f64) -> Vec<TrackPoint> {
    let (x0, y0, _) = track_at(track, truth[0].0);
    let (s, c) = theta.sin_cos();
    track
        .iter()
        .map(|q| {
            let (dx, dy) = (q.x_m - x0, q.y_m - y0);
            TrackPoint {
                x_m: truth[0].1 + c * dx - s * dy,
                y_m: truth[0].2 + s * dx + c * dy,
                ..*q
            }
        })
        .collect()
}

/// The rotation (rad, anticlockwise on the plan) that best turns a start-pinned track
/// onto the waypoints after the first (least squares over the waypoint times).
pub fn best_rotation(track: &[TrackPoint], waypoints: &[(f64, f64, f64)]) -> Option<f64> {
    let (x0, y0, _) = track_at(track, waypoints.first()?.0);
    let (w0x, w0y) = (waypoints[0].1, waypoints[0].2);
    let (mut s, mut c) = (0.0, 0.0);
    for w in &waypoints[1..] {
        let (x, y, _) = track_at(track, w.0);
        let (ax, ay) = (x - x0, y - y0);
        let (bx, by) = (w.1 - w0x, w.2 - w0y);
        s += ax * by - ay * bx;
        c += ax * bx + ay * by;
    }
    (s != 0.0 || c != 0.0).then(|| s.atan2(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(p: &[(f64, f64, f64)]) -> Vec<TrackPoint> {
        p.iter()
            .map(|&(t_s, x_m, y_m)| TrackPoint {
                t_s,
                x_m,
                y_m,
                distance_m: 0.0,
            })
            .collect()
    }

    #[test]
    fn scores_skip_the_first_and_the_excluded_waypoints() {
        let wp = [(0.0, 0.0, 0.0), (1.0, 10.0, 0.0), (2.0, 20.0, 0.0)];
        // 1 m north of the truth everywhere after the start.
        let t = track(&[(0.0, 5.0, 5.0), (1.0, 10.0, 1.0), (2.0, 20.0, 1.0)]);
        let s = map_score(&t, &wp, &[false; 3]).unwrap();
        assert!((s.rmse_m - 1.0).abs() < 1e-12 && (s.end_m - 1.0).abs() < 1e-12);
        let t = track(&[(0.0, 0.0, 0.0), (1.0, 10.0, 3.0), (2.0, 20.0, 1.0)]);
        let s = map_score(&t, &wp, &[false, true, false]).unwrap();
        assert_eq!((s.rmse_m, s.end_m), (1.0, 1.0));
        assert!(map_score(&t, &wp[..1], &[false]).is_none());
        assert_eq!(quantile([1.0, 2.0, 3.0, 4.0, f64::NAN], 0.5), 2.5);
        assert!((quantile((1..=10).map(f64::from), 0.9) - 9.1).abs() < 1e-12);
    }

    #[test]
    fn the_best_rotation_of_a_turned_track_is_its_turn() {
        let wp = [(0.0, 0.0, 0.0), (1.0, 10.0, 0.0), (2.0, 10.0, 10.0)];
        let th: f64 = 0.3;
        let (s, c) = th.sin_cos();
        let t: Vec<_> = wp
            .iter()
            .map(|w| (w.0, c * w.1 + s * w.2, -s * w.1 + c * w.2))
            .collect();
        let r = best_rotation(&track(&t), &wp).unwrap();
        assert!((r - th).abs() < 1e-9, "{r}");
        let back = pinned(&track(&t), &wp, r);
        assert!((back[2].x_m - 10.0).abs() < 1e-9 && (back[2].y_m - 10.0).abs() < 1e-9);
    }
}
