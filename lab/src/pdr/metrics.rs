//! Accuracy of a 2-D trajectory against sparse surveyed waypoints (the definitions of
//! docs/phone.md). The map's axes are not north-aligned, so every measure allows one
//! rotation:
//!
//! - **ATE**: RMSE over the waypoints of the estimate (interpolated at the waypoint
//!   times) after the best 2-D rotation + translation (least squares, no scale);
//! - **start-pinned**: the estimate at the first waypoint's time moved onto it and
//!   rotated about it by the single best angle (least squares over the other
//!   waypoints); the mean error over the other waypoints;
//! - **end error**: the same pinning, the error at the last waypoint, as % of the
//!   length of the waypoint polyline;
//! - **distance error**: the estimated path length (the length of the estimated
//!   track's positions) between the first and the last waypoint times against the
//!   polyline's length, %.
//!
//! Pure functions, no I/O; the evaluation (`eval_pdr_real`) and `stridekit pdr` use
//! them.

/// A trajectory point: time s, x m, y m, distance the engine reports so far m (for
/// output; [`evaluate`] measures the path length from the positions).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackPoint {
    pub t_s: f64,
    pub x_m: f64,
    pub y_m: f64,
    pub distance_m: f64,
}

/// The four measures of one trajectory.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Metrics {
    pub ate_m: f64,
    pub start_pinned_m: f64,
    pub end_pct: f64,
    /// Signed, % (estimate − polyline) / polyline.
    pub distance_pct: f64,
    /// Waypoint polyline length, m.
    pub polyline_m: f64,
}

/// Linear interpolation of the track at `t` (clamped at its ends): (x, y, distance).
pub fn track_at(track: &[TrackPoint], t: f64) -> (f64, f64, f64) {
    if track.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let i = track.partition_point(|p| p.t_s <= t);
    if i == 0 {
        let p = track[0];
        return (p.x_m, p.y_m, p.distance_m);
    }
    if i >= track.len() {
        let p = track[track.len() - 1];
        return (p.x_m, p.y_m, p.distance_m);
    }
    let (a, b) = (track[i - 1], track[i]);
    let k = if b.t_s > a.t_s {
        (t - a.t_s) / (b.t_s - a.t_s)
    } else {
        1.0
    };
    (
        a.x_m + k * (b.x_m - a.x_m),
        a.y_m + k * (b.y_m - a.y_m),
        a.distance_m + k * (b.distance_m - a.distance_m),
    )
}

/// Length of a polyline through `points`, m.
pub fn polyline_m(points: &[(f64, f64)]) -> f64 {
    points
        .windows(2)
        .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
        .sum()
}

/// Best rotation angle θ (anticlockwise) taking vectors `a` onto `b` in the least
/// squares sense.
fn best_angle(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let (mut s, mut c) = (0.0, 0.0);
    for (p, q) in a.iter().zip(b) {
        s += p.0 * q.1 - p.1 * q.0;
        c += p.0 * q.0 + p.1 * q.1;
    }
    if s == 0.0 && c == 0.0 {
        0.0
    } else {
        s.atan2(c)
    }
}

fn rotate(p: (f64, f64), th: f64) -> (f64, f64) {
    let (s, c) = th.sin_cos();
    (c * p.0 - s * p.1, s * p.0 + c * p.1)
}

/// The rigid 2-D transform (rotation θ about the origin, then translation) that best
/// maps `est` onto `truth` (least squares): `(θ, tx, ty)`.
pub fn best_rigid(est: &[(f64, f64)], truth: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = est.len().max(1) as f64;
    let ce = est
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let ct = truth
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let a: Vec<_> = est.iter().map(|p| (p.0 - ce.0, p.1 - ce.1)).collect();
    let b: Vec<_> = truth.iter().map(|p| (p.0 - ct.0, p.1 - ct.1)).collect();
    let th = best_angle(&a, &b);
    let r = rotate(ce, th);
    (th, ct.0 - r.0, ct.1 - r.1)
}

/// Apply `(θ, tx, ty)` from [`best_rigid`].
pub fn apply_rigid(p: (f64, f64), t: (f64, f64, f64)) -> (f64, f64) {
    let r = rotate(p, t.0);
    (r.0 + t.1, r.1 + t.2)
}

/// The start-pinned transform: translation putting `est[0]` on `truth[0]`, then the
/// best rotation about it: maps an estimate point to the map.
pub fn start_pinned(est: &[(f64, f64)], truth: &[(f64, f64)]) -> impl Fn((f64, f64)) -> (f64, f64) {
    let (e0, w0) = (est[0], truth[0]);
    let a: Vec<_> = est[1..].iter().map(|p| (p.0 - e0.0, p.1 - e0.1)).collect();
    let b: Vec<_> = truth[1..]
        .iter()
        .map(|p| (p.0 - w0.0, p.1 - w0.1))
        .collect();
    let th = best_angle(&a, &b);
    move |p: (f64, f64)| {
        let r = rotate((p.0 - e0.0, p.1 - e0.1), th);
        (w0.0 + r.0, w0.1 + r.1)
    }
}

