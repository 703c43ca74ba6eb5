//! `stridekit eval foot`: the foot-mounted navigator on the pyshoe / UofT VICON trials
//! (foot IMU at 200 Hz with motion-capture truth), every zero-velocity detector with
//! one configuration for all trials, next to the same filter driven by the data set's
//! per-trial optimised stance labels (an oracle no causal detector has).
//!
//! Splits. Trials are sorted by name; even positions (0, 2, 4, …) are the TRAINING
//! split on which the detector defaults were chosen (`eval foot --tune`), odd
//! positions the HELD-OUT split. The SVM is cross-validated: `SVM_FOLDS` folds by
//! position modulo `SVM_FOLDS`; each trial is detected by a model trained (same code
//! as `stridekit train zupt`) on the other folds only.
//!
//! Gait. Per sample, from the truth: the foot's horizontal path over ±0.5 s (one
//! stride) divided by 1 s; above [`RUN_SPEED_MPS`] the sample is running, otherwise
//! walking. The stairs and crawling session (trials named [`OTHER_PREFIX`]*; the data
//! confirm it: truth height range 0.6–0.7 m on three of them, a foot upside down at
//! rest — stance tilt ~155° — on the crawling ones, and mean horizontal speed
//! ≤ 0.33 m/s on all) is "other" in every sample. A trial's gait is its samples'
//! majority. The table prints the height range, stance tilt and mean speed.

use std::path::Path;

use stridekit_core::foot::{
    AdaptiveShoe, AdaptiveThresholds, Correction, FixedThresholds, FootConfig, FootEstimate,
    FootNavigator, FootSample, GyroCeiling, ShoeDetector, SvmAdaptive, WindowStats,
    ZeroVelocityDetector,
};
use stridekit_core::vec3::norm;
use stridekit_formats::{list_foot_trials, read_foot_csv, FootRecording};

use crate::foot::sessions::Loso;
use crate::foot::train_zupt;
use crate::table::Table as TextTable;

/// Foot speed averaged over one stride above which a sample is running, m/s.
pub const RUN_SPEED_MPS: f64 = 1.8;
/// The recording session of stairs and crawling trials ("other").
pub const OTHER_PREFIX: &str = "2018-02-";
/// Folds of the SVM cross-validation.
pub const SVM_FOLDS: usize = 6;

#[derive(Clone, Debug)]
pub struct Method {
    pub name: String,
    pub config: FootConfig,
    /// Drive the updates with this label column of the file instead of the detector;
    /// `"best"` means the column of the trial's best detector in `_summary.csv`.
    pub labels: Option<String>,
}

/// Gait of a sample (or, by majority, of a trial).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GaitClass {
    Walk = 0,
    Run = 1,
    Other = 2,
}

impl GaitClass {
    pub fn name(self) -> &'static str {
        ["walk", "run", "other"][self as usize]
    }
}

/// What one method did on one trial.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outcome {
    /// Position RMSE against truth after the best rotation about the vertical and
    /// translation, m.
    pub rmse_m: f64,
    /// The same fit, horizontal components only (the aligned horizontal RMSE), m.
    pub rmse_h_m: f64,
    /// |(estimated − true) start→end displacement| / path length, %, 3-D.
    pub closure_pct: f64,
    /// The same, horizontal only (the usual gait-tracker figure), %.
    pub closure_h_pct: f64,
    /// Fraction of samples whose stance flag equals the reference labels, %.
    pub zv_accuracy_pct: f64,
    /// Per sample gait (walk, run, other): samples agreeing with the reference labels
    /// and samples.
    pub zv_agree: [usize; 3],
    pub zv_total: [usize; 3],
    /// Samples called stance where the reference says swing, per gait.
    pub false_stance: [usize; 3],
    pub strides: u64,
    pub distance_m: f64,
    /// pyshoe's published metric (`process_error_vicon.py`): both tracks shifted to
    /// start at 0, the estimate rotated about the vertical so that its position at
    /// the first sample 0.8 m from the start points the same way as the truth's, then
    /// the mean over samples of the RMS over the two horizontal axes (‖e‖/√2), m.
    pub armse_2d_m: f64,
}

#[derive(Clone, Debug)]
pub struct Trial {
    pub rec: FootRecording,
    /// Label column of the best detector (reference for the zero-velocity accuracy).
    pub best: String,
    /// Label column of the detector with the second-lowest pyshoe error (another
    /// per-trial optimum: how far two oracles agree bounds any agreement figure).
    pub runner_up: Option<String>,
    /// pyshoe's own filter on the best labels (`best_error_m` of `_summary.csv`,
    /// same metric as [`Outcome::armse_2d_m`]), m.
    pub pyshoe_best_m: Option<f64>,
    /// The trial's majority gait is running (the evaluation itself reads
    /// [`TrialInfo`]; kept for callers such as `stridekit foot`).
    #[allow(dead_code)]
    pub run: bool,
    pub path_m: f64,
}

/// What the truth says about a trial beyond [`Trial`].
#[derive(Clone, Debug, Default)]
pub struct TrialInfo {
    /// Per sample gait.
    pub gait: Vec<Option<GaitClass>>,
    /// Majority gait.
    pub kind: Option<GaitClass>,
    pub z_range_m: f64,
    pub mean_speed_mps: f64,
    /// Angle between the sensor's down axis and the mean specific force while the
    /// foot is still (‖ω‖ < 0.3 rad/s), deg: ~15–27° on foot, ~155° crawling.
    pub stance_tilt_deg: f64,
    pub run_fraction: f64,
    /// The truth as recorded (before `mirror_truth`), for the mirror check.
    pub raw_truth: Vec<[f64; 3]>,
}

impl TrialInfo {
    fn kind(&self) -> GaitClass {
        self.kind.unwrap_or(GaitClass::Walk)
    }
}

pub fn base_config() -> FootConfig {
    FootConfig {
        axis_remap: FootConfig::pyshoe_axes(),
        gyro_range_rads: Some(UOFT_GYRO_RANGE_RADS),
        ..FootConfig::calibrated_imu()
    }
}

/// The gyroscope range of the UofT data set's MicroStrain, rad/s, as its data show it:
/// on 10 of the 35 walking and running trials the pitch rate (sensor y) stops at a
/// plateau of 9.12–9.22 rad/s (its largest magnitude, held by 4–48 samples within
/// 0.05 rad/s of it), so the ceiling is about 9.13 rad/s ≈ 99 % of 9.2 rad/s. A
/// property of the device read off the raw samples, like a data sheet's range, not a
/// fitted setting (docs/lab/2026-12-06-foot-history.md, "Gyroscope clipping"). The evaluation gives it to
/// every trial (one device); [`GyroCeilings`] prints what the ceiling detector
/// finds per trial beside it. `stridekit foot` does not assume it: it detects.
pub const UOFT_GYRO_RANGE_RADS: f64 = 9.2;

/// What the ceiling detector (`GyroCeilingDetector`) finds on the trials: per trial,
/// and over all trials as one device.
#[derive(Clone, Debug, Default)]
pub struct GyroCeilings {
    pub trials: usize,
    /// The lowest ceiling of each trial that shows clipping.
    pub per_trial: Vec<GyroCeiling>,
    /// Every axis and sign with a ceiling, all trials as one device.
    pub pooled: Vec<GyroCeiling>,
}

