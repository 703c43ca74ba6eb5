//! Accuracy evaluation of the pace methods against a reference speed.
//!
//! Shared by the tests, `stridekit eval pace` and `stridekit demo`, so every number
//! in the docs comes from one code path. Pure computation, no I/O.
//!
//! Methods compared: raw GNSS differentiation, the paper's GNSS EMA smoothing, the
//! as-published complementary filter, and the default adaptive filter. All are
//! replayed over the same time-ordered samples; each method's speed is read on a
//! 1 s grid as its latest output (what a watch would display at that second).

use stridekit_core::pace::{Baseline, BaselineKind};
use stridekit_core::pace::{PaceConfig, PaceEstimate, PaceSample, PaceTracker};
use stridekit_sim::{Rng, SimulatedRun, Zone, ZoneKind};

/// The four methods, in table order.
pub const METHODS: [&str; 4] = ["raw GNSS diff", "GNSS EMA", "AsPublished", "default"];

/// Speeds (and fused extras) of every method on a 1 s grid.
#[derive(Clone, Debug, Default)]
pub struct Replay {
    pub t_s: Vec<f64>,
    /// `speed[m][i]`: method m at grid time i, m/s (NaN before its first output).
    pub speed: [Vec<f64>; 4],
    /// GNSS weight of AsPublished and default at grid times.
    pub weight: [Vec<f64>; 2],
    /// Cumulative distance of AsPublished and default at grid times, metres.
    pub distance: [Vec<f64>; 2],
    /// Estimated step length of default at grid times, metres (NaN when unknown).
    pub step_length: Vec<f64>,
    /// Whether a fix was received within the last 2 s at each grid time.
    pub has_gnss: Vec<bool>,
    /// Fused position of default at grid times, metres east / north of the first fix
    /// (NaN before it).
    pub position_enu_m: Vec<(f64, f64)>,
    /// Cumulative distance of the raw GNSS track (sum of fix-to-fix distances), metres.
    pub gnss_track_distance_m: f64,
    /// What the default tracker learned, to carry to a next session
    /// (`PaceTracker::calibration()` after the replay).
    pub calibration: Option<stridekit_core::PaceCalibration>,
}

/// Replay samples (time-ordered) through all methods. Rejected samples are skipped.
pub fn replay(samples: &[PaceSample], published: PaceConfig, default: PaceConfig) -> Replay {
    let mut raw = Baseline::new(BaselineKind::RawDifferentiation);
    let mut ema = Baseline::new(BaselineKind::GnssEma);
    let mut trackers = [
        PaceTracker::new(published).expect("valid AsPublished config"),
        PaceTracker::new(default).expect("valid default config"),
    ];
    let mut out = Replay::default();
    let Some(t0) = samples.first().map(|s| s.t_s().ceil()) else {
        return out;
    };
    let t_end = samples.last().map(|s| s.t_s()).unwrap_or(t0);
    let mut latest = [f64::NAN; 4];
    let mut last_fix_t = f64::NEG_INFINITY;
    let mut grid_t = t0;
    let mut raw_track = 0.0;
    let mut i = 0;
    while grid_t <= t_end {
        while i < samples.len() && samples[i].t_s() <= grid_t {
            let s = &samples[i];
            if let PaceSample::Fix(f) = s {
                if let Some(v) = raw.push(f) {
                    latest[0] = v;
                    // Raw speed × dt is the fix-to-fix distance.
                    raw_track += v * (f.t_s - last_fix_t);
                }
                if let Some(v) = ema.push(f) {
                    latest[1] = v;
                }
                last_fix_t = f.t_s;
            }
            for (k, tr) in trackers.iter_mut().enumerate() {
                if tr.push(s).is_ok() {
                    if let Some(e) = tr.estimate() {
                        latest[2 + k] = e.speed_mps;
                    }
                }
            }
            i += 1;
        }
        out.t_s.push(grid_t);
        for (series, &v) in out.speed.iter_mut().zip(&latest) {
            series.push(v);
        }
        for (k, tr) in trackers.iter().enumerate() {
            let e = tr.estimate().unwrap_or(PaceEstimate::initial(None));
            out.weight[k].push(e.gnss_weight);
            out.distance[k].push(e.distance_m);
        }
        out.step_length.push(
            trackers[1]
                .estimate()
                .and_then(|e| e.step_length_m)
                .unwrap_or(f64::NAN),
        );
        out.position_enu_m.push(
            trackers[1]
                .position_enu_m()
                .map_or((f64::NAN, f64::NAN), |p| (p[0], p[1])),
        );
        out.has_gnss.push(grid_t - last_fix_t <= 2.0);
        grid_t += 1.0;
    }
    out.gnss_track_distance_m = raw_track;
    out.calibration = trackers[1].calibration();
    out
}

