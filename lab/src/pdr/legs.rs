//! Heading against distance, leg by leg: part of `stridekit eval pdr --diagnose`.
//!
//! The replayed track (the one the tables score) is read at the waypoint times, and
//! each waypoint leg is rebuilt from one part of the estimate and one part of the
//! truth:
//! - **our heading, the leg's distance exact**: the direction of the track's
//!   displacement over the leg, its length set to the leg's (an oracle step length,
//!   leg by leg);
//! - **our distance, the leg's direction exact**: the length of the track's
//!   displacement over the leg along the leg's own direction;
//! - **the rotation vector's heading, the leg's distance exact**: the mean azimuth of
//!   Android's rotation vector +y (the top edge, where this surveyor walks) over the
//!   leg, the leg's length.
//!
//! Chained from the first waypoint, each rebuilt track is scored with the issue's
//! measures. The first isolates what the heading costs, the second what the distance
//! costs, and the third what the phone's own fused orientation would cost with a
//! perfect step length. A three-way comparison of the leg azimuths (ours, the rotation
//! vector's, the waypoints', each walk's rotation removed) splits the spread into the
//! three sources if their errors were independent; ours and the rotation vector share
//! the gyroscope, so the waypoints' share that this gives is an upper bound.

use std::fmt::Write as _;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use stridekit_core::angle::wrap;

use crate::pdr::metrics::{evaluate, median, track_at, Metrics, TrackPoint};
use crate::pdr::walks::{replay, ReplayOptions, Walk};
use crate::table::Table;

/// Legs at least this long (m) enter the three-way azimuth comparison: on shorter
/// legs the waypoints' position noise dominates any heading.
const AZIMUTH_MIN_LEG_M: f64 = 5.0;

/// Unit vector (east, north) of the rotation vector's +y over `[t0, t1)`: the mean of
/// the azimuth's sine and cosine, or `None` without a sample there.
fn mean_top_edge(orientation: &[(f64, [f64; 4])], t0: f64, t1: f64) -> Option<(f64, f64)> {
    let i = orientation.partition_point(|o| o.0 < t0);
    let (mut se, mut sn) = (0.0, 0.0);
    for (_, q) in orientation[i..].iter().take_while(|o| o.0 < t1) {
        let q = UnitQuaternion::new_normalize(Quaternion::new(q[0], q[1], q[2], q[3]));
        let v = q * Vector3::y();
        let h = v.x.hypot(v.y);
        if h > 0.3 {
            se += v.x / h;
            sn += v.y / h;
        }
    }
    let n = se.hypot(sn);
    (n > 0.0).then(|| (se / n, sn / n))
}

/// A track from `start` through the legs, one point at each waypoint time.
fn chain(times: &[f64], start: (f64, f64), legs: &[(f64, f64)]) -> Vec<TrackPoint> {
    let mut p = start;
    let mut out = vec![TrackPoint {
        t_s: times[0],
        x_m: p.0,
        y_m: p.1,
        distance_m: 0.0,
    }];
    let mut d = 0.0;
    for (k, l) in legs.iter().enumerate() {
        p = (p.0 + l.0, p.1 + l.1);
        d += l.0.hypot(l.1);
        out.push(TrackPoint {
            t_s: times[k + 1],
            x_m: p.0,
            y_m: p.1,
            distance_m: d,
        });
    }
    out
}

/// Robust sd (1.4826 · median absolute deviation from the median).
pub(crate) fn robust_sd(v: &[f64]) -> f64 {
    let m = median(v.to_vec());
    1.4826 * median(v.iter().map(|x| (x - m).abs()).collect::<Vec<f64>>())
}

/// Per-walk circular mean of angle differences.
fn circ_mean(v: &[f64]) -> f64 {
    let (s, c) = v
        .iter()
        .fold((0.0, 0.0), |a, x| (a.0 + x.sin(), a.1 + x.cos()));
    s.atan2(c)
}

/// The rebuilt tracks of [`LegsReport`], in its table's order.
const REBUILT: [&str; 5] = [
    "the track as scored (its positions at the waypoint times)",
    "our heading, each leg's distance exact",
    "our distance, each leg's direction exact",
    "the same, our distance scaled to the walk's polyline (one factor per walk)",
    "rotation vector +y heading, each leg's distance exact",
];

