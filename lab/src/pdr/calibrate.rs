//! `stridekit calibrate pdr --data DIR --out FILE [--model NAME]`: learn what is
//! personal in PDR from walks with surveyed waypoints (Android sensor logs) and write
//! a calibration file (format: `stridekit_core::pdr::calibration`).
//!
//! Learned, for the one user and phone of the recordings:
//! - **step length**: the step-length model's θ by least squares over walks, each
//!   walk one equation: polyline length between its first and last waypoint =
//!   θ · Σ x(step) over the steps the navigator's detector finds in that span (x the
//!   model's features, e.g. √h for the pendulum (h the step's vertical displacement
//!   as the navigator measures it) or (a_max − a_min)^¼ for Weinberg, times the step's
//!   gait-initiation share as the navigator applies it), each walk weighted by
//!   1 / polyline (its error grows with its length), on top of the population prior;
//!   the 1-σ written is the posterior's, floored at 1 % of θ;
//! - **carrying**: the navigator's own converged walking direction in the phone's
//!   body frame (its stride-axis estimate at the end of each walk), averaged over the
//!   walks when they agree (mean resultant length ≥ 0.8): the way the user holds the
//!   phone, held fixed from the start of a walk instead of re-estimated.
//!
//! Nothing is fitted per walk; the same calibration serves every later walk.

use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Vector3};
use stridekit_core::ahrs::ImuSample;
use stridekit_core::pdr::{NavigatorConfig, PdrCalibration, PhoneNavigator};
use stridekit_core::stepdetect::StepDetector;
use stridekit_core::steplength::{prior_of, BoutPosition, StepLengthEstimator, StepLengthModel};

use crate::pdr::metrics::polyline_m;
use crate::pdr::walks::Walk;

/// Largest calibration file read, bytes (the parser checks the text too).
const MAX_FILE_BYTES: u64 = 64 * 1024;
/// Relative 1-σ of one walk's polyline as a measure of the distance walked.
const WALK_REL_SIGMA: f64 = 0.1;
/// Floor of the written θ 1-σ, share of θ.
const MIN_REL_SIGMA: f64 = 0.01;
/// Carrying estimates agree when their mean resultant length reaches this.
const MIN_CARRYING_AGREEMENT: f64 = 0.8;
/// Step frequency assumed for a step without a duration, steps/s.
const DEFAULT_STEP_HZ: f64 = 1.8;

/// Read a calibration file.
pub fn read(path: &Path) -> Result<PdrCalibration, String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let meta = std::fs::metadata(path).map_err(|e| err(&e))?;
    if meta.len() > MAX_FILE_BYTES {
        return Err(err(&format!(
            "{} bytes is too large for a calibration file",
            meta.len()
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| err(&e))?;
    PdrCalibration::parse(&text).map_err(|e| err(&e))
}

/// Options of `stridekit calibrate pdr`.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrateArgs {
    pub data: PathBuf,
    pub out: PathBuf,
    pub model: StepLengthModel,
}

/// Model names on the command line.
pub fn model_from_arg(s: &str) -> Result<StepLengthModel, String> {
    Ok(match s {
        "constant" => StepLengthModel::Constant,
        "linear" => StepLengthModel::Linear,
        "linear-f" => StepLengthModel::LinearFrequencyOnly,
        "weinberg" => StepLengthModel::Weinberg,
        "pendulum" => StepLengthModel::Pendulum,
        _ => {
            return Err(format!(
                "unknown step-length model {s} (constant|linear|linear-f|weinberg|pendulum)"
            ))
        }
    })
}

/// Run the command: learn from every walk under `--data` and write the file.
pub fn run(a: &CalibrateArgs, command_line: &str) -> Result<String, String> {
    let walks = crate::pdr::real::load_walks_with_progress(&a.data)?;
    let refs: Vec<&Walk> = walks.iter().collect();
    let config = NavigatorConfig::default();
    let c = learn(&refs, &config, a.model)?;
    let text = c.to_text(&[
        format!("trained by: {command_line}"),
        format!(
            "data: {} walks with waypoints under {}",
            walks.len(),
            a.data.display()
        ),
    ]);
    std::fs::write(&a.out, &text).map_err(|e| format!("{}: {e}", a.out.display()))?;
    Ok(format!("wrote {}:\n{text}", a.out.display()))
}

/// What one walk teaches: Σ of the model's step features over the steps the
/// navigator's detector finds between the walk's first and last waypoint, and the
/// navigator's carrying estimate at the end of the walk (body frame), if known.
fn replay_walk(
    w: &Walk,
    config: &NavigatorConfig,
    model: StepLengthModel,
) -> Result<([f64; 3], Option<[f64; 3]>), String> {
    let wp = &w.rec.truth;
    let (t0, t1) = (wp[0].0, wp[wp.len() - 1].0);
    // The navigator measures each step's vertical displacement (the pendulum
    // model's feature); its detector is this one, so its steps have these times.
    let mut nav = PhoneNavigator::new(*config).map_err(|e| e.to_string())?;
    let mut d = StepDetector::new(config.detector).map_err(|e| e.to_string())?;
    let mut events = Vec::new();
    // (time, vertical displacement) of every step the navigator placed, in order.
    let mut vertical: Vec<(f64, f64)> = Vec::new();
    let mut seen = 0u64;
    for s in &w.rec.samples {
        let _ = nav.push_imu(&ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: s.mag_ut,
        });
        vertical.extend(
            nav.steps_since(seen)
                .map(|p| (p.t_s, p.vertical_displacement_m)),
        );
        seen = nav.recent_steps().1;
        let Ok(first) = d.push_accel(s.t_s, s.accel_mps2) else {
            continue;
        };
        events.extend(first.into_iter().chain(std::iter::from_fn(|| d.pop_step())));
    }
    let mut sum = [0.0; 3];
    let mut last_hz = DEFAULT_STEP_HZ;
    // The navigator shortens the first steps of a walk (gait initiation): the same
    // shares here, so that θ is the model of steady steps.
    let mut walk = BoutPosition::STEADY;
    let mut last_t: Option<f64> = None;
    for e in &events {
        let hz = e.frequency_hz();
        let f = if hz.is_finite() && e.duration_s <= 5.0 {
            last_hz = hz;
            hz
        } else {
            last_hz
        };
        let share = walk.next_step(e.t_s, last_t);
        last_t = Some(e.t_s);
        if e.t_s < t0 || e.t_s > t1 {
            continue;
        }
        let wf = (e.accel_max_mps2 - e.accel_min_mps2).max(0.0).powf(0.25);
        let h = vertical
            .binary_search_by(|(t, _)| t.total_cmp(&e.t_s))
            .map_or(f64::NAN, |i| vertical[i].1);
        let x = StepLengthEstimator::model_features(model, f, e.accel_variance_m2ps4, wf, h.sqrt());
        if x.iter().all(|v| v.is_finite()) {
            for i in 0..3 {
                sum[i] += share * x[i];
            }
        }
    }
    Ok((sum, nav.walking_direction().forward_body()))
}

