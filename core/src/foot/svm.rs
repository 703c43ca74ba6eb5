//! The SVM zero-velocity detector (method 2 of docs/architecture.md): six Gaussian-kernel SVMs, one per
//! feature pair (peak ‖f‖ over the gait window, σ of one sensor axis over the
//! detector window); a sample is stance only if all six say so.
//!
//! # Model file (text, version 1)
//!
//! ```text
//! stridekit-zupt-svm 1
//! # free comment lines (how the model was trained)
//! svm acc_x gamma 0.8 rho -0.12 mean 30.1 -1.2 sd 12.3 1.1 box -3 4 -4 4 n 2
//! 0.73 0.12 -1.5
//! -0.73 1.20 0.3
//! svm acc_y ...
//! ```
//!
//! One `svm` block per axis (`acc_x acc_y acc_z gyro_x gyro_y gyro_z`, each exactly
//! once), followed by `n` support-vector lines `coef x0 x1` in scaled units.
//! Features: `x0 = (peak‖f‖ − mean0) / sd0`, `x1 = (ln(σ + 1e−3) − mean1) / sd1`
//! (σ in m/s² or rad/s). Decision `Σ coef_i·exp(−γ‖x − s_i‖²) − ρ > 0` ⇒ stance.
//! `box` is the scaled feature region the training data covered: the detector reads
//! a 128 × 128 table of the decision function over it, built at load time (bilinear
//! interpolation, a few ns). Features outside the box are clamped onto its edge:
//! a Gaussian-kernel sum decays to `−ρ` away from the data, which for `ρ < 0` would
//! call an extreme swing (σ far above anything seen) stance; clamping keeps the
//! decision the data supported at the edge (stiller than any training sample stays
//! stance, wilder stays swing).

use super::detect::WindowStats;
use super::error::FootError;
use crate::model_text::numbered_lines;

const GRID: usize = 128;
/// Most support vectors one block may hold (the shipped model has about 360): loading
/// costs about 20 µs per support vector, so a model file costs at most ~0.3 s.
pub const MAX_SUPPORT_VECTORS: usize = 2_000;
/// Largest model text accepted, bytes (6 full blocks fit in about 0.6 MB).
pub const MAX_MODEL_BYTES: usize = 1 << 20;
const AXES: [&str; 6] = ["acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z"];
/// Offset inside the logarithm of σ.
pub const SIGMA_EPS: f64 = 1e-3;

/// One SVM on a (peak ‖f‖, σ of one axis) pair.
#[derive(Clone, Debug, PartialEq)]
pub struct PairSvm {
    /// 0..=5: acc x, y, z, gyro x, y, z.
    pub axis: usize,
    pub gamma: f64,
    pub rho: f64,
    pub mean: [f64; 2],
    pub sd: [f64; 2],
    /// Scaled feature box `[lo0, hi0, lo1, hi1]` covered by the table.
    pub bbox: [f64; 4],
    /// Support vectors: `(coef = α·y, x0, x1)`.
    pub support: Vec<[f64; 3]>,
    grid: Vec<f32>,
}

impl PairSvm {
    pub fn new(
        axis: usize,
        gamma: f64,
        rho: f64,
        mean: [f64; 2],
        sd: [f64; 2],
        bbox: [f64; 4],
        support: Vec<[f64; 3]>,
    ) -> Result<Self, FootError> {
        let bad = |w: &str| {
            Err(FootError::InvalidModel(format!(
                "{}: {w}",
                AXES[axis.min(5)]
            )))
        };
        if axis > 5 {
            return Err(FootError::InvalidModel(format!("axis index {axis} > 5")));
        }
        if !(gamma.is_finite() && gamma > 0.0) {
            return bad("gamma must be > 0");
        }
        if !rho.is_finite() || !mean.iter().all(|v| v.is_finite()) {
            return bad("rho and mean must be finite");
        }
        if !sd.iter().all(|v| v.is_finite() && *v > 0.0) {
            return bad("sd must be > 0");
        }
        if !bbox.iter().all(|v| v.is_finite()) || bbox[1] <= bbox[0] || bbox[3] <= bbox[2] {
            return bad("box must be finite with lo < hi");
        }
        if support.is_empty() || support.iter().flatten().any(|v| !v.is_finite()) {
            return bad("support vectors must be finite and at least one");
        }
        let mut s = Self {
            axis,
            gamma,
            rho,
            mean,
            sd,
            bbox,
            support,
            grid: Vec::new(),
        };
        s.grid = s.table();
        Ok(s)
    }