/// Heading against distance, computed ([`LegsReport::render`] writes it).
#[derive(Clone, Debug, Default)]
pub struct LegsReport {
    /// Per rebuilt track ([`REBUILT`]): the metrics of every walk scored.
    pub rows: [Vec<Metrics>; 5],
    /// Signed leg azimuth differences, each walk's mean removed: ours − waypoints,
    /// rotation vector − waypoints, ours − rotation vector, rad.
    pub az: [Vec<f64>; 3],
}

/// One walk's legs, each rebuilt from one part of the estimate and one of the truth.
struct WalkLegs {
    /// Our direction with each leg's exact length.
    ours_exact_len: Vec<(f64, f64)>,
    /// Each leg's exact direction with our length.
    exact_dir_ours: Vec<(f64, f64)>,
    /// The rotation vector's direction with each leg's exact length.
    rv_exact_len: Vec<(f64, f64)>,
    /// Azimuths (map, ours, rotation vector) of the legs of [`AZIMUTH_MIN_LEG_M`] or more.
    azimuths: Vec<[f64; 3]>,
}

/// Heading against distance, leg by leg, over every walk with 3 or more waypoints and
/// a rotation vector.
pub fn legs(walks: &[Walk], mag: bool) -> Result<LegsReport, String> {
    let o = ReplayOptions {
        mag,
        ..ReplayOptions::default()
    };
    let mut report = LegsReport::default();
    for w in walks {
        let wp = &w.rec.truth;
        if wp.len() < 3 {
            continue;
        }
        let r = replay(&w.rec, &o)?;
        let times: Vec<f64> = wp.iter().map(|p| p.0).collect();
        let est: Vec<(f64, f64)> = times
            .iter()
            .map(|&t| {
                let p = track_at(&r.track, t);
                (p.0, p.1)
            })
            .collect();
        let Some(legs) = walk_legs(wp, &est, &w.rec.orientation) else {
            continue;
        };
        for (row, t) in report
            .rows
            .iter_mut()
            .zip(&rebuilt_tracks(wp, &times, &est, &legs))
        {
            if let Some(m) = evaluate(t, wp) {
                row.push(m);
            }
        }
        if legs.azimuths.len() >= 2 {
            // (first, second) of (map, ours, rotation vector): ours − map, rotation
            // vector − map, ours − rotation vector.
            for (acc, (i, j)) in report.az.iter_mut().zip([(1, 0), (2, 0), (1, 2)]) {
                let d: Vec<f64> = legs.azimuths.iter().map(|l| wrap(l[i] - l[j])).collect();
                let c = circ_mean(&d);
                acc.extend(d.iter().map(|x| wrap(x - c)));
            }
        }
    }
    Ok(report)
}

/// The walk's legs rebuilt; `None` when a leg has no rotation-vector sample.
fn walk_legs(
    wp: &[(f64, f64, f64)],
    est: &[(f64, f64)],
    orientation: &[(f64, [f64; 4])],
) -> Option<WalkLegs> {
    let mut legs = WalkLegs {
        ours_exact_len: Vec::new(),
        exact_dir_ours: Vec::new(),
        rv_exact_len: Vec::new(),
        azimuths: Vec::new(),
    };
    let mut rv_ok = true;
    for k in 0..wp.len() - 1 {
        let (tx, ty) = (wp[k + 1].1 - wp[k].1, wp[k + 1].2 - wp[k].2);
        let (ex, ey) = (est[k + 1].0 - est[k].0, est[k + 1].1 - est[k].1);
        let (lt, le) = (tx.hypot(ty), ex.hypot(ey));
        let u = if le > 1e-6 {
            (ex / le, ey / le)
        } else {
            (0.0, 0.0)
        };
        legs.ours_exact_len.push((u.0 * lt, u.1 * lt));
        let v = if lt > 1e-6 {
            (tx / lt, ty / lt)
        } else {
            (0.0, 0.0)
        };
        legs.exact_dir_ours.push((v.0 * le, v.1 * le));
        match mean_top_edge(orientation, wp[k].0, wp[k + 1].0) {
            Some(rv) => {
                legs.rv_exact_len.push((rv.0 * lt, rv.1 * lt));
                if lt >= AZIMUTH_MIN_LEG_M && le > 1.0 {
                    legs.azimuths
                        .push([tx.atan2(ty), ex.atan2(ey), rv.0.atan2(rv.1)]);
                }
            }
            None => rv_ok = false,
        }
    }
    rv_ok.then_some(legs)
}

