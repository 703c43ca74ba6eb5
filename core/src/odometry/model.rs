//! The velocity regressor and the model file.
//!
//! One [`Regressor`] per placement class ([`crate::placement::Placement`], the classes
//! the placement classifier outputs) plus a general one (used when the placement is
//! unknown, not confident enough, or has no regressor of its own). A regressor maps a
//! window's [`WindowFeatures`] to a horizontal velocity in the stabilised frame S:
//! - speed: ridge regression on the standardised scalars,
//!   `ŝ = clamp(b + Σ w_j (s_j − mean_j) / sd_j, 0, 10 m/s)`;
//! - direction: a complex-linear (yaw-equivariant) combination of the 2-D
//!   features plus a constant direction in S (the placement's usual heading of the
//!   phone relative to the walk), `d = Σ c_k f_k + c_0`, fitted by least squares
//!   to the unit true direction;
//! - `v_S = ŝ · d / |d|` (0 when `|d| < 1e-9`).
//!
//! # Model file (text, version 2)
//!
//! ```text
//! stridekit-odometry 2
//! # free comment lines (how the model was trained)
//! pipeline rate_hz 100 window 200 hop 10 sigma 2 lambda 1
//! regressor general mean m1 … m10 sd s1 … s10 speed b w1 … w10 direction re1 im1 … re5 im5
//! regressor in_hand mean … (one line per placement, any subset, each at most once)
//! ```
//!
//! `pipeline`: model rate (Hz; input at other rates is resampled onto it), window
//! length and hop (grid samples, window ≤ 400), Gaussian σ (grid samples, ≤ 10) and
//! the bias-correction weight λ. The `general` regressor is required. Placement
//! names (the [`Placement`] classes): `in_hand pocket bag neck_pouch armband
//! swinging_arm`.
//!
//! Version 1 keyed the regressors by the simulator's 7 placements (separate
//! `front_pocket` and `back_pocket`); this build reads only version 2 and rejects a
//! version-1 file with [`OdometryError::ModelVersion`] (retrain it with
//! `stridekit train odometry`).
//! Scalar order: [`SCALAR_NAMES`]; direction pairs: the [`N_VECTOR`] features, then
//! the constant. Numbers are written with Rust's shortest round-trip formatting, so
//! `parse(to_text(m)) == m` bit for bit.

use super::error::OdometryError;
use super::features::{WindowFeatures, MAX_WINDOW, N_SCALAR, N_VECTOR, SCALAR_NAMES};
use super::smooth::MAX_SIGMA_SAMPLES;
use crate::model_text::{finite, numbered_lines};
use crate::placement::{Placement, CLASSES};

/// Largest speed a regressor outputs, m/s.
pub const MAX_SPEED_MPS: f64 = 10.0;
const HEADER: &str = "stridekit-odometry";
/// Model file format version this build reads and writes.
pub const MODEL_VERSION: u32 = 2;
const VERSION: u32 = MODEL_VERSION;
/// Regressor slots: the general one, then one per [`Placement`] class.
pub const SLOTS: usize = 1 + CLASSES;

/// Parameters of the signal pipeline the model was trained with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PipelineParams {
    pub rate_hz: f64,
    pub window: usize,
    pub hop: usize,
    pub sigma_samples: f64,
    /// Weight of the bias term in the correction (see `super::bias`).
    pub lambda: f64,
}

impl Default for PipelineParams {
    fn default() -> Self {
        Self {
            rate_hz: 100.0,
            window: 200,
            hop: 10,
            sigma_samples: 2.0,
            lambda: 1.0,
        }
    }
}

impl PipelineParams {
    pub fn validate(&self) -> Result<(), &'static str> {
        if !(self.rate_hz.is_finite() && (20.0..=1000.0).contains(&self.rate_hz)) {
            return Err("rate_hz must be in 20..=1000");
        }
        if !(8..=MAX_WINDOW).contains(&self.window) {
            return Err("window must be in 8..=400 samples");
        }
        if self.hop == 0 || self.hop > self.window {
            return Err("hop must be in 1..=window");
        }
        if !(self.sigma_samples.is_finite()
            && (0.0..=MAX_SIGMA_SAMPLES).contains(&self.sigma_samples))
        {
            return Err("sigma must be in 0..=10 samples");
        }
        if !(self.lambda.is_finite() && self.lambda > 0.0 && self.lambda <= 1e6) {
            return Err("lambda must be in (0, 1e6]");
        }
        Ok(())
    }

    /// Hop length, s.
    pub fn hop_s(&self) -> f64 {
        self.hop as f64 / self.rate_hz
    }
}

