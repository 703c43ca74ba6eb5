//! Placement features of one window of [`WINDOW`] bins on the 50 Hz grid (5.12 s).
//!
//! Gravity is the window's mean vector `g` (a 5-s low-pass); `ĝ = g/‖g‖`. The dynamic
//! acceleration `d = a − g` splits into a vertical part `v = d·ĝ` and a horizontal
//! part `h = d − v ĝ`. Every feature is a function of `‖a‖`, `v`, `‖h‖` or of the
//! gravity direction in the phone frame, so a rotation of the phone about the
//! vertical changes nothing; the gravity direction itself is kept on purpose (a
//! pocket phone is upright, a phone read in the hand lies nearly flat). The absolute
//! values `|ĝ_x|, |ĝ_y|, |ĝ_z|` make a phone upside down the same as upright.
//!
//! | # | name            | definition |
//! |---|-----------------|------------|
//! | 0 | `ln_sd_norm`    | ln(σ(‖a‖) + 0.01) |
//! | 1 | `ln_sd_vert`    | ln(σ(v) + 0.01) |
//! | 2 | `ln_rms_horiz`  | ln(rms(‖h‖) + 0.01) |
//! | 3 | `ln_wander`     | ln(1 − ‖g‖ / mean‖a‖ + 0.001): how much the phone turns |
//! | 4–6 | `grav_x/y/z`  | `|ĝ_x|`, `|ĝ_y|`, `|ĝ_z|` |
//! | 7 | `skew_norm`     | skewness of ‖a‖ |
//! | 8 | `ln_kurt_norm`  | ln(kurtosis of ‖a‖) |
//! | 9 | `skew_vert`     | skewness of v |
//! | 10 | `ln_range_norm`| ln(p95 − p5 of ‖a‖ + 0.01) |
//! | 11–12 | `ac_norm_step/stride` | max autocorrelation of ‖a‖ over lags 0.30–0.74 s / 0.76–1.50 s |
//! | 13–14 | `ac_vert_step/stride` | the same for v |
//! | 15–16 | `ac_horiz_step/stride` | the same for ‖h‖ |
//! | 17–21 | `band_*`     | ln(fraction + 1e−4) of the dynamic ‖a‖ energy in 0.2–1, 1–2.5, 2.5–5, 5–10, 10–25 Hz |
//! | 22 | `vh_corr`      | correlation of v and ‖h‖ |
//!
//! The autocorrelation at lag L is the normalised correlation of the overlapping
//! parts, `Σ x_n x_{n+L} / √(Σ x_n² · Σ x_{n+L}²)` (zero when a part is flat).
//! Everything is computed on stack arrays: no heap. Non-finite inputs cannot occur
//! (the classifier checks samples at the door), degenerate windows give finite values.

use super::resample::BIN_S;

/// Bins per window (5.12 s; a power of two, the DFT indexes its table with a mask).
pub const WINDOW: usize = 256;
const _: () = assert!(WINDOW.is_power_of_two());
/// Number of features.
pub const FEATURES: usize = 23;

/// Feature names, in order (model files list them).
pub const FEATURE_NAMES: [&str; FEATURES] = [
    "ln_sd_norm",
    "ln_sd_vert",
    "ln_rms_horiz",
    "ln_wander",
    "grav_x",
    "grav_y",
    "grav_z",
    "skew_norm",
    "ln_kurt_norm",
    "skew_vert",
    "ln_range_norm",
    "ac_norm_step",
    "ac_norm_stride",
    "ac_vert_step",
    "ac_vert_stride",
    "ac_horiz_step",
    "ac_horiz_stride",
    "band_0.2_1",
    "band_1_2.5",
    "band_2.5_5",
    "band_5_10",
    "band_10_25",
    "vh_corr",
];

/// Step lag range, bins (0.30–0.74 s).
const STEP_LAGS: (usize, usize) = (15, 37);
/// Stride lag range, bins (0.76–1.50 s).
const STRIDE_LAGS: (usize, usize) = (38, 75);
/// Band edges, Hz.
const BANDS_HZ: [f64; 6] = [0.2, 1.0, 2.5, 5.0, 10.0, 25.0];

/// A feature vector.
pub type Features = [f64; FEATURES];

