//! The placement model: multinomial logistic regression on standardised features.
//!
//! # Model file (text, version 1)
//!
//! ```text
//! stridekit-placement-lr 1
//! # free comment lines (how the model was trained)
//! classes 6 InHand Pocket Bag NeckPouch Armband SwingingArm
//! features 23 ln_sd_norm ln_sd_vert ... vh_corr
//! mean m_0 ... m_22
//! sd s_0 ... s_22
//! class InHand b w_0 ... w_22
//! class Pocket b w_0 ... w_22
//! ...
//! ```
//!
//! Lines in this order after the comments; `classes` lists every class of
//! [`Placement::ALL`] once (any order), `features` must list this build's
//! [`FEATURE_NAMES`] in order (a different count is
//! [`PlacementError::ModelFeatureCount`]), then one `class` line per class.
//! Standardised features `z_i = clamp((f_i − m_i) / s_i, ±8)`; class score
//! `b + Σ w_i z_i`; probabilities are the softmax of the scores. Clamping keeps a
//! window unlike anything in training from being decided by one extreme feature.
//! Numbers are written with Rust's shortest round-trip formatting, so
//! write → parse is exact.

use super::class::{Placement, CLASSES};
use super::error::PlacementError;
use super::features::{Features, FEATURES, FEATURE_NAMES};
use crate::model_text::{finite_numbers, numbered_lines};

/// First line of a version-1 model file.
pub const MAGIC: &str = "stridekit-placement-lr 1";
/// Bound of the standardised features.
pub const Z_CLAMP: f64 = 8.0;

/// A trained placement model.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacementModel {
    pub mean: Features,
    pub sd: Features,
    /// Per class (in [`Placement::ALL`] order): bias, then one weight per feature.
    pub weights: [[f64; FEATURES + 1]; CLASSES],
    /// Comment lines (provenance).
    pub comments: Vec<String>,
}

fn softmax(s: &mut [f64; CLASSES]) {
    let max = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut sum = 0.0;
    for v in s.iter_mut() {
        *v = (*v - max).exp();
        sum += *v;
    }
    for v in s.iter_mut() {
        *v /= sum;
    }
}

/// Largest model text accepted, bytes (the shipped model is 4.5 kB; parsing is
/// linear in the text).
pub const MAX_MODEL_BYTES: usize = 256 * 1024;

impl PlacementModel {
    /// The model trained on all Oxford Step Counter traces that ships with the SDK
    /// (`core/models/placement_lr_v1.txt`; its comment lines give the command).
    pub fn shipped() -> Self {
        Self::parse(SHIPPED).expect("the shipped placement model parses")
    }