    /// The decision values on the grid. The Gaussian kernel factorises,
    /// e^(−γ(d0² + d1²)) = e^(−γ d0²)·e^(−γ d1²), so each support vector costs two
    /// rows of GRID exponentials and one outer product: linear in the number of
    /// support vectors, about 30× cheaper than evaluating the kernel per cell.
    fn table(&self) -> Vec<f32> {
        let axis = |lo: f64, hi: f64| -> [f64; GRID] {
            std::array::from_fn(|i| lo + (hi - lo) * i as f64 / (GRID - 1) as f64)
        };
        let g0 = axis(self.bbox[0], self.bbox[1]);
        let g1 = axis(self.bbox[2], self.bbox[3]);
        let mut acc = vec![-self.rho; GRID * GRID];
        let (mut e0, mut e1) = ([0.0; GRID], [0.0; GRID]);
        for sv in &self.support {
            for i in 0..GRID {
                let d0 = g0[i] - sv[1];
                e0[i] = sv[0] * (-self.gamma * d0 * d0).exp();
                let d1 = g1[i] - sv[2];
                e1[i] = (-self.gamma * d1 * d1).exp();
            }
            for (row, &a) in acc.chunks_exact_mut(GRID).zip(&e0) {
                for (cell, &b) in row.iter_mut().zip(&e1) {
                    *cell += a * b;
                }
            }
        }
        acc.into_iter().map(|v| v as f32).collect()
    }

    /// Scaled features of a window.
    #[inline]
    pub fn features(&self, s: &WindowStats) -> (f64, f64) {
        let sigma = if self.axis < 3 {
            s.acc_std_mps2[self.axis]
        } else {
            s.gyro_std_rads[self.axis - 3]
        };
        (
            (s.peak_acc_norm_mps2 - self.mean[0]) / self.sd[0],
            ((sigma + SIGMA_EPS).ln() - self.mean[1]) / self.sd[1],
        )
    }

    /// The decision value at scaled features, by the kernel sum.
    pub fn exact_scaled(&self, x0: f64, x1: f64) -> f64 {
        let mut f = -self.rho;
        for sv in &self.support {
            let d0 = x0 - sv[1];
            let d1 = x1 - sv[2];
            f += sv[0] * (-self.gamma * (d0 * d0 + d1 * d1)).exp();
        }
        f
    }

    /// The decision value at scaled features, from the table, with the features
    /// clamped onto the box (see the module docs). Non-finite features give −∞
    /// (swing).
    #[inline]
    pub fn decision_scaled(&self, x0: f64, x1: f64) -> f64 {
        if !(x0.is_finite() && x1.is_finite()) {
            return f64::NEG_INFINITY;
        }
        let top = (GRID - 1) as f64;
        let u = ((x0 - self.bbox[0]) / (self.bbox[1] - self.bbox[0]) * top).clamp(0.0, top);
        let v = ((x1 - self.bbox[2]) / (self.bbox[3] - self.bbox[2]) * top).clamp(0.0, top);
        let (i, j) = ((u as usize).min(GRID - 2), (v as usize).min(GRID - 2));
        let (fu, fv) = (u - i as f64, v - j as f64);
        let g = |a: usize, b: usize| self.grid[a * GRID + b] as f64;
        let f0 = g(i, j) * (1.0 - fv) + g(i, j + 1) * fv;
        let f1 = g(i + 1, j) * (1.0 - fv) + g(i + 1, j + 1) * fv;
        f0 * (1.0 - fu) + f1 * fu
    }

    /// The decision value of a window (> 0: stance).
    #[inline]
    pub fn decision(&self, s: &WindowStats) -> f64 {
        let (x0, x1) = self.features(s);
        self.decision_scaled(x0, x1)
    }
}

/// Six pair SVMs; stance only if all agree.
#[derive(Clone, Debug, PartialEq)]
pub struct SvmModel {
    /// Indexed by axis (acc x, y, z, gyro x, y, z).
    pub pairs: Vec<PairSvm>,
    /// The comment lines of the file (provenance).
    pub comments: Vec<String>,
}

impl SvmModel {
    /// The model trained on the development data that ships with the SDK (see
    /// `docs/foot.md` for how to reproduce it).
    pub fn shipped() -> Self {
        Self::parse(SHIPPED).expect("the shipped zero-velocity model parses")
    }

    /// The shipped model, parsed once per process and shared (its tables are
    /// ~400 kB; every navigator using it holds the same copy).
    pub fn shared_shipped() -> std::sync::Arc<Self> {
        static SHARED: std::sync::OnceLock<std::sync::Arc<SvmModel>> = std::sync::OnceLock::new();
        SHARED
            .get_or_init(|| std::sync::Arc::new(Self::shipped()))
            .clone()
    }

    /// This is the shipped model (same content).
    pub fn is_shipped(&self) -> bool {
        let shipped = Self::shared_shipped();
        std::ptr::eq(self, &*shipped) || *self == *shipped
    }

