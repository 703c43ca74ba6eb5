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
//!   absolute heading is (one building, one map rotation);
//! - **the truth itself**: when the phone turns at a waypoint where the polyline turns
//!   (rotation vector and navigator), against the waypoint's time; and how noisy the
//!   waypoints are: the along-track residual per leg (leg length − the navigator's
//!   displacement over the leg, the walk's scale removed) has a variance a + b·d² over
//!   legs of displacement d, and the leg's azimuth error a variance h² + c/L² over legs
//!   of length L; the parts that do not grow with the leg, a = 2σ²_along and
//!   c = 2σ²_across, bound the per-waypoint noise (what no estimator can remove, plus
//!   any error of ours that does not grow with the leg), and the ATE a perfect track
//!   would score against these waypoints with that noise added (simulated, fixed seed);
//! - **heading against distance** ([`crate::pdr::legs`]): each leg rebuilt from our
//!   heading and the leg's length, or our distance and the leg's direction, or the
//!   rotation vector's heading and the leg's length, scored with the same measures.

use std::f64::consts::FRAC_PI_2;
use std::fmt::Write as _;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use stridekit_core::ahrs::ImuSample;
use stridekit_core::angle::wrap;
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};

use stridekit_formats::InertialRecording;

use crate::pdr::metrics::{evaluate, median, Metrics, TrackPoint};
use crate::pdr::walks::Walk;
use crate::table::Table;

/// Legs shorter than this (m) or quicker (s) carry no direction.
const MIN_LEG_M: f64 = 2.0;
const MIN_LEG_S: f64 = 1.5;

fn azimuth_of(q: &UnitQuaternion<f64>, axis: Vector3<f64>) -> Option<f64> {
    let v = q * axis;
    (v.x.hypot(v.y) > 0.3).then(|| v.x.atan2(v.y))
}

/// One sample of a walk as the navigator saw it.
#[derive(Clone, Copy)]
struct Pt {
    t_s: f64,
    east_m: f64,
    north_m: f64,
    steps: u64,
    distance_m: f64,
    /// Azimuth of the phone's +y from the navigator's attitude (μ-corrected), rad.
    attitude_y_rad: Option<f64>,
    /// Azimuth of +y from the recording's rotation vector, rad.
    rotation_vector_y_rad: Option<f64>,
    /// The navigator's walking azimuth, rad.
    walking_rad: Option<f64>,
}

/// The navigator's azimuth error on one leg (the walk's rotation removed).
struct LegError {
    t_into_walk_s: f64,
    err_rad: f64,
    length_m: f64,
}

/// One leg between waypoints.
struct Leg {
    length_m: f64,
    /// Azimuths (rad) of the leg on the map, of the navigator's track over it, and the
    /// means over it of the attitude's +y, the rotation vector's +y and the walking
    /// azimuth.
    map_rad: f64,
    track_rad: Option<f64>,
    attitude_y_rad: Option<f64>,
    rotation_vector_y_rad: Option<f64>,
    walking_rad: Option<f64>,
    /// Time of its middle into the walk, s.
    t_into_walk_s: f64,
}

/// Circular mean of angles weighted by `w`.
fn circ_mean(v: &[(f64, f64)]) -> f64 {
    let (s, c) = v.iter().fold((0.0, 0.0), |a, (x, w)| {
        (a.0 + w * x.sin(), a.1 + w * x.cos())
    });
    s.atan2(c)
}

/// Per-walk and per-leg values of every diagnosed quantity.
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
    leg_err_by_time: Vec<LegError>,
    /// Turn centre − waypoint time at turning waypoints: rotation vector, navigator.
    turn_rv_s: Vec<f64>,
    turn_nav_s: Vec<f64>,
    /// Per leg: (displacement with the walk's scale, leg length − that), m.
    leg_resid: Vec<(f64, f64)>,
}

