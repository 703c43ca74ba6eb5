//! `stridekit eval pdr --data DIR --diagnose`: where the PDR error on the real walks
//! comes from. Second opinions: the waypoint legs (straight, constant speed between
//! consecutive waypoints) and Android's rotation vector.
//!
//! Per walk and per leg (consecutive waypoints ≥ 2 m and ≥ 1.5 s apart):
//! - **start**: how long after the first waypoint the first step is counted and the
//!   position starts to move, and the waypoint distance walked by then;
//! - **step length**: Σ step lengths over the waypoint span against the polyline, and
//!   the polyline / steps against the model's mean step length;
//! - **heading**: the azimuth of the estimated displacement over each leg against the
//!   leg's azimuth, after the walk's single best rotation (a rotation-free error per
//!   leg), and the same for the azimuth of the phone's top edge (device +y) from the
//!   navigator's attitude and from the rotation vector; and the per-walk rotation
//!   itself (map → estimate), whose spread across walks shows how consistent the
//!   absolute heading is (one building, one map rotation).

use std::f64::consts::FRAC_PI_2;
use std::fmt::Write as _;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use stridekit_core::ahrs::ImuSample;
use stridekit_core::pdr::wrap;
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};

use crate::pdr::metrics::median;
use crate::pdr::walks::Walk;

/// Legs shorter than this (m) or quicker (s) carry no direction.
const MIN_LEG_M: f64 = 2.0;
const MIN_LEG_S: f64 = 1.5;

fn azimuth_of(q: &UnitQuaternion<f64>, axis: Vector3<f64>) -> Option<f64> {
    let v = q * axis;
    (v.x.hypot(v.y) > 0.3).then(|| v.x.atan2(v.y))
}

/// Per sample: t, east, north, steps, distance, attitude azimuth of +y (μ-corrected),
/// rotation-vector azimuth of +y, walking azimuth.
type Pt = (
    f64,
    f64,
    f64,
    u64,
    f64,
    Option<f64>,
    Option<f64>,
    Option<f64>,
);
/// Per leg: length, map azimuth, track azimuth, mean attitude +y azimuth, mean
/// rotation-vector +y azimuth, mean walking azimuth, time into the walk.
type Leg = (
    f64,
    f64,
    Option<f64>,
    Option<f64>,
    Option<f64>,
    Option<f64>,
    f64,
);

/// Circular mean of angles weighted by `w`.
fn circ_mean(v: &[(f64, f64)]) -> f64 {
    let (s, c) = v.iter().fold((0.0, 0.0), |a, (x, w)| {
        (a.0 + w * x.sin(), a.1 + w * x.cos())
    });
    s.atan2(c)
}

#[derive(Default)]
struct Acc {
    first_step_s: Vec<f64>,
    first_event_s: Vec<f64>,
    release_lag_s: Vec<f64>,
    events_per_poly: Vec<f64>,
    first_move_s: Vec<f64>,
    lost_start_pct: Vec<f64>,
    dist_steps_pct: Vec<f64>,
    true_step_m: Vec<f64>,
    model_step_m: Vec<f64>,
    cadence_hz: Vec<f64>,
    speed_mps: Vec<f64>,
    leg_err_nav: Vec<f64>,
    leg_err_ahrs_y: Vec<f64>,
    leg_err_rv_y: Vec<f64>,
    walk_rot_nav: Vec<f64>,
    walk_rot_rv: Vec<f64>,
    carry_rv: Vec<f64>,
    carry_nav: Vec<f64>,
    leg_err_by_time: Vec<(f64, f64, f64)>,
}

