//! `stridekit eval foot --detector-gap`: where the default zero-velocity detector
//! departs from each trial's oracle stance labels and what it costs (the navigator of
//! `eval foot` through `push_with_stance`), as recorded and on time-stretched copies.

use std::path::Path;

use stridekit_core::foot::{AdaptiveShoe, FootEstimate, FootNavigator, FootSample, WindowStats};
use stridekit_sim::Rng;

use crate::foot::eval::{base_config, load_with_info, median, score, GaitClass, Trial};
use crate::perturb::imu::perturb;
use crate::perturb::Perturbation;

/// A mismatch within this many samples (25 ms at 200 Hz) of an oracle stance edge is
/// an edge error; further in, a stance or swing called wrong.
pub const EDGE_SAMPLES: usize = 5;

/// Multipliers of the default threshold tried per trial (the best of them per trial
/// bounds what any single threshold adaptation could gain).
pub const SCALES: [f64; 4] = [0.5, 0.7, 1.4, 2.0];

/// Time-stretch factors of the summary (the bench's `walking speed` perturbation).
pub const SPEEDS: [f64; 2] = [0.85, 1.2];

/// One trial as a sample stream, with the recording index each sample stands for.
struct Stream {
    samples: Vec<FootSample>,
    src: Vec<usize>,
}

fn stream(trial: &Trial, speed: Option<f64>) -> Result<Stream, String> {
    let rec = &trial.rec;
    let Some(factor) = speed else {
        return Ok(Stream {
            samples: (0..rec.len())
                .map(|i| crate::foot::eval::foot_sample(rec, i))
                .collect(),
            src: (0..rec.len()).collect(),
        });
    };
    let imu = crate::perturb::foot::imu_of(trial)?;
    let p = perturb(&imu, &Perturbation::Speed { factor }, &mut Rng::new(1))
        .ok_or("time stretch needs gravity per sample")?;
    let p = crate::perturb::foot::within_range(p, &imu);
    Ok(Stream {
        samples: (0..p.len())
            .map(|k| FootSample {
                t_s: p.t_s[k],
                accel_mps2: p.accel[k],
                gyro_rads: p.gyro[k],
            })
            .collect(),
        src: (0..p.len()).map(|k| p.source_index(k)).collect(),
    })
}

/// The detector statistics per sample of the stream (`None` before alignment).
fn window_stats(s: &Stream) -> Result<Vec<Option<WindowStats>>, String> {
    let mut nav = FootNavigator::new(base_config()).map_err(|e| e.to_string())?;
    let mut out = vec![None; s.samples.len()];
    for x in &s.samples {
        if let Ok(Some(e)) = nav.push(x) {
            let k = s.samples.partition_point(|y| y.t_s < e.t_s);
            if let Some(o) = out.get_mut(k) {
                *o = nav.detector_stats();
            }
        }
    }
    Ok(out)
}

/// The navigator on the stream with these stance flags; estimates carry the
/// recording index.
fn replay(s: &Stream, stance: &[bool]) -> Result<Vec<(usize, FootEstimate)>, String> {
    let mut nav = FootNavigator::new(base_config()).map_err(|e| e.to_string())?;
    let mut est = Vec::with_capacity(s.samples.len());
    for (x, &st) in s.samples.iter().zip(stance) {
        if let Ok(Some(e)) = nav.push_with_stance(x, st) {
            let k = s.samples.partition_point(|y| y.t_s < e.t_s);
            est.push((s.src[k.min(s.src.len() - 1)], e));
        }
    }
    Ok(est)
}

/// Stance flags of the default detector with its threshold × `scale`, the
/// stillness floor on or off. Before alignment: stance (the start rest).
fn flags(stats: &[Option<WindowStats>], scale: f64, floor: bool) -> Vec<bool> {
    let d = AdaptiveShoe::default();
    stats
        .iter()
        .map(|s| {
            s.is_none_or(|s| {
                let s = if floor {
                    s
                } else {
                    WindowStats {
                        still_acc_ms2_sq: 0.0,
                        still_gyro_rads_sq: 0.0,
                        ..s
                    }
                };
                if scale == 1.0 {
                    d.is_stance(&s)
                } else {
                    d.shoe.statistic(&s) < scale * d.threshold(&s)
                }
            })
        })
        .collect()
}

/// Runs of `true`: `[start, end)`.
pub fn segments(flags: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &x) in flags.iter().enumerate() {
        match (x, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, flags.len()));
    }
    out
}

/// How a detector's flags differ from the reference's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Mismatch {
    /// Reference stance called swing, within [`EDGE_SAMPLES`] of a reference edge / further in.
    pub missed_edge: usize,
    pub missed_inside: usize,
    /// Reference swing called stance, likewise.
    pub false_edge: usize,
    pub false_inside: usize,
    /// Reference stances, and those with no detector stance sample at all.
    pub stances: usize,
    pub stances_missed: usize,
    /// Detector stances, and those with no reference stance sample at all.
    pub detected: usize,
    pub detected_false: usize,
    /// Median stance length, samples: reference, detector.
    pub length_ref: f64,
    pub length_det: f64,
    /// Median over reference stances of (first overlapping detector stance start −
    /// reference start) and (last overlapping detector stance end − reference end),
    /// samples: negative onset = the detector starts early, positive offset = it ends late.
    pub onset_lag: f64,
    pub offset_lag: f64,
}