/// Waypoints where the polyline turns at least this much get a turn-timing row, rad.
const TURN_MIN_RAD: f64 = 45.0 * std::f64::consts::PI / 180.0;
/// Window around the waypoint searched for the turn, and the least turn seen in it.
const TURN_WINDOW_S: f64 = 3.0;
const TURN_SEEN_RAD: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// Time of the centre of a turn of sign `sign` in the azimuth series `az` (t, rad)
/// within ±[`TURN_WINDOW_S`] of `t`, relative to `t`: when the azimuth, unwrapped
/// over the window, has made half of its net change (which must be at least
/// [`TURN_SEEN_RAD`] in the turn's direction). Symmetric noise does not move it.
fn turn_centre(az: &[(f64, f64)], t: f64, sign: f64) -> Option<f64> {
    let window = || {
        az.iter()
            .filter(move |p| (p.0 - t).abs() <= TURN_WINDOW_S && p.1.is_finite())
    };
    let mut prev: Option<f64> = None;
    let mut total = 0.0;
    for &(_, a) in window() {
        if let Some(ap) = prev {
            total += wrap(a - ap);
        }
        prev = Some(a);
    }
    if total * sign < TURN_SEEN_RAD {
        return None;
    }
    let (mut prev, mut acc) = (None::<(f64, f64)>, 0.0);
    for &(ti, a) in window() {
        if let Some((tp, ap)) = prev {
            let d = wrap(a - ap);
            if (acc + d) * sign >= 0.5 * total * sign {
                // Interpolate within the sample interval.
                let k = if d != 0.0 {
                    (0.5 * total - acc) / d
                } else {
                    1.0
                };
                return Some(tp + k.clamp(0.0, 1.0) * (ti - tp) - t);
            }
            acc += d;
        }
        prev = Some((ti, a));
    }
    None
}

fn pct(v: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// The percentiles of one diagnosed quantity: its row of the table.
fn percentile_row(name: &str, v: &[f64], scale: f64, unit: &str) -> Vec<String> {
    let s: Vec<f64> = v.iter().map(|x| x * scale).collect();
    vec![
        name.to_string(),
        s.len().to_string(),
        format!("{:.2}", pct(&s, 0.1)),
        format!("{:.2}", pct(&s, 0.25)),
        format!("{:.2}", median(s.iter().copied())),
        format!("{:.2}", pct(&s, 0.75)),
        format!("{:.2}", pct(&s, 0.9)),
        unit.to_string(),
    ]
}

/// `eval pdr --diagnose`, one magnetometer setting, computed
/// ([`DiagnoseReport::render`] writes it).
pub struct DiagnoseReport {
    pub walks: usize,
    pub mag: bool,
    samples: Acc,
    noise: WaypointNoise,
    /// Heading against distance ([`crate::pdr::legs`]).
    legs: crate::pdr::legs::LegsReport,
    /// [`crate::pdr::shared::report`] as it renders (with the magnetometer only: the
    /// distance does not depend on it, once is enough).
    shared: Option<String>,
}

/// Where the PDR error on the real walks comes from (see the module doc).
pub fn diagnose(walks: &[Walk], mag: bool) -> Result<DiagnoseReport, String> {
    let mut a = Acc::default();
    for w in walks {
        diagnose_walk(&mut a, &w.rec, mag)?;
    }
    let azimuth: Vec<(f64, f64)> = a
        .leg_err_by_time
        .iter()
        .map(|l| (l.length_m, l.err_rad))
        .collect();
    let noise = WaypointNoise::fit(&a.leg_resid, &azimuth, walks);
    let legs = crate::pdr::legs::legs(walks, mag)?;
    let shared = if mag {
        let mut s = String::new();
        crate::pdr::shared::report(&mut s, walks)?;
        Some(s)
    } else {
        None
    };
    Ok(DiagnoseReport {
        walks: walks.len(),
        mag,
        samples: a,
        noise,
        legs,
        shared,
    })
}

/// One walk's contribution to every diagnosed quantity.
fn diagnose_walk(a: &mut Acc, rec: &InertialRecording, mag: bool) -> Result<(), String> {
    let pts = navigator_track(rec, mag)?;
    if pts.is_empty() {
        return Ok(());
    }
    step_events(a, rec)?;
    start_delay(a, &pts, &rec.truth);
    step_length(a, &pts, &rec.truth);
    let legs = waypoint_legs(&pts, &rec.truth);
    turn_timing(a, &pts, &rec.truth);
    along_track_residuals(a, &pts, &rec.truth);
    leg_headings(a, &legs);
    Ok(())
}

/// The navigator over the walk: one [`Pt`] per sample with an estimate.
fn navigator_track(rec: &InertialRecording, mag: bool) -> Result<Vec<Pt>, String> {
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).map_err(|e| e.to_string())?;
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
        pts.push(Pt {
            t_s: s.t_s,
            east_m: e.east_m,
            north_m: e.north_m,
            steps: e.steps,
            distance_m: e.distance_m,
            attitude_y_rad: ahrs_y,
            rotation_vector_y_rad: rv_y,
            walking_rad: e.walking_azimuth_rad,
        });
    }
    Ok(pts)
}