    /// Checks a model built in code.
    pub fn new(
        mean: Features,
        sd: Features,
        weights: [[f64; FEATURES + 1]; CLASSES],
        comments: Vec<String>,
    ) -> Result<Self, PlacementError> {
        let bad = |reason: &str| PlacementError::Model {
            line: 0,
            reason: reason.into(),
        };
        if !mean.iter().all(|v| v.is_finite()) {
            return Err(bad("mean must be finite"));
        }
        if !sd.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(bad("sd must be finite and > 0"));
        }
        if !weights.iter().flatten().all(|v| v.is_finite()) {
            return Err(bad("weights must be finite"));
        }
        Ok(Self {
            mean,
            sd,
            weights,
            comments,
        })
    }

    /// Standardised, clamped features.
    pub fn standardise(&self, f: &Features) -> Features {
        let mut z = [0.0; FEATURES];
        for i in 0..FEATURES {
            let v = (f[i] - self.mean[i]) / self.sd[i];
            z[i] = if v.is_finite() {
                v.clamp(-Z_CLAMP, Z_CLAMP)
            } else {
                0.0
            };
        }
        z
    }

    /// Class scores (logits) of standardised features.
    pub fn scores(&self, z: &Features) -> [f64; CLASSES] {
        let mut s = [0.0; CLASSES];
        for (c, w) in self.weights.iter().enumerate() {
            let mut v = w[0];
            for i in 0..FEATURES {
                v += w[i + 1] * z[i];
            }
            s[c] = v;
        }
        s
    }

    /// Class probabilities of a feature vector (in [`Placement::ALL`] order).
    pub fn probabilities(&self, f: &Features) -> [f64; CLASSES] {
        let mut s = self.scores(&self.standardise(f));
        softmax(&mut s);
        s
    }

    /// Size of the parameters, bytes (what a phone has to hold).
    pub fn parameter_bytes(&self) -> usize {
        std::mem::size_of::<Features>() * 2 + std::mem::size_of::<[[f64; FEATURES + 1]; CLASSES]>()
    }

    /// Reads a model file (format in the module docs).
    pub fn parse(text: &str) -> Result<Self, PlacementError> {
        if text.len() > MAX_MODEL_BYTES {
            return Err(line_error(0, "larger than 256 KiB"));
        }
        let mut lines = numbered_lines(text).filter(|(_, l)| !l.is_empty());
        match lines.next() {
            Some((_, MAGIC)) => {}
            Some((_, l)) => {
                return Err(PlacementError::ModelVersion {
                    found: l.chars().take(60).collect(),
                })
            }
            None => return Err(line_error(0, "empty file")),
        }
        // Comments before the first keyword line are the model's; later ones are
        // skipped.
        let mut comments = Vec::new();
        let mut body = Vec::new();
        for (ln, l) in lines {
            match l.strip_prefix('#') {
                Some(c) if body.is_empty() => comments.push(c.trim().to_string()),
                Some(_) => {}
                None => body.push((ln, l)),
            }
        }
        let mut body = Body {
            lines: body.into_iter(),
            last_line: text.lines().count(),
        };
        let order = parse_classes(body.next("classes")?)?;
        parse_features(body.next("features")?)?;
        let (_, mean) = body.vector("mean")?;
        let (ln_sd, sd) = body.vector("sd")?;
        if sd.iter().any(|v| *v <= 0.0) {
            return Err(line_error(ln_sd, "sd must be > 0"));
        }
        let mut weights = [[0.0; FEATURES + 1]; CLASSES];
        for &class in &order {
            weights[class] = parse_class_weights(body.next("class")?, class)?;
        }
        if let Some((ln, _)) = body.lines.next() {
            return Err(line_error(ln, "unexpected line after the last class"));
        }
        Self::new(mean, sd, weights, comments)
    }

    /// The model as a file (inverse of [`parse`](Self::parse), floats round-trip).
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut out = format!("{MAGIC}\n");
        for c in &self.comments {
            let _ = writeln!(out, "# {c}");
        }
        let _ = write!(out, "classes {CLASSES}");
        for p in Placement::ALL {
            let _ = write!(out, " {}", p.name());
        }
        let _ = write!(out, "\nfeatures {FEATURES}");
        for n in FEATURE_NAMES {
            let _ = write!(out, " {n}");
        }
        let row = |out: &mut String, key: &str, v: &[f64]| {
            let _ = write!(out, "\n{key}");
            for x in v {
                let _ = write!(out, " {x:?}");
            }
        };
        row(&mut out, "mean", &self.mean);
        row(&mut out, "sd", &self.sd);
        for (c, w) in self.weights.iter().enumerate() {
            row(&mut out, &format!("class {}", Placement::ALL[c].name()), w);
        }
        out.push('\n');
        out
    }
}

const SHIPPED: &str = include_str!("../../models/placement_lr_v1.txt");

/// A model-file error at a line (0: the file as a whole).
fn line_error(line: usize, reason: &str) -> PlacementError {
    PlacementError::Model {
        line,
        reason: reason.into(),
    }
}

/// The numbers of a line, all finite.
fn numbers(ln: usize, toks: &[&str]) -> Result<Vec<f64>, PlacementError> {
    finite_numbers(toks).map_err(|t| line_error(ln, &format!("{t:?} is not a finite number")))
}

/// The keyword lines of a model file, in order.
struct Body<'a, I: Iterator<Item = (usize, &'a str)>> {
    lines: I,
    last_line: usize,
}

impl<'a, I: Iterator<Item = (usize, &'a str)>> Body<'a, I> {
    /// The next line, which should be the `what` line.
    fn next(&mut self, what: &str) -> Result<(usize, &'a str), PlacementError> {
        self.lines.next().ok_or_else(|| {
            line_error(
                self.last_line,
                &format!("file ends before the '{what}' line"),
            )
        })
    }

    /// A `key` line of [`FEATURES`] numbers, with its line number.
    fn vector(&mut self, key: &str) -> Result<(usize, Features), PlacementError> {
        let (ln, l) = self.next(key)?;
        let tok: Vec<&str> = l.split_whitespace().collect();
        if tok.first() != Some(&key) {
            return Err(line_error(ln, &format!("expected a '{key}' line")));
        }
        let v = numbers(ln, &tok[1..])?;
        if v.len() != FEATURES {
            return Err(line_error(
                ln,
                &format!("'{key}' needs {FEATURES} numbers, found {}", v.len()),
            ));
        }
        let mut out = [0.0; FEATURES];
        out.copy_from_slice(&v);
        Ok((ln, out))
    }
}

