//! `stridekit train zupt`: host-side training of the SVM zero-velocity detector
//! (method 2 of docs/architecture.md): six Gaussian-kernel SVMs, one per feature pair (peak ‖f‖ over
//! the gait window, ln(σ of one axis + 1e-3)), labels = the stance labels of each
//! training trial's best detector (`zv_<best>_opt`, per `_summary.csv`).
//!
//! The features come from the navigator itself ([`FootNavigator::detector_stats`]),
//! so training and inference share one code path. The solver is a small SMO
//! (LIBSVM's second-order working-set selection) on a class-balanced, gait-stratified
//! subsample of a few thousand points: the problem is 2-D and small, a hand-written
//! solver keeps the build dependency-free and CI fast (seconds in release).

use std::path::Path;

use stridekit_core::foot::{FootConfig, FootNavigator, FootSample, SvmModel, WindowStats};
use stridekit_core::foot::{PairSvm, SIGMA_EPS};

use crate::foot::eval::Trial;

/// Training hyper-parameters: γ = 0.5, C = 1 chosen among (1, 1), (2, 10), (0.5, 1)
/// by 3-fold cross-validation inside the training split (`stridekit eval foot
/// --tune`, see docs/foot.md).
#[derive(Clone, Copy, Debug)]
pub struct TrainParams {
    /// Kernel width in standardised feature units: K = exp(−γ‖a − b‖²).
    pub gamma: f64,
    /// Box constraint.
    pub c: f64,
    /// Points per class in the training subsample.
    pub per_class: usize,
    /// Seed of the subsample.
    pub seed: u64,
}

impl Default for TrainParams {
    fn default() -> Self {
        Self {
            gamma: 0.5,
            c: 1.0,
            per_class: 300,
            seed: 1,
        }
    }
}

/// One training sample: the window statistics the navigator's detector saw and the
/// reference label.
pub type Labelled = (WindowStats, bool);

/// Window statistics of every sample of a trial (index of the sample, stats), by the
/// navigator's own code path.
pub fn trial_stats(
    trial: &Trial,
    config: &FootConfig,
) -> Result<Vec<(usize, WindowStats)>, String> {
    let rec = &trial.rec;
    let mut nav = FootNavigator::new(config.clone()).map_err(|e| e.to_string())?;
    let mut out = Vec::with_capacity(rec.len());
    for i in 0..rec.len() {
        let s = FootSample {
            t_s: rec.t_s[i],
            accel_mps2: rec.accel_mps2[i],
            gyro_rads: rec.gyro_rads[i],
        };
        if let Some(e) = nav
            .push(&s)
            .map_err(|e| format!("{} sample {i}: {e}", rec.name))?
        {
            let k = rec.t_s.partition_point(|&t| t < e.t_s);
            if let Some(st) = nav.detector_stats() {
                out.push((k, st));
            }
        }
    }
    Ok(out)
}

/// Labelled samples of the training trials (reference: each trial's best detector).
pub fn labelled(trials: &[&Trial], config: &FootConfig) -> Result<Vec<Labelled>, String> {
    let mut out = Vec::new();
    for t in trials {
        out.extend(labelled_from(t, &trial_stats(t, config)?)?);
    }
    Ok(out)
}

/// Labelled samples of one trial from its window statistics ([`trial_stats`]).
pub fn labelled_from(t: &Trial, stats: &[(usize, WindowStats)]) -> Result<Vec<Labelled>, String> {
    let labels = t
        .rec
        .label(&t.best)
        .ok_or_else(|| format!("{}: no label column {}", t.rec.name, t.best))?;
    Ok(stats
        .iter()
        .filter(|(_, st)| !st.saturated)
        .map(|(k, st)| (*st, labels[*k]))
        .collect())
}

fn sigma(s: &WindowStats, axis: usize) -> f64 {
    if axis < 3 {
        s.acc_std_mps2[axis]
    } else {
        s.gyro_std_rads[axis - 3]
    }
}

fn raw_features(s: &WindowStats, axis: usize) -> [f64; 2] {
    [s.peak_acc_norm_mps2, (sigma(s, axis) + SIGMA_EPS).ln()]
}

/// splitmix64.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Peak ‖f‖ from which a training point counts as running for the stratified
/// subsample, m/s² (run stance has a median peak of ~77 m/s², walk swing ~29).
const RUN_PEAK: f64 = 60.0;

