//! Fitting the regressors on simulated walks ([`stridekit_sim::phone`]), and the
//! scenarios used for training and evaluation. Training runs off the phone (it
//! allocates freely); the engine computes the features, so training and inference
//! see exactly the same numbers.

use nalgebra::{DMatrix, DVector};

use stridekit_core::odometry::ImuSample;
use stridekit_core::odometry::{slot, OdometryModel, PipelineParams, Regressor};
use stridekit_core::odometry::{OdometryConfig, PhoneOdometry, PlacementSource};
use stridekit_core::odometry::{WindowFeatures, N_SCALAR, N_VECTOR};
use stridekit_core::placement::Placement;
use stridekit_formats::InertialRecording;
use stridekit_sim::phone::PhoneSegment;
use stridekit_sim::{simulate_phone, PhoneActivity, PhonePlacement, PhoneScenario, Rng};

/// Seeds at or above this are never used for training (evaluation only).
pub const FIRST_EVAL_SEED: u64 = 10_000;
/// Ridge penalty of the speed regression (standardised features).
pub const SPEED_RIDGE: f64 = 1.0;
/// Ridge penalty of the direction fit.
pub const DIRECTION_RIDGE: f64 = 1e-3;
/// Windows slower than this (m/s) do not train the direction.
pub const MIN_DIRECTION_SPEED_MPS: f64 = 0.3;

/// A walk of about 4 minutes for training and evaluation: three walking segments
/// at speeds drawn from the seed in 0.8–1.8 m/s, a 10 s stop, random turns;
/// 100 Hz, no GNSS.
pub fn sim_scenario(seed: u64, placement: PhonePlacement) -> PhoneScenario {
    let mut rng = Rng::new(seed ^ 0x0D0_0E7E);
    let mut v = || rng.range(0.8, 1.8);
    let (v1, v2, v3) = (v(), v(), v());
    let seg = |activity, duration_s| PhoneSegment {
        activity,
        duration_s,
    };
    PhoneScenario {
        segments: vec![
            seg(PhoneActivity::Walking { speed_mps: v1 }, 90.0),
            seg(PhoneActivity::Standing, 10.0),
            seg(PhoneActivity::Walking { speed_mps: v2 }, 90.0),
            seg(PhoneActivity::Walking { speed_mps: v3 }, 60.0),
        ],
        gnss: false,
        ..PhoneScenario::walk(seed, placement, 1.3, 0.0)
    }
}

/// One labelled window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LabelledWindow {
    /// Placement class of the recording (`None` = unknown: trains only the general
    /// regressor).
    pub placement: Option<Placement>,
    pub features: WindowFeatures,
    /// Mean true velocity over the window in S, m/s.
    pub velocity_s_mps: [f64; 2],
}

/// A recording with ground truth: IMU samples and true ENU positions.
pub trait Truth {
    /// True (east, north) at `t_s`, metres.
    fn position_at(&self, t_s: f64) -> (f64, f64);
}

impl Truth for stridekit_sim::SimulatedPhone {
    fn position_at(&self, t_s: f64) -> (f64, f64) {
        let p = self.truth_at(t_s);
        (p.east_m, p.north_m)
    }
}

/// Truth of a recorded walk (RIDI, RoNIN, an Android log with waypoints): its
/// positions, linearly interpolated.
pub struct RecTruth<'a>(pub &'a InertialRecording);

impl Truth for RecTruth<'_> {
    fn position_at(&self, t: f64) -> (f64, f64) {
        self.0.position_at(t)
    }
}

/// A recording's samples as the engine takes them.
pub fn samples_of(rec: &InertialRecording) -> Vec<ImuSample> {
    rec.samples
        .iter()
        .map(|s| ImuSample {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
            gyro_rads: s.gyro_rads,
            mag_ut: s.mag_ut,
        })
        .collect()
}

/// The engine's windows over a recording, labelled from its truth.
pub fn labelled_windows(
    samples: &[ImuSample],
    truth: &dyn Truth,
    placement: Option<Placement>,
    params: PipelineParams,
) -> Vec<LabelledWindow> {
    // Any valid regressor: only the features are used.
    let r = Regressor {
        mean: [0.0; N_SCALAR],
        sd: [1.0; N_SCALAR],
        speed: [0.0; N_SCALAR + 1],
        direction: [[0.0; 2]; N_VECTOR + 1],
    };
    let model = OdometryModel::new(params, r).expect("valid params");
    let cfg = OdometryConfig {
        placement: PlacementSource::Unknown,
        ..OdometryConfig::default()
    };
    let mut eng = PhoneOdometry::new(cfg, model).expect("valid");
    eng.push_batch(samples)
        .estimates
        .iter()
        .map(|e| {
            let f = e.features;
            let (e0, n0) = truth.position_at(f.t_start_s);
            let (e1, n1) = truth.position_at(f.t_end_s);
            let span = (f.t_end_s - f.t_start_s).max(1e-6);
            let v = [(e1 - e0) / span, (n1 - n0) / span];
            let (s, c) = f.yaw_rad.sin_cos();
            LabelledWindow {
                placement,
                features: f,
                velocity_s_mps: [c * v[0] + s * v[1], -s * v[0] + c * v[1]],
            }
        })
        .collect()
}

/// Ridge least squares `min ‖A w − b‖² + α ‖w‖²` (α not applied to `free` leading
/// columns).
fn ridge(a: &DMatrix<f64>, b: &DVector<f64>, alpha: f64, free: usize) -> DVector<f64> {
    let mut ata = a.transpose() * a;
    for i in free..ata.nrows() {
        ata[(i, i)] += alpha;
    }
    let atb = a.transpose() * b;
    ata.cholesky()
        .map(|c| c.solve(&atb))
        .unwrap_or_else(|| DVector::zeros(a.ncols()))
}

