//! Learning a foot IMU's accelerometer-to-gyroscope alignment
//! ([`FootConfig::accel_alignment_rad`]) from level walks (`stridekit calibrate foot`).
//!
//! Why: when the accelerometer's axes are turned against the gyroscope's by a degree
//! or so (consumer IMUs), the swing's forward acceleration is partly read as vertical.
//! The foot starts and ends each swing at rest, so the velocity error is back to about
//! zero at the next stance and no zero-velocity update sees it, but the height moves by
//! about the angle × the stride length at every stride (x-io's NGIMU walks: +1.5 cm a
//! stride; docs/foot.md). Nothing inside a walk tells the engine the floor is level, so
//! the alignment is a device calibration learned once from a walk the user states is
//! level, like a magnetometer calibration.
//!
//! How: the stance periods of a replay with the given configuration are found once;
//! the residuals are the height changes from each stance to the next (the mean height
//! over each stance), zero on a level walk. One angle is fitted, about the body's
//! lateral axis (y: the tilt that leaks the forward acceleration into the vertical), by
//! Gauss–Newton with central-difference derivatives (each evaluation is one replay of
//! the walks) and a weak prior (σ [`PRIOR_SIGMA_RAD`]) towards zero.
//!
//! File format (versioned text, one record per line, `#` comments):
//!
//! ```text
//! stridekit-foot-calibration 1
//! accel_alignment_rad 0.00012 0.02391 -0.00040
//! ```

use stridekit_core::foot::{FootConfig, FootNavigator, FootSample, MAX_ACCEL_ALIGNMENT_RAD};

/// First line of a foot calibration file.
pub const HEADER: &str = "stridekit-foot-calibration 1";
/// Shortest stance whose height counts, s.
pub const MIN_STANCE_S: f64 = 0.05;
/// Prior 1-σ of each alignment angle, rad (≈ 2.9°).
pub const PRIOR_SIGMA_RAD: f64 = 0.05;
/// Scale of a residual (stance-to-stance height change) against which the prior is
/// weighed, m.
const RESIDUAL_SCALE_M: f64 = 0.01;
/// Central-difference step, rad (≈ 0.11°).
const STEP_RAD: f64 = 0.002;
const MAX_ITERATIONS: usize = 12;

/// A stance: estimate indices `[start, end)` within one walk's replay.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stance {
    start: usize,
    end: usize,
}

/// One walk replayed: estimate times, heights and stance flags, in order.
struct Replay {
    t_s: Vec<f64>,
    z_m: Vec<f64>,
    stance: Vec<bool>,
    end_m: [f64; 3],
    start_m: [f64; 3],
    distance_m: f64,
}

fn replay(config: &FootConfig, samples: &[FootSample]) -> Result<Replay, String> {
    let mut nav = FootNavigator::new(config.clone()).map_err(|e| e.to_string())?;
    let mut r = Replay {
        t_s: Vec::with_capacity(samples.len()),
        z_m: Vec::with_capacity(samples.len()),
        stance: Vec::with_capacity(samples.len()),
        end_m: [0.0; 3],
        start_m: [f64::NAN; 3],
        distance_m: 0.0,
    };
    nav.push_batch_with(samples, |e| {
        if r.t_s.is_empty() {
            r.start_m = e.position_m;
        }
        r.t_s.push(e.t_s);
        r.z_m.push(e.position_m[2]);
        r.stance.push(e.stance);
        r.end_m = e.position_m;
        r.distance_m = e.distance_m;
    });
    if r.t_s.is_empty() {
        return Err("no estimate (too short, or no rest to align at the start)".into());
    }
    Ok(r)
}

fn stances(r: &Replay) -> Vec<Stance> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < r.stance.len() {
        if !r.stance[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i < r.stance.len() && r.stance[i] {
            i += 1;
        }
        if r.t_s[i - 1] - r.t_s[start] >= MIN_STANCE_S {
            out.push(Stance { start, end: i });
        }
    }
    out
}

fn heights(r: &Replay, st: &[Stance]) -> Vec<f64> {
    st.iter()
        .map(|s| {
            // The stances were found on another replay of the same samples: the same
            // estimate indices (the alignment changes no rejection and no delay);
            // guarded all the same.
            let end = s.end.min(r.z_m.len());
            match r.z_m.get(s.start..end) {
                Some(z) if !z.is_empty() => z.iter().sum::<f64>() / z.len() as f64,
                _ => f64::NAN,
            }
        })
        .collect()
}