/// Class-balanced subsample, stratified by gait (peak ‖f‖ below / above `RUN_PEAK`) so
/// the few running strides are not drowned by walking: per class, half the points
/// from each stratum when it has enough.
fn subsample(data: &[Labelled], per_class: usize, seed: u64) -> Vec<Labelled> {
    let mut rng = Rng(seed);
    let mut out = Vec::new();
    for class in [true, false] {
        let strata: [Vec<&Labelled>; 2] = [
            data.iter()
                .filter(|(s, l)| *l == class && s.peak_acc_norm_mps2 < RUN_PEAK)
                .collect(),
            data.iter()
                .filter(|(s, l)| *l == class && s.peak_acc_norm_mps2 >= RUN_PEAK)
                .collect(),
        ];
        let want_hi = (per_class / 2).min(strata[1].len());
        let want_lo = (per_class - want_hi).min(strata[0].len());
        for (pool, want) in [(&strata[0], want_lo), (&strata[1], want_hi)] {
            let mut idx: Vec<usize> = (0..pool.len()).collect();
            // Partial Fisher–Yates.
            for k in 0..want {
                let j = k + rng.below(idx.len() - k);
                idx.swap(k, j);
                out.push(*pool[idx[k]]);
            }
        }
    }
    out
}

/// A trained binary SVM: `f(x) = Σ coef_i K(x, s_i) − ρ`.
#[derive(Clone, Debug, PartialEq)]
pub struct Trained {
    /// `(α_i·y_i, x_i)` of the support vectors (α > 0).
    pub support: Vec<(f64, [f64; 2])>,
    pub rho: f64,
    pub iterations: usize,
}

impl Trained {
    #[cfg(test)]
    pub fn decision(&self, x: [f64; 2], gamma: f64) -> f64 {
        self.support
            .iter()
            .map(|(c, s)| c * (-gamma * ((x[0] - s[0]).powi(2) + (x[1] - s[1]).powi(2))).exp())
            .sum::<f64>()
            - self.rho
    }
}

/// C-SVM with a Gaussian kernel by SMO (LIBSVM's second-order working-set selection
/// and ρ). `y` is ±1.
pub fn smo(x: &[[f64; 2]], y: &[f64], gamma: f64, c: f64, eps: f64, max_iter: usize) -> Trained {
    let mut s = Smo {
        n: x.len(),
        y,
        c,
        kmat: kernel_matrix(x, gamma),
        alpha: vec![0.0_f64; x.len()],
        grad: vec![-1.0_f64; x.len()],
    };
    let mut iterations = 0;
    while iterations < max_iter {
        iterations += 1;
        let Some((i, j)) = s.working_set(eps) else {
            break;
        };
        s.step(i, j);
    }
    let rho = s.rho();
    let support = (0..s.n)
        .filter(|&t| s.alpha[t] > 0.0)
        .map(|t| (s.alpha[t] * y[t], x[t]))
        .collect();
    Trained {
        support,
        rho,
        iterations,
    }
}

/// Floor of the curvature along a working-set direction (LIBSVM's τ).
const SMO_TAU: f64 = 1e-12;

/// The Gaussian kernel matrix of `x`, row-major n × n.
fn kernel_matrix(x: &[[f64; 2]], gamma: f64) -> Vec<f64> {
    let n = x.len();
    let k = |a: usize, b: usize| -> f64 {
        let d0 = x[a][0] - x[b][0];
        let d1 = x[a][1] - x[b][1];
        (-gamma * (d0 * d0 + d1 * d1)).exp()
    };
    let mut kmat = vec![0.0_f64; n * n];
    for a in 0..n {
        for b in a..n {
            let v = k(a, b);
            kmat[a * n + b] = v;
            kmat[b * n + a] = v;
        }
    }
    kmat
}

/// The SMO state: labels, bound, kernel matrix, multipliers and gradient.
struct Smo<'a> {
    n: usize,
    y: &'a [f64],
    c: f64,
    kmat: Vec<f64>,
    alpha: Vec<f64>,
    grad: Vec<f64>,
}