/// One velocity regressor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Regressor {
    pub mean: [f64; N_SCALAR],
    pub sd: [f64; N_SCALAR],
    /// Intercept then one weight per scalar.
    pub speed: [f64; N_SCALAR + 1],
    /// Complex weights `[re, im]` of the vector features, then the constant.
    pub direction: [[f64; 2]; N_VECTOR + 1],
}

impl Regressor {
    /// The speed alone, m/s.
    #[inline]
    pub fn speed(&self, f: &WindowFeatures) -> f64 {
        let mut s = self.speed[0];
        for j in 0..N_SCALAR {
            s += self.speed[j + 1] * (f.scalars[j] - self.mean[j]) / self.sd[j];
        }
        if s.is_finite() {
            s.clamp(0.0, MAX_SPEED_MPS)
        } else {
            0.0
        }
    }

    /// Unnormalised direction in S.
    #[inline]
    pub fn direction(&self, f: &WindowFeatures) -> [f64; 2] {
        let c = &self.direction[N_VECTOR];
        let mut d = [c[0], c[1]];
        for k in 0..N_VECTOR {
            let (w, v) = (self.direction[k], f.vectors[k]);
            d[0] += w[0] * v[0] - w[1] * v[1];
            d[1] += w[0] * v[1] + w[1] * v[0];
        }
        d
    }

    /// Horizontal velocity in S, m/s.
    #[inline]
    pub fn predict(&self, f: &WindowFeatures) -> [f64; 2] {
        let s = self.speed(f);
        let d = self.direction(f);
        let n = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if n.is_finite() && n > 1e-9 {
            [s * d[0] / n, s * d[1] / n]
        } else {
            [0.0, 0.0]
        }
    }

    fn is_valid(&self) -> bool {
        self.mean.iter().all(|v| v.is_finite())
            && self.sd.iter().all(|v| v.is_finite() && *v > 0.0)
            && self.speed.iter().all(|v| v.is_finite())
            && self.direction.iter().flatten().all(|v| v.is_finite())
    }
}

/// Name of a placement in the model file (`None` = general).
pub fn placement_name(p: Option<Placement>) -> &'static str {
    match p {
        None => "general",
        Some(Placement::InHand) => "in_hand",
        Some(Placement::Pocket) => "pocket",
        Some(Placement::Bag) => "bag",
        Some(Placement::NeckPouch) => "neck_pouch",
        Some(Placement::Armband) => "armband",
        Some(Placement::SwingingArm) => "swinging_arm",
    }
}

/// The placement of a name (`Some(None)` = general).
pub fn placement_from_name(s: &str) -> Option<Option<Placement>> {
    if s == "general" {
        return Some(None);
    }
    Placement::ALL
        .into_iter()
        .find(|&p| placement_name(Some(p)) == s)
        .map(Some)
}

/// Slot of a placement in [`OdometryModel::regressors`] (0 = general).
pub fn slot(p: Option<Placement>) -> usize {
    p.map_or(0, |p| 1 + p.index())
}

/// Placement of a slot (0 = general; `None` when out of range).
pub fn slot_placement(k: usize) -> Option<Option<Placement>> {
    match k {
        0 => Some(None),
        _ => Placement::ALL.get(k - 1).map(|&p| Some(p)),
    }
}

/// Pipeline parameters and the regressors.
#[derive(Clone, Debug, PartialEq)]
pub struct OdometryModel {
    pub params: PipelineParams,
    /// Slot 0 general, then [`Placement::ALL`] order; `None` = not trained.
    pub regressors: [Option<Regressor>; SLOTS],
    /// Comment lines (without `# `), kept for `to_text`.
    pub comments: Vec<String>,
}

const SHIPPED: &str = include_str!("../../models/odometry_v1.txt");

/// Largest model text accepted, bytes (the shipped model is a few kB; parsing is
/// linear in the text).
pub const MAX_MODEL_BYTES: usize = 1 << 20;

impl OdometryModel {
    /// A model with only a general regressor.
    pub fn new(params: PipelineParams, general: Regressor) -> Result<Self, OdometryError> {
        let mut regressors = [None; SLOTS];
        regressors[0] = Some(general);
        let m = Self {
            params,
            regressors,
            comments: Vec::new(),
        };
        m.validate()?;
        Ok(m)
    }