/// Fit one regressor on labelled windows (at least a few dozen).
pub fn fit_regressor(windows: &[&LabelledWindow]) -> Option<Regressor> {
    let n = windows.len();
    if n < 20 {
        return None;
    }
    let mut mean = [0.0; N_SCALAR];
    let mut sd = [0.0; N_SCALAR];
    for w in windows {
        for (m, x) in mean.iter_mut().zip(&w.features.scalars) {
            *m += x / n as f64;
        }
    }
    for w in windows {
        for j in 0..N_SCALAR {
            sd[j] += (w.features.scalars[j] - mean[j]).powi(2) / n as f64;
        }
    }
    let sd = sd.map(|v| v.sqrt().max(1e-6));
    // Speed.
    let a = DMatrix::from_fn(n, N_SCALAR + 1, |i, j| {
        if j == 0 {
            1.0
        } else {
            (windows[i].features.scalars[j - 1] - mean[j - 1]) / sd[j - 1]
        }
    });
    let b = DVector::from_fn(n, |i, _| {
        let v = windows[i].velocity_s_mps;
        (v[0] * v[0] + v[1] * v[1]).sqrt()
    });
    let w = ridge(&a, &b, SPEED_RIDGE, 1);
    let mut speed = [0.0; N_SCALAR + 1];
    speed.copy_from_slice(w.as_slice());
    // Direction: complex least squares to the unit true direction.
    let moving: Vec<_> = windows
        .iter()
        .filter(|w| {
            let v = w.velocity_s_mps;
            (v[0] * v[0] + v[1] * v[1]).sqrt() > MIN_DIRECTION_SPEED_MPS
        })
        .collect();
    let m = moving.len();
    let k = N_VECTOR + 1;
    let mut a = DMatrix::zeros(2 * m, 2 * k);
    let mut b = DVector::zeros(2 * m);
    for (i, w) in moving.iter().enumerate() {
        let v = w.velocity_s_mps;
        let s = (v[0] * v[0] + v[1] * v[1]).sqrt();
        b[2 * i] = v[0] / s;
        b[2 * i + 1] = v[1] / s;
        for j in 0..k {
            let (p, q) = if j < N_VECTOR {
                (w.features.vectors[j][0], w.features.vectors[j][1])
            } else {
                (1.0, 0.0)
            };
            // (a + i b)(p + i q) = (a p − b q) + i (a q + b p)
            a[(2 * i, 2 * j)] = p;
            a[(2 * i, 2 * j + 1)] = -q;
            a[(2 * i + 1, 2 * j)] = q;
            a[(2 * i + 1, 2 * j + 1)] = p;
        }
    }
    let wd = if m >= 10 {
        ridge(&a, &b, DIRECTION_RIDGE, 0)
    } else {
        DVector::zeros(2 * k)
    };
    let mut direction = [[0.0; 2]; N_VECTOR + 1];
    for (j, d) in direction.iter_mut().enumerate() {
        *d = [wd[2 * j], wd[2 * j + 1]];
    }
    if wd.iter().all(|v| *v == 0.0) {
        direction[N_VECTOR] = [1.0, 0.0];
    }
    Some(Regressor {
        mean,
        sd,
        speed,
        direction,
    })
}

/// The comment line naming the features, written into every trained model file.
pub const FEATURES_COMMENT: &str = "features: core/src/odometry/features.rs (scalars sd_az sqrt_sd_az sd_ah sd_gz sd_gh zc_hz zc_hz2 zc_sqrt_sd_az ln_sd_az mean_g_norm)";

/// Write a trained model to `out` as text; returns "N regressors, B bytes of weights".
pub fn write_model(model: &OdometryModel, out: &std::path::Path) -> Result<String, String> {
    std::fs::write(out, model.to_text()).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(format!(
        "{} regressors, {} bytes of weights",
        model.regressors.iter().flatten().count(),
        model.size_bytes()
    ))
}

/// Fit the general regressor on every window and one per placement class present
/// (the simulator's front and back pockets both train `Pocket`).
pub fn fit_model(
    windows: &[LabelledWindow],
    params: PipelineParams,
    comments: Vec<String>,
) -> Option<OdometryModel> {
    let all: Vec<&LabelledWindow> = windows.iter().collect();
    let general = fit_regressor(&all)?;
    let mut model = OdometryModel::new(params, general).ok()?;
    for p in Placement::ALL {
        let mine: Vec<&LabelledWindow> =
            windows.iter().filter(|w| w.placement == Some(p)).collect();
        model.regressors[slot(Some(p))] = fit_regressor(&mine);
    }
    model.comments = comments;
    model.validate().ok()?;
    Some(model)
}

/// Labelled windows of `seeds` simulated walks per simulator placement (seeds below
/// [`FIRST_EVAL_SEED`]), labelled with the placement's class.
pub fn simulated_windows(seeds: u64, params: PipelineParams) -> Vec<LabelledWindow> {
    let mut out = Vec::new();
    for p in PhonePlacement::ALL {
        for seed in 1..=seeds.min(FIRST_EVAL_SEED - 1) {
            let sim = simulate_phone(&sim_scenario(seed, p));
            let samples: Vec<ImuSample> = sim.samples.iter().map(Into::into).collect();
            out.extend(labelled_windows(&samples, &sim, Some(p.into()), params));
        }
    }
    out
}