impl GyroCeilings {
    pub fn find(trials: &[Trial]) -> Self {
        use crate::foot::device::evidence;
        let per_trial = trials
            .iter()
            .filter_map(|t| evidence(&[&t.rec]).ceiling)
            .collect();
        let all = evidence(&trials.iter().map(|t| &t.rec).collect::<Vec<_>>());
        Self {
            trials: trials.len(),
            per_trial,
            pooled: all.ceilings,
        }
    }

    /// One paragraph: the device range the evaluation uses, and the ceilings found.
    pub fn render(&self) -> String {
        use crate::foot::device::side_name;
        let mut sides: Vec<String> = self.per_trial.iter().map(side_name).collect();
        sides.sort_unstable();
        sides.dedup();
        let (lo, hi) = self
            .per_trial
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| {
                (l.min(c.ceiling_rads), h.max(c.ceiling_rads))
            });
        let pooled: Vec<String> = self
            .pooled
            .iter()
            .map(|c| {
                format!(
                    "{} {:.2} rad/s ({} flat tops)",
                    side_name(c),
                    c.ceiling_rads,
                    c.flat_tops
                )
            })
            .collect();
        format!(
            "Gyroscope: range {UOFT_GYRO_RANGE_RADS} rad/s for every trial (the UofT MicroStrain, one device; clipped swing peaks repaired). The ceiling detector (`GyroCeilingDetector`, what `stridekit foot` uses when no range is given) finds clipping on {} of {} trials ({}; lowest flat-top samples {}), and over all trials as one device on {}.\n\n",
            self.per_trial.len(),
            self.trials,
            if sides.is_empty() { "none".to_string() } else { format!("sensor {}", sides.join(", ")) },
            if self.per_trial.is_empty() { "—".to_string() } else { format!("{lo:.2}–{hi:.2} rad/s") },
            if pooled.is_empty() { "no axis".to_string() } else { pooled.join(", ") },
        )
    }
}

fn with(name: &str, detector: ZeroVelocityDetector) -> Method {
    Method {
        name: name.into(),
        config: FootConfig {
            detector,
            ..base_config()
        },
        labels: None,
    }
}

/// The methods with fixed configurations (the SVM is added per fold by [`run`]).
pub fn methods() -> Vec<Method> {
    vec![
        with(
            "fixed",
            ZeroVelocityDetector::Fixed(FixedThresholds::default()),
        ),
        with(
            "adaptive",
            ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
        ),
        with("shoe", ZeroVelocityDetector::Shoe(ShoeDetector::default())),
        with(
            "adaptive shoe",
            ZeroVelocityDetector::AdaptiveShoe(AdaptiveShoe::default()),
        ),
        Method {
            name: "shoe, as published".into(),
            config: FootConfig {
                detector: ZeroVelocityDetector::Shoe(ShoeDetector::default()),
                correction: Correction::AsPublished,
                zupt_gate_nis: None,
                ..base_config()
            },
            labels: None,
        },
        Method {
            name: "oracle labels".into(),
            config: base_config(),
            labels: Some("best".into()),
        },
        Method {
            name: "runner-up oracle labels".into(),
            config: base_config(),
            labels: Some("runner-up".into()),
        },
    ]
}

pub fn load(dir: &Path) -> Result<Vec<Trial>, String> {
    Ok(load_with_info(dir)?.into_iter().map(|(t, _)| t).collect())
}

pub fn load_with_info(dir: &Path) -> Result<Vec<(Trial, TrialInfo)>, String> {
    let summary = std::fs::read_to_string(dir.join("_summary.csv")).unwrap_or_default();
    let mut best_of = std::collections::HashMap::new();
    let mut lines = summary.lines();
    if let Some(h) = lines.next() {
        let cols: Vec<&str> = h.split(',').collect();
        let ti = cols.iter().position(|c| *c == "trial");
        let bi = cols.iter().position(|c| *c == "best_detector");
        let ei = cols.iter().position(|c| *c == "best_error_m");
        // Per-detector errors of pyshoe's filter: `err_<detector>`.
        let errs: Vec<(usize, &str)> = cols
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.strip_prefix("err_").map(|d| (i, d)))
            .collect();
        if let (Some(ti), Some(bi)) = (ti, bi) {
            for l in lines {
                let f: Vec<&str> = l.split(',').collect();
                if let (Some(t), Some(b)) = (f.get(ti), f.get(bi)) {
                    let err = ei
                        .and_then(|e| f.get(e))
                        .and_then(|v| v.parse::<f64>().ok());
                    // The other detector whose optimised labels gave pyshoe the
                    // lowest error.
                    let runner_up = errs
                        .iter()
                        .filter(|(_, d)| d != b)
                        .filter_map(|(i, d)| Some((f.get(*i)?.parse::<f64>().ok()?, *d)))
                        .min_by(|x, y| x.0.total_cmp(&y.0))
                        .map(|(_, d)| format!("{d}_opt"));
                    best_of.insert(t.to_string(), (format!("{b}_opt"), err, runner_up));
                }
            }
        }
    }
    let mut out = Vec::new();
    for path in list_foot_trials(dir).map_err(|e| e.to_string())? {
        let mut rec = read_foot_csv(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let tilt = stance_tilt_deg(&rec);
        let Some(truth) = rec.truth_m.as_mut() else {
            continue;
        };
        let raw_truth = truth.clone();
        mirror_truth(truth);
        let (best, pyshoe_best_m, runner_up) = best_of
            .get(&rec.name)
            .cloned()
            .unwrap_or_else(|| ("shoe_opt".into(), None, None));
        let other = rec.name.starts_with(OTHER_PREFIX);
        let mut info = gait_info(&rec.t_s, truth, raw_truth, other);
        info.stance_tilt_deg = tilt;
        let path_m = path_length(&rec.t_s, truth);
        out.push((
            Trial {
                run: info.kind == Some(GaitClass::Run),
                best,
                runner_up,
                pyshoe_best_m,
                path_m,
                rec,
            },
            info,
        ));
    }
    Ok(out)
}

/// The VICON positions of this set are a mirror image of the IMU's (right-handed)
/// navigation frame: with the truth's y axis negated, every trial's estimate fits
/// it by a rotation (RMSE ~0.1 m); without, only a mirror fits (RMSE ~1–2 m). The IMU
/// data are self-consistent (a mirrored IMU would break the strapdown solution, which
/// closes its loops to ~1 %), so the truth is what gets mirrored. `eval foot` prints
/// the check on every run.
pub fn mirror_truth(truth: &mut [[f64; 3]]) {
    for g in truth.iter_mut() {
        g[1] = -g[1];
    }
}

