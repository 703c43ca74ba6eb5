//! `stridekit eval steps`: step counting of the AsPublished and default detectors on the
//! Oxford Step Counter traces (phones carried 7 ways, shoe-worn heel-strike reference),
//! at the native rate, resampled to 100 and 50 Hz, with jittered timestamps and 10 %
//! of the samples dropped (at the native rate and at 50 Hz), and with 10 % dropped in
//! bursts.
//!
//! Scores per trace: count error (detected − reference) / reference, and step-event F1:
//! a detected step matches a reference heel strike within ±0.25 s, one-to-one (greedy
//! in time order, which is a maximum matching for a fixed tolerance).

use std::fmt::Write as _;
use std::path::Path;

use crate::table::Table;
use stridekit_core::stepdetect::{AccelSample, RobustStepParams, StepDetector, StepDetectorConfig};
use stridekit_formats::{list_oxford_traces, read_oxford_trace, OxfordPosition, OxfordTrace};

/// Matching tolerance between a detected step and a reference heel strike, s.
pub const MATCH_TOLERANCE_S: f64 = 0.25;

/// Heel strikes of each foot from a trace's `stepcounter.csv` (ns, foot-1, foot-2
/// contact; a 0→1 transition is a strike), in time order, with the foot (0 or 1).
pub fn strikes_by_foot(dir: &Path) -> Result<Vec<(f64, u8)>, String> {
    let path = dir.join("stepcounter.csv");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = Vec::new();
    let mut prev: Option<[u8; 2]> = None;
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let bad = || format!("{}: line {}: bad row", path.display(), i + 1);
        if f.len() < 3 {
            return Err(bad());
        }
        let t_ns: i64 = f[0].parse().map_err(|_| bad())?;
        let c: [u8; 2] = [
            f[1].parse().map_err(|_| bad())?,
            f[2].parse().map_err(|_| bad())?,
        ];
        if let Some(p) = prev {
            for foot in 0..2 {
                if c[foot] == 1 && p[foot] == 0 {
                    out.push((t_ns as f64 * 1e-9, foot as u8));
                }
            }
        }
        prev = Some(c);
    }
    Ok(out)
}

/// The reference made consistent with alternating feet, and how many strikes were
/// dropped and inserted. Walking alternates feet, so two strikes of the same foot in a
/// row are a sensor fault: sooner than 1.5 median step intervals (less than ¾ of a
/// stride: the foot cannot have swung) the second is contact chatter and is dropped; at
/// 1.5–2.5 intervals (one stride) the other foot's strike was not registered and one is
/// inserted at the midpoint; later (a pause) nothing is changed.
pub fn alternation_checked(strikes: &[(f64, u8)]) -> (Vec<f64>, usize, usize) {
    let mut iv: Vec<f64> = strikes.windows(2).map(|w| w[1].0 - w[0].0).collect();
    iv.sort_by(f64::total_cmp);
    let m = iv.get(iv.len() / 2).copied().unwrap_or(f64::NAN);
    let (mut out, mut dropped, mut inserted) = (Vec::<(f64, u8)>::new(), 0, 0);
    for &(t, foot) in strikes {
        if let Some(&(tp, fp)) = out.last() {
            if fp == foot {
                let dt = t - tp;
                if dt < 1.5 * m {
                    dropped += 1;
                    continue;
                }
                if dt <= 2.5 * m {
                    out.push((0.5 * (tp + t), 1 - foot));
                    inserted += 1;
                }
            }
        }
        out.push((t, foot));
    }
    (out.into_iter().map(|s| s.0).collect(), dropped, inserted)
}

/// How the accelerometer stream is presented to the detectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// As recorded (100–405 Hz).
    Native,
    /// Linearly interpolated onto a 100 Hz grid (the rate of many phones).
    Resampled100Hz,
    /// Linearly interpolated onto a 50 Hz grid.
    Resampled50Hz,
    /// 10 % of the samples dropped at random, the others' timestamps jittered by a
    /// Gaussian of σ = half the mean spacing, in recorded order: a sample whose time
    /// is not after the previous one is rejected by the detector and skipped (values
    /// unchanged: the phone sampled on time, the clock read late or early).
    Jittered,
    /// The same at 50 Hz (resampled first).
    Jittered50Hz,
    /// 10 % of the time dropped in bursts of 0.05–1 s (a busy phone), timestamps exact.
    Bursts,
    /// Linearly interpolated onto a 25 Hz grid (a phone or watch logging slowly to
    /// save power; below the 50–500 Hz of issue 14).
    Resampled25Hz,
}