/// The step detector alone: when its first event falls, how late events are
/// released, and the polyline per event in the waypoint span.
fn step_events(a: &mut Acc, rec: &InertialRecording) -> Result<(), String> {
    use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig};
    let wp = &rec.truth;
    let (t0, t1) = (wp[0].0, wp[wp.len() - 1].0);
    let mut d = StepDetector::new(StepDetectorConfig::default()).map_err(|e| e.to_string())?;
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
    if n > 5.0 {
        a.events_per_poly.push(polyline_m(wp) / n);
    }
    Ok(())
}

/// Length of the waypoint polyline, m.
fn polyline_m(wp: &[(f64, f64, f64)]) -> f64 {
    wp.windows(2)
        .map(|x| (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2))
        .sum()
}

/// The last track point at or before `t` (the first one before the track starts).
fn at(pts: &[Pt], t: f64) -> Pt {
    let i = pts.partition_point(|p| p.t_s <= t).saturating_sub(1);
    pts[i]
}

/// Start: first step and first movement after the first waypoint, and the waypoint
/// distance walked before the position moved.
fn start_delay(a: &mut Acc, pts: &[Pt], wp: &[(f64, f64, f64)]) {
    let t0 = wp[0].0;
    let first_step = pts.iter().find(|p| p.steps > 0).map(|p| p.t_s);
    let first_move = pts
        .iter()
        .find(|p| p.east_m != 0.0 || p.north_m != 0.0)
        .map(|p| p.t_s);
    a.first_step_s.push(first_step.map_or(f64::NAN, |t| t - t0));
    a.first_move_s.push(first_move.map_or(f64::NAN, |t| t - t0));
    if let Some(tm) = first_move {
        let mut d = 0.0;
        for x in wp.windows(2) {
            let leg = (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2);
            if tm >= x[1].0 {
                d += leg;
            } else if tm > x[0].0 {
                d += leg * (tm - x[0].0) / (x[1].0 - x[0].0);
            }
        }
        a.lost_start_pct.push(100.0 * d / polyline_m(wp));
    }
}

/// Step length, cadence and speed over the waypoint span.
fn step_length(a: &mut Acc, pts: &[Pt], wp: &[(f64, f64, f64)]) {
    let (t0, t1) = (wp[0].0, wp[wp.len() - 1].0);
    let poly = polyline_m(wp);
    let (p0, p1) = (at(pts, t0), at(pts, t1));
    let steps = p1.steps.saturating_sub(p0.steps) as f64;
    let walked_m = p1.distance_m - p0.distance_m;
    a.dist_steps_pct.push(100.0 * (walked_m - poly) / poly);
    if steps > 5.0 {
        a.true_step_m.push(poly / steps);
        a.model_step_m.push(walked_m / steps);
        a.cadence_hz.push(steps / (t1 - t0));
        a.speed_mps.push(poly / (t1 - t0));
    }
}

/// The legs long enough to carry a direction, with the navigator's azimuths over them.
fn waypoint_legs(pts: &[Pt], wp: &[(f64, f64, f64)]) -> Vec<Leg> {
    let t0 = wp[0].0;
    let mut legs: Vec<Leg> = Vec::new();
    for x in wp.windows(2) {
        let (dx, dy) = (x[1].1 - x[0].1, x[1].2 - x[0].2);
        let len = dx.hypot(dy);
        if len < MIN_LEG_M || x[1].0 - x[0].0 < MIN_LEG_S {
            continue;
        }
        let map_az = dx.atan2(dy);
        let (e0, e1) = (at(pts, x[0].0), at(pts, x[1].0));
        let (ex, ey) = (e1.east_m - e0.east_m, e1.north_m - e0.north_m);
        let nav_az = (ex.hypot(ey) > 0.5).then(|| ex.atan2(ey));
        // Mean +y azimuths over the leg.
        let mean_of = |f: &dyn Fn(&Pt) -> Option<f64>| {
            let v: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.t_s >= x[0].0 && p.t_s <= x[1].0)
                .filter_map(|p| f(p).map(|a| (a, 1.0)))
                .collect();
            (!v.is_empty()).then(|| circ_mean(&v))
        };
        legs.push(Leg {
            length_m: len,
            map_rad: map_az,
            track_rad: nav_az,
            attitude_y_rad: mean_of(&|p| p.attitude_y_rad),
            rotation_vector_y_rad: mean_of(&|p| p.rotation_vector_y_rad),
            walking_rad: mean_of(&|p| p.walking_rad),
            t_into_walk_s: 0.5 * (x[0].0 + x[1].0) - t0,
        });
    }
    legs
}