/// Cumulative horizontal path of the truth, sampled every 0.1 s (VICON jitter would
/// inflate a per-sample sum), interpolated back to every sample.
fn cumulative_path(t: &[f64], g: &[[f64; 3]]) -> Vec<f64> {
    let mut knots = vec![(t[0], 0.0)];
    let mut last = 0usize;
    let mut s = 0.0;
    for i in 1..t.len() {
        if t[i] - t[last] >= 0.1 || i == t.len() - 1 {
            s += (g[i][0] - g[last][0]).hypot(g[i][1] - g[last][1]);
            knots.push((t[i], s));
            last = i;
        }
    }
    let mut out = Vec::with_capacity(t.len());
    let mut k = 0;
    for &ti in t {
        while k + 2 < knots.len() && knots[k + 1].0 < ti {
            k += 1;
        }
        let (t0, s0) = knots[k];
        let (t1, s1) = knots[(k + 1).min(knots.len() - 1)];
        let f = if t1 > t0 {
            ((ti - t0) / (t1 - t0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(s0 + f * (s1 - s0));
    }
    out
}

fn path_length(t: &[f64], g: &[[f64; 3]]) -> f64 {
    cumulative_path(t, g).last().copied().unwrap_or(0.0)
}

/// See [`TrialInfo::stance_tilt_deg`] (sensor z down, as in the pyshoe data).
fn stance_tilt_deg(rec: &FootRecording) -> f64 {
    let mut m = [0.0; 3];
    for (f, w) in rec.accel_mps2.iter().zip(&rec.gyro_rads) {
        if norm(*w) < 0.3 {
            for i in 0..3 {
                m[i] += f[i];
            }
        }
    }
    m[0].hypot(m[1]).atan2(-m[2]).to_degrees()
}

fn gait_info(t: &[f64], g: &[[f64; 3]], raw_truth: Vec<[f64; 3]>, other: bool) -> TrialInfo {
    let n = t.len();
    let s = cumulative_path(t, g);
    let (zmin, zmax) = g
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[2]), b.max(p[2]))
        });
    let dur = (t[n - 1] - t[0]).max(1e-9);
    let mean_speed = s[n - 1] / dur;
    let mut gait = Vec::with_capacity(n);
    let (mut lo, mut hi) = (0usize, 0usize);
    for i in 0..n {
        while t[lo] < t[i] - 0.5 {
            lo += 1;
        }
        while hi + 1 < n && t[hi + 1] <= t[i] + 0.5 {
            hi += 1;
        }
        let span = t[hi] - t[lo];
        gait.push(Some(if other {
            GaitClass::Other
        } else if span > 0.0 && (s[hi] - s[lo]) / span > RUN_SPEED_MPS {
            GaitClass::Run
        } else {
            GaitClass::Walk
        }));
    }
    let count = |c| gait.iter().filter(|g| **g == Some(c)).count();
    let (w, r, o) = (
        count(GaitClass::Walk),
        count(GaitClass::Run),
        count(GaitClass::Other),
    );
    let kind = if o >= w.max(r) {
        GaitClass::Other
    } else if r > w {
        GaitClass::Run
    } else {
        GaitClass::Walk
    };
    TrialInfo {
        run_fraction: r as f64 / n as f64,
        gait,
        kind: Some(kind),
        z_range_m: zmax - zmin,
        mean_speed_mps: mean_speed,
        stance_tilt_deg: 0.0,
        raw_truth,
    }
}

/// Runs one method over a trial; returns the estimates with their sample indices
/// (samples the navigator rejects are skipped, see [`replay_counted`]).
pub fn replay(trial: &Trial, m: &Method) -> Result<Vec<(usize, FootEstimate)>, String> {
    Ok(replay_counted(trial, m)?.estimates)
}

/// What a replay produced.
#[derive(Clone, Debug, Default)]
pub struct Replayed {
    /// Estimates with the index of their sample in the recording.
    pub estimates: Vec<(usize, FootEstimate)>,
    /// Samples the navigator rejected (skipped), by reason.
    pub skipped: crate::foot::Skipped,
    /// Sample rate the navigator measured at alignment, Hz (0: never aligned).
    pub rate_hz: f64,
    /// Detector window, samples.
    pub window: usize,
    /// Divergence-guard resets.
    pub resets: u64,
    /// The accelerometer ceiling the navigator worked with at the end, m/s²
    /// (`FootNavigator::accel_ceiling_mps2`; `None`: no clipping seen).
    pub accel_ceiling_mps2: Option<f64>,
}

/// Row `i` of a recording as the navigator's sample.
pub fn foot_sample(rec: &FootRecording, i: usize) -> FootSample {
    FootSample {
        t_s: rec.t_s[i],
        accel_mps2: rec.accel_mps2[i],
        gyro_rads: rec.gyro_rads[i],
    }
}

/// Runs one method over a trial. A sample the navigator rejects (repeated or
/// reversed timestamp, NaN/∞, out of range, units of g) is skipped and counted by
/// reason; it changes nothing in the navigator (engine contract).
pub fn replay_counted(trial: &Trial, m: &Method) -> Result<Replayed, String> {
    let rec = &trial.rec;
    let labels = match m.labels.as_deref() {
        Some("best") => Some(
            rec.label(&trial.best)
                .ok_or_else(|| format!("{}: no label column {}", rec.name, trial.best))?,
        ),
        Some("runner-up") => {
            let col = trial.runner_up.as_deref().unwrap_or(&trial.best);
            Some(
                rec.label(col)
                    .ok_or_else(|| format!("{}: no label column {col}", rec.name))?,
            )
        }
        Some(other) => Some(rec.label(other).ok_or_else(|| {
            let have: Vec<&str> = rec.labels.iter().map(|(n, _)| n.as_str()).collect();
            format!(
                "{}: no label column zv_{other} (the file has: {})",
                rec.name,
                if have.is_empty() {
                    "none".to_string()
                } else {
                    have.join(", ")
                }
            )
        })?),
        None => None,
    };
    let mut nav = FootNavigator::new(m.config.clone()).map_err(|e| e.to_string())?;
    let mut out = Replayed {
        estimates: Vec::with_capacity(rec.len()),
        ..Default::default()
    };
    // (t_s, index) of the accepted samples: strictly increasing in t_s.
    let mut accepted: Vec<(f64, usize)> = Vec::with_capacity(rec.len());
    for i in 0..rec.len() {
        let s = foot_sample(rec, i);
        let r = match labels {
            Some(l) => nav.push_with_stance(&s, l[i]),
            None => nav.push(&s),
        };
        match r {
            Ok(e) => {
                accepted.push((s.t_s, i));
                if let Some(e) = e {
                    // Estimates come in sample order, `delay` samples late.
                    let j = accepted.partition_point(|&(t, _)| t < e.t_s);
                    let k = accepted.get(j).map_or(i, |&(_, k)| k);
                    out.estimates.push((k, e));
                }
            }
            Err(e) => out.skipped.add(i, &e),
        }
    }
    out.rate_hz = nav.sample_rate_hz();
    out.window = nav.detector_window();
    out.resets = nav.divergence_resets();
    out.accel_ceiling_mps2 = nav.accel_ceiling_mps2();
    Ok(out)
}