/// The four measures of `track` against `waypoints` `(t_s, x_m, y_m)` (at least 2).
pub fn evaluate(track: &[TrackPoint], waypoints: &[(f64, f64, f64)]) -> Option<Metrics> {
    if waypoints.len() < 2 || track.is_empty() {
        return None;
    }
    let truth: Vec<(f64, f64)> = waypoints.iter().map(|w| (w.1, w.2)).collect();
    // Path length of the positions, as the distance column.
    let mut path = 0.0;
    let track: Vec<TrackPoint> = track
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if i > 0 {
                path += (p.x_m - track[i - 1].x_m).hypot(p.y_m - track[i - 1].y_m);
            }
            TrackPoint {
                distance_m: path,
                ..*p
            }
        })
        .collect();
    let at: Vec<(f64, f64, f64)> = waypoints.iter().map(|w| track_at(&track, w.0)).collect();
    let est: Vec<(f64, f64)> = at.iter().map(|p| (p.0, p.1)).collect();
    let poly = polyline_m(&truth);
    let rigid = best_rigid(&est, &truth);
    let ate = (est
        .iter()
        .zip(&truth)
        .map(|(e, w)| {
            let p = apply_rigid(*e, rigid);
            (p.0 - w.0).powi(2) + (p.1 - w.1).powi(2)
        })
        .sum::<f64>()
        / est.len() as f64)
        .sqrt();
    let pin = start_pinned(&est, &truth);
    let errs: Vec<f64> = est[1..]
        .iter()
        .zip(&truth[1..])
        .map(|(e, w)| {
            let p = pin(*e);
            (p.0 - w.0).hypot(p.1 - w.1)
        })
        .collect();
    let start_pinned_m = errs.iter().sum::<f64>() / errs.len() as f64;
    let end = errs[errs.len() - 1];
    let travelled = at[at.len() - 1].2 - at[0].2;
    let pct = |x: f64| {
        if poly > 0.0 {
            100.0 * x / poly
        } else {
            f64::NAN
        }
    };
    Some(Metrics {
        ate_m: ate,
        start_pinned_m,
        end_pct: pct(end),
        distance_pct: pct(travelled - poly),
        polyline_m: poly,
    })
}

pub use crate::stats::median;

#[cfg(test)]
mod tests {
    use super::*;

    fn track(points: &[(f64, f64, f64)]) -> Vec<TrackPoint> {
        let mut d = 0.0;
        let mut out: Vec<TrackPoint> = Vec::new();
        for &(t, x, y) in points {
            if let Some(p) = out.last() {
                d += (x - p.x_m).hypot(y - p.y_m);
            }
            out.push(TrackPoint {
                t_s: t,
                x_m: x,
                y_m: y,
                distance_m: d,
            });
        }
        out
    }

    #[test]
    fn a_rotated_shifted_copy_is_perfect() {
        // An L walk: 10 m east, then 5 m north; the estimate is rotated by 0.7 rad
        // and shifted.
        let wp = [(0.0, 0.0, 0.0), (10.0, 10.0, 0.0), (15.0, 10.0, 5.0)];
        let est: Vec<_> = wp
            .iter()
            .map(|&(t, x, y)| {
                let r = rotate((x, y), 0.7);
                (t, r.0 + 3.0, r.1 - 2.0)
            })
            .collect();
        let m = evaluate(&track(&est), &wp).unwrap();
        assert!(m.ate_m < 1e-9 && m.start_pinned_m < 1e-9 && m.end_pct.abs() < 1e-9);
        assert!(m.distance_pct.abs() < 1e-9);
        assert!((m.polyline_m - 15.0).abs() < 1e-12);
    }

    #[test]
    fn a_scaled_track_has_the_expected_errors() {
        // Straight 20 m walk estimated 10 % long: start-pinned errors at 10 m and
        // 20 m are 1 and 2 m; end 2 m = 10 %; distance +10 %; ATE: best fit of
        // (0, 11, 22) to (0, 10, 20) shifted: residuals −1, 0, 1 → RMSE √(2/3).
        let wp = [(0.0, 0.0, 0.0), (1.0, 10.0, 0.0), (2.0, 20.0, 0.0)];
        let est = [(0.0, 0.0, 0.0), (1.0, 11.0, 0.0), (2.0, 22.0, 0.0)];
        let m = evaluate(&track(&est), &wp).unwrap();
        assert!((m.start_pinned_m - 1.5).abs() < 1e-9, "{m:?}");
        assert!((m.end_pct - 10.0).abs() < 1e-9, "{m:?}");
        assert!((m.distance_pct - 10.0).abs() < 1e-9, "{m:?}");
        assert!((m.ate_m - (2.0f64 / 3.0).sqrt()).abs() < 1e-9, "{m:?}");
    }

    #[test]
    fn the_track_is_interpolated_at_waypoint_times() {
        let t = track(&[(0.0, 0.0, 0.0), (2.0, 2.0, 0.0)]);
        assert_eq!(track_at(&t, 1.0), (1.0, 0.0, 1.0));
        assert_eq!(track_at(&t, -1.0), (0.0, 0.0, 0.0));
        assert_eq!(track_at(&t, 5.0), (2.0, 0.0, 2.0));
        assert!(evaluate(&t, &[(0.0, 0.0, 0.0)]).is_none());
        assert_eq!(median([3.0, f64::NAN, 1.0, 2.0]), 2.0);
        assert_eq!(median([4.0, 1.0]), 2.5);
    }
}