/// Compare detector flags with reference flags of the same samples.
pub fn mismatch(reference: &[bool], det: &[bool]) -> Mismatch {
    let edges: Vec<usize> = (1..reference.len())
        .filter(|&i| reference[i] != reference[i - 1])
        .collect();
    let near_edge = |i: usize| {
        let j = edges.partition_point(|&e| e < i);
        let before = j.checked_sub(1).map_or(usize::MAX, |j| i - edges[j]);
        let after = edges.get(j).map_or(usize::MAX, |&e| e - i);
        before.min(after) <= EDGE_SAMPLES
    };
    let mut m = Mismatch::default();
    for (i, (&r, &d)) in reference.iter().zip(det).enumerate() {
        let slot = match (r, d, near_edge(i)) {
            (true, false, true) => &mut m.missed_edge,
            (true, false, false) => &mut m.missed_inside,
            (false, true, true) => &mut m.false_edge,
            (false, true, false) => &mut m.false_inside,
            _ => continue,
        };
        *slot += 1;
    }
    let rs = segments(reference);
    let ds = segments(det);
    m.stances = rs.len();
    m.detected = ds.len();
    m.stances_missed = rs
        .iter()
        .filter(|&&(a, b)| !det[a..b].contains(&true))
        .count();
    m.detected_false = ds
        .iter()
        .filter(|&&(a, b)| !reference[a..b].contains(&true))
        .count();
    let len = |s: &[(usize, usize)]| median(s.iter().map(|&(a, b)| (b - a) as f64));
    m.length_ref = len(&rs);
    m.length_det = len(&ds);
    let (mut on, mut off) = (Vec::new(), Vec::new());
    for &(a, b) in &rs {
        let over: Vec<&(usize, usize)> = ds.iter().filter(|&&(c, e)| c < b && e > a).collect();
        if let (Some(first), Some(last)) = (over.first(), over.last()) {
            on.push(first.0 as f64 - a as f64);
            off.push(last.1 as f64 - b as f64);
        }
    }
    m.onset_lag = median(on);
    m.offset_lag = median(off);
    m
}

/// Horizontal and 3-D RMSE of one run, m.
type Errors = (f64, f64);

struct TrialRow {
    name: String,
    gait: &'static str,
    default: Errors,
    no_floor: Errors,
    oracle: Errors,
    scaled: Vec<Errors>,
    mismatch: Mismatch,
}

/// The runs of one trial (at one speed).
fn measure(trial: &Trial, speed: Option<f64>) -> Result<(Vec<Errors>, Mismatch), String> {
    let s = stream(trial, speed)?;
    let stats = window_stats(&s)?;
    let labels = trial
        .rec
        .label(&trial.best)
        .ok_or_else(|| format!("{}: no label column {}", trial.rec.name, trial.best))?;
    let oracle: Vec<bool> = s.src.iter().map(|&i| labels[i]).collect();
    let run = |f: &[bool]| -> Result<Errors, String> {
        let mut est = replay(&s, f)?;
        est.retain(|(i, _)| *i < trial.rec.len());
        let o = score(trial, &est);
        Ok((o.rmse_h_m, o.rmse_m))
    };
    let own = flags(&stats, 1.0, true);
    // Order: default, floor off, oracle, then SCALES.
    let mut errors = vec![run(&own)?, run(&flags(&stats, 1.0, false))?, run(&oracle)?];
    for k in SCALES {
        errors.push(run(&flags(&stats, k, true))?);
    }
    Ok((errors, mismatch(&oracle, &own)))
}

fn f3((h, d): Errors) -> String {
    format!("{h:.3} / {d:.3}")
}

/// Median horizontal, worst horizontal and median 3-D over trials of column `c`.
fn summary(rows: &[Vec<Errors>], c: usize) -> String {
    let h = median(rows.iter().map(|r| r[c].0));
    let worst = rows.iter().map(|r| r[c].0).fold(0.0, f64::max);
    let d = median(rows.iter().map(|r| r[c].1));
    format!("{h:.3} / {worst:.3} / {d:.3}")
}

/// The per-trial best of the default and the scaled thresholds (a bound, not a detector).
fn best_scale(r: &[Errors]) -> Errors {
    std::iter::once(r[0]).chain(r[3..].iter().copied()).fold(
        (f64::INFINITY, f64::INFINITY),
        |a, b| if b.0 < a.0 { b } else { a },
    )
}