/// Best rotation θ about the vertical and translation `t` with `truth ≈ R(θ)·est + t`
/// (least squares, horizontal rotation only). Also used by `stridekit foot`.
pub fn align(est: &[[f64; 3]], truth: &[[f64; 3]]) -> (f64, [f64; 3]) {
    let n = est.len().max(1) as f64;
    let mut ce = [0.0; 3];
    let mut cg = [0.0; 3];
    for (e, g) in est.iter().zip(truth) {
        for i in 0..3 {
            ce[i] += e[i] / n;
            cg[i] += g[i] / n;
        }
    }
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for (e, g) in est.iter().zip(truth) {
        let (ex, ey) = (e[0] - ce[0], e[1] - ce[1]);
        let (gx, gy) = (g[0] - cg[0], g[1] - cg[1]);
        sxx += ex * gx + ey * gy;
        sxy += ex * gy - ey * gx;
    }
    let th = sxy.atan2(sxx);
    let (s, c) = th.sin_cos();
    let t = [
        cg[0] - (c * ce[0] - s * ce[1]),
        cg[1] - (s * ce[0] + c * ce[1]),
        cg[2] - ce[2],
    ];
    (th, t)
}

fn rot(th: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = th.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

/// RMSE after the best rotation + translation, and that rotation.
fn fit(est: &[(usize, FootEstimate)], truth: &[[f64; 3]]) -> (f64, f64, [f64; 3]) {
    let (r3, _, th, t) = fit_h(est, truth);
    (r3, th, t)
}

/// 3-D and horizontal RMSE after the best rotation about the vertical +
/// translation (the rotation and the horizontal translation are the same for both:
/// the vertical decouples), the rotation and the translation.
fn fit_h(est: &[(usize, FootEstimate)], truth: &[[f64; 3]]) -> (f64, f64, f64, [f64; 3]) {
    let e: Vec<[f64; 3]> = est.iter().map(|(_, e)| e.position_m).collect();
    let g: Vec<[f64; 3]> = est.iter().map(|(k, _)| truth[*k]).collect();
    let (th, t) = align(&e, &g);
    let (mut se, mut sh) = (0.0, 0.0);
    for (a, b) in e.iter().zip(&g) {
        let r = rot(th, *a);
        let d: Vec<f64> = (0..3).map(|i| (r[i] + t[i] - b[i]).powi(2)).collect();
        se += d[0] + d[1] + d[2];
        sh += d[0] + d[1];
    }
    let n = e.len() as f64;
    ((se / n).sqrt(), (sh / n).sqrt(), th, t)
}

pub fn score(trial: &Trial, est: &[(usize, FootEstimate)]) -> Outcome {
    score_with_gait(trial, None, est)
}

fn score_with_gait(
    trial: &Trial,
    gait: Option<&[Option<GaitClass>]>,
    est: &[(usize, FootEstimate)],
) -> Outcome {
    let Some(truth) = trial.rec.truth_m.as_ref() else {
        return Outcome::default();
    };
    if est.len() < 2 {
        return Outcome::default();
    }
    let (rmse, rmse_h, th, _) = fit_h(est, truth);
    let e0 = est[0].1.position_m;
    let e1 = est[est.len() - 1].1.position_m;
    let de = rot(th, sub(e1, e0));
    let dg = sub(truth[est[est.len() - 1].0], truth[est[0].0]);
    let closure = norm(sub(de, dg)) / trial.path_m.max(1e-9) * 100.0;
    let closure_h = (de[0] - dg[0]).hypot(de[1] - dg[1]) / trial.path_m.max(1e-9) * 100.0;
    let mut o = Outcome {
        rmse_m: rmse,
        rmse_h_m: rmse_h,
        closure_pct: closure,
        closure_h_pct: closure_h,
        zv_accuracy_pct: f64::NAN,
        ..Default::default()
    };
    if let Some(r) = trial.rec.label(&trial.best) {
        let mut ok = 0;
        for (k, e) in est {
            let c = gait.and_then(|g| g[*k]).unwrap_or(GaitClass::Walk) as usize;
            o.zv_total[c] += 1;
            if r[*k] == e.stance {
                ok += 1;
                o.zv_agree[c] += 1;
            } else if e.stance {
                o.false_stance[c] += 1;
            }
        }
        o.zv_accuracy_pct = ok as f64 / est.len() as f64 * 100.0;
    }
    o.armse_2d_m = pyshoe_armse_2d(est, truth);
    let last = est[est.len() - 1].1;
    o.strides = last.strides;
    o.distance_m = last.distance_m;
    o
}

/// pyshoe's ARMSE (see [`Outcome::armse_2d_m`]).
fn pyshoe_armse_2d(est: &[(usize, FootEstimate)], truth: &[[f64; 3]]) -> f64 {
    let e0 = est[0].1.position_m;
    let g0 = truth[est[0].0];
    let e: Vec<[f64; 3]> = est.iter().map(|(_, x)| sub(x.position_m, e0)).collect();
    let g: Vec<[f64; 3]> = est.iter().map(|(k, _)| sub(truth[*k], g0)).collect();
    let ind = e
        .iter()
        .position(|p| p[0].hypot(p[1]) >= 0.8)
        .unwrap_or(300.min(e.len() - 1));
    let th = g[ind][1].atan2(g[ind][0]) - e[ind][1].atan2(e[ind][0]);
    let sum: f64 = e
        .iter()
        .zip(&g)
        .map(|(a, b)| {
            let r = rot(th, *a);
            // Per sample the RMS over the two axes, as `compute_error` does.
            (r[0] - b[0]).hypot(r[1] - b[1]) * std::f64::consts::FRAC_1_SQRT_2
        })
        .sum();
    sum / e.len() as f64
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub use crate::stats::median;

/// Geometric mean of the RMSEs (the tuning objective: every trial counts, none
/// dominates).
fn geo_mean(v: &[f64]) -> f64 {
    let n = v.len().max(1) as f64;
    (v.iter().map(|x| x.max(1e-6).ln()).sum::<f64>() / n).exp()
}

/// The SVM models of the cross-validation: model `f` is trained on every trial whose
/// position modulo `folds` is not `f`.
pub fn svm_folds(
    trials: &[Trial],
    stats: &[Vec<(usize, WindowStats)>],
    folds: usize,
) -> Result<Vec<stridekit_core::foot::SvmModel>, String> {
    let p = train_zupt::TrainParams::default();
    (0..folds)
        .map(|f| {
            let mut data = Vec::new();
            for (i, (t, st)) in trials.iter().zip(stats).enumerate() {
                if i % folds != f {
                    data.extend(train_zupt::labelled_from(t, st)?);
                }
            }
            train_zupt::train(
                &data,
                &p,
                vec![format!("cross-validation fold {}/{folds}", f + 1)],
            )
        })
        .collect()
}

/// Every method's outcome on every trial.
#[derive(Clone, Debug, Default)]
pub struct MethodResults {
    /// Column names, one per method.
    pub names: Vec<String>,
    /// `results[trial][method]`.
    pub results: Vec<Vec<Outcome>>,
}

/// Medians of one group of trials per gait, as a titled markdown table.
fn gait_summary(
    title: &str,
    infos: &[&TrialInfo],
    names: &[String],
    rows: &[&Vec<Outcome>],
) -> String {
    let count = |k: GaitClass| infos.iter().filter(|i| i.kind() == k).count();
    let mut out = format!(
        "\n{title} ({} trials: {} walk, {} run, {} other):\n\n",
        rows.len(),
        count(GaitClass::Walk),
        count(GaitClass::Run),
        count(GaitClass::Other),
    );
    let mut t = TextTable::new([
        "method",
        "pyshoe metric m all",
        "horizontal RMSE m all",
        "RMSE m all",
        "RMSE m walk",
        "RMSE m run",
        "RMSE m other",
        "closure % walk (horizontal)",
        "closure % walk",
        "closure % run",
        "ZV % walk samples",
        "ZV % run samples",
        "ZV % other samples",
        "false stance % run samples",
    ]);
    for (j, name) in names.iter().enumerate() {
        let col = |kind: Option<GaitClass>, f: fn(&Outcome) -> f64| {
            median(
                infos
                    .iter()
                    .zip(rows)
                    .filter(|(i, _)| kind.is_none_or(|k| i.kind() == k))
                    .map(|(_, row)| f(&row[j]))
                    .collect::<Vec<f64>>(),
            )
        };
        let pooled = |c: usize, num: fn(&Outcome, usize) -> usize| {
            let a: usize = rows.iter().map(|r| num(&r[j], c)).sum();
            let n: usize = rows.iter().map(|r| r[j].zv_total[c]).sum();
            if n == 0 {
                f64::NAN
            } else {
                a as f64 / n as f64 * 100.0
            }
        };
        t.row([
            name.clone(),
            cell(col(None, |o| o.armse_2d_m), 3),
            cell(col(None, |o| o.rmse_h_m), 3),
            cell(col(None, |o| o.rmse_m), 3),
            cell(col(Some(GaitClass::Walk), |o| o.rmse_m), 3),
            cell(col(Some(GaitClass::Run), |o| o.rmse_m), 3),
            cell(col(Some(GaitClass::Other), |o| o.rmse_m), 3),
            cell(col(Some(GaitClass::Walk), |o| o.closure_h_pct), 2),
            cell(col(Some(GaitClass::Walk), |o| o.closure_pct), 2),
            cell(col(Some(GaitClass::Run), |o| o.closure_pct), 2),
            cell(pooled(0, |o, c| o.zv_agree[c]), 1),
            cell(pooled(1, |o, c| o.zv_agree[c]), 1),
            cell(pooled(2, |o, c| o.zv_agree[c]), 1),
            cell(pooled(1, |o, c| o.false_stance[c]), 1),
        ]);
    }
    out.push_str(&t.render());
    out
}

/// A median with `decimals`; a gait with no trial in the group (a small folder) gets
/// "–", not NaN.
fn cell(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        "–".to_string()
    }
}

/// Window statistics of every trial (what the detectors see with `config`).
fn all_stats(
    trials: &[Trial],
    config: &FootConfig,
) -> Result<Vec<Vec<(usize, WindowStats)>>, String> {
    trials
        .iter()
        .map(|t| train_zupt::trial_stats(t, config))
        .collect()
}

/// The SVM-based detectors with a given (cross-validation) model.
fn svm_methods(model: &stridekit_core::foot::SvmModel) -> Vec<Method> {
    let model = std::sync::Arc::new(model.clone());
    vec![
        with("svm", ZeroVelocityDetector::Svm(model.clone())),
        with(
            "svm+adaptive",
            ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::with_model(model)),
        ),
    ]
}