/// A walk, and what the fit saw of it.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkFit {
    pub name: String,
    /// Stance-to-stance steps (strides and rests) whose height change was fitted.
    pub steps: usize,
    pub distance_m: f64,
    /// RMS stance-to-stance height change, m: with the starting alignment, fitted.
    pub rms_before_m: f64,
    pub rms_after_m: f64,
    /// End − start height, m, and 3-D end − start distance, m.
    pub height_before_m: f64,
    pub height_after_m: f64,
    pub closure_before_m: f64,
    pub closure_after_m: f64,
    /// Each stance's time (s after the walk's first estimate) and mean height above
    /// the first stance's (m): with the starting alignment, fitted.
    pub stances_before: Vec<(f64, f64)>,
    pub stances_after: Vec<(f64, f64)>,
}

/// The learned alignment.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelFit {
    /// The starting alignment with its y component (about the body's lateral axis)
    /// fitted.
    pub alignment_rad: [f64; 3],
    pub walks: Vec<WalkFit>,
    pub iterations: usize,
}

struct Problem<'a> {
    base: &'a FootConfig,
    walks: &'a [(String, Vec<FootSample>)],
    stances: Vec<Vec<Stance>>,
}

impl Problem<'_> {
    fn config(&self, a: [f64; 3]) -> FootConfig {
        FootConfig {
            accel_alignment_rad: a,
            ..self.base.clone()
        }
    }

    /// Height-change residuals of every walk, then the prior's.
    fn residuals(&self, a: [f64; 3]) -> Result<Vec<f64>, String> {
        let config = self.config(a);
        let mut out = Vec::new();
        for ((_, samples), st) in self.walks.iter().zip(&self.stances) {
            let r = replay(&config, samples)?;
            let h = heights(&r, st);
            out.push(h[h.len() - 1] - h[0]);
        }
        out.push(a[1] / PRIOR_SIGMA_RAD * RESIDUAL_SCALE_M);
        Ok(out)
    }
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Fit the accelerometer alignment about the body's lateral axis that makes every
/// stance of `walks` level, starting from `base` (its own `accel_alignment_rad` is the
/// starting point; its x and z components are kept). `walks`: name
/// and samples of each walk; each must start with the navigator's alignment rest.
pub fn learn(base: &FootConfig, walks: &[(String, Vec<FootSample>)]) -> Result<LevelFit, String> {
    if walks.is_empty() {
        return Err("no walk given".into());
    }
    // The filter's own heights: the level-floor constraint would hide the climb the
    // fit measures (and the figures before and after are without it too).
    let base = &FootConfig {
        level_stride_max_grade: None,
        ..base.clone()
    };
    let (before, stance_sets) = replay_walks(base, walks)?;
    let p = Problem {
        base,
        walks,
        stances: stance_sets,
    };
    let (a, iterations) = fit_lateral(&p)?;
    let after_config = p.config(a);
    let fits = walks
        .iter()
        .zip(&p.stances)
        .zip(&before)
        .map(|(((name, samples), st), b)| walk_fit(&after_config, name, samples, st, b))
        .collect::<Result<Vec<_>, String>>()?;
    Ok(LevelFit {
        alignment_rad: a,
        walks: fits,
        iterations,
    })
}

/// Every walk replayed with `base`, and its stances (at least 4 each).
fn replay_walks(
    base: &FootConfig,
    walks: &[(String, Vec<FootSample>)],
) -> Result<(Vec<Replay>, Vec<Vec<Stance>>), String> {
    let mut stance_sets = Vec::new();
    let mut before = Vec::new();
    for (name, samples) in walks {
        let r = replay(base, samples).map_err(|e| format!("{name}: {e}"))?;
        let st = stances(&r);
        if st.len() < 4 {
            return Err(format!(
                "{name}: {} stances of at least {MIN_STANCE_S} s found; a level walk of \
                 a few strides is needed",
                st.len()
            ));
        }
        before.push(r);
        stance_sets.push(st);
    }
    Ok((before, stance_sets))
}