/// `classes N NAME...`: this build's classes, in the order of the `class` lines.
fn parse_classes((ln, l): (usize, &str)) -> Result<[usize; CLASSES], PlacementError> {
    let tok: Vec<&str> = l.split_whitespace().collect();
    if tok.first() != Some(&"classes") || tok.len() < 2 {
        return Err(line_error(ln, "expected 'classes N NAME...'"));
    }
    let n: usize = tok[1]
        .parse()
        .map_err(|_| line_error(ln, "class count is not a number"))?;
    if n != CLASSES || tok.len() != 2 + n {
        return Err(line_error(
            ln,
            &format!(
                "expected {CLASSES} classes (this build's), found {}",
                tok.len() - 2
            ),
        ));
    }
    let mut order = [usize::MAX; CLASSES];
    for (k, name) in tok[2..].iter().enumerate() {
        let p = Placement::from_name(name)
            .ok_or_else(|| line_error(ln, &format!("unknown class {name:?}")))?;
        if order.contains(&p.index()) {
            return Err(line_error(ln, &format!("class {name} listed twice")));
        }
        order[k] = p.index();
    }
    Ok(order)
}

/// `features N NAME...`: exactly this build's feature set.
fn parse_features((ln, l): (usize, &str)) -> Result<(), PlacementError> {
    let tok: Vec<&str> = l.split_whitespace().collect();
    if tok.first() != Some(&"features") || tok.len() < 2 {
        return Err(line_error(ln, "expected 'features N NAME...'"));
    }
    let n: usize = tok[1]
        .parse()
        .map_err(|_| line_error(ln, "feature count is not a number"))?;
    if n != FEATURES {
        return Err(PlacementError::ModelFeatureCount {
            expected: FEATURES,
            found: n,
        });
    }
    if tok.len() != 2 + n || tok[2..] != FEATURE_NAMES {
        return Err(line_error(
            ln,
            "feature names differ from this build's feature set",
        ));
    }
    Ok(())
}

/// `class NAME b w...`: the weights of `class` (bias first).
fn parse_class_weights(
    (ln, l): (usize, &str),
    class: usize,
) -> Result<[f64; FEATURES + 1], PlacementError> {
    let tok: Vec<&str> = l.split_whitespace().collect();
    let want = Placement::ALL[class].name();
    if tok.first() != Some(&"class") || tok.get(1) != Some(&want) {
        return Err(line_error(ln, &format!("expected 'class {want} ...'")));
    }
    let v = numbers(ln, &tok[2..])?;
    if v.len() != FEATURES + 1 {
        return Err(line_error(
            ln,
            &format!(
                "class line needs {} numbers, found {}",
                FEATURES + 1,
                v.len()
            ),
        ));
    }
    let mut w = [0.0; FEATURES + 1];
    w.copy_from_slice(&v);
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> PlacementModel {
        let mut w = [[0.0; FEATURES + 1]; CLASSES];
        for (c, row) in w.iter_mut().enumerate() {
            for (i, v) in row.iter_mut().enumerate() {
                *v = ((c * 31 + i * 7) % 13) as f64 / 7.0 - 0.9;
            }
        }
        PlacementModel::new([0.5; FEATURES], [1.5; FEATURES], w, vec!["test".into()]).unwrap()
    }

    #[test]
    fn round_trips_exactly() {
        let m = model();
        let back = PlacementModel::parse(&m.to_text()).unwrap();
        assert_eq!(back, m);
        let p = m.probabilities(&[0.3; FEATURES]);
        assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn shipped_model_parses() {
        let m = PlacementModel::shipped();
        assert!(!m.comments.is_empty());
    }

    #[test]
    fn bad_files_are_typed_errors() {
        let t = model().to_text();
        assert!(matches!(
            PlacementModel::parse(&t.replace(" 1\n", " 2\n")),
            Err(PlacementError::ModelVersion { .. })
        ));
        assert!(matches!(
            PlacementModel::parse(&t.replace("features 23", "features 22")),
            Err(PlacementError::ModelFeatureCount {
                expected: 23,
                found: 22
            })
        ));
        let cut = &t[..t.len() - 40];
        assert!(matches!(
            PlacementModel::parse(cut),
            Err(PlacementError::Model { .. })
        ));
        assert!(matches!(
            PlacementModel::parse(&t.replace("sd 1.5", "sd -1.5")),
            Err(PlacementError::Model { line: 6, .. })
        ));
        assert!(matches!(
            PlacementModel::parse(""),
            Err(PlacementError::Model { line: 0, .. })
        ));
    }
}