/// Columns: the fixed methods, with the SVM-based ones inserted after the second
/// (6-fold CV), and the SVM-based ones again with leave-one-session-out models at
/// the end.
fn evaluate(
    trials: &[Trial],
    infos: &[TrialInfo],
    svm: &[stridekit_core::foot::SvmModel],
    loso: &Loso,
) -> Result<MethodResults, String> {
    let ms = methods();
    let mut names: Vec<String> = ms.iter().map(|m| m.name.clone()).collect();
    let cv = svm_methods(&svm[0]);
    for (j, m) in cv.iter().enumerate() {
        names.insert(2 + j, format!("{} ({}-fold CV)", m.name, svm.len()));
    }
    // A folder of one session has nothing to leave out: no such columns.
    if loso.available() {
        for m in &cv {
            names.push(format!("{} (leave one session out)", m.name));
        }
    }
    let mut results = Vec::new();
    let pb = crate::progress::bar(trials.len(), "eval foot: trials");
    for (i, (trial, info)) in trials.iter().zip(infos).enumerate() {
        pb.inc(1);
        let mut row = Vec::new();
        for m in &ms {
            let est = replay(trial, m)?;
            row.push(score_with_gait(trial, Some(&info.gait), &est));
        }
        for (j, m) in svm_methods(&svm[i % svm.len()]).iter().enumerate() {
            let est = replay(trial, m)?;
            row.insert(2 + j, score_with_gait(trial, Some(&info.gait), &est));
        }
        if let Some(model) = loso.model_for(&trial.rec.name) {
            for m in &svm_methods(model) {
                let est = replay(trial, m)?;
                row.push(score_with_gait(trial, Some(&info.gait), &est));
            }
        }
        results.push(row);
    }
    Ok(MethodResults { names, results })
}

/// The oracle-label run of one trial fitted (rotation + translation) to the truth as
/// mirrored and as recorded.
#[derive(Clone, Debug)]
pub struct MirrorFit {
    pub trial: String,
    pub path_m: f64,
    pub mirrored_m: f64,
    pub recorded_m: f64,
}

impl MirrorFit {
    fn better_mirrored(&self) -> bool {
        self.mirrored_m < self.recorded_m
    }
}

/// The mirror check of every trial (see [`mirror_truth`]).
fn mirror_check(trials: &[Trial], infos: &[TrialInfo]) -> Result<Vec<MirrorFit>, String> {
    let oracle = Method {
        name: "oracle".into(),
        config: base_config(),
        labels: Some("best".into()),
    };
    let mut fits = Vec::with_capacity(trials.len());
    for (trial, info) in trials.iter().zip(infos) {
        let est = replay(trial, &oracle)?;
        let (mirrored_m, _, _) = fit(&est, trial.rec.truth_m.as_deref().unwrap_or(&[]));
        let (recorded_m, _, _) = fit(&est, &info.raw_truth);
        fits.push(MirrorFit {
            trial: trial.rec.name.clone(),
            path_m: trial.path_m,
            mirrored_m,
            recorded_m,
        });
    }
    Ok(fits)
}

/// `eval foot`: everything its report shows, computed ([`EvalReport::render`] writes it).
pub struct EvalReport {
    pub dir: std::path::PathBuf,
    pub trials: Vec<Trial>,
    pub infos: Vec<TrialInfo>,
    /// Folds of the SVM cross-validation actually used.
    pub svm_folds: usize,
    pub loso: Loso,
    pub results: MethodResults,
    pub mirror: Vec<MirrorFit>,
    pub gyro: GyroCeilings,
    /// The default detector's thresholds refitted leave one session out.
    pub detector_loso: crate::foot::sessions::DetectorLoso,
}