/// The way the phone is usually carried: the mean of the walks' carrying estimates,
/// each first turned to the side of the mean axis (the stride axis's forward sign
/// can be wrong on a walk), if they agree and most had that sign.
fn typical_carrying(f: &[Vector3<f64>]) -> Option<[f64; 3]> {
    let mean: Vector3<f64> = f.iter().sum();
    let axis = mean.try_normalize(1e-9)?;
    let aligned: Vector3<f64> = f
        .iter()
        .map(|v| if v.dot(&axis) >= 0.0 { *v } else { -v })
        .sum();
    let agreement = aligned.norm() / f.len() as f64;
    let forward = f.iter().filter(|v| v.dot(&axis) >= 0.0).count();
    (agreement >= MIN_CARRYING_AGREEMENT && 3 * forward >= 2 * f.len())
        .then(|| (aligned / aligned.norm()).into())
}

/// Learn a calibration from `walks` (see the module docs).
pub fn learn(
    walks: &[&Walk],
    config: &NavigatorConfig,
    model: StepLengthModel,
) -> Result<PdrCalibration, String> {
    let (mean0, sigma0) = prior_of(model, &config.step_length);
    let mut info = Matrix3::<f64>::zeros();
    let mut eta = Vector3::<f64>::zeros();
    for i in 0..3 {
        let p = 1.0 / (sigma0[i] * sigma0[i]);
        info[(i, i)] = p;
        eta[i] = p * mean0[i];
    }
    let mut used = 0;
    let mut carrying: Vec<Vector3<f64>> = Vec::new();
    let mut ratios: Vec<(f64, Vector3<f64>)> = Vec::new();
    for w in walks {
        let poly = polyline_m(&w.rec.truth.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>());
        if poly < 2.0 {
            continue;
        }
        let (x, forward) = replay_walk(w, config, model)?;
        let x = Vector3::from(x);
        if x.iter().all(|v| *v == 0.0) {
            continue;
        }
        let sigma = WALK_REL_SIGMA * poly;
        let wgt = 1.0 / (sigma * sigma);
        info += wgt * x * x.transpose();
        eta += wgt * poly * x;
        used += 1;
        ratios.push((poly, x));
        if let Some(f) = forward {
            carrying.push(Vector3::from(f));
        }
    }
    if used == 0 {
        return Err("no walk with waypoints and steps to calibrate from".into());
    }
    let cov = info
        .try_inverse()
        .ok_or("calibration normal equations are singular")?;
    let mut theta = cov * eta;
    // Robust level: scale θ so that the median walk's distance is right (a few walks
    // with missed or extra detections pull least squares).
    let mut r: Vec<f64> = ratios
        .iter()
        .filter_map(|(poly, x)| {
            let l = theta.dot(x);
            (l > 0.0).then(|| poly / l)
        })
        .collect();
    if !r.is_empty() {
        r.sort_by(f64::total_cmp);
        theta *= r[r.len() / 2];
    }
    let sigma: Vec<f64> = (0..3)
        .map(|i| {
            cov[(i, i)]
                .sqrt()
                .max(MIN_REL_SIGMA * theta[i].abs())
                .max(1e-6)
        })
        .collect();
    let carrying_body = typical_carrying(&carrying);
    let c = PdrCalibration {
        step_length_model: model,
        step_length_theta: [theta[0], theta[1], theta[2]],
        step_length_sigma: [sigma[0], sigma[1], sigma[2]],
        carrying_body,
    };
    c.validate().map_err(|e| e.to_string())?;
    Ok(c)
}
