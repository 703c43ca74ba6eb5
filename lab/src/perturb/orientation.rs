//! The bench's orientation sweep: the default AHRS (magnetometer on) over the BROAD
//! trials, scored with the benchmark's metric (total error, RMSE over the movement
//! phases) against the optical truth turned by any rocking the perturbation added.

use std::path::Path;

use stridekit_core::ahrs::{Ahrs, AhrsSettings};
use stridekit_formats::{InertialSample, OrientationRecording};
use stridekit_sim::Rng;

use super::imu::{perturb, Imu};
use super::report::{Aggregate, Report};
use super::{measure, Engine, Perturbation, Scored};
use crate::orientation::eval::load;
use crate::orientation::metric::ErrorSums;

/// The recording's streams as the perturbations see them.
pub fn imu_of(samples: &[InertialSample]) -> Imu {
    Imu::new(
        samples.iter().map(|s| s.t_s).collect(),
        samples.iter().map(|s| s.gyro_rads).collect(),
        samples.iter().map(|s| s.accel_mps2).collect(),
        samples.iter().map(|s| s.mag_ut).collect(),
    )
}

/// The recording's streams with its optical truth as the attitude (unit length; an
/// occluded sample takes the nearest truth before it, the first ones the first truth);
/// without any truth, none.
pub fn imu_with_attitude(rec: &OrientationRecording) -> Imu {
    let mut imu = imu_of(&rec.samples);
    let Some(first) = rec.truth.iter().flatten().next() else {
        return imu;
    };
    let mut last = *first;
    imu.attitude = Some(
        rec.truth
            .iter()
            .map(|t| {
                if let Some(q) = t {
                    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
                    if n > 0.0 {
                        last = q.map(|c| c / n);
                    }
                }
                last
            })
            .collect(),
    );
    imu
}

/// q ⊗ exp(θ/2): the truth of a body rocked by θ (rotation vector, body frame).
fn rocked(q: &[f64; 4], th: &[f64; 3]) -> [f64; 4] {
    let a = (th[0] * th[0] + th[1] * th[1] + th[2] * th[2]).sqrt();
    if a < 1e-15 {
        return *q;
    }
    let (s, c) = (0.5 * a).sin_cos();
    let r = [c, s * th[0] / a, s * th[1] / a, s * th[2] / a];
    [
        q[0] * r[0] - q[1] * r[1] - q[2] * r[2] - q[3] * r[3],
        q[0] * r[1] + q[1] * r[0] + q[2] * r[3] - q[3] * r[2],
        q[0] * r[2] - q[1] * r[3] + q[2] * r[0] + q[3] * r[1],
        q[0] * r[3] + q[1] * r[2] - q[2] * r[1] + q[3] * r[0],
    ]
}

/// One replay of `imu` (a copy of `rec`) through the filter of `settings`: the
/// error sums against the truth and the samples refused.
pub fn replay(
    settings: AhrsSettings,
    rec: &OrientationRecording,
    imu: &Imu,
) -> Result<(ErrorSums, u64), String> {
    let mut ahrs = Ahrs::new(settings).map_err(|e| e.to_string())?;
    let mut sums = ErrorSums::default();
    let mut refused = 0;
    for k in 0..imu.len() {
        if ahrs
            .update(imu.t_s[k], imu.gyro[k], imu.accel[k], imu.mag[k])
            .is_err()
        {
            refused += 1;
            continue;
        }
        let i = imu.source_index(k).min(rec.len() - 1);
        if let (true, Some(t), Some(q)) = (rec.movement[i], rec.truth[i], ahrs.quaternion()) {
            let t = match &imu.wobble {
                Some(w) => rocked(&t, &w[k]),
                None => t,
            };
            sums.add(&q, &t);
        }
    }
    Ok((sums, refused))
}

/// The sweep over the trials of `dir`.
pub fn sweep(dir: &Path, cases: &[Perturbation]) -> Result<Report, String> {
    let trials = load(dir)?;
    let imus: Vec<Imu> = trials.iter().map(imu_with_attitude).collect();
    let settings = AhrsSettings::default();
    let score = |r: usize, p: Option<&Perturbation>, rng: &mut Rng| -> Result<Scored, String> {
        let imu = match p {
            Some(p) => perturb(&imus[r], p, rng).unwrap_or_else(|| imus[r].clone()),
            None => imus[r].clone(),
        };
        let (sums, refused) = replay(settings, &trials[r], &imu)?;
        Ok((sums.rmse().total_deg, refused))
    };
    let (baseline, cases) = measure(trials.len(), cases, "perturb orientation", score)?;
    Ok(Report {
        engine: Engine::Orientation,
        metric: "total orientation error against the optical truth, RMSE over the movement phases, °",
        decimals: 2,
        aggregate: Aggregate::Mean,
        recordings: trials.iter().map(|t| t.name.clone()).collect(),
        baseline,
        cases,
        notes: vec![format!(
            "Data: {} (BROAD). The default filter with the magnetometer; a vibration also rocks the truth by the angle it rocked the device.",
            dir.display()
        )],
    })
}