/// The five tracks of [`REBUILT`], chained from the first waypoint's estimate.
fn rebuilt_tracks(
    wp: &[(f64, f64, f64)],
    times: &[f64],
    est: &[(f64, f64)],
    legs: &WalkLegs,
) -> [Vec<TrackPoint>; 5] {
    let ours: Vec<TrackPoint> = times
        .iter()
        .zip(est)
        .map(|(&t, p)| TrackPoint {
            t_s: t,
            x_m: p.0,
            y_m: p.1,
            distance_m: 0.0,
        })
        .collect();
    let (lt, le) = wp
        .windows(2)
        .zip(&legs.exact_dir_ours)
        .fold((0.0, 0.0), |a, (x, l)| {
            (
                a.0 + (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2),
                a.1 + l.0.hypot(l.1),
            )
        });
    let k = if le > 0.0 { lt / le } else { 1.0 };
    let exact_dir_scaled: Vec<(f64, f64)> = legs
        .exact_dir_ours
        .iter()
        .map(|l| (k * l.0, k * l.1))
        .collect();
    [
        ours,
        chain(times, est[0], &legs.ours_exact_len),
        chain(times, est[0], &legs.exact_dir_ours),
        chain(times, est[0], &exact_dir_scaled),
        chain(times, est[0], &legs.rv_exact_len),
    ]
}

impl LegsReport {
    /// The section as markdown.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "\nHeading against distance, leg by leg ({} walks with 3 or more waypoints and a rotation vector; each leg rebuilt from one part of the estimate and one of the truth, chained from the first waypoint; medians):\n",
            self.rows[0].len()
        );
        let mut t = Table::new(["leg by leg", "ATE", "start-pinned", "end"]);
        for (name, row) in REBUILT.iter().zip(&self.rows) {
            let med = |f: fn(&Metrics) -> f64| median(row.iter().map(f).collect::<Vec<f64>>());
            t.row([
                name.to_string(),
                format!("{:.2} m", med(|m| m.ate_m)),
                format!("{:.2} m", med(|m| m.start_pinned_m)),
                format!("{:.1} %", med(|m| m.end_pct)),
            ]);
        }
        out.push_str(&t.render());
        let az = &self.az;
        let sd: Vec<f64> = az.iter().map(|v| robust_sd(v).to_degrees()).collect();
        // Independent errors: s_ow² = o² + w², s_rw² = r² + w², s_or² = o² + r².
        let (ow, rw, or) = (sd[0] * sd[0], sd[1] * sd[1], sd[2] * sd[2]);
        let part = |x: f64| x.max(0.0).sqrt();
        let _ = writeln!(
            out,
            "\nLeg azimuths on legs of {AZIMUTH_MIN_LEG_M} m or more ({} legs; each walk's rotation removed; robust sd): ours − waypoints {:.1}°, rotation vector − waypoints {:.1}°, ours − rotation vector {:.1}°. Were the three errors independent: waypoints {:.1}°, ours {:.1}°, rotation vector {:.1}° (ours and the rotation vector share the gyroscope, so the waypoints' part is an upper bound).",
            az[0].len(),
            sd[0],
            sd[1],
            sd[2],
            part((ow + rw - or) / 2.0),
            part((ow + or - rw) / 2.0),
            part((rw + or - ow) / 2.0),
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chaining_legs_rebuilds_the_polyline() {
        let t = chain(&[0.0, 1.0, 2.0], (1.0, 2.0), &[(3.0, 0.0), (0.0, 4.0)]);
        assert_eq!(t.len(), 3);
        assert_eq!((t[2].x_m, t[2].y_m, t[2].distance_m), (4.0, 6.0, 7.0));
    }

    #[test]
    fn the_top_edge_of_an_unrotated_phone_points_north() {
        let o = vec![(0.0, [1.0, 0.0, 0.0, 0.0]), (0.5, [1.0, 0.0, 0.0, 0.0])];
        let (e, n) = mean_top_edge(&o, 0.0, 1.0).unwrap();
        assert!(e.abs() < 1e-12 && (n - 1.0).abs() < 1e-12);
        assert!(mean_top_edge(&o, 2.0, 3.0).is_none());
    }

    #[test]
    fn the_robust_sd_of_a_symmetric_spread() {
        assert!((robust_sd(&[-1.0, 0.0, 1.0]) - 1.4826).abs() < 1e-12);
    }
}