    /// The model shipped in `core/models/odometry_v1.txt` (file format version 2; the
    /// file name is historical): trained on 287 real hand-held indoor walks (`stridekit
    /// train odometry --android`), the general and in-hand regressors; its comment
    /// lines hold the command and its fitted and leave-one-floor-out figures.
    /// Experimental: the PDR (`pdr::PhoneNavigator`) is more accurate on those walks.
    pub fn shipped() -> Self {
        Self::parse(SHIPPED).expect("the shipped odometry model parses")
    }

    /// Whether `placement` has a regressor of its own (`None`: the general one).
    pub fn has_regressor(&self, placement: Option<Placement>) -> bool {
        self.regressors[slot(placement)].is_some()
    }

    /// The regressor used for `placement` (its own, else the general one).
    pub fn regressor(&self, placement: Option<Placement>) -> &Regressor {
        self.regressors[slot(placement)]
            .as_ref()
            .or(self.regressors[0].as_ref())
            .expect("validated: a general regressor exists")
    }

    /// Serialised size of the numbers (8 bytes per f64 of every regressor present).
    pub fn size_bytes(&self) -> usize {
        self.regressors.iter().flatten().count() * std::mem::size_of::<Regressor>()
    }

    pub fn validate(&self) -> Result<(), OdometryError> {
        let bad = |reason: &str| OdometryError::InvalidModel {
            line: 0,
            reason: reason.to_string(),
        };
        self.params.validate().map_err(bad)?;
        if self.regressors[0].is_none() {
            return Err(bad("no general regressor"));
        }
        if !self.regressors.iter().flatten().all(Regressor::is_valid) {
            return Err(bad("non-finite weight or sd ≤ 0"));
        }
        Ok(())
    }

    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = format!("{HEADER} {VERSION}\n");
        for c in &self.comments {
            let _ = writeln!(s, "# {c}");
        }
        let p = &self.params;
        let _ = writeln!(
            s,
            "pipeline rate_hz {} window {} hop {} sigma {} lambda {}",
            p.rate_hz, p.window, p.hop, p.sigma_samples, p.lambda
        );
        for (i, r) in self.regressors.iter().enumerate() {
            let Some(r) = r else { continue };
            let name = placement_name(slot_placement(i).flatten());
            let _ = write!(s, "regressor {name} mean");
            for v in r.mean {
                let _ = write!(s, " {v}");
            }
            s.push_str(" sd");
            for v in r.sd {
                let _ = write!(s, " {v}");
            }
            s.push_str(" speed");
            for v in r.speed {
                let _ = write!(s, " {v}");
            }
            s.push_str(" direction");
            for v in r.direction.iter().flatten() {
                let _ = write!(s, " {v}");
            }
            s.push('\n');
        }
        s
    }

    pub fn parse(text: &str) -> Result<Self, OdometryError> {
        if text.len() > MAX_MODEL_BYTES {
            return Err(line_error(
                0,
                format!("larger than {MAX_MODEL_BYTES} bytes"),
            ));
        }
        let mut lines = numbered_lines(text);
        parse_header(lines.next())?;
        let mut params = None;
        let mut regressors = [None; SLOTS];
        let mut comments = Vec::new();
        for (n, line) in lines {
            if line.is_empty() {
                continue;
            }
            if let Some(c) = line.strip_prefix('#') {
                comments.push(c.trim().to_string());
                continue;
            }
            let tok: Vec<&str> = line.split_whitespace().collect();
            match tok[0] {
                "pipeline" => {
                    if params.is_some() {
                        return Err(line_error(n, "second `pipeline` line".into()));
                    }
                    params = Some(parse_pipeline(n, &tok)?);
                }
                "regressor" => {
                    let name = tok.get(1).copied().unwrap_or("");
                    let placement = placement_from_name(name)
                        .ok_or_else(|| line_error(n, format!("unknown placement `{name}`")))?;
                    let k = slot(placement);
                    if regressors[k].is_some() {
                        return Err(line_error(n, format!("second regressor `{name}`")));
                    }
                    regressors[k] = Some(parse_regressor(n, &tok)?);
                }
                other => return Err(line_error(n, format!("unknown line `{other}`"))),
            }
        }
        let params = params.ok_or_else(|| line_error(0, "no `pipeline` line".into()))?;
        if regressors[0].is_none() {
            return Err(line_error(0, "no `regressor general` line".into()));
        }
        let _ = SCALAR_NAMES;
        Ok(Self {
            params,
            regressors,
            comments,
        })
    }
}

