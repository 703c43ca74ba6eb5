//! Experiment for `stridekit eval placement --mlp`: a one-hidden-layer perceptron
//! (16 tanh units) on the same standardised features as the logistic regression,
//! class-balanced cross-entropy + L2, full-batch Adam, deterministic initialisation.
//! Used only to compare against the shipped logistic regression under the same
//! leave-one-user-out protocol; it has no model file.

use stridekit_core::placement::{Features, Placement, PlacementModel, CLASSES, FEATURES};

const H: usize = 16;
const ITERATIONS: usize = 1500;
const LR: f64 = 0.01;

pub struct Mlp {
    scale: PlacementModel,
    w1: Vec<[f64; FEATURES + 1]>,
    w2: [[f64; H + 1]; CLASSES],
}

impl Mlp {
    fn forward(&self, z: &Features) -> ([f64; H], [f64; CLASSES]) {
        let mut h = [0.0; H];
        for (j, w) in self.w1.iter().enumerate() {
            let mut v = w[0];
            for i in 0..FEATURES {
                v += w[i + 1] * z[i];
            }
            h[j] = v.tanh();
        }
        let mut s = [0.0; CLASSES];
        for (k, w) in self.w2.iter().enumerate() {
            let mut v = w[0];
            for j in 0..H {
                v += w[j + 1] * h[j];
            }
            s[k] = v;
        }
        let max = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let sum: f64 = s.iter().map(|v| (v - max).exp()).sum();
        for v in &mut s {
            *v = (*v - max).exp() / sum;
        }
        (h, s)
    }

    pub fn predict(&self, f: &Features) -> Placement {
        let (_, p) = self.forward(&self.scale.standardise(f));
        let best = (0..CLASSES)
            .max_by(|&a, &b| p[a].total_cmp(&p[b]))
            .unwrap_or(0);
        Placement::ALL[best]
    }

    /// Parameter bytes (f64).
    pub fn parameter_bytes() -> usize {
        8 * (H * (FEATURES + 1) + CLASSES * (H + 1) + 2 * FEATURES)
    }
}

pub fn train(data: &[(Features, Placement)], l2: f64) -> Result<Mlp, String> {
    // Standardisation from a logistic regression trained for 0 iterations.
    let params = crate::placement::TrainParams {
        iterations: 0,
        ..Default::default()
    };
    let scale = crate::placement::train(data, &params, Vec::new()).map_err(|e| e.to_string())?;
    let z: Vec<(Features, usize)> = data
        .iter()
        .map(|(f, p)| (scale.standardise(f), p.index()))
        .collect();
    let (count, cw) = crate::placement::class_weights(z.iter().map(|(_, c)| *c));
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let s1 = 2.0 / (FEATURES as f64).sqrt();
    let s2 = 2.0 / (H as f64).sqrt();
    let mut m = Mlp {
        scale,
        w1: (0..H)
            .map(|_| {
                let mut w = [0.0; FEATURES + 1];
                for v in w.iter_mut().skip(1) {
                    *v = rnd() * s1;
                }
                w
            })
            .collect(),
        w2: [[0.0; H + 1]; CLASSES],
    };
    for w in &mut m.w2 {
        for v in w.iter_mut().skip(1) {
            *v = rnd() * s2;
        }
    }
    // Flattened parameters for Adam.
    let n1 = H * (FEATURES + 1);
    let n = n1 + CLASSES * (H + 1);
    let (mut mo, mut ve) = (vec![0.0; n], vec![0.0; n]);
    for it in 1..=ITERATIONS {
        let mut g = vec![0.0; n];
        for (zf, c) in &z {
            let (h, p) = m.forward(zf);
            let sw = cw[*c];
            let mut dh = [0.0; H];
            for k in 0..CLASSES {
                let r = sw * (p[k] - if k == *c { 1.0 } else { 0.0 });
                g[n1 + k * (H + 1)] += r;
                for j in 0..H {
                    g[n1 + k * (H + 1) + j + 1] += r * h[j];
                    dh[j] += r * m.w2[k][j + 1];
                }
            }
            for j in 0..H {
                let d = dh[j] * (1.0 - h[j] * h[j]);
                g[j * (FEATURES + 1)] += d;
                for i in 0..FEATURES {
                    g[j * (FEATURES + 1) + i + 1] += d * zf[i];
                }
            }
        }
        for j in 0..H {
            for i in 1..=FEATURES {
                g[j * (FEATURES + 1) + i] += l2 * m.w1[j][i];
            }
        }
        for k in 0..CLASSES {
            for j in 1..=H {
                g[n1 + k * (H + 1) + j] += l2 * m.w2[k][j];
            }
        }
        let (b1, b2) = (0.9f64, 0.999f64);
        for q in 0..n {
            mo[q] = b1 * mo[q] + (1.0 - b1) * g[q];
            ve[q] = b2 * ve[q] + (1.0 - b2) * g[q] * g[q];
            let step = LR * (mo[q] / (1.0 - b1.powi(it as i32)))
                / ((ve[q] / (1.0 - b2.powi(it as i32))).sqrt() + 1e-8);
            if q < n1 {
                m.w1[q / (FEATURES + 1)][q % (FEATURES + 1)] -= step;
            } else {
                let r = q - n1;
                m.w2[r / (H + 1)][r % (H + 1)] -= step;
            }
        }
    }
    for (w, &c) in m.w2.iter_mut().zip(&count) {
        if c == 0 {
            *w = [0.0; H + 1];
            w[0] = -30.0;
        }
    }
    Ok(m)
}