impl Smo<'_> {
    fn q(&self, a: usize, b: usize) -> f64 {
        self.y[a] * self.y[b] * self.kmat[a * self.n + b]
    }

    /// The pair to update: i maximises −y G over I_up, j by second-order gain over
    /// I_low; `None` when optimal within `eps` (or no pair is left).
    fn working_set(&self, eps: f64) -> Option<(usize, usize)> {
        let (y, alpha, grad, c) = (self.y, &self.alpha, &self.grad, self.c);
        let mut gmax = f64::NEG_INFINITY;
        let mut i = usize::MAX;
        for t in 0..self.n {
            let up = if y[t] > 0.0 {
                alpha[t] < c
            } else {
                alpha[t] > 0.0
            };
            if up && -y[t] * grad[t] >= gmax {
                gmax = -y[t] * grad[t];
                i = t;
            }
        }
        if i == usize::MAX {
            return None;
        }
        let (n, kmat) = (self.n, &self.kmat);
        let mut gmin = f64::INFINITY;
        let mut j = usize::MAX;
        let mut best = f64::INFINITY;
        for t in 0..n {
            let low = if y[t] > 0.0 {
                alpha[t] > 0.0
            } else {
                alpha[t] < c
            };
            if !low {
                continue;
            }
            let v = -y[t] * grad[t];
            gmin = gmin.min(v);
            let b = gmax - v;
            if b > 0.0 {
                let a = (kmat[i * n + i] + kmat[t * n + t] - 2.0 * kmat[i * n + t]).max(SMO_TAU);
                let obj = -b * b / a;
                if obj <= best {
                    best = obj;
                    j = t;
                }
            }
        }
        if j == usize::MAX || gmax - gmin < eps {
            return None;
        }
        Some((i, j))
    }

    /// Update α_i, α_j (clipped to the box) and the gradient.
    fn step(&mut self, i: usize, j: usize) {
        let (ai, aj) = (self.alpha[i], self.alpha[j]);
        let n = self.n;
        let quad =
            (self.kmat[i * n + i] + self.kmat[j * n + j] - 2.0 * self.kmat[i * n + j]).max(SMO_TAU);
        if self.y[i] != self.y[j] {
            self.step_opposite(i, j, quad);
        } else {
            self.step_same(i, j, quad);
        }
        let (di, dj) = (self.alpha[i] - ai, self.alpha[j] - aj);
        for t in 0..n {
            let d = self.q(t, i) * di + self.q(t, j) * dj;
            self.grad[t] += d;
        }
    }

    /// y_i ≠ y_j: α_i − α_j stays constant.
    fn step_opposite(&mut self, i: usize, j: usize, quad: f64) {
        let (c, alpha) = (self.c, &mut self.alpha);
        let delta = (-self.grad[i] - self.grad[j]) / quad;
        let diff = alpha[i] - alpha[j];
        alpha[i] += delta;
        alpha[j] += delta;
        if diff > 0.0 {
            if alpha[j] < 0.0 {
                alpha[j] = 0.0;
                alpha[i] = diff;
            }
        } else if alpha[i] < 0.0 {
            alpha[i] = 0.0;
            alpha[j] = -diff;
        }
        if diff > 0.0 {
            if alpha[i] > c {
                alpha[i] = c;
                alpha[j] = c - diff;
            }
        } else if alpha[j] > c {
            alpha[j] = c;
            alpha[i] = c + diff;
        }
    }

    /// y_i = y_j: α_i + α_j stays constant.
    fn step_same(&mut self, i: usize, j: usize, quad: f64) {
        let (c, alpha) = (self.c, &mut self.alpha);
        let delta = (self.grad[i] - self.grad[j]) / quad;
        let sum = alpha[i] + alpha[j];
        alpha[i] -= delta;
        alpha[j] += delta;
        if sum > c {
            if alpha[i] > c {
                alpha[i] = c;
                alpha[j] = sum - c;
            }
        } else if alpha[j] < 0.0 {
            alpha[j] = 0.0;
            alpha[i] = sum;
        }
        if sum > c {
            if alpha[j] > c {
                alpha[j] = c;
                alpha[i] = sum - c;
            }
        } else if alpha[i] < 0.0 {
            alpha[i] = 0.0;
            alpha[j] = sum;
        }
    }

    /// ρ as in LIBSVM: the mean of y G over the free multipliers, else the middle of
    /// the bounds.
    fn rho(&self) -> f64 {
        let (y, alpha, c) = (self.y, &self.alpha, self.c);
        let (mut ub, mut lb) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut nfree, mut sfree) = (0usize, 0.0);
        for t in 0..self.n {
            let yg = y[t] * self.grad[t];
            if alpha[t] >= c {
                if y[t] < 0.0 {
                    ub = ub.min(yg);
                } else {
                    lb = lb.max(yg);
                }
            } else if alpha[t] <= 0.0 {
                if y[t] > 0.0 {
                    ub = ub.min(yg);
                } else {
                    lb = lb.max(yg);
                }
            } else {
                nfree += 1;
                sfree += yg;
            }
        }
        if nfree > 0 {
            sfree / nfree as f64
        } else {
            0.5 * (ub + lb)
        }
    }
}