/// Precomputed tables of the feature computation (cosine table of the DFT).
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureTables {
    cos: [f64; WINDOW],
}

impl Default for FeatureTables {
    fn default() -> Self {
        let mut cos = [0.0; WINDOW];
        for (n, c) in cos.iter_mut().enumerate() {
            *c = (std::f64::consts::TAU * n as f64 / WINDOW as f64).cos();
        }
        Self { cos }
    }
}

fn mean(x: &[f64; WINDOW]) -> f64 {
    x.iter().sum::<f64>() / WINDOW as f64
}

/// Central moments 2, 3, 4 of x.
fn moments(x: &[f64; WINDOW]) -> (f64, f64, f64, f64) {
    let m = mean(x);
    let (mut m2, mut m3, mut m4) = (0.0, 0.0, 0.0);
    for v in x {
        let d = v - m;
        let d2 = d * d;
        m2 += d2;
        m3 += d2 * d;
        m4 += d2 * d2;
    }
    let n = WINDOW as f64;
    (m, m2 / n, m3 / n, m4 / n)
}

fn skew_kurt(m2: f64, m3: f64, m4: f64) -> (f64, f64) {
    if m2 < 1e-12 {
        return (0.0, 3.0);
    }
    (
        (m3 / m2.powf(1.5)).clamp(-20.0, 20.0),
        (m4 / (m2 * m2)).clamp(1.0, 400.0),
    )
}

/// Maximum normalised autocorrelation of zero-mean `x` over lags `lo..=hi`.
fn max_autocorr(x: &[f64; WINDOW], (lo, hi): (usize, usize)) -> f64 {
    let mut best = -1.0f64;
    for lag in lo..=hi {
        let (mut xy, mut xx, mut yy) = (0.0, 0.0, 0.0);
        for n in 0..WINDOW - lag {
            let (a, b) = (x[n], x[n + lag]);
            xy += a * b;
            xx += a * a;
            yy += b * b;
        }
        let den = (xx * yy).sqrt();
        let r = if den > 1e-12 { xy / den } else { 0.0 };
        best = best.max(r);
    }
    best
}

fn centre(x: &mut [f64; WINDOW]) {
    let m = mean(x);
    for v in x.iter_mut() {
        *v -= m;
    }
}

/// Band energies of the dynamic magnitude `norm` (centred) by a direct DFT over bins
/// 1..N/2, summed per band of [`BANDS_HZ`].
fn band_energies(tables: &FeatureTables, norm: &[f64; WINDOW]) -> [f64; 5] {
    let df = 1.0 / (WINDOW as f64 * BIN_S);
    let mut bands = [0.0f64; 5];
    for kf in 1..=WINDOW / 2 {
        let hz = kf as f64 * df;
        let Some(b) = (0..5).find(|&b| hz >= BANDS_HZ[b] && hz < BANDS_HZ[b + 1] + 1e-9) else {
            continue;
        };
        let (mut re, mut im) = (0.0, 0.0);
        // Table indices of kf·n and kf·n − N/4 (sin θ = cos(θ − π/2)), modulo N.
        let (mut i, mut j) = (0usize, 3 * WINDOW / 4);
        for x in norm {
            re += x * tables.cos[i];
            im += x * tables.cos[j];
            i = (i + kf) & (WINDOW - 1);
            j = (j + kf) & (WINDOW - 1);
        }
        bands[b] += re * re + im * im;
    }
    bands
}