/// The whole evaluation (`stridekit eval foot`), computed.
pub fn eval(dir: &Path) -> Result<EvalReport, String> {
    let sp = crate::progress::spinner("eval foot: reading the trials");
    let loaded = load_with_info(dir)?;
    let (trials, infos): (Vec<Trial>, Vec<TrialInfo>) = loaded.into_iter().unzip();
    sp.set_message("eval foot: detector statistics of every trial");
    let stats = all_stats(&trials, &base_config())?;
    if trials.len() < 2 {
        return Err(format!(
            "{}: eval foot needs at least two trials (its SVM is cross-validated over trials); `stridekit foot FILE` replays one",
            dir.display()
        ));
    }
    let folds = SVM_FOLDS.min(trials.len());
    sp.set_message(format!("eval foot: training {folds} SVM folds"));
    let svm = svm_folds(&trials, &stats, folds)?;
    sp.set_message("eval foot: training the leave-one-session-out SVMs");
    let loso = Loso::train(&trials, &stats)?;
    sp.finish_and_clear();
    let results = evaluate(&trials, &infos, &svm, &loso)?;
    let detector_loso = crate::foot::sessions::DetectorLoso::measure(&trials)?;
    Ok(EvalReport {
        detector_loso,
        dir: dir.to_path_buf(),
        svm_folds: svm.len(),
        mirror: mirror_check(&trials, &infos)?,
        gyro: GyroCeilings::find(&trials),
        trials,
        infos,
        loso,
        results,
    })
}

impl EvalReport {
    /// The report as markdown.
    pub fn render(&self) -> String {
        let mut out = format!(
            "Foot-mounted navigation on {} trials of {} (one configuration per detector for all trials; SVM by {}-fold cross-validation over trials).\n\n",
            self.trials.len(),
            self.dir.display(),
            self.svm_folds
        );
        out.push_str(&self.mirror_paragraph());
        out.push_str(&self.gyro.render());
        out.push_str(&format!(
            "Gait per sample from the truth: horizontal foot path over ±0.5 s / 1 s > {RUN_SPEED_MPS} m/s = run, else walk; the stairs/crawling session {OTHER_PREFIX}* = other (see its height range, stance tilt and mean speed). Split: even positions in name order = training (defaults chosen there), odd = held-out.\n\n"
        ));
        out.push_str("Per trial: horizontal position RMSE after the best rotation about the vertical + translation, m / 3-D loop-closure error, % of path / zero-velocity agreement with the best detector's labels, %.\n\n");
        out.push_str(&self.trial_table().render());
        out.push_str("\nMedians of the per-trial RMSE and closure, grouped by the trial's majority gait; ZV agreement pooled over the samples of each gait (per sample gait); false stance = detector says stance where the reference says swing.\n");
        out.push_str(&self.split_summaries());
        let MethodResults { names, results } = &self.results;
        out.push_str(&crate::foot::sessions::session_table(
            &self.trials,
            names,
            results,
            &self.loso,
        ));
        out.push_str(&self.filter_check());
        out.push_str(&self.target_check());
        out.push_str(&self.detector_loso.table());
        out
    }

    fn oracle(&self) -> usize {
        let names = &self.results.names;
        names.iter().position(|n| n == "oracle labels").unwrap_or(0)
    }

    /// Mirror check: the oracle-label run against the truth as recorded and mirrored.
    fn mirror_paragraph(&self) -> String {
        let better_mirrored = self.mirror.iter().filter(|m| m.better_mirrored()).count();
        let not_mirrored: Vec<String> = self
            .mirror
            .iter()
            .filter(|m| !m.better_mirrored())
            .map(|m| {
                format!(
                    "{} ({:.3} m as recorded vs {:.3} m mirrored, path {:.1} m)",
                    m.trial, m.recorded_m, m.mirrored_m, m.path_m
                )
            })
            .collect();
        format!(
            "Mirror check (oracle-label run fitted by rotation + translation): {better_mirrored} of {} trials fit better with the truth's y axis negated (median RMSE {:.3} m mirrored vs {:.3} m as recorded), so the truth is mirrored.{}\n\n",
            self.trials.len(),
            median(self.mirror.iter().map(|m| m.mirrored_m).collect::<Vec<f64>>()),
            median(self.mirror.iter().map(|m| m.recorded_m).collect::<Vec<f64>>()),
            if not_mirrored.is_empty() {
                String::new()
            } else {
                format!(" Not better mirrored: {}.", not_mirrored.join(", "))
            }
        )
    }

    /// Per trial: its truth's description, then each method's RMSE / closure / ZV.
    fn trial_table(&self) -> TextTable {
        let mut header: Vec<String> = [
            "trial",
            "split",
            "gait",
            "run %",
            "z range m",
            "stance tilt °",
            "mean speed m/s",
            "path m",
        ]
        .map(String::from)
        .to_vec();
        header.extend(self.results.names.iter().cloned());
        let mut t = TextTable::new(header);
        let rows = self
            .trials
            .iter()
            .zip(&self.infos)
            .zip(&self.results.results);
        for (i, ((trial, info), row)) in rows.enumerate() {
            let mut cells = vec![
                trial.rec.name.clone(),
                if i % 2 == 0 { "train" } else { "held-out" }.to_string(),
                info.kind().name().to_string(),
                format!("{:.0}", info.run_fraction * 100.0),
                format!("{:.2}", info.z_range_m),
                format!("{:.0}", info.stance_tilt_deg),
                format!("{:.2}", info.mean_speed_mps),
                format!("{:.1}", trial.path_m),
            ];
            cells.extend(row.iter().map(|o| {
                format!(
                    "{:.3} / {:.2} / {:.1}",
                    o.rmse_h_m, o.closure_pct, o.zv_accuracy_pct
                )
            }));
            t.row(cells);
        }
        t
    }

    /// The gait summaries of the held-out split, all trials and the training split.
    fn split_summaries(&self) -> String {
        let names = &self.results.names;
        let pick = |keep: &dyn Fn(usize) -> bool| -> (Vec<&TrialInfo>, Vec<&Vec<Outcome>>) {
            (0..self.trials.len())
                .filter(|&i| keep(i))
                .map(|i| (&self.infos[i], &self.results.results[i]))
                .unzip()
        };
        let mut out = String::new();
        let (hi, hr) = pick(&|i| i % 2 == 1);
        out.push_str(&gait_summary("Held-out split", &hi, names, &hr));
        let (ai, ar) = pick(&|_| true);
        out.push_str(&gait_summary("All trials", &ai, names, &ar));
        let (ti, tr) = pick(&|i| i % 2 == 0);
        out.push_str(&gait_summary(
            "Training split (where the defaults were chosen)",
            &ti,
            names,
            &tr,
        ));
        out
    }

    /// This navigator on each trial's best labels against pyshoe's filter on them.
    fn filter_check(&self) -> String {
        let oracle = self.oracle();
        let ours: Vec<f64> = self
            .results
            .results
            .iter()
            .map(|r| r[oracle].armse_2d_m)
            .collect();
        let theirs: Vec<f64> = self
            .trials
            .iter()
            .map(|t| t.pyshoe_best_m.unwrap_or(f64::NAN))
            .collect();
        let better = ours.iter().zip(&theirs).filter(|(a, b)| a <= b).count();
        if theirs.iter().any(|x| x.is_finite()) {
            format!(
                "\nFilter check against pyshoe (same labels, same metric — pyshoe's 2-D ARMSE with its own alignment): this navigator driven by each trial's best labels, median {:.3} m; pyshoe's filter on the same labels (`best_error_m` in `_summary.csv`), median {:.3} m; ours is as good or better on {better} of {} trials.\n",
                median(ours),
                median(theirs),
                self.trials.len()
            )
        } else {
            format!(
                "\nFilter check against pyshoe: this navigator driven by each trial's best labels, median {:.3} m in pyshoe's metric; pyshoe's own errors (`_summary.csv`) are not in this folder.\n",
                median(ours),
            )
        }
    }