/// The alignment (and the iterations) by Gauss–Newton on one angle: about the body's
/// lateral axis (y). A tilt about it is what leaks the swing's forward acceleration
/// into the vertical; a turn about the forward axis leaks the small lateral
/// accelerations (barely seen in the heights), one about the vertical none (invisible
/// to them): fitting those too only fits noise (measured on x-io's walks: 2–4° about x
/// and z, the horizontal closure spoiled).
fn fit_lateral(p: &Problem) -> Result<([f64; 3], usize), String> {
    let start = p.base.accel_alignment_rad;
    let at = |y: f64| [start[0], y, start[2]];
    let mut y = start[1];
    let mut r = p.residuals(at(y))?;
    let mut cost = sum_sq(&r);
    let mut iterations = 0;
    for _ in 0..MAX_ITERATIONS {
        iterations += 1;
        let (rh, rl) = (
            p.residuals(at(y + STEP_RAD))?,
            p.residuals(at(y - STEP_RAD))?,
        );
        let j: Vec<f64> = rh
            .iter()
            .zip(&rl)
            .map(|(h, l)| (h - l) / (2.0 * STEP_RAD))
            .collect();
        let jtj: f64 = j.iter().map(|v| v * v).sum();
        let g: f64 = j.iter().zip(&r).map(|(a, b)| a * b).sum();
        if jtj.is_nan() || jtj <= 0.0 {
            break;
        }
        // Gauss–Newton step, halved until the cost falls.
        let mut step = -g / jtj;
        let mut moved = false;
        for _ in 0..8 {
            let cand = (y + step).clamp(-MAX_ACCEL_ALIGNMENT_RAD, MAX_ACCEL_ALIGNMENT_RAD);
            let rc = p.residuals(at(cand))?;
            let cc = sum_sq(&rc);
            if cc < cost {
                moved = (cand - y).abs() > 1e-6;
                y = cand;
                r = rc;
                cost = cc;
                break;
            }
            step *= 0.5;
        }
        if !moved {
            break;
        }
    }
    Ok((at(y), iterations))
}

/// One walk before (`b`) and after the fit (replayed with `after_config`).
fn walk_fit(
    after_config: &FootConfig,
    name: &str,
    samples: &[FootSample],
    st: &[Stance],
    b: &Replay,
) -> Result<WalkFit, String> {
    let after = replay(after_config, samples)?;
    Ok(WalkFit {
        name: name.to_string(),
        steps: st.len() - 1,
        distance_m: after.distance_m,
        rms_before_m: stride_rms(b, st),
        rms_after_m: stride_rms(&after, st),
        height_before_m: b.end_m[2] - b.start_m[2],
        height_after_m: after.end_m[2] - after.start_m[2],
        closure_before_m: closure(b),
        closure_after_m: closure(&after),
        stances_before: stance_series(b, st),
        stances_after: stance_series(&after, st),
    })
}

/// RMS of the stance-to-stance height changes, m.
fn stride_rms(r: &Replay, st: &[Stance]) -> f64 {
    let h = heights(r, st);
    let d: Vec<f64> = h.windows(2).map(|w| w[1] - w[0]).collect();
    (sum_sq(&d) / d.len().max(1) as f64).sqrt()
}

