//! What the per-walk distance error shares: part of `stridekit eval pdr --diagnose`.
//!
//! Each walk's distance between its first and last waypoint times is estimated four
//! ways from the same recording, each with one factor for all walks (only the
//! spread from walk to walk counts, not the level):
//! - **the default** (the inverted pendulum's step lengths, the scored track's);
//! - **Weinberg's** `(a_max − a_min)^¼` step lengths on the same steps (another
//!   step-length feature, from the acceleration's range instead of the rise and fall);
//! - **the step count** alone (one length for every step);
//! - **the walking time** alone: the time whose accelerometer norm varies like walking
//!   (SD over 1 s above [`WALKING_SD_MPS2`]), no step and no length at all.
//!
//! The per-walk error of each is ln(polyline / estimate), centred on its median. Two
//! estimates whose errors move together share their cause: the steps themselves or
//! the walk (its pace, the path the polyline leaves out, the waypoints), not a
//! step-length feature. How far they move together is a rank correlation, which one
//! odd walk cannot drive.

use std::fmt::Write as _;

use stridekit_core::steplength::StepLengthModel;
use stridekit_formats::InertialRecording;

use crate::pdr::legs::robust_sd;
use crate::pdr::metrics::{median, polyline_m};
use crate::pdr::walks::{replay, ReplayOptions, Walk};

/// Accelerometer-norm SD over 1 s above which the phone moves like walking, m/s².
const WALKING_SD_MPS2: f64 = 1.2;
/// Walks with a shorter polyline are left out (a few steps say little about scale), m.
const MIN_POLYLINE_M: f64 = 5.0;

/// Seconds in `[t0, t1]` whose accelerometer norm has an SD over the surrounding 1 s
/// above [`WALKING_SD_MPS2`]; each sample counts for the time to the next one.
pub(crate) fn walking_time_s(rec: &InertialRecording, t0: f64, t1: f64) -> f64 {
    let s = &rec.samples;
    let norm: Vec<f64> = s
        .iter()
        .map(|x| x.accel_mps2.iter().map(|a| a * a).sum::<f64>().sqrt())
        .collect();
    let (mut lo, mut hi) = (0, 0);
    let (mut sum, mut sum2) = (0.0, 0.0);
    let mut total = 0.0;
    for i in 0..s.len().saturating_sub(1) {
        let t = s[i].t_s;
        while hi < s.len() && s[hi].t_s <= t + 0.5 {
            sum += norm[hi];
            sum2 += norm[hi] * norm[hi];
            hi += 1;
        }
        while s[lo].t_s < t - 0.5 {
            sum -= norm[lo];
            sum2 -= norm[lo] * norm[lo];
            lo += 1;
        }
        if t < t0 || t > t1 {
            continue;
        }
        let n = (hi - lo) as f64;
        let var = (sum2 / n - (sum / n).powi(2)).max(0.0);
        if var.sqrt() > WALKING_SD_MPS2 {
            total += (s[i + 1].t_s.min(t1) - t).max(0.0);
        }
    }
    total
}

/// Ranks (0-based, ties in input order) of `v`.
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    for (k, &i) in idx.iter().enumerate() {
        r[i] = k as f64;
    }
    r
}

/// Spearman's rank correlation of two equally long series.
pub(crate) fn rank_correlation(a: &[f64], b: &[f64]) -> f64 {
    let (ra, rb) = (ranks(a), ranks(b));
    let n = ra.len() as f64;
    let (ma, mb) = (ra.iter().sum::<f64>() / n, rb.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in ra.iter().zip(&rb) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

/// Append the section to `out`.
pub fn report(out: &mut String, walks: &[Walk]) -> Result<(), String> {
    let default = ReplayOptions::default();
    let mut weinberg = ReplayOptions::default();
    weinberg.config.step_length_model = StepLengthModel::Weinberg;
    // Per walk: polyline, then the four estimates.
    let mut rows: Vec<[f64; 5]> = Vec::new();
    for w in walks {
        let wp = &w.rec.truth;
        if wp.len() < 2 {
            continue;
        }
        let poly = polyline_m(&wp.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>());
        if poly < MIN_POLYLINE_M {
            continue;
        }
        let (t0, t1) = (wp[0].0, wp[wp.len() - 1].0);
        let span = |o: &ReplayOptions| -> Result<(f64, f64), String> {
            let r = replay(&w.rec, o)?;
            Ok(r.steps
                .iter()
                .filter(|s| s.t_s >= t0 && s.t_s <= t1)
                .fold((0.0, 0.0), |a, s| (a.0 + s.length_m, a.1 + 1.0)))
        };
        let (pendulum, count) = span(&default)?;
        let (weinberg, _) = span(&weinberg)?;
        let time = walking_time_s(&w.rec, t0, t1);
        if count < 5.0 || time <= 0.0 {
            continue;
        }
        rows.push([poly, pendulum, weinberg, count, time]);
    }
    let errors: Vec<Vec<f64>> = (1..5)
        .map(|j| {
            let e: Vec<f64> = rows.iter().map(|r| (r[0] / r[j]).ln() * 100.0).collect();
            let m = median(e.clone());
            e.iter().map(|x| x - m).collect()
        })
        .collect();
    let _ = writeln!(
        out,
        "\nWhat the per-walk distance error shares ({} walks with a polyline of {MIN_POLYLINE_M} m or more; each estimate of the distance between the first and last waypoint times scaled by one factor for all walks; its per-walk error ln(polyline / estimate), robust sd, and its rank correlation with the default's):\n",
        rows.len()
    );
    let _ = writeln!(
        out,
        "| distance from | per-walk error, robust sd | rank correlation with the default's |"
    );
    let _ = writeln!(out, "|---|---|---|");
    let names = [
        "the default's step lengths (inverted pendulum)",
        "Weinberg's step lengths on the same steps",
        "the step count alone",
        "the walking time alone (no steps)",
    ];
    for (name, e) in names.iter().zip(&errors) {
        let _ = writeln!(
            out,
            "| {name} | {:.1} % | {:+.2} |",
            robust_sd(e),
            rank_correlation(&errors[0], e)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use stridekit_formats::InertialSample;

    fn recording(f: impl Fn(f64) -> f64) -> InertialRecording {
        InertialRecording {
            samples: (0..1000)
                .map(|i| {
                    let t = i as f64 * 0.02;
                    InertialSample {
                        t_s: t,
                        accel_mps2: [0.0, 0.0, 9.81 + f(t)],
                        ..Default::default()
                    }
                })
                .collect(),
            ..Default::default()
        }
    }

    #[test]
    fn walking_time_counts_only_the_shaken_seconds() {
        // 20 s: still for the first 10, a 2 Hz bounce of 3 m/s² (SD 2.1) after.
        let rec = recording(|t| {
            if t >= 10.0 {
                3.0 * (2.0 * std::f64::consts::TAU * t).sin()
            } else {
                0.0
            }
        });
        let w = walking_time_s(&rec, 0.0, 20.0);
        assert!((w - 10.0).abs() < 0.6, "{w}");
        assert!(walking_time_s(&rec, 0.0, 9.0) < 1e-9);
    }

    #[test]
    fn rank_correlation_of_monotone_and_reversed_series() {
        let a = [1.0, 5.0, 2.0, 9.0];
        let b = [10.0, 50.0, 20.0, 90.0];
        assert!((rank_correlation(&a, &b) - 1.0).abs() < 1e-12);
        let c: Vec<f64> = b.iter().map(|x| -x).collect();
        assert!((rank_correlation(&a, &c) + 1.0).abs() < 1e-12);
    }
}