/// A model-file error at a line (0: the file as a whole).
fn line_error(line: usize, reason: String) -> OdometryError {
    OdometryError::InvalidModel { line, reason }
}

/// A token of line `n` as a finite number.
fn number(n: usize, s: &str) -> Result<f64, OdometryError> {
    finite(s).ok_or_else(|| line_error(n, format!("`{s}` is not a finite number")))
}

/// The first line: `HEADER VERSION`, of this build's version.
fn parse_header(first: Option<(usize, &str)>) -> Result<(), OdometryError> {
    let (n, first) = first.ok_or_else(|| line_error(1, "empty file".into()))?;
    let mut head = first.split_whitespace();
    if head.next() != Some(HEADER) {
        return Err(line_error(
            n,
            format!("first line must start with `{HEADER}`"),
        ));
    }
    match head.next().map(str::parse::<u32>) {
        Some(Ok(VERSION)) => Ok(()),
        Some(Ok(v)) => Err(OdometryError::ModelVersion {
            found: v,
            supported: VERSION,
        }),
        _ => Err(line_error(n, "missing or bad version number".into())),
    }
}

/// `pipeline rate_hz R window W hop H sigma S lambda L` (line `n`, its tokens).
fn parse_pipeline(n: usize, tok: &[&str]) -> Result<PipelineParams, OdometryError> {
    let keys = ["rate_hz", "window", "hop", "sigma", "lambda"];
    if tok.len() != 1 + 2 * keys.len() {
        return Err(line_error(n, "pipeline needs 5 key value pairs".into()));
    }
    let mut v = [0.0; 5];
    for (i, k) in keys.iter().enumerate() {
        if tok[1 + 2 * i] != *k {
            return Err(line_error(n, format!("expected `{k}`")));
        }
        v[i] = number(n, tok[2 + 2 * i])?;
    }
    let int = |x: f64| -> Result<usize, OdometryError> {
        if x.fract() == 0.0 && (0.0..1e6).contains(&x) {
            Ok(x as usize)
        } else {
            Err(line_error(n, "window and hop must be whole numbers".into()))
        }
    };
    let [rate_hz, window, hop, sigma_samples, lambda] = v;
    let p = PipelineParams {
        rate_hz,
        window: int(window)?,
        hop: int(hop)?,
        sigma_samples,
        lambda,
    };
    p.validate().map_err(|r| line_error(n, r.to_string()))?;
    Ok(p)
}

/// `regressor NAME mean … sd … speed … direction …` (line `n`, its tokens; the name is
/// checked by the caller).
fn parse_regressor(n: usize, tok: &[&str]) -> Result<Regressor, OdometryError> {
    let mut pos = 2;
    let mut section = |key: &str, count: usize| -> Result<Vec<f64>, OdometryError> {
        if tok.get(pos) != Some(&key) {
            return Err(line_error(n, format!("expected `{key}`")));
        }
        let vals = tok
            .get(pos + 1..)
            .unwrap_or(&[])
            .iter()
            .take_while(|t| t.parse::<f64>().is_ok())
            .map(|t| number(n, t))
            .collect::<Result<Vec<_>, _>>()?;
        if vals.len() != count {
            return Err(line_error(
                n,
                format!("`{key}` has {} numbers, expected {count}", vals.len()),
            ));
        }
        pos += 1 + count;
        Ok(vals)
    };
    let mean = section("mean", N_SCALAR)?;
    let sd = section("sd", N_SCALAR)?;
    let speed = section("speed", N_SCALAR + 1)?;
    let dir = section("direction", 2 * (N_VECTOR + 1))?;
    if pos != tok.len() {
        return Err(line_error(n, "trailing tokens".into()));
    }
    let mut r = Regressor {
        mean: [0.0; N_SCALAR],
        sd: [0.0; N_SCALAR],
        speed: [0.0; N_SCALAR + 1],
        direction: [[0.0; 2]; N_VECTOR + 1],
    };
    r.mean.copy_from_slice(&mean);
    r.sd.copy_from_slice(&sd);
    r.speed.copy_from_slice(&speed);
    for (k, d) in r.direction.iter_mut().enumerate() {
        *d = [dir[2 * k], dir[2 * k + 1]];
    }
    if !r.is_valid() {
        return Err(line_error(n, "sd must be > 0".into()));
    }
    Ok(r)
}