pub fn run(dir: &Path) -> Result<String, String> {
    let trials = load_with_info(dir)?;
    if trials.is_empty() {
        return Err(format!("{}: no foot trials to compare", dir.display()));
    }
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    for (t, info) in &trials {
        let (e, m) = measure(t, None)?;
        rows.push(TrialRow {
            name: t.rec.name.clone(),
            gait: info.kind.unwrap_or(GaitClass::Walk).name(),
            default: e[0],
            no_floor: e[1],
            oracle: e[2],
            scaled: e[3..].to_vec(),
            mismatch: m,
        });
        errors.push(e);
    }
    let mut out = format!(
        "Zero-velocity detector against the oracle labels on {} trials of {} (the navigator of `eval foot`, every run through `push_with_stance`). Errors: horizontal / 3-D RMSE after the best rotation about the vertical + translation, m. Samples missed (oracle stance, detector swing) and false (oracle swing, detector stance), at an edge = within {EDGE_SAMPLES} samples of an oracle stance edge. Stance lengths and lags in samples (200 Hz); onset < 0: the detector's stance starts early, offset > 0: it ends late.\n\n",
        trials.len(),
        dir.display()
    );
    out.push_str("| trial | gait | default | oracle labels | stillness floor off | threshold × 0.5 | × 0.7 | × 1.4 | × 2 | missed edge / inside | false edge / inside | oracle stances (missed whole) | detector stances (false whole) | stance length oracle / detector | onset / offset lag |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in &rows {
        let m = &r.mismatch;
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} / {} | {} / {} | {} ({}) | {} ({}) | {:.0} / {:.0} | {:+.0} / {:+.0} |\n",
            r.name,
            r.gait,
            f3(r.default),
            f3(r.oracle),
            f3(r.no_floor),
            r.scaled.iter().map(|&e| f3(e)).collect::<Vec<_>>().join(" | "),
            m.missed_edge,
            m.missed_inside,
            m.false_edge,
            m.false_inside,
            m.stances,
            m.stances_missed,
            m.detected,
            m.detected_false,
            m.length_ref,
            m.length_det,
            m.onset_lag,
            m.offset_lag,
        ));
    }
    out.push_str("\nSummary: median horizontal / worst horizontal / median 3-D RMSE over the trials, m. Time-stretched copies as the perturbation bench makes them (`eval perturb --engine foot`, walking speed; oracle labels carried over from the recording).\n\n| run | as recorded |");
    let mut by_speed = vec![errors];
    for sp in SPEEDS {
        out.push_str(&format!(" speed × {sp} |"));
        by_speed.push(
            trials
                .iter()
                .map(|(t, _)| measure(t, Some(sp)).map(|(e, _)| e))
                .collect::<Result<Vec<_>, String>>()?,
        );
    }
    out.push_str("\n|---|---|");
    for _ in SPEEDS {
        out.push_str("---|");
    }
    out.push('\n');
    let mut names = vec![
        "default detector".to_string(),
        "stillness floor off".to_string(),
        "oracle labels".to_string(),
    ];
    names.extend(SCALES.iter().map(|k| format!("threshold × {k}")));
    for (c, n) in names.iter().enumerate() {
        out.push_str(&format!("| {n} |"));
        for e in &by_speed {
            out.push_str(&format!(" {} |", summary(e, c)));
        }
        out.push('\n');
    }
    out.push_str("| best scale per trial (of × 0.5–2; a bound, not a detector) |");
    for e in &by_speed {
        let best: Vec<Vec<Errors>> = e.iter().map(|r| vec![best_scale(r)]).collect();
        out.push_str(&format!(" {} |", summary(&best, 0)));
    }
    out.push('\n');
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_without_trials_is_refused() {
        let dir = std::env::temp_dir().join(format!("stridekit-gap-empty-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let r = run(&dir);
        std::fs::remove_dir_all(&dir).ok();
        assert!(r.unwrap_err().contains("no foot trials"));
    }

    #[test]
    fn segments_are_the_runs_of_true() {
        let f = [true, true, false, false, true, false, true];
        assert_eq!(segments(&f), vec![(0, 2), (4, 5), (6, 7)]);
        assert!(segments(&[false, false]).is_empty());
    }

    #[test]
    fn mismatch_tells_edges_from_whole_stances() {
        // Reference: two stances of 20 samples in swings of 30.
        let mut r = vec![false; 100];
        r[30..50].fill(true);
        r[80..100].fill(true);
        // Detector: the first stance 3 samples early and 2 late, the second missed,
        // and a stance of its own in the middle of a swing.
        let mut d = vec![false; 100];
        d[27..52].fill(true);
        d[62..66].fill(true);
        let m = mismatch(&r, &d);
        assert_eq!((m.false_edge, m.false_inside), (5, 4));
        assert_eq!(m.missed_edge + m.missed_inside, 20);
        assert_eq!((m.stances, m.stances_missed), (2, 1));
        assert_eq!((m.detected, m.detected_false), (2, 1));
        assert_eq!((m.onset_lag, m.offset_lag), (-3.0, 2.0));
    }
}