/// Turn timing at the waypoints where the polyline turns by [`TURN_MIN_RAD`] or more.
fn turn_timing(a: &mut Acc, pts: &[Pt], wp: &[(f64, f64, f64)]) {
    let rv_az: Vec<(f64, f64)> = pts
        .iter()
        .filter_map(|p| p.rotation_vector_y_rad.map(|a| (p.t_s, a)))
        .collect();
    let nav_az: Vec<(f64, f64)> = pts
        .iter()
        .filter_map(|p| p.walking_rad.map(|a| (p.t_s, a)))
        .collect();
    for k in 1..wp.len().saturating_sub(1) {
        let a1 = (wp[k].1 - wp[k - 1].1).atan2(wp[k].2 - wp[k - 1].2);
        let a2 = (wp[k + 1].1 - wp[k].1).atan2(wp[k + 1].2 - wp[k].2);
        let turn = wrap(a2 - a1);
        if turn.abs() < TURN_MIN_RAD {
            continue;
        }
        let (c_rv, c_nav) = (
            turn_centre(&rv_az, wp[k].0, turn.signum()),
            turn_centre(&nav_az, wp[k].0, turn.signum()),
        );
        if let (Some(r), Some(n)) = (c_rv, c_nav) {
            a.turn_rv_s.push(r);
            a.turn_nav_s.push(n);
        }
    }
}

/// Along-track residual per leg, the walk's scale removed.
fn along_track_residuals(a: &mut Acc, pts: &[Pt], wp: &[(f64, f64, f64)]) {
    let mut walk_legs: Vec<(f64, f64)> = Vec::new();
    for x in wp.windows(2) {
        if x[1].0 - x[0].0 < MIN_LEG_S {
            continue;
        }
        let (e0, e1) = (at(pts, x[0].0), at(pts, x[1].0));
        let d = (e1.east_m - e0.east_m).hypot(e1.north_m - e0.north_m);
        walk_legs.push((d, (x[1].1 - x[0].1).hypot(x[1].2 - x[0].2)));
    }
    let (sl, sd) = walk_legs
        .iter()
        .fold((0.0, 0.0), |s, l| (s.0 + l.1, s.1 + l.0));
    if walk_legs.len() >= 2 && sd > 0.0 {
        let k = sl / sd;
        a.leg_resid
            .extend(walk_legs.iter().map(|&(d, len)| (k * d, len - k * d)));
    }
}

/// The walk's rotation map → `get` (length-weighted circular mean over its legs).
fn walk_rotation(legs: &[Leg], get: &dyn Fn(&Leg) -> Option<f64>) -> Option<f64> {
    let v: Vec<(f64, f64)> = legs
        .iter()
        .filter_map(|l| get(l).map(|az| (wrap(az - l.map_rad), l.length_m)))
        .collect();
    (v.len() >= 2).then(|| circ_mean(&v))
}

/// Leg azimuth errors after each source's walk rotation, and the carrying angles.
fn leg_headings(a: &mut Acc, legs: &[Leg]) {
    if let Some(r) = walk_rotation(legs, &|l| l.track_rad) {
        a.walk_rot_nav.push(r);
        for l in legs {
            if let Some(az) = l.track_rad {
                let e = wrap(az - l.map_rad - r);
                a.leg_err_nav.push(e.abs());
                a.leg_err_by_time.push(LegError {
                    t_into_walk_s: l.t_into_walk_s,
                    err_rad: e,
                    length_m: l.length_m,
                });
            }
        }
    }
    if let Some(r) = walk_rotation(legs, &|l| l.attitude_y_rad) {
        for l in legs {
            if let Some(az) = l.attitude_y_rad {
                a.leg_err_ahrs_y.push(wrap(az - l.map_rad - r).abs());
            }
        }
    }
    if let Some(r) = walk_rotation(legs, &|l| l.rotation_vector_y_rad) {
        a.walk_rot_rv.push(r);
        for l in legs {
            if let Some(az) = l.rotation_vector_y_rad {
                a.leg_err_rv_y.push(wrap(az - l.map_rad - r).abs());
            }
        }
    }
    // Carrying: walking direction (legs, via RV's map rotation) minus +y.
    for l in legs {
        if let (Some(w), Some(y)) = (l.walking_rad, l.attitude_y_rad) {
            a.carry_nav.push(wrap(w - y));
        }
    }
    if let Some(r) = walk_rotation(legs, &|l| l.rotation_vector_y_rad) {
        for l in legs {
            if let Some(y) = l.rotation_vector_y_rad {
                // true walking azimuth in RV frame = map_az + r
                a.carry_rv.push(wrap(l.map_rad + r - y));
            }
        }
    }
}