    /// Each method against the targets (median RMSE, ZV on running samples, closure).
    fn target_check(&self) -> String {
        let MethodResults { names, results } = &self.results;
        let oracle = self.oracle();
        let med_oracle = median(
            results
                .iter()
                .map(|r| r[oracle].rmse_m)
                .collect::<Vec<f64>>(),
        );
        let mut out = format!(
            "\nTarget check (all trials): median RMSE ≤ oracle labels' {med_oracle:.3} m; ZV agreement ≥ 98 % on running samples; median loop closure ≤ 0.3 % on walking trials.\n\n"
        );
        let mut t = TextTable::new([
            "method",
            "median RMSE m",
            "≤ oracle?",
            "ZV % run samples",
            "≥ 98 %?",
            "closure % walk, horizontal / 3-D",
            "≤ 0.3 %?",
        ]);
        let walk: Vec<usize> = (0..self.trials.len())
            .filter(|&i| self.infos[i].kind() == GaitClass::Walk)
            .collect();
        let yes = |b: bool| if b { "yes" } else { "no" };
        for (j, name) in names.iter().enumerate() {
            let rmse = median(results.iter().map(|r| r[j].rmse_m).collect::<Vec<f64>>());
            let (a, n) = results.iter().fold((0, 0), |(a, n), r| {
                (
                    a + r[j].zv_agree[GaitClass::Run as usize],
                    n + r[j].zv_total[GaitClass::Run as usize],
                )
            });
            // No running sample in the folder: no agreement to state.
            let zv = if n == 0 {
                f64::NAN
            } else {
                a as f64 / n as f64 * 100.0
            };
            let walk_median = |f: fn(&Outcome) -> f64| {
                median(
                    walk.iter()
                        .map(|&i| f(&results[i][j]))
                        .collect::<Vec<f64>>(),
                )
            };
            let ch = walk_median(|o| o.closure_h_pct);
            let c3 = walk_median(|o| o.closure_pct);
            let (zv_cell, zv_met) = if zv.is_finite() {
                (format!("{zv:.1}"), yes(zv >= 98.0))
            } else {
                ("–".to_string(), "no running samples")
            };
            t.row([
                name.clone(),
                format!("{rmse:.3}"),
                yes(rmse <= med_oracle).to_string(),
                zv_cell,
                zv_met.to_string(),
                format!("{ch:.2} / {c3:.2}"),
                format!("{} (horizontal), {} (3-D)", yes(ch <= 0.3), yes(c3 <= 0.3)),
            ]);
        }
        out.push_str(&t.render());
        out
    }
}

/// A tuning score: geometric mean and median of the trials' position RMSE, m.
#[derive(Clone, Copy, Debug)]
pub struct Score {
    pub geo_mean_m: f64,
    pub median_m: f64,
}

/// One SVM setting scored by 3-fold cross-validation inside the training split.
#[derive(Clone, Copy, Debug)]
pub struct SvmTrial {
    pub gamma: f64,
    pub c: f64,
    pub score: Score,
}

/// One adaptive-threshold setting: gait boundaries and the jog / run scale factors of
/// the walking (fixed) thresholds.
#[derive(Clone, Copy, Debug)]
pub struct AdaptiveTrial {
    pub jog_peak_mps2: f64,
    pub run_peak_mps2: f64,
    pub jog_scale: f64,
    pub run_scale: f64,
    pub detector: AdaptiveThresholds,
    pub score: Score,
}

/// The grid searches at one detector window.
#[derive(Clone, Debug)]
pub struct WindowTuning {
    pub window_s: f64,
    pub svm: Vec<SvmTrial>,
    pub shoe: Vec<(ShoeDetector, Score)>,
    /// The best SHOE threshold (lowest geometric mean; the default when none scores).
    pub best_shoe: (f64, ShoeDetector),
    /// The full fixed-threshold grid, best first.
    pub fixed: Vec<(FixedThresholds, Score)>,
    pub adaptive: Vec<AdaptiveTrial>,
    /// The best adaptive setting (lowest geometric mean; the default when none scores).
    pub best_adaptive: (f64, AdaptiveThresholds),
}

/// `eval foot --tune`, computed ([`TuneReport::render`] writes it).
#[derive(Clone, Debug)]
pub struct TuneReport {
    pub train_trials: usize,
    pub windows: Vec<WindowTuning>,
    /// `eval foot --tune-adaptive-shoe` as it renders (its last part).
    pub adaptive_shoe: String,
}

/// The scores of one configuration over the training trials.
fn objective(train: &[Trial], config: &FootConfig) -> Result<Score, String> {
    let m = Method {
        name: "tune".into(),
        config: config.clone(),
        labels: None,
    };
    let mut r = Vec::new();
    for t in train {
        r.push(score(t, &replay(t, &m)?).rmse_m);
    }
    Ok(Score {
        geo_mean_m: geo_mean(&r),
        median_m: median(r),
    })
}

/// `eval foot --tune`: the grid searches that chose the detector window and the
/// detector defaults, on the training split only (objective: geometric mean of the
/// trials' position RMSE). The SVM is scored by 3-fold cross-validation inside the
/// training split.
pub fn tune(dir: &Path, windows: &[f64]) -> Result<TuneReport, String> {
    let loaded = load_with_info(dir)?;
    let train: Vec<Trial> = loaded
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 2 == 0)
        .map(|(_, (t, _))| t.clone())
        .collect();
    let windows = windows
        .iter()
        .map(|&w| tune_window(&train, w))
        .collect::<Result<Vec<_>, String>>()?;
    Ok(TuneReport {
        train_trials: train.len(),
        windows,
        adaptive_shoe: crate::foot::tune_shoe::run(dir)?,
    })
}

/// Every grid search at one detector window.
fn tune_window(train: &[Trial], window_s: f64) -> Result<WindowTuning, String> {
    let base = FootConfig {
        detector_window_s: window_s,
        ..base_config()
    };
    let svm = tune_svm(train, &base)?;
    let shoe = tune_shoe_threshold(train, &base)?;
    let mut best_shoe = (f64::INFINITY, ShoeDetector::default());
    for (d, s) in &shoe {
        if s.geo_mean_m < best_shoe.0 {
            best_shoe = (s.geo_mean_m, *d);
        }
    }
    let fixed = tune_fixed(train, &base)?;
    let adaptive = tune_adaptive(train, &base, fixed[0].0)?;
    let mut best_adaptive = (f64::INFINITY, AdaptiveThresholds::default());
    for a in &adaptive {
        if a.score.geo_mean_m < best_adaptive.0 {
            best_adaptive = (a.score.geo_mean_m, a.detector);
        }
    }
    Ok(WindowTuning {
        window_s,
        svm,
        shoe,
        best_shoe,
        fixed,
        adaptive,
        best_adaptive,
    })
}