    /// All six SVMs say stance.
    #[inline]
    pub fn is_stance(&self, s: &WindowStats) -> bool {
        self.pairs.iter().all(|p| p.decision(s) > 0.0)
    }

    /// Read a model file (format in the module docs).
    pub fn parse(text: &str) -> Result<Self, FootError> {
        if text.len() > MAX_MODEL_BYTES {
            return Err(FootError::InvalidModel(format!(
                "model text of {} bytes is larger than {MAX_MODEL_BYTES} bytes",
                text.len()
            )));
        }
        let mut lines = numbered_lines(text);
        check_header(lines.next())?;
        let mut comments = Vec::new();
        let mut pairs: Vec<Option<PairSvm>> = vec![None; 6];
        while let Some((ln, line)) = lines.next() {
            if line.is_empty() {
                continue;
            }
            if let Some(c) = line.strip_prefix('#') {
                comments.push(c.trim().to_string());
                continue;
            }
            let (axis, pair) = parse_block(ln, line, &mut lines, &pairs)?;
            pairs[axis] = Some(pair);
        }
        let pairs: Vec<PairSvm> = pairs
            .into_iter()
            .enumerate()
            .map(|(i, p)| {
                p.ok_or_else(|| FootError::InvalidModel(format!("no svm for {}", AXES[i])))
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { pairs, comments })
    }

    /// The model as a file (inverse of [`parse`](Self::parse), floats round-trip).
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut out = String::from("stridekit-zupt-svm 1\n");
        for c in &self.comments {
            let _ = writeln!(out, "# {c}");
        }
        for p in &self.pairs {
            let _ = writeln!(
                out,
                "svm {} gamma {:?} rho {:?} mean {:?} {:?} sd {:?} {:?} box {:?} {:?} {:?} {:?} n {}",
                AXES[p.axis],
                p.gamma,
                p.rho,
                p.mean[0],
                p.mean[1],
                p.sd[0],
                p.sd[1],
                p.bbox[0],
                p.bbox[1],
                p.bbox[2],
                p.bbox[3],
                p.support.len()
            );
            for sv in &p.support {
                let _ = writeln!(out, "{:?} {:?} {:?}", sv[0], sv[1], sv[2]);
            }
        }
        out
    }
}

const SHIPPED: &str = include_str!("../../models/zupt_svm_v1.txt");

/// A model-file error at a line.
fn line_error(line: usize, what: &str) -> FootError {
    FootError::InvalidModel(format!("line {line}: {what}"))
}

/// The first line: `stridekit-zupt-svm 1`.
fn check_header(first: Option<(usize, &str)>) -> Result<(), FootError> {
    match first {
        Some((_, "stridekit-zupt-svm 1")) => Ok(()),
        Some((_, l)) if l.starts_with("stridekit-zupt-svm ") => Err(FootError::InvalidModel(
            format!("unsupported version '{l}' (this build reads version 1)"),
        )),
        _ => Err(FootError::InvalidModel(
            "not a stridekit zero-velocity model (first line must be 'stridekit-zupt-svm 1')"
                .into(),
        )),
    }
}