/// Bins of time into the walk for the heading-error table, s.
const TIME_BINS_S: [(f64, f64); 6] = [
    (0.0, 5.0),
    (5.0, 10.0),
    (10.0, 20.0),
    (20.0, 40.0),
    (40.0, 80.0),
    (80.0, 200.0),
];

impl DiagnoseReport {
    /// The report as markdown.
    pub fn render(&self) -> String {
        let a = &self.samples;
        let mut out = format!(
            "Diagnosis on {} walks ({}): percentiles over walks or legs.\n\n",
            self.walks,
            if self.mag {
                "magnetometer"
            } else {
                "no magnetometer"
            }
        );
        out.push_str(&self.percentile_table().render());
        // The surveyor walks where the top edge points (the rotation vector's row above):
        // a leg more than 90° off it was dead-reckoned backwards.
        let backwards = a.carry_nav.iter().filter(|x| x.abs() > FRAC_PI_2).count();
        let _ = writeln!(
            out,
            "\nLegs dead-reckoned backwards (navigator walking azimuth more than 90° from its +y): {backwards} of {}.",
            a.carry_nav.len()
        );
        out.push_str(&self.noise.render());
        let _ = writeln!(
            out,
            "\nNavigator leg azimuth error against time into the walk (median |error|, °):\n"
        );
        out.push_str(&self.time_table().render());
        out.push_str(&self.legs.render());
        if let Some(s) = &self.shared {
            out.push_str(s);
        }
        out
    }

    /// Percentiles of every quantity over walks or legs.
    fn percentile_table(&self) -> Table {
        let mut t = Table::new(["what", "n", "p10", "p25", "median", "p75", "p90", "unit"]);
        for (name, v, scale, unit) in self.start_and_step_rows() {
            t.row(percentile_row(name, v, scale, unit));
        }
        for (name, v, scale, unit) in self.heading_rows() {
            t.row(percentile_row(name, &v, scale, unit));
        }
        t
    }

    /// Start delay and step length: (what, values, scale, unit).
    fn start_and_step_rows(&self) -> [(&'static str, &[f64], f64, &'static str); 11] {
        let a = &self.samples;
        [
            (
                "first step counted after the first waypoint",
                &a.first_step_s,
                1.0,
                "s",
            ),
            (
                "first step event's own time after the first waypoint",
                &a.first_event_s,
                1.0,
                "s",
            ),
            (
                "release time − step time (all steps)",
                &a.release_lag_s,
                1.0,
                "s",
            ),
            (
                "polyline / step events in the waypoint span",
                &a.events_per_poly,
                1.0,
                "m",
            ),
            (
                "position starts moving after the first waypoint",
                &a.first_move_s,
                1.0,
                "s",
            ),
            (
                "waypoint distance walked before the position moves",
                &a.lost_start_pct,
                1.0,
                "% of polyline",
            ),
            (
                "Σ step lengths − polyline",
                &a.dist_steps_pct,
                1.0,
                "% of polyline",
            ),
            (
                "polyline / steps (step length the waypoints imply)",
                &a.true_step_m,
                1.0,
                "m",
            ),
            ("model step length", &a.model_step_m, 1.0, "m"),
            ("cadence", &a.cadence_hz, 1.0, "steps/s"),
            ("waypoint speed", &a.speed_mps, 1.0, "m/s"),
        ]
    }

    /// Heading, carrying angle and turn timing: (what, values, scale, unit).
    fn heading_rows(&self) -> [(&'static str, Vec<f64>, f64, &'static str); 9] {
        let a = &self.samples;
        let deg = 180.0 / std::f64::consts::PI;
        let spread = |v: &[f64]| {
            let m = circ_mean(&v.iter().map(|x| (*x, 1.0)).collect::<Vec<_>>());
            v.iter().map(|x| wrap(x - m)).collect::<Vec<_>>()
        };
        [
            (
                "|leg azimuth error|, navigator track (per-walk rotation)",
                a.leg_err_nav.clone(),
                deg,
                "°",
            ),
            (
                "|leg azimuth error|, navigator attitude +y",
                a.leg_err_ahrs_y.clone(),
                deg,
                "°",
            ),
            (
                "|leg azimuth error|, rotation vector +y",
                a.leg_err_rv_y.clone(),
                deg,
                "°",
            ),
            (
                "per-walk rotation map → navigator, minus its circular mean",
                spread(&a.walk_rot_nav),
                deg,
                "°",
            ),
            (
                "per-walk rotation map → rotation vector, minus its circular mean",
                spread(&a.walk_rot_rv),
                deg,
                "°",
            ),
            (
                "walking direction − +y (rotation vector, per leg)",
                a.carry_rv.clone(),
                deg,
                "°",
            ),
            (
                "navigator walking azimuth − its +y azimuth (per leg)",
                a.carry_nav.clone(),
                deg,
                "°",
            ),
            (
                "turn centre − waypoint time, rotation vector (waypoints turning ≥ 45°)",
                a.turn_rv_s.clone(),
                1.0,
                "s",
            ),
            (
                "turn centre − waypoint time, navigator walking azimuth",
                a.turn_nav_s.clone(),
                1.0,
                "s",
            ),
        ]
    }