fn mean_sd(v: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = v.clone().count().max(1) as f64;
    let m = v.clone().sum::<f64>() / n;
    let var = v.map(|x| (x - m).powi(2)).sum::<f64>() / n;
    (m, var.sqrt().max(1e-6))
}

/// Trains the six pair SVMs on labelled samples; `comments` go into the model file.
pub fn train(
    data: &[Labelled],
    p: &TrainParams,
    comments: Vec<String>,
) -> Result<SvmModel, String> {
    let sub = subsample(data, p.per_class, p.seed);
    let npos = sub.iter().filter(|(_, l)| *l).count();
    if npos < 10 || sub.len() - npos < 10 {
        return Err(format!(
            "too few labelled samples of a class ({npos} stance, {} swing)",
            sub.len() - npos
        ));
    }
    let y: Vec<f64> = sub
        .iter()
        .map(|(_, l)| if *l { 1.0 } else { -1.0 })
        .collect();
    let mut pairs = Vec::new();
    for axis in 0..6 {
        let raw: Vec<[f64; 2]> = sub.iter().map(|(s, _)| raw_features(s, axis)).collect();
        let (m0, s0) = mean_sd(raw.iter().map(|r| r[0]));
        let (m1, s1) = mean_sd(raw.iter().map(|r| r[1]));
        let x: Vec<[f64; 2]> = raw
            .iter()
            .map(|r| [(r[0] - m0) / s0, (r[1] - m1) / s1])
            .collect();
        let t = smo(&x, &y, p.gamma, p.c, 1e-3, 200_000);
        // Box: the region the training data covered (slightly padded); beyond it
        // the detector holds the edge value (see the svm module docs).
        let pad = 0.2;
        let lo = |d: usize| x.iter().map(|v| v[d]).fold(f64::INFINITY, f64::min) - pad;
        let hi = |d: usize| x.iter().map(|v| v[d]).fold(f64::NEG_INFINITY, f64::max) + pad;
        let support: Vec<[f64; 3]> = t.support.iter().map(|(c, s)| [*c, s[0], s[1]]).collect();
        pairs.push(
            PairSvm::new(
                axis,
                p.gamma,
                t.rho,
                [m0, m1],
                [s0, s1],
                [lo(0), hi(0), lo(1), hi(1)],
                support,
            )
            .map_err(|e| e.to_string())?,
        );
    }
    Ok(SvmModel { pairs, comments })
}

/// Which trials a `--trials` / `--split` option selects for training.
/// `K/N` of `--split`: fold K of N, 1 ≤ K ≤ N, N ≥ 2.
pub fn parse_split(split: &str) -> Result<(usize, usize), String> {
    split
        .split_once('/')
        .and_then(|(k, n)| Some((k.parse::<usize>().ok()?, n.parse::<usize>().ok()?)))
        .filter(|&(k, n)| n >= 2 && (1..=n).contains(&k))
        .ok_or_else(|| "--split takes K/N with 1 ≤ K ≤ N, N ≥ 2".to_string())
}

pub fn select<'a>(
    trials: &'a [Trial],
    list: Option<&str>,
    split: Option<&str>,
) -> Result<Vec<&'a Trial>, String> {
    if let Some(list) = list {
        let names: Vec<&str> = list.split(',').map(str::trim).collect();
        let sel: Vec<&Trial> = trials
            .iter()
            .filter(|t| names.contains(&t.rec.name.as_str()))
            .collect();
        if sel.len() != names.len() {
            return Err(format!(
                "--trials: {} of {} names found",
                sel.len(),
                names.len()
            ));
        }
        return Ok(sel);
    }
    if let Some(split) = split {
        let (k, n) = parse_split(split)?;
        return Ok(trials
            .iter()
            .enumerate()
            .filter(|(i, _)| i % n != k - 1)
            .map(|(_, t)| t)
            .collect());
    }
    Ok(trials.iter().collect())
}

