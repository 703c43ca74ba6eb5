//! Feature windows: the last `window` smoothed grid samples of angular rate and
//! linear acceleration (ENU), in a fixed-capacity ring, and the features of one
//! window expressed in the stabilised frame S (gravity-aligned, x/y turned by the
//! device yaw at the window's end).
//!
//! Engineered features (the paper feeds the raw window to an SVR; a phone-sized
//! linear model needs them):
//! - scalars ([`N_SCALAR`]), for the speed: standard deviations of vertical and
//!   horizontal acceleration and of vertical and horizontal angular rate, the
//!   vertical-acceleration zero-crossing rate (≈ 2 × step frequency) and products
//!   that a step-length × cadence law needs;
//! - 2-D vectors ([`N_VECTOR`]), for the direction, as complex numbers `x + i·y` in S:
//!   normalised covariances of horizontal acceleration and of horizontal angular
//!   rate with vertical acceleration and with its derivative (vertical jerk). The
//!   forward surge of a gait leads the vertical oscillation by a quarter period,
//!   so `cov(a_h, ȧ_z)` points along the walking direction whatever the yaw of the
//!   phone; limb swing turns about the lateral axis, so the gyro terms point
//!   sideways. They rotate with the frame (yaw-equivariant).

use super::resample::Channels;
use crate::signal::Ring;

/// Longest window, grid samples.
pub const MAX_WINDOW: usize = 400;
/// Number of scalar features.
pub const N_SCALAR: usize = 10;
/// Number of 2-D (complex) features.
pub const N_VECTOR: usize = 4;
/// Names of the scalar features (model file and docs).
pub const SCALAR_NAMES: [&str; N_SCALAR] = [
    "sd_az",
    "sqrt_sd_az",
    "sd_ah",
    "sd_gz",
    "sd_gh",
    "zc_hz",
    "zc_hz2",
    "zc_sqrt_sd_az",
    "ln_sd_az",
    "mean_g_norm",
];

/// Features of one window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindowFeatures {
    /// Time of the window's first and last smoothed sample, s.
    pub t_start_s: f64,
    pub t_end_s: f64,
    /// Yaw of S (device yaw at the window's end), rad.
    pub yaw_rad: f64,
    pub scalars: [f64; N_SCALAR],
    /// `[re, im]` = (x, y) in S.
    pub vectors: [[f64; 2]; N_VECTOR],
}

impl WindowFeatures {
    pub fn is_finite(&self) -> bool {
        self.scalars.iter().all(|v| v.is_finite())
            && self.vectors.iter().flatten().all(|v| v.is_finite())
            && self.yaw_rad.is_finite()
    }
}

/// The window ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureWindow {
    pub(crate) len: usize,
    pub(crate) ring: Ring<(f64, Channels), MAX_WINDOW>,
}

impl FeatureWindow {
    pub fn new(len: usize) -> Self {
        Self {
            len: len.clamp(2, MAX_WINDOW),
            ring: Ring::new(),
        }
    }

    pub fn reset(&mut self) {
        self.ring.clear();
    }

    pub fn push(&mut self, t: f64, x: &Channels) {
        self.ring.push((t, *x));
    }

    /// Whether a full window is held.
    pub fn is_full(&self) -> bool {
        self.ring.len() >= self.len
    }

