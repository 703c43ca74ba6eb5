//! The bench's pace sweep: the default pace tracker over the real runs with `eval
//! pace`'s injected GNSS degradation (same seeds), scored as the speed RMSE against
//! the clean-track reference over every second that has one (GNSS, disturbance
//! zones and outages). Its inputs are a GNSS stream and a cadence stream, so the
//! perturbations are of their timing: fixes thinned, timestamps jittered, cadence
//! samples dropped in bursts.

use std::path::Path;

use stridekit_core::{GnssFix, PaceConfig, PaceSample, StepSample};
use stridekit_sim::Rng;

use super::imu::{bursts, jittered};
use super::report::{Aggregate, Report};
use super::{measure, Engine, Perturbation, Scored};
use crate::activity::{activity_files, degraded, prepare, Prepared};
use crate::pace::{replay, rmse, smoothed_track_speed};
use crate::pace_eval::REFERENCE_HALF_WINDOW_S;
use crate::stats::median;

fn with_time(s: &PaceSample, t: f64) -> PaceSample {
    match *s {
        PaceSample::Fix(f) => PaceSample::Fix(GnssFix { t_s: t, ..f }),
        PaceSample::Steps(StepSample::Count { steps, .. }) => {
            PaceSample::Steps(StepSample::Count { t_s: t, steps })
        }
        PaceSample::Steps(StepSample::Event { .. }) => {
            PaceSample::Steps(StepSample::Event { t_s: t })
        }
        PaceSample::Steps(StepSample::Cadence { steps_per_min, .. }) => {
            PaceSample::Steps(StepSample::Cadence {
                t_s: t,
                steps_per_min,
            })
        }
    }
}

/// The stream with `p` applied.
pub fn perturb_stream(samples: &[PaceSample], p: &Perturbation, rng: &mut Rng) -> Vec<PaceSample> {
    match *p {
        Perturbation::Rate { hz } => {
            let mut last = f64::NEG_INFINITY;
            samples
                .iter()
                .filter(|s| match s {
                    PaceSample::Fix(f) if f.t_s < last + 1.0 / hz - 1e-6 => false,
                    PaceSample::Fix(f) => {
                        last = f.t_s;
                        true
                    }
                    _ => true,
                })
                .copied()
                .collect()
        }
        Perturbation::Jitter { share } => {
            let t: Vec<f64> = samples.iter().map(|s| s.t_s()).collect();
            let gaps: Vec<f64> = t
                .windows(2)
                .map(|w| w[1] - w[0])
                .filter(|d| *d > 0.0)
                .collect();
            let sigma = share * median(gaps);
            let j = jittered(&t, if sigma.is_finite() { sigma } else { 0.0 }, rng);
            samples
                .iter()
                .zip(j)
                .map(|(s, t)| with_time(s, t))
                .collect()
        }
        Perturbation::Bursts {
            share,
            min_s,
            max_s,
        } => {
            let (Some(a), Some(b)) = (samples.first(), samples.last()) else {
                return samples.to_vec();
            };
            let t0 = a.t_s();
            let cut = bursts(t0, b.t_s() - t0, share, min_s, max_s, rng);
            samples
                .iter()
                .filter(|s| {
                    !matches!(s, PaceSample::Steps(_))
                        || !cut.iter().any(|&(x, y)| s.t_s() >= x && s.t_s() < y)
                })
                .copied()
                .collect()
        }
        _ => samples.to_vec(),
    }
}

/// The sweep over the runs of `dir`.
pub fn sweep(dir: &Path, cases: &[Perturbation]) -> Result<Report, String> {
    let mut runs: Vec<(String, Prepared, u64)> = Vec::new();
    let mut notes = vec![format!(
        "Data: {} (real runs). The default tracker with eval pace's injected GNSS degradation; error over the grid seconds with a clean-track reference.",
        dir.display()
    )];
    for (i, path) in activity_files(dir)?.iter().enumerate() {
        let name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        match stridekit_formats::read_activity(path) {
            Ok(a) => {
                let p = prepare(&a);
                if p.track.len() < 30 || !p.has_steps {
                    notes.push(format!("Skipped {name}: no GNSS track or no cadence."));
                } else {
                    // The same seed as `eval pace` gives this file.
                    runs.push((name, p, 1000 + i as u64));
                }
            }
            Err(e) => notes.push(format!("Skipped {name}: {e}")),
        }
    }
    let (published, default) = (PaceConfig::as_published(), PaceConfig::default());
    let scorer = |r: usize, p: Option<&Perturbation>, rng: &mut Rng| -> Result<Scored, String> {
        let (_, prep, seed) = &runs[r];
        let (samples, _zones) = degraded(prep, *seed);
        let samples = match p {
            Some(p) => perturb_stream(&samples, p, rng),
            None => samples,
        };
        let out = replay(&samples, published, default);
        let reference = smoothed_track_speed(&prep.track, &out.t_s, REFERENCE_HALF_WINDOW_S);
        Ok((rmse(&out.speed[3], &reference, |_| true), 0))
    };
    let (baseline, cases) = measure(runs.len(), cases, "perturb pace", scorer)?;
    Ok(Report {
        engine: Engine::Pace,
        metric: "speed RMSE of the default tracker against the clean-track reference, m/s",
        decimals: 3,
        aggregate: Aggregate::Mean,
        recordings: runs.iter().map(|r| r.0.clone()).collect(),
        baseline,
        cases,
        notes,
    })
}