/// The whole command: returns a summary for the terminal.
pub fn run(
    dir: &Path,
    list: Option<&str>,
    split: Option<&str>,
    out: &Path,
    command_line: &str,
) -> Result<String, String> {
    let sp = crate::progress::spinner("train zupt: reading the trials");
    let trials = crate::foot::eval::load(dir)?;
    let sel = select(&trials, list, split)?;
    let config = crate::foot::eval::base_config();
    sp.set_message("train zupt: labelled window statistics");
    let data = labelled(&sel, &config)?;
    sp.set_message("train zupt: training six SVMs");
    let p = TrainParams::default();
    let comments = vec![
        format!("trained by: {command_line}"),
        format!(
            "{} trials, {} labelled samples (labels: each trial's best detector zv_*_opt); subsample {} per class (seed {}), gamma {}, C {}",
            sel.len(),
            data.len(),
            p.per_class,
            p.seed,
            p.gamma,
            p.c
        ),
        format!(
            "features from FootNavigator with median_window {}, detector_window_s {}, gait_window_s {}",
            config.median_window, config.detector_window_s, config.gait_window_s
        ),
        format!(
            "trials: {}",
            sel.iter()
                .map(|t| t.rec.name.as_str())
                .collect::<Vec<_>>()
                .join(",")
        ),
    ];
    let model = train(&data, &p, comments)?;
    sp.finish_and_clear();
    let text = model.to_text();
    SvmModel::parse(&text).map_err(|e| format!("written model does not parse: {e}"))?;
    std::fs::write(out, &text).map_err(|e| format!("{}: {e}", out.display()))?;
    let agree = data
        .iter()
        .filter(|(s, l)| model.is_stance(s) == *l)
        .count() as f64
        / data.len().max(1) as f64
        * 100.0;
    let sv: Vec<String> = model
        .pairs
        .iter()
        .map(|p| p.support.len().to_string())
        .collect();
    Ok(format!(
        "wrote {} ({} trials, {} samples; support vectors per pair {}; agreement with the labels on the training samples {agree:.1} %)",
        out.display(),
        sel.len(),
        data.len(),
        sv.join(" ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smo_separates_a_toy_set() {
        // Two separable blobs and a ring: the Gaussian kernel must get all right.
        let mut x = Vec::new();
        let mut y = Vec::new();
        let mut rng = Rng(7);
        let mut u = || (rng.next() % 10_000) as f64 / 10_000.0 - 0.5;
        for _ in 0..60 {
            x.push([u() * 0.8, u() * 0.8]);
            y.push(1.0);
            let a = u() * std::f64::consts::TAU;
            let r = 1.5 + u() * 0.3;
            x.push([r * a.cos(), r * a.sin()]);
            y.push(-1.0);
        }
        let t = smo(&x, &y, 1.0, 10.0, 1e-4, 100_000);
        for (xi, yi) in x.iter().zip(&y) {
            assert_eq!(t.decision(*xi, 1.0) > 0.0, *yi > 0.0, "{xi:?}");
        }
        assert!(t.support.len() < x.len() / 2, "{} SVs", t.support.len());
        // Dual feasibility: Σ α y = 0.
        let s: f64 = t.support.iter().map(|(c, _)| c).sum();
        assert!(s.abs() < 1e-9, "{s}");
    }

    #[test]
    fn trained_model_round_trips_and_table_matches_kernel() {
        let mut data = Vec::new();
        let mut rng = Rng(3);
        for k in 0..800 {
            let stance = k % 2 == 0;
            let peak = 15.0 + (rng.next() % 5000) as f64 / 100.0;
            let base = if stance { 0.05 } else { 1.5 };
            let mut s = WindowStats {
                peak_acc_norm_mps2: peak,
                ..Default::default()
            };
            for i in 0..3 {
                s.acc_std_mps2[i] = base * (1.0 + (rng.next() % 100) as f64 / 100.0);
                s.gyro_std_rads[i] = 0.3 * base * (1.0 + (rng.next() % 100) as f64 / 100.0);
            }
            data.push((s, stance));
        }
        let p = TrainParams {
            per_class: 200,
            ..TrainParams::default()
        };
        let m = train(&data, &p, vec!["toy".into()]).unwrap();
        let back = SvmModel::parse(&m.to_text()).unwrap();
        assert_eq!(back, m);
        let ok = data.iter().filter(|(s, l)| m.is_stance(s) == *l).count();
        assert!(ok as f64 > 0.99 * data.len() as f64, "{ok}");
        for pair in &m.pairs {
            for (s, _) in data.iter().take(200) {
                let (x0, x1) = pair.features(s);
                let d = (pair.decision_scaled(x0, x1) - pair.exact_scaled(x0, x1)).abs();
                assert!(d < 0.02, "table vs kernel {d}");
            }
        }
    }
}
