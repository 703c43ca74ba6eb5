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
pub(crate) fn imu_of(trial: &Trial) -> Result<Imu, String> {
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

/// A time-stretched copy as the device would record it: its gyroscope stops at the
/// range the navigator is given (`base_config`, the UofT MicroStrain's 9.2 rad/s) or
/// at the largest rate the recording itself holds, whichever is larger. A faster
/// copy (`× 1.2` turns a 9 rad/s swing into 11 rad/s) would otherwise hold samples
/// the device cannot report, which the navigator takes for clipped peaks and
/// "repairs" (docs/lab/2026-12-06-foot-detector.md).
pub(crate) fn within_range(mut copy: Imu, recorded: &Imu) -> Imu {
    let Some(range) = base_config().gyro_range_rads else {
        return copy;
    };
    let seen = recorded
        .gyro
        .iter()
        .flat_map(|w| w.iter().map(|x| x.abs()))
        .fold(0.0, f64::max);
    let limit = range.max(seen);
    for w in copy.gyro.iter_mut() {
        *w = w.map(|x| x.clamp(-limit, limit));
    }
    copy
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
            Some(p) => {
                let copy = perturb(&imus[r], p, rng).unwrap_or_else(|| imus[r].clone());
                if matches!(p, Perturbation::Speed { .. }) {
                    within_range(copy, &imus[r])
                } else {
                    copy
                }
            }
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
            "Data: {} (UofT VICON trials). The navigator of `eval foot` (device profile, default detector); walking speed: the recording time-stretched with its gravity kept (gravity per sample from the navigator's attitude on the oracle labels), resampled to 200 Hz. A time-stretched copy's gyroscope stops where the device's does (its range, {} rad/s, or the recording's largest rate if that is larger).",
            dir.display(),
            base_config().gyro_range_rads.unwrap_or(f64::INFINITY)
        )],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_faster_copy_stops_at_the_device_range() {
        let range = base_config().gyro_range_rads.unwrap();
        let n = 400;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.005).collect();
        // A swing at 0.95 × the range on y, and one recorded sample above it on x.
        let mut gyro: Vec<[f64; 3]> = t
            .iter()
            .map(|&t| [0.0, 0.95 * range * (std::f64::consts::TAU * t).sin(), 0.0])
            .collect();
        gyro[10][0] = -1.03 * range;
        let mut imu = Imu::new(t, gyro, vec![[0.0, 0.0, 9.81]; n], Vec::new());
        imu.gravity = Some(vec![[0.0, 0.0, 9.81]; n]);
        let fast = perturb(&imu, &Perturbation::Speed { factor: 1.4 }, &mut Rng::new(1)).unwrap();
        let peak = |m: &Imu| {
            m.gyro
                .iter()
                .flat_map(|w| w.iter().map(|x| x.abs()))
                .fold(0.0, f64::max)
        };
        assert!(
            peak(&fast) > 1.3 * range,
            "the stretch itself exceeds the range"
        );
        let kept = within_range(fast, &imu);
        // The recording's own largest rate (1.03 × range) is the limit here.
        assert!((peak(&kept) - 1.03 * range).abs() < 1e-9, "{}", peak(&kept));
        // Without a sample above the range, the range is the limit.
        imu.gyro[10][0] = 0.0;
        let fast = perturb(&imu, &Perturbation::Speed { factor: 1.4 }, &mut Rng::new(1)).unwrap();
        assert!((peak(&within_range(fast, &imu)) - range).abs() < 1e-9);
    }
}
