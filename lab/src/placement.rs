//! Training of the logistic-regression placement model: features standardised with
//! the training mean and standard deviation, class-balanced softmax cross-entropy
//! (each class weighs the same in total, whatever its number of windows) plus an L2
//! penalty on the weights (not the biases), minimised by full-batch gradient descent
//! with Nesterov momentum. Deterministic: same data → same model.

use stridekit_core::placement::PlacementError;

/// Why training produced no model.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    /// The training data cannot produce a model.
    #[error("cannot train: {reason}")]
    Data { reason: String },
    /// The trained weights do not make a valid model.
    #[error(transparent)]
    Model(#[from] PlacementError),
}
use stridekit_core::placement::PlacementModel;
use stridekit_core::placement::{Features, FEATURES};
use stridekit_core::placement::{Placement, CLASSES};

/// Training hyper-parameters. The step actually taken is `step / (1 + 2·l2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrainParams {
    /// L2 penalty on the weights (per unit of mean class-balanced loss).
    pub l2: f64,
    /// Gradient-descent iterations.
    pub iterations: usize,
    /// Step size.
    pub step: f64,
    /// Momentum.
    pub momentum: f64,
}

impl Default for TrainParams {
    fn default() -> Self {
        Self {
            l2: 1e-2,
            iterations: 600,
            step: 0.5,
            momentum: 0.9,
        }
    }
}

/// Trains a model on labelled windows. Classes without windows get a bias far below
/// the others (they are never predicted).
pub fn train(
    data: &[(Features, Placement)],
    params: &TrainParams,
    comments: Vec<String>,
) -> Result<PlacementModel, TrainError> {
    if data.len() < 2 {
        return Err(TrainError::Data {
            reason: format!("{} windows, need at least 2", data.len()),
        });
    }
    let n = data.len() as f64;
    let mut mean = [0.0; FEATURES];
    for (f, _) in data {
        for i in 0..FEATURES {
            mean[i] += f[i] / n;
        }
    }
    let mut sd = [0.0; FEATURES];
    for (f, _) in data {
        for i in 0..FEATURES {
            sd[i] += (f[i] - mean[i]).powi(2) / n;
        }
    }
    for s in &mut sd {
        *s = s.sqrt().max(1e-6);
    }
    let scratch = PlacementModel::new(mean, sd, [[0.0; FEATURES + 1]; CLASSES], Vec::new())?;
    let z: Vec<(Features, usize)> = data
        .iter()
        .map(|(f, p)| (scratch.standardise(f), p.index()))
        .collect();
    let (count, cw) = class_weights(z.iter().map(|(_, c)| *c));

    type W = [[f64; FEATURES + 1]; CLASSES];
    let mut w: W = [[0.0; FEATURES + 1]; CLASSES];
    let mut vel: W = [[0.0; FEATURES + 1]; CLASSES];
    let gradient = |w: &W| -> W {
        let mut g: W = [[0.0; FEATURES + 1]; CLASSES];
        let m = PlacementModel {
            weights: *w,
            ..scratch.clone()
        };
        for (zf, c) in &z {
            let mut p = m.scores(zf);
            let max = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let mut sum = 0.0;
            for v in &mut p {
                *v = (*v - max).exp();
                sum += *v;
            }
            let sw = cw[*c];
            for k in 0..CLASSES {
                let r = sw * (p[k] / sum - if k == *c { 1.0 } else { 0.0 });
                g[k][0] += r;
                for i in 0..FEATURES {
                    g[k][i + 1] += r * zf[i];
                }
            }
        }
        for k in 0..CLASSES {
            for i in 1..=FEATURES {
                g[k][i] += params.l2 * w[k][i];
            }
        }
        g
    };
    // The penalty adds l2 to the curvature: shrink the step so descent stays stable.
    let step = params.step / (1.0 + 2.0 * params.l2.max(0.0));
    for _ in 0..params.iterations {
        let mut look = w;
        for k in 0..CLASSES {
            for i in 0..=FEATURES {
                look[k][i] += params.momentum * vel[k][i];
            }
        }
        let g = gradient(&look);
        for k in 0..CLASSES {
            for i in 0..=FEATURES {
                vel[k][i] = params.momentum * vel[k][i] - step * g[k][i];
                w[k][i] += vel[k][i];
            }
        }
    }
    if !w.iter().flatten().all(|v| v.is_finite()) {
        return Err(TrainError::Data {
            reason: "gradient descent diverged (lower the step)".into(),
        });
    }
    for k in 0..CLASSES {
        if count[k] == 0 {
            w[k] = [0.0; FEATURES + 1];
            w[k][0] = -30.0;
        }
    }
    Ok(PlacementModel::new(mean, sd, w, comments)?)
}

/// Fraction of windows whose most probable class is the label.
/// Samples per class, and the class-balanced sample weights: the samples of each
/// class present sum to 1 / (classes present).
pub(crate) fn class_weights(classes: impl Iterator<Item = usize>) -> ([usize; CLASSES], Vec<f64>) {
    let mut count = [0usize; CLASSES];
    for c in classes {
        count[c] += 1;
    }
    let present = count.iter().filter(|&&c| c > 0).count() as f64;
    let weights = count
        .iter()
        .map(|&c| {
            if c > 0 {
                1.0 / (present * c as f64)
            } else {
                0.0
            }
        })
        .collect();
    (count, weights)
}

pub fn accuracy(model: &PlacementModel, data: &[(Features, Placement)]) -> f64 {
    if data.is_empty() {
        return f64::NAN;
    }
    let ok = data.iter().filter(|(f, p)| predict(model, f) == *p).count();
    ok as f64 / data.len() as f64
}

/// Most probable class of one window.
pub fn predict(model: &PlacementModel, f: &Features) -> Placement {
    let p = model.probabilities(f);
    let mut best = 0;
    for c in 1..CLASSES {
        if p[c] > p[best] {
            best = c;
        }
    }
    Placement::ALL[best]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separable_classes_are_learned() {
        let mut data = Vec::new();
        for k in 0..200 {
            let c = k % 3;
            let mut f = [0.0; FEATURES];
            f[c] = 1.0 + (k as f64 * 0.37).sin() * 0.2;
            f[5] = (k as f64 * 1.3).cos();
            data.push((f, Placement::ALL[c]));
        }
        let m = train(&data, &TrainParams::default(), vec![]).unwrap();
        assert!(accuracy(&m, &data) > 0.99);
        // Absent classes are never predicted.
        assert!(m.weights[5][0] < -20.0);
        assert!(train(&data[..1], &TrainParams::default(), vec![]).is_err());
    }
}