/// One SVM block: its `svm AXIS …` line (`ln`, `line`) and the support-vector lines
/// that follow it in `lines`, for an axis not among those `read` so far; the axis index
/// and the SVM.
fn parse_block<'a>(
    ln: usize,
    line: &str,
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    read: &[Option<PairSvm>],
) -> Result<(usize, PairSvm), FootError> {
    let tok: Vec<&str> = line.split_whitespace().collect();
    if tok.first() != Some(&"svm") || tok.len() != 19 {
        return Err(line_error(
            ln,
            "expected 'svm AXIS gamma G rho R mean M0 M1 sd S0 S1 box L0 H0 L1 H1 n N'",
        ));
    }
    let keys = [
        (2, "gamma"),
        (4, "rho"),
        (6, "mean"),
        (9, "sd"),
        (12, "box"),
        (17, "n"),
    ];
    if keys.iter().any(|&(i, k)| tok[i] != k) {
        return Err(line_error(
            ln,
            "keys must be gamma, rho, mean, sd, box, n in this order",
        ));
    }
    let axis = AXES
        .iter()
        .position(|a| *a == tok[1])
        .ok_or_else(|| line_error(ln, "unknown axis"))?;
    if read[axis].is_some() {
        return Err(line_error(ln, "axis given twice"));
    }
    let num = |i: usize| -> Result<f64, FootError> {
        tok[i]
            .parse::<f64>()
            .map_err(|_| line_error(ln, "not a number"))
    };
    let n: usize = tok[18]
        .parse()
        .map_err(|_| line_error(ln, "n is not a count"))?;
    if n == 0 || n > MAX_SUPPORT_VECTORS {
        return Err(line_error(ln, "n must be 1..=2000"));
    }
    let mut support = Vec::with_capacity(n);
    for _ in 0..n {
        let (ln2, l2) = lines
            .next()
            .ok_or_else(|| line_error(ln, "file ends inside a block"))?;
        let v: Vec<f64> = l2
            .split_whitespace()
            .map(|x| x.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| line_error(ln2, "support vector line must be three numbers"))?;
        if v.len() != 3 {
            return Err(line_error(ln2, "support vector line must be three numbers"));
        }
        support.push([v[0], v[1], v[2]]);
    }
    let pair = PairSvm::new(
        axis,
        num(3)?,
        num(5)?,
        [num(7)?, num(8)?],
        [num(10)?, num(11)?],
        [num(13)?, num(14)?, num(15)?, num(16)?],
        support,
    )?;
    Ok((axis, pair))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(axis: &str, rho: f64) -> String {
        format!(
            "svm {axis} gamma 0.8 rho {rho} mean 20.0 -3.0 sd 10.0 1.5 box -3.0 4.0 -4.0 4.0 n 3\n\
             1.5 -1.0 -1.0\n-0.7 1.0 1.2\n-0.8 0.5 -0.2\n"
        )
    }

    fn model_text() -> String {
        let mut t = String::from("stridekit-zupt-svm 1\n# a comment\n");
        for (i, a) in AXES.iter().enumerate() {
            t.push_str(&block(a, -0.1 * i as f64));
        }
        t
    }

    #[test]
    fn parses_and_round_trips() {
        let m = SvmModel::parse(&model_text()).unwrap();
        assert_eq!(m.pairs.len(), 6);
        assert_eq!(m.comments, vec!["a comment".to_string()]);
        let back = SvmModel::parse(&m.to_text()).unwrap();
        assert_eq!(back, m);
        assert_eq!(back.to_text(), m.to_text());
    }

    #[test]
    fn shipped_model_parses_and_is_small() {
        let m = SvmModel::shipped();
        for p in &m.pairs {
            assert!(p.support.len() <= 1000, "{} SVs", p.support.len());
        }
    }

    #[test]
    fn rejects_bad_files() {
        assert!(SvmModel::parse("hello").is_err());
        assert!(SvmModel::parse("stridekit-zupt-svm 2\n").is_err());
        // Missing an axis.
        let t = model_text();
        let cut = t.find("svm gyro_z").unwrap();
        assert!(SvmModel::parse(&t[..cut]).is_err());
        // An axis twice.
        let twice = format!("{t}{}", block("acc_x", 0.0));
        assert!(SvmModel::parse(&twice).is_err());
        // Truncated block, non-numbers.
        assert!(SvmModel::parse(&t[..t.len() - 10]).is_err());
        assert!(SvmModel::parse(&t.replace("gamma 0.8", "gamma x")).is_err());
        assert!(SvmModel::parse(&t.replace("gamma 0.8", "gamma -1")).is_err());
    }

    #[test]
    fn table_agrees_with_the_kernel_sum() {
        let m = SvmModel::parse(&model_text()).unwrap();
        let p = &m.pairs[0];
        let mut worst: f64 = 0.0;
        for i in 0..60 {
            for j in 0..60 {
                let x0 = -3.0 + 7.0 * i as f64 / 59.0;
                let x1 = -4.0 + 8.0 * j as f64 / 59.0;
                let d = (p.decision_scaled(x0, x1) - p.exact_scaled(x0, x1)).abs();
                worst = worst.max(d);
            }
        }
        assert!(worst < 5e-3, "table vs exact {worst}");
        // Features → decision: the same point through WindowStats.
        let s = WindowStats {
            peak_acc_norm_mps2: 25.0,
            acc_std_mps2: [0.05, 0.1, 0.2],
            gyro_std_rads: [0.01, 0.02, 0.03],
            ..Default::default()
        };
        let (x0, x1) = p.features(&s);
        assert!((x0 - 0.5).abs() < 1e-12);
        assert!((x1 - ((0.05f64 + SIGMA_EPS).ln() + 3.0) / 1.5).abs() < 1e-12);
        assert!((p.decision(&s) - p.exact_scaled(x0, x1)).abs() < 5e-3);
        // Outside the box: the edge value, not the kernel's decay to −ρ.
        assert_eq!(p.decision_scaled(100.0, 1.0), p.decision_scaled(4.0, 1.0));
        assert_eq!(
            p.decision_scaled(-9.0, -50.0),
            p.decision_scaled(-3.0, -4.0)
        );
        assert_eq!(p.decision_scaled(f64::NAN, 0.0), f64::NEG_INFINITY);
    }
}