/// Root-mean-square error of the finite pairs selected by `keep`; NaN if none.
pub fn rmse(est: &[f64], reference: &[f64], keep: impl Fn(usize) -> bool) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for (i, (e, r)) in est.iter().zip(reference).enumerate() {
        if keep(i) && e.is_finite() && r.is_finite() {
            s += (e - r) * (e - r);
            n += 1;
        }
    }
    if n == 0 {
        f64::NAN
    } else {
        (s / n as f64).sqrt()
    }
}

/// RMSE of every method in three segments.
#[derive(Clone, Debug, PartialEq)]
pub struct Scores {
    /// Where GNSS is available (clean and disturbed), per method.
    pub all: [f64; 4],
    /// Inside GNSS disturbance zones only.
    pub disturbed: [f64; 4],
    /// Inside GNSS outages (fusion methods only; NaN for GNSS-only methods).
    pub outage: [f64; 4],
    /// Final distance of AsPublished and default, metres.
    pub distance_m: [f64; 2],
}

/// Score a replay against reference speeds on its grid (NaN reference = not scored).
pub fn score(replay: &Replay, reference: &[f64], zones: &[Zone]) -> Scores {
    let in_zone = |t: f64, k: ZoneKind| {
        zones
            .iter()
            .any(|z| z.kind == k && t >= z.start_s && t < z.end_s)
    };
    let mut s = Scores {
        all: [f64::NAN; 4],
        disturbed: [f64::NAN; 4],
        outage: [f64::NAN; 4],
        distance_m: [
            replay.distance[0].last().copied().unwrap_or(0.0),
            replay.distance[1].last().copied().unwrap_or(0.0),
        ],
    };
    let t = &replay.t_s;
    for m in 0..4 {
        let est = &replay.speed[m];
        s.all[m] = rmse(est, reference, |i| replay.has_gnss[i]);
        s.disturbed[m] = rmse(est, reference, |i| {
            replay.has_gnss[i] && in_zone(t[i], ZoneKind::Disturbance)
        });
        if m >= 2 {
            s.outage[m] = rmse(est, reference, |i| in_zone(t[i], ZoneKind::Outage));
        }
    }
    s
}

/// Distance by a reference speed and by a method, over the grid seconds where the
/// reference is defined (apples to apples), metres: (reference, method).
pub fn distance_against(replay: &Replay, reference: &[f64], method: usize) -> (f64, f64) {
    let d = &replay.distance[method];
    let (mut r, mut e) = (0.0, 0.0);
    for i in 1..reference.len().min(d.len()) {
        if reference[i].is_finite() && reference[i - 1].is_finite() {
            let dt = replay.t_s[i] - replay.t_s[i - 1];
            r += 0.5 * (reference[i] + reference[i - 1]) * dt;
            e += d[i] - d[i - 1];
        }
    }
    (r, e)
}

/// Truth speed of a simulated run on a replay's grid.
pub fn sim_reference(run: &SimulatedRun, replay: &Replay) -> Vec<f64> {
    replay
        .t_s
        .iter()
        .map(|&t| run.truth_at(t).speed_mps)
        .collect()
}

/// A clean GNSS track point: time and local east/north, metres.
pub type TrackPoint = (f64, f64, f64);

/// Reference speed from a clean track: slope of a centred least-squares line through
/// the positions within ±`half_window_s` of each grid time (non-causal smoothing).
/// A line, not a quadratic: on tracks with fixes 2–7 s apart a quadratic's derivative
/// amplifies position noise, and |v| turns that noise into an upward bias. NaN where
/// fewer than 3 fixes, spanning less than `half_window_s`, fall in the window.
pub fn smoothed_track_speed(track: &[TrackPoint], grid: &[f64], half_window_s: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(grid.len());
    let mut lo = 0;
    for &g in grid {
        while lo < track.len() && track[lo].0 < g - half_window_s {
            lo += 1;
        }
        let mut hi = lo;
        while hi < track.len() && track[hi].0 <= g + half_window_s {
            hi += 1;
        }
        let w = &track[lo..hi];
        if w.len() < 3 || w[0].0 > g || w[w.len() - 1].0 < g {
            out.push(f64::NAN);
            continue;
        }
        if w[w.len() - 1].0 - w[0].0 < half_window_s {
            out.push(f64::NAN);
            continue;
        }
        let ve = linear_slope(w.iter().map(|p| (p.0 - g, p.1)));
        let vn = linear_slope(w.iter().map(|p| (p.0 - g, p.2)));
        out.push(ve.hypot(vn));
    }
    out
}