/// SVM settings, 3-fold cross-validation inside the training split.
fn tune_svm(train: &[Trial], base: &FootConfig) -> Result<Vec<SvmTrial>, String> {
    const FOLDS: usize = 3;
    let stats = all_stats(train, base)?;
    let mut out = Vec::new();
    for (gamma, c) in [(1.0, 1.0), (2.0, 10.0), (0.5, 1.0)] {
        let p = train_zupt::TrainParams {
            gamma,
            c,
            ..train_zupt::TrainParams::default()
        };
        let mut r = Vec::new();
        for f in 0..FOLDS {
            let mut data = Vec::new();
            for (i, (t, st)) in train.iter().zip(&stats).enumerate() {
                if i % FOLDS != f {
                    data.extend(train_zupt::labelled_from(t, st)?);
                }
            }
            let model = train_zupt::train(&data, &p, vec![])?;
            let m = Method {
                name: "svm".into(),
                config: FootConfig {
                    detector: ZeroVelocityDetector::Svm(std::sync::Arc::new(model)),
                    ..base.clone()
                },
                labels: None,
            };
            for (i, t) in train.iter().enumerate() {
                if i % FOLDS == f {
                    r.push(score(t, &replay(t, &m)?).rmse_m);
                }
            }
        }
        let score = Score {
            geo_mean_m: geo_mean(&r),
            median_m: median(r),
        };
        out.push(SvmTrial { gamma, c, score });
    }
    Ok(out)
}

/// The SHOE threshold grid.
fn tune_shoe_threshold(
    train: &[Trial],
    base: &FootConfig,
) -> Result<Vec<(ShoeDetector, Score)>, String> {
    [3e4, 1e5, 3e5, 1e6, 3e6, 1e7]
        .into_iter()
        .map(|gamma| {
            let d = ShoeDetector {
                threshold: gamma,
                ..ShoeDetector::default()
            };
            let config = FootConfig {
                detector: ZeroVelocityDetector::Shoe(d),
                ..base.clone()
            };
            Ok((d, objective(train, &config)?))
        })
        .collect()
}

/// The fixed thresholds' full grid, best first.
fn tune_fixed(train: &[Trial], base: &FootConfig) -> Result<Vec<(FixedThresholds, Score)>, String> {
    let mut rows = Vec::new();
    for acc_dev in [1.0, 2.0, 4.0] {
        for gyro in [0.3, 0.6, 1.2] {
            for acc_std in [0.3, 0.8, 2.4] {
                for gyro_std in [0.1, 0.3, 0.9] {
                    let d = FixedThresholds {
                        acc_dev_mps2: acc_dev,
                        gyro_rads: gyro,
                        acc_std_mps2: acc_std,
                        gyro_std_rads: gyro_std,
                    };
                    let config = FootConfig {
                        detector: ZeroVelocityDetector::Fixed(d),
                        ..base.clone()
                    };
                    rows.push((d, objective(train, &config)?));
                }
            }
        }
    }
    rows.sort_by(|a, b| a.1.geo_mean_m.total_cmp(&b.1.geo_mean_m));
    Ok(rows)
}

/// Adaptive: walk = the fixed choice; jog and run scaled versions of it, and the gait
/// boundaries, by a grid over the scale factors and boundaries.
fn tune_adaptive(
    train: &[Trial],
    base: &FootConfig,
    walk: FixedThresholds,
) -> Result<Vec<AdaptiveTrial>, String> {
    let scale = |d: FixedThresholds, k: f64| FixedThresholds {
        acc_dev_mps2: d.acc_dev_mps2 * k,
        gyro_rads: d.gyro_rads * k,
        acc_std_mps2: d.acc_std_mps2 * k,
        gyro_std_rads: d.gyro_std_rads * k,
    };
    let mut out = Vec::new();
    for (jog_peak, run_peak) in [(40.0, 60.0), (50.0, 80.0)] {
        for (kj, kr) in [
            (1.0, 1.5),
            (1.0, 2.0),
            (1.5, 2.0),
            (1.5, 3.0),
            (2.0, 3.0),
            (2.0, 4.0),
        ] {
            let d = AdaptiveThresholds {
                jog_peak_mps2: jog_peak,
                run_peak_mps2: run_peak,
                walk,
                jog: scale(walk, kj),
                run: scale(walk, kr),
            };
            let config = FootConfig {
                detector: ZeroVelocityDetector::Adaptive(d),
                ..base.clone()
            };
            out.push(AdaptiveTrial {
                jog_peak_mps2: jog_peak,
                run_peak_mps2: run_peak,
                jog_scale: kj,
                run_scale: kr,
                detector: d,
                score: objective(train, &config)?,
            });
        }
    }
    Ok(out)
}

impl TuneReport {
    /// The report as text.
    pub fn render(&self) -> String {
        let mut out = format!(
            "Tuning on the training split ({} trials; objective: geometric mean of the position RMSE, m; median in brackets).\n",
            self.train_trials
        );
        for w in &self.windows {
            out.push_str(&w.render());
        }
        out.push_str("\n## adaptive shoe (detector window 0.025 s)\n\n");
        out.push_str(&self.adaptive_shoe);
        out
    }
}

impl WindowTuning {
    fn render(&self) -> String {
        let mut out = format!("\n## detector window {} s\n\n", self.window_s);
        for SvmTrial { gamma, c, score } in &self.svm {
            out.push_str(&format!(
                "svm γ {gamma} C {c} (3-fold CV): {:.3} ({:.3})\n",
                score.geo_mean_m, score.median_m
            ));
        }
        for (d, s) in &self.shoe {
            out.push_str(&format!(
                "shoe γ {:e}: {:.3} ({:.3})\n",
                d.threshold, s.geo_mean_m, s.median_m
            ));
        }
        out.push_str(&format!(
            "→ shoe γ {:e}: {:.3}\n",
            self.best_shoe.1.threshold, self.best_shoe.0
        ));
        out.push_str(&format!("fixed, best 3 of {}:\n", self.fixed.len()));
        for (d, s) in self.fixed.iter().take(3) {
            out.push_str(&format!("{d:?}: {:.3} ({:.3})\n", s.geo_mean_m, s.median_m));
        }
        let (best_fixed, best_score) = &self.fixed[0];
        out.push_str(&format!(
            "→ fixed {best_fixed:?}: {:.3}\n",
            best_score.geo_mean_m
        ));
        for a in &self.adaptive {
            out.push_str(&format!(
                "adaptive peaks {}/{} m/s², jog ×{}, run ×{}: {:.3} ({:.3})\n",
                a.jog_peak_mps2,
                a.run_peak_mps2,
                a.jog_scale,
                a.run_scale,
                a.score.geo_mean_m,
                a.score.median_m
            ));
        }
        out.push_str(&format!(
            "→ adaptive {:?}: {:.3}\n",
            self.best_adaptive.1, self.best_adaptive.0
        ));
        out
    }
}