impl Variant {
    pub const ALL: [Variant; 7] = [
        Variant::Native,
        Variant::Resampled100Hz,
        Variant::Resampled50Hz,
        Variant::Jittered,
        Variant::Jittered50Hz,
        Variant::Bursts,
        Variant::Resampled25Hz,
    ];
    fn name(self) -> &'static str {
        match self {
            Variant::Native => "native rate",
            Variant::Resampled100Hz => "resampled to 100 Hz",
            Variant::Resampled50Hz => "resampled to 50 Hz",
            Variant::Jittered => "jittered timestamps (σ ½ spacing), 10 % dropped",
            Variant::Jittered50Hz => "50 Hz, jittered timestamps (σ ½ spacing), 10 % dropped",
            Variant::Bursts => "10 % dropped in bursts of 0.05–1 s",
            Variant::Resampled25Hz => "resampled to 25 Hz",
        }
    }
}

/// Deterministic xorshift in 0..1.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = self.next().max(1e-300);
        let v = self.next();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// Linear interpolation of `raw` onto a grid of `hz`.
fn resample(raw: &[AccelSample], hz: f64) -> Vec<AccelSample> {
    let mut out = Vec::new();
    let (Some(first), Some(last)) = (raw.first(), raw.last()) else {
        return out;
    };
    let dt = 1.0 / hz;
    let mut k = 0u64;
    let mut j = 0;
    loop {
        let t = first.t_s + k as f64 * dt;
        if t > last.t_s {
            break;
        }
        while j + 1 < raw.len() && raw[j + 1].t_s < t {
            j += 1;
        }
        let (a, b) = (raw[j], raw[(j + 1).min(raw.len() - 1)]);
        let f = if b.t_s > a.t_s {
            ((t - a.t_s) / (b.t_s - a.t_s)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let v: [f64; 3] =
            std::array::from_fn(|i| a.accel_mps2[i] + f * (b.accel_mps2[i] - a.accel_mps2[i]));
        out.push(AccelSample {
            t_s: t,
            accel_mps2: v,
        });
        k += 1;
    }
    out
}

/// 10 % dropped at random, timestamps jittered by N(0, (½ mean spacing)²), order kept.
fn jitter_and_drop(raw: Vec<AccelSample>) -> Vec<AccelSample> {
    let (Some(a), Some(b)) = (raw.first(), raw.last()) else {
        return raw;
    };
    let dt = (b.t_s - a.t_s) / (raw.len().max(2) - 1) as f64;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut out = Vec::with_capacity(raw.len());
    for s in raw {
        if rng.next() < 0.1 {
            continue;
        }
        let j = rng.normal();
        out.push(AccelSample {
            t_s: s.t_s + 0.5 * dt * j,
            ..s
        });
    }
    out
}

/// 10 % of the time dropped in bursts of 0.05–1 s, spread over the trace.
fn drop_bursts(raw: Vec<AccelSample>) -> Vec<AccelSample> {
    let (Some(a), Some(b)) = (raw.first(), raw.last()) else {
        return raw;
    };
    let (t0, span) = (a.t_s, b.t_s - a.t_s);
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    // Bursts placed uniformly over the trace (lengths 0.05–1 s) until 10 % of its
    // span is covered.
    let mut bursts: Vec<(f64, f64)> = Vec::new();
    let mut covered = 0.0;
    while covered < 0.1 * span {
        let start = t0 + rng.next() * span;
        let len = 0.05 + 0.95 * rng.next();
        bursts.push((start, start + len));
        covered += len;
    }
    raw.into_iter()
        .filter(|s| !bursts.iter().any(|&(x, y)| s.t_s >= x && s.t_s < y))
        .collect()
}

/// The trace's samples as presented by `variant`.
pub fn samples(trace: &OxfordTrace, variant: Variant) -> Vec<AccelSample> {
    let raw: Vec<AccelSample> = trace
        .accel
        .iter()
        .map(|a| AccelSample {
            t_s: a.t_s,
            accel_mps2: a.accel_mps2,
        })
        .collect();
    match variant {
        Variant::Native => raw,
        Variant::Resampled100Hz => resample(&raw, 100.0),
        Variant::Resampled50Hz => resample(&raw, 50.0),
        Variant::Jittered => jitter_and_drop(raw),
        Variant::Jittered50Hz => jitter_and_drop(resample(&raw, 50.0)),
        Variant::Bursts => drop_bursts(raw),
        Variant::Resampled25Hz => resample(&raw, 25.0),
    }
}

/// Step times of one detector over `samples`.
pub fn detect(config: StepDetectorConfig, samples: &[AccelSample]) -> Vec<f64> {
    let mut d = StepDetector::new(config).expect("valid configuration");
    d.push_batch(samples)
        .estimates
        .iter()
        .map(|e| e.t_s)
        .collect()
}

/// Matched pairs within the tolerance, one-to-one (both lists sorted).
pub fn matches(detected: &[f64], reference: &[f64], tol_s: f64) -> usize {
    let (mut i, mut j, mut n) = (0, 0, 0);
    while i < detected.len() && j < reference.len() {
        let d = detected[i] - reference[j];
        if d.abs() <= tol_s {
            n += 1;
            i += 1;
            j += 1;
        } else if d < 0.0 {
            i += 1;
        } else {
            j += 1;
        }
    }
    n
}

/// Scores of one detector on one trace.
#[derive(Clone, Copy, Debug)]
pub struct Score {
    pub reference: usize,
    pub detected: usize,
    pub count_error_pct: f64,
    pub f1: f64,
    /// Median of detected − matched reference time, s.
    pub lag_s: f64,
}

pub fn score(detected: &[f64], reference: &[f64]) -> Score {
    let m = matches(detected, reference, MATCH_TOLERANCE_S) as f64;
    let (nd, nr) = (detected.len() as f64, reference.len() as f64);
    let f1 = if nd + nr > 0.0 {
        2.0 * m / (nd + nr)
    } else {
        1.0
    };
    // Lag: nearest reference to each detected step (informative only).
    let mut lags: Vec<f64> = detected
        .iter()
        .filter_map(|&t| {
            let k = reference.partition_point(|&r| r < t);
            let cands = [k.checked_sub(1), Some(k)];
            cands
                .iter()
                .flatten()
                .filter_map(|&k| reference.get(k).map(|r| t - r))
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        })
        .collect();
    lags.sort_by(f64::total_cmp);
    Score {
        reference: reference.len(),
        detected: detected.len(),
        count_error_pct: 100.0 * (nd - nr) / nr,
        f1,
        lag_s: lags.get(lags.len() / 2).copied().unwrap_or(f64::NAN),
    }
}

use crate::stats::median;

/// Summary of a set of scores: median |count error| %, worst |count error| %, median F1,
/// mean F1.
fn summary(s: &[Score]) -> Summary {
    let abs: Vec<f64> = s.iter().map(|s| s.count_error_pct.abs()).collect();
    let worst = abs.iter().copied().fold(0.0, f64::max);
    let f1: Vec<f64> = s.iter().map(|s| s.f1).collect();
    let mean_f1 = f1.iter().sum::<f64>() / f1.len().max(1) as f64;
    (median(abs), worst, median(f1), mean_f1)
}

const NV: usize = Variant::ALL.len();

struct Row {
    trace: OxfordTrace,
    rate_hz: f64,
    /// [variant][detector]
    scores: [[Score; 2]; NV],
    /// Against the alternation-checked reference, [variant][detector].
    checked: [[Score; 2]; NV],
    /// Reference strikes dropped / inserted by the alternation check.
    fixes: (usize, usize),
}

/// Parameters of the default detector varied by the sensitivity and leave-one-user-out
/// checks.
type Knob = (&'static str, fn(&mut RobustStepParams) -> &mut f64);
const KNOBS: [Knob; 8] = [
    ("lowpass_hz", |p| &mut p.lowpass_hz),
    ("hysteresis_rel", |p| &mut p.hysteresis_rel),
    ("min_amplitude_mps2", |p| &mut p.min_amplitude_mps2),
    ("relative_amplitude", |p| &mut p.relative_amplitude),
    ("min_periodicity", |p| &mut p.min_periodicity),
    ("regularity", |p| &mut p.regularity),
    ("refractory", |p| &mut p.refractory),
    ("min_impact_ratio", |p| &mut p.min_impact_ratio),
];

/// Native-rate scores of `config` on every trace.
fn scores_of(config: StepDetectorConfig, traces: &[(OxfordTrace, Vec<AccelSample>)]) -> Vec<Score> {
    traces
        .iter()
        .map(|(t, s)| score(&detect(config, s), &t.heel_strikes_t_s))
        .collect()
}

/// A summary of scores: median |count error| %, worst |count error| %, median F1, mean F1.
type Summary = (f64, f64, f64, f64);

/// The sensitivity and leave-one-user-out checks of the default detector, rendered by
/// [`RobustnessReport::render`].
pub struct RobustnessReport {
    /// Traces scored (all, native rate, alternation-checked reference).
    traces: usize,
    /// The default detector's summary.
    defaults: Summary,
    knobs: Vec<KnobRow>,
    held_out: Vec<HeldOut>,
}

/// One parameter of the default detector scaled by 0.75 and 1.25.
struct KnobRow {
    name: &'static str,
    default: f64,
    /// The summary at ×0.75 and ×1.25; `None` when the scaled setting is invalid.
    scaled: [Option<Summary>; 2],
}

/// One held-out user of the leave-one-user-out check.
struct HeldOut {
    user: String,
    traces: usize,
    /// The grid setting chosen on the other users and its held-out summary; `None`
    /// when there is no other user to choose on.
    chosen: Option<(RobustStepParams, Summary)>,
    /// The fixed default's held-out summary.
    fixed: Summary,
}

/// Sensitivity of the default detector to each parameter (×0.75, ×1.25), and a
/// leave-one-user-out check: a grid search over three parameters picks the best setting
/// on two users (lowest mean |count error|) and is scored on the third, next to the
/// fixed default.
pub fn robustness(dir: &Path) -> Result<RobustnessReport, String> {
    let traces = checked_traces(dir)?;
    let base = StepDetectorConfig::default();
    let fixed = scores_of(base, &traces);
    Ok(RobustnessReport {
        traces: traces.len(),
        defaults: summary(&fixed),
        knobs: sensitivity(base, &traces),
        held_out: leave_one_user_out(base, &traces, &fixed),
    })
}

/// Every trace under `dir` at its native rate, its reference replaced by the
/// alternation-checked one.
fn checked_traces(dir: &Path) -> Result<Vec<(OxfordTrace, Vec<AccelSample>)>, String> {
    let paths = list_oxford_traces(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut traces = Vec::new();
    for p in &paths {
        let mut t = read_oxford_trace(p).map_err(|e| format!("{}: {e}", p.display()))?;
        let s = samples(&t, Variant::Native);
        t.heel_strikes_t_s = alternation_checked(&strikes_by_foot(p)?).0;
        traces.push((t, s));
    }
    Ok(traces)
}

/// Each knob of `base` scaled by 0.75 and 1.25, the others at their defaults.
fn sensitivity(
    base: StepDetectorConfig,
    traces: &[(OxfordTrace, Vec<AccelSample>)],
) -> Vec<KnobRow> {
    let pb = crate::progress::bar(KNOBS.len(), "eval steps: sensitivity");
    KNOBS
        .iter()
        .map(|&(name, get)| {
            pb.inc(1);
            let scaled = [0.75, 1.25].map(|f| {
                let mut c = base;
                *get(&mut c.robust) *= f;
                StepDetector::new(c)
                    .ok()
                    .map(|_| summary(&scores_of(c, traces)))
            });
            let mut c = base;
            KnobRow {
                name,
                default: *get(&mut c.robust),
                scaled,
            }
        })
        .collect()
}

/// The settings the leave-one-user-out check chooses among: `base` with relative
/// amplitude, periodicity, hysteresis, regularity and refractory varied.
fn grid(base: StepDetectorConfig) -> Vec<StepDetectorConfig> {
    let mut g = Vec::new();
    for ra in [0.35, 0.45, 0.55] {
        for mp in [0.3, 0.4, 0.5] {
            for hr in [0.4, 0.5, 0.6] {
                for rg in [0.2, 0.3] {
                    for rf in [0.6, 0.65, 0.7] {
                        let mut c = base;
                        c.robust.relative_amplitude = ra;
                        c.robust.min_periodicity = mp;
                        c.robust.hysteresis_rel = hr;
                        c.robust.regularity = rg;
                        c.robust.refractory = rf;
                        g.push(c);
                    }
                }
            }
        }
    }
    g
}

/// Each user held out in turn: the grid setting with the lowest mean |count error| on
/// the others, scored on this user next to the fixed default (`fixed`: its scores).
fn leave_one_user_out(
    base: StepDetectorConfig,
    traces: &[(OxfordTrace, Vec<AccelSample>)],
    fixed: &[Score],
) -> Vec<HeldOut> {
    let grid = grid(base);
    let all: Vec<Vec<Score>> = grid.iter().map(|c| scores_of(*c, traces)).collect();
    users_of(traces.iter().map(|t| &t.0))
        .into_iter()
        .map(|user| held_out(user, traces, &grid, &all, fixed))
        .collect()
}

/// `user` held out: the best of `grid` (scores `all`) on the other users, scored on
/// this user's traces.
fn held_out(
    user: String,
    traces: &[(OxfordTrace, Vec<AccelSample>)],
    grid: &[StepDetectorConfig],
    all: &[Vec<Score>],
    fixed: &[Score],
) -> HeldOut {
    let (held, train): (Vec<usize>, Vec<usize>) =
        (0..traces.len()).partition(|&i| traces[i].0.user == user);
    let pick = |g: &[Score]| held.iter().map(|&i| g[i]).collect::<Vec<_>>();
    let chosen = (!train.is_empty()).then(|| {
        let mean_abs = |g: &[Score]| {
            train
                .iter()
                .map(|&i| g[i].count_error_pct.abs())
                .sum::<f64>()
                / train.len() as f64
        };
        let best = (0..grid.len())
            .min_by(|&a, &b| mean_abs(&all[a]).total_cmp(&mean_abs(&all[b])))
            .unwrap_or(0);
        (grid[best].robust, summary(&pick(&all[best])))
    });
    HeldOut {
        user,
        traces: held.len(),
        chosen,
        fixed: summary(&pick(fixed)),
    }
}

/// `med % / worst % / med F1`.
fn three(s: Summary) -> String {
    format!("{:.2} % / {:.2} % / {:.3}", s.0, s.1, s.2)
}

/// `med % / worst % / med F1 / mean F1`.
fn four(s: Summary) -> String {
    format!("{:.2} % / {:.2} % / {:.3} / {:.3}", s.0, s.1, s.2, s.3)
}

impl RobustnessReport {
    /// The two checks as markdown: text, then a table each.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "Sensitivity of the default detector (native rate, all {} traces, alternation-checked reference): each parameter scaled by 0.75 and 1.25, the others at their defaults.\n", self.traces);
        out.push_str(&self.sensitivity_table().render());
        let _ = writeln!(out, "\nLeave one user out (alternation-checked reference): grid over relative_amplitude ∈ {{0.35, 0.45, 0.55}} × min_periodicity ∈ {{0.3, 0.4, 0.5}} × hysteresis_rel ∈ {{0.4, 0.5, 0.6}} × regularity ∈ {{0.2, 0.3}} × refractory ∈ {{0.6, 0.65, 0.7}}; the setting with the lowest mean |count error| on the two other users is scored on the held-out user.\n");
        out.push_str(&self.held_out_table().render());
        out
    }

    fn sensitivity_table(&self) -> Table {
        let mut t = Table::new([
            "parameter",
            "default",
            "×0.75: med / worst / med F1",
            "×1.25: med / worst / med F1",
        ]);
        t.row([
            "(defaults)".to_string(),
            String::new(),
            three(self.defaults),
            String::new(),
        ]);
        for k in &self.knobs {
            let [a, b] = k.scaled.map(|s| s.map_or_else(|| "invalid".into(), three));
            t.row([k.name.to_string(), k.default.to_string(), a, b]);
        }
        t
    }

    fn held_out_table(&self) -> Table {
        let mut t = Table::new([
            "held-out user",
            "traces",
            "setting chosen on the others (rel. amp., periodicity, hysteresis, regularity, refractory)",
            "held out, chosen: med / worst / med F1",
            "held out, fixed default: med / worst / med F1",
        ]);
        for h in &self.held_out {
            let (setting, chosen) = match h.chosen {
                None => (
                    "– (no other user to choose on)".to_string(),
                    "–".to_string(),
                ),
                Some((r, c)) => (
                    format!(
                        "{}, {}, {}, {}, {}",
                        r.relative_amplitude,
                        r.min_periodicity,
                        r.hysteresis_rel,
                        r.regularity,
                        r.refractory
                    ),
                    three(c),
                ),
            };
            t.row([
                h.user.clone(),
                h.traces.to_string(),
                setting,
                chosen,
                three(h.fixed),
            ]);
        }
        t
    }
}

/// The users of `traces` in order of first appearance (the traces are sorted by
/// name), so that a folder with other users (held-out recordings) gets their rows too.
fn users_of<'a>(traces: impl Iterator<Item = &'a OxfordTrace>) -> Vec<String> {
    let mut users: Vec<String> = Vec::new();
    for t in traces {
        if !users.contains(&t.user) {
            users.push(t.user.clone());
        }
    }
    users
}

/// Every trace scored by both detectors on every variant, rendered by
/// [`StepsReport::render`].
pub struct StepsReport {
    /// The folder of the traces, as displayed.
    dir: String,
    rows: Vec<Row>,
}

/// The full evaluation: the AsPublished and default detectors on every trace.
pub fn run(dir: &Path) -> Result<StepsReport, String> {
    let paths = list_oxford_traces(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if paths.is_empty() {
        return Err(format!("no Oxford traces in {}", dir.display()));
    }
    let configs = [
        StepDetectorConfig::as_published(),
        StepDetectorConfig::default(),
    ];
    let mut rows = Vec::new();
    let pb = crate::progress::bar(paths.len(), "eval steps: traces");
    for p in &paths {
        pb.inc(1);
        rows.push(score_trace(p, &configs)?);
    }
    Ok(StepsReport {
        dir: dir.display().to_string(),
        rows,
    })
}

/// One trace scored by `configs` on every variant, against the recorded and the
/// alternation-checked reference (the samples are dropped after).
fn score_trace(p: &Path, configs: &[StepDetectorConfig; 2]) -> Result<Row, String> {
    let mut trace = read_oxford_trace(p).map_err(|e| format!("{}: {e}", p.display()))?;
    let (clean_ref, dropped, inserted) = alternation_checked(&strikes_by_foot(p)?);
    let mut scores = [[None; 2]; NV];
    let mut checked = [[None; 2]; NV];
    for (vi, v) in Variant::ALL.iter().enumerate() {
        let s = samples(&trace, *v);
        for (ci, c) in configs.iter().enumerate() {
            let det = detect(*c, &s);
            scores[vi][ci] = Some(score(&det, &trace.heel_strikes_t_s));
            checked[vi][ci] = Some(score(&det, &clean_ref));
        }
    }
    let rate_hz = trace.rate_hz();
    trace.accel = Vec::new();
    Ok(Row {
        trace,
        rate_hz,
        scores: scores.map(|v| v.map(|s| s.expect("scored"))),
        checked: checked.map(|v| v.map(|s| s.expect("scored"))),
        fixes: (dropped, inserted),
    })
}

impl StepsReport {
    /// The evaluation as markdown: the per-trace table, then the summaries against the
    /// recorded and the alternation-checked reference.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Oxford Step Counter traces ({}, {} traces; Salvi et al. 2018, CC BY 4.0). Reference: heel strikes of the shoe-worn sensor. Count error = (detected − reference) / reference; F1: detected step within ±{MATCH_TOLERANCE_S} s of a reference heel strike, one-to-one. One configuration for all traces.\n",
            self.dir,
            self.rows.len()
        );
        let _ = writeln!(out, "Per trace, native rate:\n");
        out.push_str(&self.per_trace_table().render());
        let [recorded, checked] = self.summary_tables();
        let _ = writeln!(
            out,
            "\nSummary (median |count error|, worst |count error|, median F1, mean F1):\n"
        );
        out.push_str(&recorded.render());
        let _ = writeln!(out, "\nAgainst the alternation-checked reference (walking alternates feet: a strike of the same foot as the previous one within 1.5 median step intervals is contact chatter and dropped; one a stride later means the other foot's strike was not registered and one is inserted; the per-trace table gives the counts):\n\n{}", checked.render());
        out
    }

    fn per_trace_table(&self) -> Table {
        let mut t = Table::new([
            "trace",
            "Hz",
            "reference",
            "AsPublished steps",
            "AsPublished error",
            "AsPublished F1",
            "default steps",
            "default error",
            "default F1",
            "default lag s",
            "default error @100 Hz / @50 Hz / jittered / 50 Hz jittered / bursts / @25 Hz",
            "alternation check: reference strikes dropped / inserted",
            "default vs checked reference: error / F1",
        ]);
        for r in &self.rows {
            let [p, d] = r.scores[0];
            let db = r.checked[0][1];
            let others: Vec<String> = (1..NV)
                .map(|v| format!("{:+.1} %", r.scores[v][1].count_error_pct))
                .collect();
            t.row([
                r.trace.name.clone(),
                format!("{:.0}", r.rate_hz),
                p.reference.to_string(),
                p.detected.to_string(),
                format!("{:+.1} %", p.count_error_pct),
                format!("{:.3}", p.f1),
                d.detected.to_string(),
                format!("{:+.1} %", d.count_error_pct),
                format!("{:.3}", d.f1),
                format!("{:+.3}", d.lag_s),
                others.join(" / "),
                format!("{} / {}", r.fixes.0, r.fixes.1),
                format!("{:+.1} % / {:.3}", db.count_error_pct, db.f1),
            ]);
        }
        t
    }

    /// The summary tables against the recorded and the alternation-checked reference:
    /// every variant, each position and user at the native rate, each user per variant.
    fn summary_tables(&self) -> [Table; 2] {
        let header = [
            "group",
            "traces",
            "AsPublished: med / worst / med F1 / mean F1",
            "default: med / worst / med F1 / mean F1",
        ];
        let mut tables = [Table::new(header), Table::new(header)];
        let mut line = |name: String, sel: &dyn Fn(&Row) -> bool, vi: usize| {
            line_of(&mut tables[0], &self.rows, &name, sel, &|r: &Row| {
                r.scores[vi]
            });
            line_of(&mut tables[1], &self.rows, &name, sel, &|r: &Row| {
                r.checked[vi]
            });
        };
        for (vi, v) in Variant::ALL.iter().enumerate() {
            line(format!("**all, {}**", v.name()), &|_| true, vi);
        }
        for pos in OxfordPosition::ALL
            .into_iter()
            .chain([OxfordPosition::Other])
        {
            line(format!("{pos}"), &|r: &Row| r.trace.position == pos, 0);
        }
        let users = users_of(self.rows.iter().map(|r| &r.trace));
        for user in &users {
            line(format!("user {user}"), &|r: &Row| &r.trace.user == user, 0);
        }
        for (vi, v) in Variant::ALL.iter().enumerate().skip(1) {
            for user in &users {
                line(
                    format!("user {user}, {}", v.name()),
                    &|r: &Row| &r.trace.user == user,
                    vi,
                );
            }
        }
        tables
    }
}

/// One summary row: the scores `pick` selects of the rows `sel` accepts.
fn line_of(
    table: &mut Table,
    rows: &[Row],
    name: &str,
    sel: &dyn Fn(&Row) -> bool,
    pick: &dyn Fn(&Row) -> [Score; 2],
) {
    let (p, d): (Vec<Score>, Vec<Score>) = rows
        .iter()
        .filter(|r| sel(r))
        .map(|r| {
            let s = pick(r);
            (s[0], s[1])
        })
        .unzip();
    if d.is_empty() {
        return;
    }
    table.row([
        name.to_string(),
        d.len().to_string(),
        four(summary(&p)),
        four(summary(&d)),
    ]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trace(user: &str) -> OxfordTrace {
        OxfordTrace {
            name: format!("Pixel_{user}_Hard_InHand_1"),
            phone: "Pixel".into(),
            user: user.into(),
            surface: "Hard".into(),
            position: OxfordPosition::InHand,
            accel: Vec::new(),
            heel_strikes_t_s: Vec::new(),
        }
    }

    #[test]
    fn users_come_from_the_traces_in_order_of_appearance() {
        let t = [trace("Jamie"), trace("Alice"), trace("Jamie"), trace("Bo")];
        assert_eq!(users_of(t.iter()), ["Jamie", "Alice", "Bo"]);
    }
}
