//! The bench's foot sweep: the navigator with `eval foot`'s configuration (the UofT
//! device profile, the default detector) over the VICON trials, scored like `eval
//! foot` (horizontal RMSE after the best rotation about the vertical and
//! translation). A time-stretched copy needs gravity in the sensor axes per sample:
//! taken from the navigator's own attitude on the trial's oracle stance labels.

use std::path::Path;

use stridekit_core::foot::{FootEstimate, FootNavigator, FootSample};
use stridekit_sim::Rng;

use super::imu::{perturb, Imu};
use super::report::{Aggregate, Report};
use super::{measure, Engine, Perturbation, Scored};
use crate::foot::eval::{base_config, load, replay as eval_replay, score, Method, Trial};

/// The trial's streams (sensor axes) with gravity per sample.
fn imu_of(trial: &Trial) -> Result<Imu, String> {
    let rec = &trial.rec;
    let mut imu = Imu::new(
        rec.t_s.clone(),
        rec.gyro_rads.clone(),
        rec.accel_mps2.clone(),
        Vec::new(),
    );
    imu.gravity = Some(gravity(trial)?);
    Ok(imu)
}

/// Gravity's specific force in sensor axes per sample, from the attitude of a replay
/// on the oracle labels (held before the first estimate).
fn gravity(trial: &Trial) -> Result<Vec<[f64; 3]>, String> {
    let config = base_config();
    let remap = config.axis_remap;
    // Body → sensor is the inverse remap; the data set's remap (x, −y, −z) is its own
    // inverse, which is checked here rather than assumed.
    let probe = [1.0, 2.0, 3.0];
    if remap.apply(remap.apply(probe)) != probe {
        return Err("the time stretch needs a self-inverse axis remap".into());
    }
    let est = eval_replay(
        trial,
        &Method {
            name: "oracle".into(),
            config,
            labels: Some("best".into()),
        },
    )?;
    let rec = &trial.rec;
    let g = local_g(trial);
    let mut out = vec![[0.0, 0.0, 0.0]; rec.len()];
    let mut last = None;
    let mut e = est.iter().peekable();
    for (i, o) in out.iter_mut().enumerate() {
        while let Some((k, x)) = e.peek() {
            if *k > i {
                break;
            }
            last = Some(x.quaternion);
            e.next();
        }
        let q = last.or_else(|| est.first().map(|(_, x)| x.quaternion));
        let Some([w, x, y, z]) = q else { continue };
        // Third row of R(q) (body → ENU): up in body axes.
        let up = [
            2.0 * (x * z - w * y),
            2.0 * (w * x + y * z),
            1.0 - 2.0 * (x * x + y * y),
        ];
        *o = remap.apply(up.map(|c| c * g));
    }
    Ok(out)
}

/// Mean |f| over the oracle stance samples (the local g the IMU reads), m/s².
fn local_g(trial: &Trial) -> f64 {
    let rec = &trial.rec;
    let (mut s, mut n) = (0.0, 0usize);
    let labels = rec.label(&trial.best);
    for (i, a) in rec.accel_mps2.iter().enumerate() {
        if labels.is_none_or(|l| l.get(i).copied().unwrap_or(false)) {
            s += (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            n += 1;
        }
    }
    if n == 0 {
        9.81
    } else {
        s / n as f64
    }
}

/// One replay of `imu` with the default detector; estimates carry the index of the
/// recording's sample they stand for.
fn replay(imu: &Imu) -> Result<(Vec<(usize, FootEstimate)>, u64), String> {
    let mut nav = FootNavigator::new(base_config()).map_err(|e| e.to_string())?;
    let mut est = Vec::with_capacity(imu.len());
    let mut accepted: Vec<(f64, usize)> = Vec::with_capacity(imu.len());
    let mut refused = 0;
    for k in 0..imu.len() {
        let s = FootSample {
            t_s: imu.t_s[k],
            accel_mps2: imu.accel[k],
            gyro_rads: imu.gyro[k],
        };
        match nav.push(&s) {
            Ok(e) => {
                accepted.push((s.t_s, k));
                if let Some(e) = e {
                    let j = accepted.partition_point(|&(t, _)| t < e.t_s);
                    let k = accepted.get(j).map_or(k, |&(_, k)| k);
                    est.push((imu.source_index(k), e));
                }
            }
            Err(_) => refused += 1,
        }
    }
    Ok((est, refused))
}

/// The sweep over the trials of `dir`.
pub fn sweep(dir: &Path, cases: &[Perturbation]) -> Result<Report, String> {
    let trials = load(dir)?;
    let imus = trials
        .iter()
        .map(imu_of)
        .collect::<Result<Vec<Imu>, String>>()?;
    let scorer = |r: usize, p: Option<&Perturbation>, rng: &mut Rng| -> Result<Scored, String> {
        let imu = match p {
            Some(p) => perturb(&imus[r], p, rng).unwrap_or_else(|| imus[r].clone()),
            None => imus[r].clone(),
        };
        let (est, refused) = replay(&imu)?;
        let mut est = est;
        est.retain(|(i, _)| *i < trials[r].rec.len());
        let e = if est.len() < 2 {
            f64::NAN
        } else {
            score(&trials[r], &est).rmse_h_m
        };
        Ok((e, refused))
    };
    let (baseline, cases) = measure(trials.len(), cases, "perturb foot", scorer)?;
    Ok(Report {
        engine: Engine::Foot,
        metric: "horizontal position RMSE after the best rotation about the vertical and translation (eval foot), m",
        decimals: 3,
        aggregate: Aggregate::Median,
        recordings: trials.iter().map(|t| t.rec.name.clone()).collect(),
        baseline,
        cases,
        notes: vec![format!(
            "Data: {} (UofT VICON trials). The navigator of `eval foot` (device profile, default detector); walking speed: the recording time-stretched with its gravity kept (gravity per sample from the navigator's attitude on the oracle labels), resampled to 200 Hz.",
            dir.display()
        )],
    })
}