    /// Features of the newest `len` samples in S (yaw `yaw_rad`); `None` until full.
    pub fn features(&self, yaw_rad: f64) -> Option<WindowFeatures> {
        if !self.is_full() {
            return None;
        }
        let n = self.len;
        let base = self.ring.len() - n;
        let inv_n = 1.0 / n as f64;
        let (mean, g_norm) = self.means(base, n, inv_n);
        // Second moments, covariances with a_z and the vertical jerk, zero crossings.
        let (t_start, _) = self.ring.get(base).unwrap_or_default();
        let (t_end, _) = self.ring.get(base + n - 1).unwrap_or_default();
        let dt = ((t_end - t_start) / (n - 1) as f64).max(1e-6);
        let mut var = [0.0; 6];
        let mut c_ah_az = [0.0; 2];
        let mut c_gh_az = [0.0; 2];
        let mut c_ah_jz = [0.0; 2];
        let mut c_gh_jz = [0.0; 2];
        let mut var_jz = 0.0;
        let mut crossings = 0u32;
        let mut prev_az: Option<f64> = None;
        for i in 0..n {
            let (_, x) = self.ring.get(base + i).unwrap_or_default();
            let mut d = [0.0; 6];
            for c in 0..6 {
                d[c] = x[c] - mean[c];
                var[c] += d[c] * d[c];
            }
            let az = d[5];
            // Central difference of a_z (one-sided at the ends).
            let (_, xa) = self
                .ring
                .get(base + i.saturating_sub(1))
                .unwrap_or_default();
            let (_, xb) = self.ring.get(base + (i + 1).min(n - 1)).unwrap_or_default();
            let span = ((i + 1).min(n - 1) - i.saturating_sub(1)) as f64 * dt;
            let jz = (xb[5] - xa[5]) / span;
            var_jz += jz * jz;
            for k in 0..2 {
                c_ah_az[k] += d[3 + k] * az;
                c_gh_az[k] += d[k] * az;
                c_ah_jz[k] += d[3 + k] * jz;
                c_gh_jz[k] += d[k] * jz;
            }
            if let Some(p) = prev_az {
                if (p < 0.0) != (az < 0.0) {
                    crossings += 1;
                }
            }
            prev_az = Some(az);
        }
        let sd = var.map(|v| (v * inv_n).sqrt());
        let sd_jz = (var_jz * inv_n).sqrt();
        let sd_az = sd[5];
        let sd_ah = (sd[3] * sd[3] + sd[4] * sd[4]).sqrt();
        let sd_gz = sd[2];
        let sd_gh = (sd[0] * sd[0] + sd[1] * sd[1]).sqrt();
        let span_s = (t_end - t_start).max(1e-6);
        let zc_hz = crossings as f64 / span_s;
        let sqrt_sd_az = sd_az.sqrt();
        let scalars = [
            sd_az,
            sqrt_sd_az,
            sd_ah,
            sd_gz,
            sd_gh,
            zc_hz,
            zc_hz * zc_hz,
            zc_hz * sqrt_sd_az,
            (sd_az + 0.01).ln(),
            g_norm,
        ];
        // Normalised covariances, turned from ENU into S by −yaw.
        const EPS: f64 = 1e-3;
        let (s, c) = yaw_rad.sin_cos();
        let into_s = |v: [f64; 2], norm: f64| -> [f64; 2] {
            let v = [v[0] * inv_n / norm, v[1] * inv_n / norm];
            [c * v[0] + s * v[1], -s * v[0] + c * v[1]]
        };
        let vectors = [
            into_s(c_ah_jz, sd_ah * sd_jz + EPS),
            into_s(c_ah_az, sd_ah * sd_az + EPS),
            into_s(c_gh_az, sd_gh * sd_az + EPS),
            into_s(c_gh_jz, sd_gh * sd_jz + EPS),
        ];
        Some(WindowFeatures {
            t_start_s: t_start,
            t_end_s: t_end,
            yaw_rad,
            scalars,
            vectors,
        })
    }

    /// The means of the window's `n` samples from `base` (`inv_n` = 1/n): of each
    /// channel, and of the norm of the first three.
    fn means(&self, base: usize, n: usize, inv_n: f64) -> ([f64; 6], f64) {
        let mut mean = [0.0; 6];
        let mut g_norm = 0.0;
        for i in 0..n {
            let (_, x) = self.ring.get(base + i).unwrap_or_default();
            for c in 0..6 {
                mean[c] += x[c];
            }
            g_norm += (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        }
        for m in mean.iter_mut() {
            *m *= inv_n;
        }
        g_norm *= inv_n;
        (mean, g_norm)
    }
}