/// Features of a window of bin means (oldest first), m/s².
pub fn window_features(tables: &FeatureTables, window: &[[f64; 3]; WINDOW]) -> Features {
    let mut f = [0.0; FEATURES];
    let mut g = [0.0; 3];
    for a in window {
        for k in 0..3 {
            g[k] += a[k];
        }
    }
    for gk in &mut g {
        *gk /= WINDOW as f64;
    }
    let gn = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let u = if gn > 1e-9 {
        [g[0] / gn, g[1] / gn, g[2] / gn]
    } else {
        [0.0, 0.0, 1.0]
    };
    let mut norm = [0.0; WINDOW];
    let mut vert = [0.0; WINDOW];
    let mut horiz = [0.0; WINDOW];
    for (i, a) in window.iter().enumerate() {
        norm[i] = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let d = [a[0] - g[0], a[1] - g[1], a[2] - g[2]];
        let v = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
        let h = [d[0] - v * u[0], d[1] - v * u[1], d[2] - v * u[2]];
        vert[i] = v;
        horiz[i] = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
    }
    let (mean_norm, n2, n3, n4) = moments(&norm);
    let (_, v2, v3, v4) = moments(&vert);
    let h_rms = (horiz.iter().map(|h| h * h).sum::<f64>() / WINDOW as f64).sqrt();
    f[0] = (n2.sqrt() + 0.01).ln();
    f[1] = (v2.sqrt() + 0.01).ln();
    f[2] = (h_rms + 0.01).ln();
    let wander = if mean_norm > 1e-9 {
        (1.0 - gn / mean_norm).max(0.0)
    } else {
        0.0
    };
    f[3] = (wander + 1e-3).ln();
    f[4] = u[0].abs();
    f[5] = u[1].abs();
    f[6] = u[2].abs();
    let (s, k) = skew_kurt(n2, n3, n4);
    f[7] = s;
    f[8] = k.ln();
    f[9] = skew_kurt(v2, v3, v4).0;
    let mut sorted = norm;
    sorted.sort_unstable_by(f64::total_cmp);
    let p = |q: f64| sorted[((WINDOW - 1) as f64 * q).round() as usize];
    f[10] = (p(0.95) - p(0.05) + 0.01).ln();

    centre(&mut norm);
    centre(&mut vert);
    let mut hc = horiz;
    centre(&mut hc);
    f[11] = max_autocorr(&norm, STEP_LAGS);
    f[12] = max_autocorr(&norm, STRIDE_LAGS);
    f[13] = max_autocorr(&vert, STEP_LAGS);
    f[14] = max_autocorr(&vert, STRIDE_LAGS);
    f[15] = max_autocorr(&hc, STEP_LAGS);
    f[16] = max_autocorr(&hc, STRIDE_LAGS);

    let bands = band_energies(tables, &norm);
    let total: f64 = bands.iter().sum();
    for b in 0..5 {
        let frac = if total > 1e-12 { bands[b] / total } else { 0.2 };
        f[17 + b] = (frac + 1e-4).ln();
    }

    let (mut vh, mut vv, mut hh) = (0.0, 0.0, 0.0);
    for i in 0..WINDOW {
        vh += vert[i] * hc[i];
        vv += vert[i] * vert[i];
        hh += hc[i] * hc[i];
    }
    let den = (vv * hh).sqrt();
    f[22] = if den > 1e-12 { vh / den } else { 0.0 };
    for v in &mut f {
        if !v.is_finite() {
            *v = 0.0;
        }
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk(rot: impl Fn([f64; 3]) -> [f64; 3]) -> [[f64; 3]; WINDOW] {
        let mut w = [[0.0; 3]; WINDOW];
        for (i, a) in w.iter_mut().enumerate() {
            let t = i as f64 * BIN_S;
            let ph = std::f64::consts::TAU * 1.8 * t;
            // Body frame: vertical bounce at step rate, sway at stride rate.
            let up = 9.81 + 2.0 * ph.cos();
            let side = 0.8 * (0.5 * ph).sin();
            *a = rot([side, 0.3 * ph.sin(), up]);
        }
        w
    }

    #[test]
    fn features_are_finite_and_invariant_to_yaw() {
        let t = FeatureTables::default();
        let a = window_features(&t, &walk(|v| v));
        // Rotate 70° about the vertical (z here): identical up to rounding.
        let (s, c) = 70f64.to_radians().sin_cos();
        let b = window_features(
            &t,
            &walk(|v| [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]),
        );
        for i in 0..FEATURES {
            assert!(a[i].is_finite());
            if !(4..=5).contains(&i) {
                assert!(
                    (a[i] - b[i]).abs() < 1e-9,
                    "{} {} {}",
                    FEATURE_NAMES[i],
                    a[i],
                    b[i]
                );
            }
        }
        // Step periodicity at 1.8 steps/s is seen.
        assert!(a[11] > 0.9, "{}", a[11]);
        // Flat and zero windows stay finite.
        for w in [[[0.0; 3]; WINDOW], [[0.0, 0.0, 9.81]; WINDOW]] {
            assert!(window_features(&t, &w).iter().all(|v| v.is_finite()));
        }
    }
}