fn pct(v: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn row(out: &mut String, name: &str, v: &[f64], scale: f64, unit: &str) {
    let s: Vec<f64> = v.iter().map(|x| x * scale).collect();
    let _ = writeln!(
        out,
        "| {name} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {unit} |",
        s.len(),
        pct(&s, 0.1),
        pct(&s, 0.25),
        median(s.iter().copied()),
        pct(&s, 0.75),
        pct(&s, 0.9),
    );
}

pub fn run(walks: &[Walk], mag: bool) -> Result<String, String> {
    let mut a = Acc::default();
    for w in walks {
        let rec = &w.rec;
        let wp = &rec.truth;
        let (t0, t1) = (wp[0].0, wp[wp.len() - 1].0);
        let mut nav = PhoneNavigator::new(NavigatorConfig::default()).map_err(|e| e.to_string())?;
        // Per sample: t, position, steps, distance, AHRS azimuth of +y (μ-corrected),
        // RV azimuth of +y, walking azimuth.
        let mut pts: Vec<Pt> = Vec::new();
        let mut ri = 0;
        for s in &rec.samples {
            let imu = ImuSample {
                t_s: s.t_s,
                gyro_rads: s.gyro_rads,
                accel_mps2: s.accel_mps2,
                mag_ut: if mag { s.mag_ut } else { None },
            };
            if nav.push_imu(&imu).is_err() {
                continue;
            }
            let Some(e) = nav.estimate() else { continue };
            let wd = nav.walking_direction();
            let [qw, qx, qy, qz] = wd.orientation();
            let q = UnitQuaternion::new_normalize(Quaternion::new(qw, qx, qy, qz));
            let ahrs_y = azimuth_of(&q, Vector3::y()).map(|az| wrap(az - wd.yaw_correction().0));
            while ri + 1 < rec.orientation.len() && rec.orientation[ri + 1].0 <= s.t_s {
                ri += 1;
            }
            let rv_y = rec.orientation.get(ri).and_then(|(_, q)| {
                let q = UnitQuaternion::new_normalize(Quaternion::new(q[0], q[1], q[2], q[3]));
                azimuth_of(&q, Vector3::y())
            });
            pts.push((
                s.t_s,
                e.east_m,
                e.north_m,
                e.steps,
                e.distance_m,
                ahrs_y,
                rv_y,
                e.walking_azimuth_rad,
            ));
        }
        if pts.is_empty() {
            continue;
        }
        {
            use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig};
            let mut d =
                StepDetector::new(StepDetectorConfig::default()).map_err(|e| e.to_string())?;
            let mut events = Vec::new();
            for s in &rec.samples {
                if let Ok(first) = d.push_accel(s.t_s, s.accel_mps2) {
                    for e in first.into_iter().chain(std::iter::from_fn(|| d.pop_step())) {
                        events.push((e.t_s, s.t_s));
                    }
                }
            }
            if let Some(e) = events.first() {
                a.first_event_s.push(e.0 - t0);
            }
            for e in &events {
                a.release_lag_s.push(e.1 - e.0);
            }
            let n = events.iter().filter(|e| e.0 >= t0 && e.0 <= t1).count() as f64;
            let poly: f64 = wp
                .windows(2)
                .map(|x| (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2))
                .sum();
            if n > 5.0 {
                a.events_per_poly.push(poly / n);
            }
        }
        let at = |t: f64| {
            let i = pts.partition_point(|p| p.0 <= t).saturating_sub(1);
            pts[i]
        };
        // Start.
        let first_step = pts.iter().find(|p| p.3 > 0).map(|p| p.0);
        let first_move = pts.iter().find(|p| p.1 != 0.0 || p.2 != 0.0).map(|p| p.0);
        a.first_step_s.push(first_step.map_or(f64::NAN, |t| t - t0));
        a.first_move_s.push(first_move.map_or(f64::NAN, |t| t - t0));
        let poly: f64 = wp
            .windows(2)
            .map(|x| (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2))
            .sum();
        if let Some(tm) = first_move {
            // Waypoint distance walked before the position moved.
            let mut d = 0.0;
            for x in wp.windows(2) {
                let leg = (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2);
                if tm >= x[1].0 {
                    d += leg;
                } else if tm > x[0].0 {
                    d += leg * (tm - x[0].0) / (x[1].0 - x[0].0);
                }
            }
            a.lost_start_pct.push(100.0 * d / poly);
        }
        // Step length.
        let (p0, p1) = (at(t0), at(t1));
        let steps = p1.3.saturating_sub(p0.3) as f64;
        a.dist_steps_pct.push(100.0 * (p1.4 - p0.4 - poly) / poly);
        if steps > 5.0 {
            a.true_step_m.push(poly / steps);
            a.model_step_m.push((p1.4 - p0.4) / steps);
            a.cadence_hz.push(steps / (t1 - t0));
            a.speed_mps.push(poly / (t1 - t0));
        }
        // Heading per leg.
        let mut legs: Vec<Leg> = Vec::new();
        for x in wp.windows(2) {
            let (dx, dy) = (x[1].1 - x[0].1, x[1].2 - x[0].2);
            let len = dx.hypot(dy);
            if len < MIN_LEG_M || x[1].0 - x[0].0 < MIN_LEG_S {
                continue;
            }
            let map_az = dx.atan2(dy);
            let (e0, e1) = (at(x[0].0), at(x[1].0));
            let (ex, ey) = (e1.1 - e0.1, e1.2 - e0.2);
            let nav_az = (ex.hypot(ey) > 0.5).then(|| ex.atan2(ey));
            // Mean +y azimuths over the leg.
            let mean_of = |f: &dyn Fn(&Pt) -> Option<f64>| {
                let v: Vec<(f64, f64)> = pts
                    .iter()
                    .filter(|p| p.0 >= x[0].0 && p.0 <= x[1].0)
                    .filter_map(|p| f(p).map(|a| (a, 1.0)))
                    .collect();
                (!v.is_empty()).then(|| circ_mean(&v))
            };
            let ahrs_y = mean_of(&|p| p.5);
            let rv_y = mean_of(&|p| p.6);
            let walk_az = mean_of(&|p| p.7);
            legs.push((
                len,
                map_az,
                nav_az,
                ahrs_y,
                rv_y,
                walk_az,
                0.5 * (x[0].0 + x[1].0) - t0,
            ));
        }
        let rot = |get: &dyn Fn(&Leg) -> Option<f64>| {
            let v: Vec<(f64, f64)> = legs
                .iter()
                .filter_map(|l| get(l).map(|az| (wrap(az - l.1), l.0)))
                .collect();
            (v.len() >= 2).then(|| circ_mean(&v))
        };
        if let Some(r) = rot(&|l| l.2) {
            a.walk_rot_nav.push(r);
            for l in &legs {
                if let Some(az) = l.2 {
                    let e = wrap(az - l.1 - r);
                    a.leg_err_nav.push(e.abs());
                    a.leg_err_by_time.push((l.6, e, l.0));
                }
            }
        }
        if let Some(r) = rot(&|l| l.3) {
            for l in &legs {
                if let Some(az) = l.3 {
                    a.leg_err_ahrs_y.push(wrap(az - l.1 - r).abs());
                }
            }
        }
        if let Some(r) = rot(&|l| l.4) {
            a.walk_rot_rv.push(r);
            for l in &legs {
                if let Some(az) = l.4 {
                    a.leg_err_rv_y.push(wrap(az - l.1 - r).abs());
                }
            }
        }
        // Carrying: walking direction (legs, via RV's map rotation) minus +y.
        for l in &legs {
            if let (Some(w), Some(y)) = (l.5, l.3) {
                a.carry_nav.push(wrap(w - y));
            }
        }
        if let Some(r) = rot(&|l| l.4) {
            for l in &legs {
                if let Some(y) = l.4 {
                    // true walking azimuth in RV frame = map_az + r
                    a.carry_rv.push(wrap(l.1 + r - y));
                }
            }
        }
    }
    let deg = 180.0 / std::f64::consts::PI;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Diagnosis on {} walks ({}): percentiles over walks or legs.\n",
        walks.len(),
        if mag {
            "magnetometer"
        } else {
            "no magnetometer"
        }
    );
    let _ = writeln!(out, "| what | n | p10 | p25 | median | p75 | p90 | unit |");
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|");
    row(
        &mut out,
        "first step counted after the first waypoint",
        &a.first_step_s,
        1.0,
        "s",
    );
    row(
        &mut out,
        "first step event's own time after the first waypoint",
        &a.first_event_s,
        1.0,
        "s",
    );
    row(
        &mut out,
        "release time − step time (all steps)",
        &a.release_lag_s,
        1.0,
        "s",
    );
    row(
        &mut out,
        "polyline / step events in the waypoint span",
        &a.events_per_poly,
        1.0,
        "m",
    );
    row(
        &mut out,
        "position starts moving after the first waypoint",
        &a.first_move_s,
        1.0,
        "s",
    );
    row(
        &mut out,
        "waypoint distance walked before the position moves",
        &a.lost_start_pct,
        1.0,
        "% of polyline",
    );
    row(
        &mut out,
        "Σ step lengths − polyline",
        &a.dist_steps_pct,
        1.0,
        "% of polyline",
    );
    row(
        &mut out,
        "polyline / steps (step length the waypoints imply)",
        &a.true_step_m,
        1.0,
        "m",
    );
    row(&mut out, "model step length", &a.model_step_m, 1.0, "m");
    row(&mut out, "cadence", &a.cadence_hz, 1.0, "steps/s");
    row(&mut out, "waypoint speed", &a.speed_mps, 1.0, "m/s");
    row(
        &mut out,
        "|leg azimuth error|, navigator track (per-walk rotation)",
        &a.leg_err_nav,
        deg,
        "°",
    );
    row(
        &mut out,
        "|leg azimuth error|, navigator attitude +y",
        &a.leg_err_ahrs_y,
        deg,
        "°",
    );
    row(
        &mut out,
        "|leg azimuth error|, rotation vector +y",
        &a.leg_err_rv_y,
        deg,
        "°",
    );
    let spread = |v: &[f64]| {
        let m = circ_mean(&v.iter().map(|x| (*x, 1.0)).collect::<Vec<_>>());
        v.iter().map(|x| wrap(x - m)).collect::<Vec<_>>()
    };
    row(
        &mut out,
        "per-walk rotation map → navigator, minus its circular mean",
        &spread(&a.walk_rot_nav),
        deg,
        "°",
    );
    row(
        &mut out,
        "per-walk rotation map → rotation vector, minus its circular mean",
        &spread(&a.walk_rot_rv),
        deg,
        "°",
    );
    row(
        &mut out,
        "walking direction − +y (rotation vector, per leg)",
        &a.carry_rv,
        deg,
        "°",
    );
    row(
        &mut out,
        "navigator walking azimuth − its +y azimuth (per leg)",
        &a.carry_nav,
        deg,
        "°",
    );
    // The surveyor walks where the top edge points (the rotation vector's row above):
    // a leg more than 90° off it was dead-reckoned backwards.
    let backwards = a.carry_nav.iter().filter(|x| x.abs() > FRAC_PI_2).count();
    let _ = writeln!(
        out,
        "\nLegs dead-reckoned backwards (navigator walking azimuth more than 90° from its +y): {backwards} of {}.",
        a.carry_nav.len()
    );
    // Heading error against time into the walk.
    let _ = writeln!(
        out,
        "\nNavigator leg azimuth error against time into the walk (median |error|, °):\n"
    );
    let _ = writeln!(
        out,
        "| time into walk | legs | median abs error | median signed |"
    );
    let _ = writeln!(out, "|---|---|---|---|");
    for (lo, hi) in [
        (0.0, 5.0),
        (5.0, 10.0),
        (10.0, 20.0),
        (20.0, 40.0),
        (40.0, 80.0),
        (80.0, 200.0),
    ] {
        let v: Vec<&(f64, f64, f64)> = a
            .leg_err_by_time
            .iter()
            .filter(|l| l.0 >= lo && l.0 < hi)
            .collect();
        let _ = writeln!(
            out,
            "| {lo}–{hi} s | {} | {:.1} | {:.1} |",
            v.len(),
            median(v.iter().map(|l| l.1.abs() * deg)),
            median(v.iter().map(|l| l.1 * deg)),
        );
    }
    Ok(out)
}