/// Distance from the start to the end, m.
fn closure(r: &Replay) -> f64 {
    let d: Vec<f64> = (0..3).map(|k| r.end_m[k] - r.start_m[k]).collect();
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Each stance's time since the start and height above the first, (s, m).
fn stance_series(r: &Replay, st: &[Stance]) -> Vec<(f64, f64)> {
    let h = heights(r, st);
    st.iter()
        .zip(&h)
        .map(|(s, z)| {
            (
                r.t_s.get(s.start).map_or(f64::NAN, |t| t - r.t_s[0]),
                z - h[0],
            )
        })
        .collect()
}

/// The calibration file's text for `alignment_rad`.
pub fn to_text(alignment_rad: [f64; 3], comment: &str) -> String {
    let mut s = format!("{HEADER}\n");
    for line in comment.lines() {
        s += &format!("# {line}\n");
    }
    s += &format!(
        "accel_alignment_rad {:.6} {:.6} {:.6}\n",
        alignment_rad[0], alignment_rad[1], alignment_rad[2]
    );
    s
}

/// Parse a foot calibration file: the header line, then exactly one
/// `accel_alignment_rad X Y Z` record (rad, each within ±0.1); blank lines and `#`
/// comments are ignored; anything else is an error naming the line.
pub fn parse(text: &str) -> Result<[f64; 3], String> {
    if text.len() > 64 * 1024 {
        return Err("larger than 64 KiB: not a foot calibration file".into());
    }
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    match lines.next() {
        Some((_, HEADER)) => {}
        Some((n, l)) if l.starts_with("stridekit-foot-calibration") => {
            return Err(format!(
                "line {n}: unsupported version `{l}` (this build reads `{HEADER}`)"
            ))
        }
        _ => return Err(format!("not a foot calibration file (no `{HEADER}` line)")),
    }
    let mut alignment = None;
    for (n, l) in lines {
        let mut f = l.split_whitespace();
        match f.next() {
            Some("accel_alignment_rad") => {
                if alignment.is_some() {
                    return Err(format!("line {n}: accel_alignment_rad given twice"));
                }
                let v: Vec<f64> = f
                    .map(|x| x.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| format!("line {n}: accel_alignment_rad needs three numbers"))?;
                let [x, y, z] = v[..] else {
                    return Err(format!("line {n}: accel_alignment_rad needs three numbers"));
                };
                if ![x, y, z].iter().all(|a| a.abs() <= MAX_ACCEL_ALIGNMENT_RAD) {
                    return Err(format!(
                        "line {n}: each angle must be finite and within ±{MAX_ACCEL_ALIGNMENT_RAD} rad"
                    ));
                }
                alignment = Some([x, y, z]);
            }
            Some(other) => return Err(format!("line {n}: unknown record `{other}`")),
            None => {}
        }
    }
    alignment.ok_or_else(|| "no accel_alignment_rad record".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn learns_a_misaligned_accelerometer_back_from_a_level_walk() {
        // The simulated IMU's accelerometer turned by 1.2° about the lateral axis
        // against its gyroscope: the height drifts; the fit finds the angle and the
        // walk ends at the height it started.
        let truth = 0.021;
        let mut sim = stridekit_sim::simulate_foot(&stridekit_sim::FootScenario::walk(5, 2));
        let back = nalgebra::Rotation3::new(nalgebra::Vector3::new(0.0, -truth, 0.0));
        for s in &mut sim.samples {
            s.accel_mps2 = (back * nalgebra::Vector3::from(s.accel_mps2)).into();
        }
        let fit = learn(&FootConfig::default(), &[("sim".into(), sim.samples)]).unwrap();
        assert_eq!(fit.alignment_rad[0], 0.0);
        assert_eq!(fit.alignment_rad[2], 0.0);
        assert!(
            (fit.alignment_rad[1] - truth).abs() < 0.003,
            "learned {} rad, applied {truth}",
            fit.alignment_rad[1]
        );
        let w = &fit.walks[0];
        assert!(w.height_before_m.abs() > 0.1, "{w:?}");
        assert!(
            w.height_after_m.abs() < 0.2 * w.height_before_m.abs(),
            "{w:?}"
        );
        assert!(learn(&FootConfig::default(), &[]).is_err());
    }

    #[test]
    fn text_round_trips_and_bad_files_are_refused() {
        let a = [0.001, -0.0235, 0.0004];
        let text = to_text(a, "learned from walk.csv");
        assert_eq!(parse(&text).unwrap(), a);
        assert!(parse("").is_err());
        assert!(
            parse("stridekit-foot-calibration 2\naccel_alignment_rad 0 0 0\n")
                .unwrap_err()
                .contains("version")
        );
        assert!(parse(&format!("{HEADER}\n")).is_err());
        assert!(parse(&format!("{HEADER}\naccel_alignment_rad 0 0\n")).is_err());
        assert!(parse(&format!("{HEADER}\naccel_alignment_rad 0 0 NaN\n")).is_err());
        assert!(parse(&format!("{HEADER}\naccel_alignment_rad 0 0.2 0\n")).is_err());
        assert!(parse(&format!("{HEADER}\nfoo 1\n")).is_err());
        assert!(parse(&format!(
            "{HEADER}\naccel_alignment_rad 0 0 0\naccel_alignment_rad 0 0 0\n"
        ))
        .is_err());
        assert_eq!(
            parse(&format!(
                "# c\n{HEADER}\n\n# c\naccel_alignment_rad 0 0 0.05\n"
            ))
            .unwrap(),
            [0.0, 0.0, 0.05]
        );
    }
}