    /// Navigator leg azimuth error against time into the walk.
    fn time_table(&self) -> Table {
        let deg = 180.0 / std::f64::consts::PI;
        let mut t = Table::new([
            "time into walk",
            "legs",
            "median abs error",
            "median signed",
        ]);
        for (lo, hi) in TIME_BINS_S {
            let v: Vec<&LegError> = self
                .samples
                .leg_err_by_time
                .iter()
                .filter(|l| l.t_into_walk_s >= lo && l.t_into_walk_s < hi)
                .collect();
            t.row([
                format!("{lo}–{hi} s"),
                v.len().to_string(),
                format!("{:.1}", median(v.iter().map(|l| l.err_rad.abs() * deg))),
                format!("{:.1}", median(v.iter().map(|l| l.err_rad * deg))),
            ]);
        }
        t
    }
}

/// Bins of leg displacement for the along-track noise fit, m.
const NOISE_BINS_M: [(f64, f64); 5] = [
    (1.0, 3.0),
    (3.0, 5.0),
    (5.0, 7.0),
    (7.0, 10.0),
    (10.0, 15.0),
];
/// Bins of leg length for the cross-track (azimuth) noise fit, m.
const AZIMUTH_BINS_M: [(f64, f64); 5] = [
    (2.0, 4.0),
    (4.0, 6.0),
    (6.0, 9.0),
    (9.0, 13.0),
    (13.0, 25.0),
];

/// One bin of a noise fit: `(lo, hi, n, robust sd, mean regressor)`.
type NoiseBin = (f64, f64, usize, f64, f64);

/// Robust sd (1.4826 · MAD) of `(x, value)` pairs per bin of x (bins with at least
/// 20 pairs), with the mean of `regressor(x)` over the bin.
fn residual_bins(
    pairs: &[(f64, f64)],
    bins: &[(f64, f64)],
    regressor: impl Fn(f64) -> f64,
) -> Vec<NoiseBin> {
    let mut rows = Vec::new();
    for &(lo, hi) in bins {
        let bin: Vec<(f64, f64)> = pairs
            .iter()
            .copied()
            .filter(|r| r.0 >= lo && r.0 < hi)
            .collect();
        if bin.len() < 20 {
            continue;
        }
        let med = median(bin.iter().map(|r| r.1));
        let sd = 1.4826 * median(bin.iter().map(|r| (r.1 - med).abs()));
        let x = bin.iter().map(|r| regressor(r.0)).sum::<f64>() / bin.len() as f64;
        rows.push((lo, hi, bin.len(), sd, x));
    }
    rows
}

/// Least squares of sd² = a + b·x over the bins of [`residual_bins`]: `(a, b)`.
fn noise_fit(rows: &[NoiseBin]) -> Option<(f64, f64)> {
    if rows.len() < 2 {
        return None;
    }
    let n = rows.len() as f64;
    let (mx, my) = (
        rows.iter().map(|r| r.4).sum::<f64>() / n,
        rows.iter().map(|r| r.3 * r.3).sum::<f64>() / n,
    );
    let sxy: f64 = rows.iter().map(|r| (r.4 - mx) * (r.3 * r.3 - my)).sum();
    let sxx: f64 = rows.iter().map(|r| (r.4 - mx).powi(2)).sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    Some((my - b * mx, b))
}

/// The noise fits of [`WaypointNoise`] and the perfect tracks they imply.
struct NoiseFits {
    /// Along-track sd² = a + b·d²: `(a, b)`.
    along: (f64, f64),
    /// Azimuth sd² = h² + c/L²: `(h², c)` (NaN without enough bins).
    azimuth: (f64, f64),
    sigma_along: f64,
    sigma_cross: f64,
    /// The RMS of the two (σ_along alone when there is no azimuth fit).
    sigma: f64,
    along_only: Metrics,
    both: Metrics,
}

