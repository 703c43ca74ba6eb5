//! The bench's PDR sweep: the phone navigator with its defaults (magnetometer on)
//! over the indoor walks, scored like `eval pdr`'s headline: the absolute trajectory
//! error at the surveyed waypoints after the best rigid fit.

use std::path::Path;

use stridekit_formats::{InertialRecording, InertialSample};
use stridekit_sim::Rng;

use super::imu::{perturb, Imu};
use super::orientation::imu_of;
use super::report::{Aggregate, Report};
use super::{measure, Engine, Perturbation, Scored};
use crate::pdr::metrics::evaluate;
use crate::pdr::real::load_walks_with_progress;
use crate::pdr::walks::{replay, ReplayOptions};

/// The recording with its samples replaced by `imu`'s.
fn with_samples(rec: &InertialRecording, imu: &Imu) -> InertialRecording {
    InertialRecording {
        samples: (0..imu.len())
            .map(|k| InertialSample {
                t_s: imu.t_s[k],
                accel_mps2: imu.accel[k],
                gyro_rads: imu.gyro[k],
                mag_ut: imu.mag[k],
            })
            .collect(),
        name: rec.name.clone(),
        placement: rec.placement.clone(),
        truth: rec.truth.clone(),
        meta: rec.meta.clone(),
        ..InertialRecording::default()
    }
}

/// The sweep over the walks under `dir`.
pub fn sweep(dir: &Path, cases: &[Perturbation]) -> Result<Report, String> {
    let walks = load_walks_with_progress(dir)?;
    let imus: Vec<Imu> = walks.iter().map(|w| imu_of(&w.rec.samples)).collect();
    let options = ReplayOptions::default();
    let scorer = |r: usize, p: Option<&Perturbation>, rng: &mut Rng| -> Result<Scored, String> {
        let rec = &walks[r].rec;
        let run = match p {
            Some(p) => {
                let imu = perturb(&imus[r], p, rng).unwrap_or_else(|| imus[r].clone());
                replay(&with_samples(rec, &imu), &options)?
            }
            None => replay(rec, &options)?,
        };
        let refused = run.rejected.total();
        let ate = evaluate(&run.track, &rec.truth).map_or(f64::NAN, |m| m.ate_m);
        Ok((ate, refused))
    };
    let (baseline, cases) = measure(walks.len(), cases, "perturb pdr", scorer)?;
    Ok(Report {
        engine: Engine::Pdr,
        metric: "absolute trajectory error at the waypoints after the best rigid fit (eval pdr's ATE), m",
        decimals: 2,
        aggregate: Aggregate::Median,
        recordings: walks
            .iter()
            .map(|w| format!("{}/{}", w.floor, w.rec.name))
            .collect(),
        baseline,
        cases,
        notes: vec![format!(
            "Data: {} (indoor walks with surveyed waypoints). The navigator's defaults with the magnetometer.",
            dir.display()
        )],
    })
}