/// Slope of the least-squares line through the points.
fn linear_slope(pts: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (mut n, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (x, y) in pts {
        n += 1.0;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    let d = n * sxx - sx * sx;
    if d.abs() < 1e-12 {
        f64::NAN
    } else {
        (n * sxy - sx * sy) / d
    }
}

/// GNSS degradation injected on a clean real track: disturbance bursts (correlated
/// error of several metres plus multipath jumps) and outages, placed on the track
/// with a seeded RNG. Returns the degraded fixes' east/north offsets (None = dropped
/// fix) and the zones.
pub fn degrade_track(track: &[TrackPoint], seed: u64) -> (Vec<Option<(f64, f64)>>, Vec<Zone>) {
    let mut rng = Rng::new(seed);
    let (Some(first), Some(last)) = (track.first(), track.last()) else {
        return (Vec::new(), Vec::new());
    };
    let (t0, t1) = (first.0, last.0);
    let dur = t1 - t0;
    // One zone per ~8 minutes: alternate disturbance / outage, after a 2 min lead-in.
    let mut zones = Vec::new();
    let slots = ((dur - 120.0) / 480.0).floor().max(0.0) as usize;
    for k in 0..slots {
        let slot_start = t0 + 120.0 + 480.0 * k as f64;
        let kind = if k % 2 == 0 {
            ZoneKind::Disturbance
        } else {
            ZoneKind::Outage
        };
        let len = match kind {
            ZoneKind::Disturbance => rng.range(30.0, 90.0),
            _ => rng.range(60.0, 180.0),
        };
        let start = slot_start + rng.range(0.0, 480.0 - len - 30.0);
        zones.push(Zone {
            kind,
            start_s: start,
            end_s: start + len,
        });
    }
    let mut out = Vec::with_capacity(track.len());
    let (mut be, mut bn) = (0.0f64, 0.0f64);
    let mut jump = (0.0, 0.0, f64::NEG_INFINITY);
    let mut prev_t = t0;
    for p in track {
        let t = p.0;
        let dt = (t - prev_t).max(0.0);
        prev_t = t;
        let zone = zones.iter().find(|z| t >= z.start_s && t < z.end_s);
        match zone.map(|z| z.kind) {
            Some(ZoneKind::Outage) => {
                out.push(None);
                continue;
            }
            Some(ZoneKind::Disturbance) => {
                let (sigma, tau) = (6.0, 5.0);
                let phi = (-dt / tau).exp();
                let q = sigma * (1.0 - phi * phi).sqrt();
                be = phi * be + q * rng.normal();
                bn = phi * bn + q * rng.normal();
                if t > jump.2 && rng.uniform() < 0.08 * dt {
                    let a = rng.range(0.0, std::f64::consts::TAU);
                    let m = rng.range(5.0, 15.0);
                    jump = (m * a.cos(), m * a.sin(), t + rng.range(2.0, 6.0));
                }
                let (je, jn) = if t <= jump.2 {
                    (jump.0, jump.1)
                } else {
                    (0.0, 0.0)
                };
                out.push(Some((
                    be + je + 0.5 * rng.normal(),
                    bn + jn + 0.5 * rng.normal(),
                )));
            }
            _ => {
                // Leave clean stretches as recorded; let the injected error decay.
                let phi = (-dt / 5.0).exp();
                be *= phi;
                bn *= phi;
                out.push(Some((0.0, 0.0)));
            }
        }
    }
    (out, zones)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothed_speed_of_a_straight_line() {
        let track: Vec<TrackPoint> = (0..60)
            .map(|i| (i as f64, 3.0 * i as f64, 4.0 * i as f64))
            .collect();
        let grid: Vec<f64> = (5..55).map(|i| i as f64).collect();
        for v in smoothed_track_speed(&track, &grid, 4.0) {
            assert!((v - 5.0).abs() < 1e-9, "{v}");
        }
    }

    #[test]
    fn rmse_basic() {
        assert_eq!(
            rmse(&[1.0, 2.0, f64::NAN], &[1.0, 4.0, 3.0], |_| true),
            2f64.sqrt()
        );
        assert!(rmse(&[], &[], |_| true).is_nan());
    }

    #[test]
    fn degradation_is_deterministic_and_places_zones() {
        let track: Vec<TrackPoint> = (0..3600).map(|i| (i as f64, i as f64, 0.0)).collect();
        let (a, za) = degrade_track(&track, 3);
        let (b, zb) = degrade_track(&track, 3);
        assert_eq!(a, b);
        assert_eq!(za, zb);
        assert!(za.iter().any(|z| z.kind == ZoneKind::Outage));
        assert!(za.iter().any(|z| z.kind == ZoneKind::Disturbance));
        assert!(a.iter().any(|o| o.is_none()));
    }
}