/// The waypoints' own noise from the leg residuals (see the module doc), and the ATE
/// of a perfect track against waypoints with that noise.
struct WaypointNoise {
    along_bins: Vec<NoiseBin>,
    azimuth_bins: Vec<NoiseBin>,
    fits: Option<NoiseFits>,
}

impl WaypointNoise {
    /// `along`: (displacement, along-track residual) per leg; `azimuth`: (leg length,
    /// azimuth error after the walk's rotation) per leg.
    fn fit(along: &[(f64, f64)], azimuth: &[(f64, f64)], walks: &[Walk]) -> Self {
        let along_bins = residual_bins(along, &NOISE_BINS_M, |d| d * d);
        let azimuth_bins = residual_bins(azimuth, &AZIMUTH_BINS_M, |l| 1.0 / (l * l));
        let fits = noise_fit(&along_bins).map(|(a0, b)| {
            let sigma_along = (a0.max(0.0) / 2.0).sqrt();
            // Azimuth: sd² = h² + c/L² (a heading error that does not shrink with the
            // leg, and the waypoints' cross-track noise, 2σ² = c).
            let (h2, c) = noise_fit(&azimuth_bins).unwrap_or((f64::NAN, f64::NAN));
            let sigma_cross = (c.max(0.0) / 2.0).sqrt();
            let sigma = if sigma_cross.is_finite() {
                (0.5 * (sigma_along * sigma_along + sigma_cross * sigma_cross)).sqrt()
            } else {
                sigma_along
            };
            NoiseFits {
                along: (a0, b),
                azimuth: (h2, c),
                sigma_along,
                sigma_cross,
                sigma,
                along_only: perfect_track(walks, sigma_along),
                both: perfect_track(walks, sigma),
            }
        });
        Self {
            along_bins,
            azimuth_bins,
            fits,
        }
    }

    fn render(&self) -> String {
        let mut out = String::from("\nWaypoint noise. Along the leg: leg length − the navigator's displacement (the walk's scale removed), by displacement; across it: the leg's azimuth error after the walk's rotation, by leg length:\n\n");
        let mut t = Table::new(["residual", "bin", "legs", "robust sd"]);
        for (lo, hi, n, sd, _) in &self.along_bins {
            t.row([
                "along".to_string(),
                format!("{lo}–{hi} m"),
                n.to_string(),
                format!("{sd:.2} m"),
            ]);
        }
        for (lo, hi, n, sd, _) in &self.azimuth_bins {
            t.row([
                "azimuth".to_string(),
                format!("{lo}–{hi} m"),
                n.to_string(),
                format!("{:.1}°", sd.to_degrees()),
            ]);
        }
        out.push_str(&t.render());
        let Some(f) = &self.fits else {
            return out;
        };
        let NoiseFits {
            along: (a0, b),
            azimuth: (h2, _),
            sigma_along,
            sigma_cross,
            sigma,
            along_only,
            both,
        } = f;
        let _ = writeln!(
            out,
            "\nFits: along-track sd² = a + b·d² gives a = {a0:.3} m² (relative along-track scatter √b = {:.1} %), per-waypoint noise σ_along = √(a/2) = {sigma_along:.2} m; azimuth sd² = h² + c/L² gives a heading error h = {:.1}° that does not shrink with the leg and σ_across = √(c/2) = {sigma_cross:.2} m. A perfect track against these waypoints with isotropic noise σ = {sigma:.2} m (the RMS of the two) added: median ATE {:.2} m, start-pinned {:.2} m, end {:.1} %, |distance| {:.1} % (with σ_along alone {:.2} m, {:.2} m, {:.1} %, {:.1} %; 5 draws per walk): what the waypoints alone charge a navigator with no error of its own.",
            100.0 * b.max(0.0).sqrt(),
            h2.max(0.0).sqrt().to_degrees(),
            both.ate_m,
            both.start_pinned_m,
            both.end_pct,
            both.distance_pct,
            along_only.ate_m,
            along_only.start_pinned_m,
            along_only.end_pct,
            along_only.distance_pct,
        );
        out
    }
}

