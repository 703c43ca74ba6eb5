//! `stridekit eval foot --diagnose`: where the foot navigator's error comes from on
//! the VICON trials, measured per stride against the truth.
//!
//! Per trial, for the stances of the oracle labels that last ≥ 0.1 s (walking
//! stances), the stance mid-points; a stride is the move between two consecutive
//! mid-points with ≥ 0.5 m of true horizontal travel. Reported:
//! - stride-length ratio: Σ estimated / Σ true horizontal stride lengths (1 = right,
//!   below 1 = the navigator's strides are short);
//! - height error per stride: mean of (estimated − true) height change per stride
//!   (the floors are flat, so this is the vertical drift);
//! - the horizontal RMSE (as in the main tables), per session and overall.
//!
//! For the oracle labels and the default detector, each with both gyro-timing
//! models ([`GyroTiming`]), with the level floor off (the filter's own heights), and
//! the default detector with the level floor on as shipped
//! ([`FootConfig::level_stride_max_grade`]).

use std::path::Path;

use stridekit_core::foot::{FootConfig, GyroTiming};

use crate::foot::eval::{base_config, load_with_info, median, replay, score, Method, Trial};
use crate::foot::sessions::session_of;

struct PerTrial {
    session: String,
    h: f64,
    ratio: f64,
    dz_per_stride_m: f64,
}

fn per_trial(t: &Trial, m: &Method) -> Result<PerTrial, String> {
    let est = replay(t, m)?;
    let o = score(t, &est);
    let truth = t.rec.truth_m.as_ref().ok_or("no truth")?;
    let lab = t
        .rec
        .label(&t.best)
        .ok_or_else(|| format!("{}: no label {}", t.rec.name, t.best))?;
    let mut mids = Vec::new();
    let mut i = 0;
    while i < lab.len() {
        if lab[i] {
            let a = i;
            while i < lab.len() && lab[i] {
                i += 1;
            }
            if t.rec.t_s[i - 1] - t.rec.t_s[a] >= 0.1 {
                mids.push((a + i) / 2);
            }
        } else {
            i += 1;
        }
    }
    let at: std::collections::HashMap<usize, usize> =
        est.iter().enumerate().map(|(j, (k, _))| (*k, j)).collect();
    let (mut se, mut sg, mut dz, mut n) = (0.0, 0.0, 0.0, 0usize);
    for w in mids.windows(2) {
        let (Some(&ja), Some(&jb)) = (at.get(&w[0]), at.get(&w[1])) else {
            continue;
        };
        let (ea, eb) = (est[ja].1.position_m, est[jb].1.position_m);
        let (ga, gb) = (truth[w[0]], truth[w[1]]);
        let lg = (gb[0] - ga[0]).hypot(gb[1] - ga[1]);
        if lg < 0.5 {
            continue;
        }
        se += (eb[0] - ea[0]).hypot(eb[1] - ea[1]);
        sg += lg;
        dz += (eb[2] - ea[2]) - (gb[2] - ga[2]);
        n += 1;
    }
    Ok(PerTrial {
        session: session_of(&t.rec.name).to_string(),
        h: o.rmse_h_m,
        ratio: if sg > 0.0 { se / sg } else { f64::NAN },
        dz_per_stride_m: if n > 0 { dz / n as f64 } else { f64::NAN },
    })
}

pub fn run(dir: &Path) -> Result<String, String> {
    let trials: Vec<Trial> = load_with_info(dir)?.into_iter().map(|(t, _)| t).collect();
    let mut sessions: Vec<String> = trials
        .iter()
        .map(|t| session_of(&t.rec.name).to_string())
        .collect();
    sessions.dedup();
    let mut out = String::from(
        "Per-stride diagnosis (oracle walking stances ≥ 0.1 s, strides ≥ 0.5 m): stride-length ratio estimated / true, height error per stride, and the median horizontal RMSE per session. The level floor is off except where the run says so: the height error is the filter's own.\n\n| run | stride-length ratio (median of trials) | height error per stride mm (median) | horizontal RMSE m, all |",
    );
    for s in &sessions {
        out.push_str(&format!(" {s} |"));
    }
    out.push_str("\n|---|---|---|---|");
    for _ in &sessions {
        out.push_str("---|");
    }
    out.push('\n');
    // The filter's own heights (the level floor off), then the shipped default with it.
    let level = base_config().level_stride_max_grade;
    let mut runs = Vec::new();
    for (labels, lname) in [(Some("best"), "oracle labels"), (None, "default detector")] {
        for (timing, tname) in [
            (GyroTiming::Instantaneous, "gyro instantaneous"),
            (
                GyroTiming::IntervalMean,
                "gyro interval mean (device profile)",
            ),
        ] {
            runs.push((labels, lname, timing, tname.to_string(), None));
        }
    }
    runs.push((
        None,
        "default detector",
        GyroTiming::IntervalMean,
        "gyro interval mean (device profile), level floor (the default)".into(),
        level,
    ));
    for (labels, lname, timing, tname, level) in runs {
        let m = Method {
            name: lname.into(),
            config: FootConfig {
                gyro_timing: timing,
                level_stride_max_grade: level,
                ..base_config()
            },
            labels: labels.map(String::from),
        };
        let rows = trials
            .iter()
            .map(|t| per_trial(t, &m))
            .collect::<Result<Vec<_>, _>>()?;
        out.push_str(&format!(
            "| {lname}, {tname} | {:.4} | {:+.1} | {:.3} |",
            median(rows.iter().map(|r| r.ratio).collect::<Vec<f64>>()),
            1000.0 * median(rows.iter().map(|r| r.dz_per_stride_m).collect::<Vec<f64>>()),
            median(rows.iter().map(|r| r.h).collect::<Vec<f64>>()),
        ));
        for s in &sessions {
            out.push_str(&format!(
                " {:.3} |",
                median(
                    rows.iter()
                        .filter(|r| &r.session == s)
                        .map(|r| r.h)
                        .collect::<Vec<f64>>()
                )
            ));
        }
        out.push('\n');
    }
    Ok(out)
}