/// Medians of the measures (ATE, start-pinned error, end error, |distance
/// error|) for a perfect track (the waypoint polyline itself) against its waypoints
/// with isotropic noise σ per axis added; 5 draws per walk, fixed seed.
fn perfect_track(walks: &[Walk], sigma: f64) -> Metrics {
    let mut rng = stridekit_sim::Rng::new(13);
    let mut all: Vec<Metrics> = Vec::new();
    for w in walks {
        let wp = &w.rec.truth;
        if wp.len() < 3 {
            continue;
        }
        let track: Vec<TrackPoint> = wp
            .iter()
            .map(|p| TrackPoint {
                t_s: p.0,
                x_m: p.1,
                y_m: p.2,
                distance_m: 0.0,
            })
            .collect();
        for _ in 0..5 {
            let noisy: Vec<(f64, f64, f64)> = wp
                .iter()
                .map(|p| (p.0, p.1 + sigma * rng.normal(), p.2 + sigma * rng.normal()))
                .collect();
            if let Some(m) = evaluate(&track, &noisy) {
                all.push(m);
            }
        }
    }
    let med = |f: fn(&Metrics) -> f64| median(all.iter().map(f).collect::<Vec<f64>>());
    Metrics {
        ate_m: med(|m| m.ate_m),
        start_pinned_m: med(|m| m.start_pinned_m),
        end_pct: med(|m| m.end_pct),
        distance_pct: med(|m| m.distance_pct.abs()),
        polyline_m: med(|m| m.polyline_m),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn a_turn_is_timed_at_its_centre_in_either_direction() {
        // 90° over 1 s centred at t = 0.7, sampled at 50 Hz, with a little noise.
        let az = |sign: f64| -> Vec<(f64, f64)> {
            (0..600)
                .map(|i| {
                    let t = -6.0 + i as f64 * 0.02;
                    let ramp = ((t - 0.2) / 1.0).clamp(0.0, 1.0);
                    let wobble = 0.01 * (37.0 * t).sin();
                    (t, wrap(sign * (0.5 * PI * ramp) + 3.0 + wobble))
                })
                .collect()
        };
        for sign in [1.0, -1.0] {
            let c = turn_centre(&az(sign), 0.0, sign).expect("a 90° turn is seen");
            assert!((c - 0.7).abs() < 0.1, "{c}");
        }
        // No turn in the window: nothing to time.
        let flat: Vec<(f64, f64)> = (0..600).map(|i| (-6.0 + i as f64 * 0.02, 1.0)).collect();
        assert_eq!(turn_centre(&flat, 0.0, 1.0), None);
    }

    #[test]
    fn the_noise_fit_recovers_a_known_waypoint_noise() {
        // Leg residual = n1 − n0 (σ = 0.4 m per waypoint) + 5 % of the displacement.
        let mut rng = stridekit_sim::Rng::new(7);
        let resid: Vec<(f64, f64)> = (0..20_000)
            .map(|_| {
                let d = rng.range(1.0, 15.0);
                let e = 0.4 * (rng.normal() - rng.normal()) + 0.05 * d * rng.normal();
                (d, e)
            })
            .collect();
        let (a, b) =
            noise_fit(&residual_bins(&resid, &NOISE_BINS_M, |d| d * d)).expect("enough legs");
        let sigma = (a / 2.0).sqrt();
        assert!((sigma - 0.4).abs() < 0.05, "σ {sigma}");
        assert!((b.sqrt() - 0.05).abs() < 0.01, "relative {}", b.sqrt());
    }

    #[test]
    fn a_perfect_track_scores_the_noise_added_to_its_waypoints() {
        // An L-shaped walk of 6 waypoints, 5 m apart.
        let truth: Vec<(f64, f64, f64)> = [
            (0.0, 0.0),
            (5.0, 0.0),
            (10.0, 0.0),
            (10.0, 5.0),
            (10.0, 10.0),
            (15.0, 10.0),
        ]
        .iter()
        .enumerate()
        .map(|(i, p)| (i as f64 * 4.0, p.0, p.1))
        .collect();
        let walks = vec![Walk {
            floor: "F".into(),
            rec: stridekit_formats::InertialRecording {
                truth,
                ..Default::default()
            },
        }];
        let exact = perfect_track(&walks, 0.0);
        assert!(
            exact.ate_m < 1e-9 && exact.start_pinned_m < 1e-9,
            "{exact:?}"
        );
        assert!(
            exact.end_pct < 1e-9 && exact.distance_pct < 1e-9,
            "{exact:?}"
        );
        let noisy = perfect_track(&walks, 0.5);
        // Rigid alignment absorbs 3 of the 12 degrees of freedom: ≈ 0.5·√(2·9/12).
        let a = noisy.ate_m;
        assert!(a > 0.3 && a < 0.9, "{a}");
        // The noisy polyline is longer or shorter than the path: |distance| > 0.
        assert!(noisy.distance_pct > 0.5, "{noisy:?}");
    }
}
