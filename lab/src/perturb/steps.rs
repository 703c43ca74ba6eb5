//! The bench's step sweep: the default step detector over the Oxford traces
//! (accelerometer only), scored like `eval steps`' headline: |count error| against
//! the alternation-checked reference. A time-stretched copy (another cadence) takes
//! gravity as the accelerometer's 1 s centred mean and moves the reference strikes
//! with the clock.

use std::path::Path;

use stridekit_core::stepdetect::{AccelSample, StepDetectorConfig};
use stridekit_formats::{list_oxford_traces, read_oxford_trace};
use stridekit_sim::Rng;

use super::imu::{perturb, Imu};
use super::report::{Aggregate, Report};
use super::{measure, Engine, Perturbation, Scored};
use crate::steps_eval::{alternation_checked, detect, score, strikes_by_foot};

/// Window of the centred mean taken as gravity for a time stretch, s.
pub const GRAVITY_WINDOW_S: f64 = 1.0;

struct Trace {
    name: String,
    imu: Imu,
    reference: Vec<f64>,
}

/// Centred moving mean of `a` over `window_s`.
fn centred_mean(t: &[f64], a: &[[f64; 3]], window_s: f64) -> Vec<[f64; 3]> {
    let n = t.len();
    let mut prefix = vec![[0.0; 3]; n + 1];
    for i in 0..n {
        for c in 0..3 {
            prefix[i + 1][c] = prefix[i][c] + a[i][c];
        }
    }
    let (mut lo, mut hi) = (0usize, 0usize);
    (0..n)
        .map(|i| {
            while t[lo] < t[i] - 0.5 * window_s {
                lo += 1;
            }
            while hi < n && t[hi] <= t[i] + 0.5 * window_s {
                hi += 1;
            }
            let m = (hi - lo).max(1) as f64;
            std::array::from_fn(|c| (prefix[hi][c] - prefix[lo][c]) / m)
        })
        .collect()
}

/// The sweep over the traces of `dir`.
pub fn sweep(dir: &Path, cases: &[Perturbation]) -> Result<Report, String> {
    let paths = list_oxford_traces(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if paths.is_empty() {
        return Err(format!("no Oxford traces in {}", dir.display()));
    }
    let mut traces = Vec::with_capacity(paths.len());
    for p in &paths {
        let tr = read_oxford_trace(p).map_err(|e| format!("{}: {e}", p.display()))?;
        let (reference, _, _) = alternation_checked(&strikes_by_foot(p)?);
        let t: Vec<f64> = tr.accel.iter().map(|a| a.t_s).collect();
        let a: Vec<[f64; 3]> = tr.accel.iter().map(|a| a.accel_mps2).collect();
        let mut imu = Imu::new(t.clone(), vec![[0.0; 3]; t.len()], a.clone(), Vec::new());
        imu.gravity = Some(centred_mean(&t, &a, GRAVITY_WINDOW_S));
        traces.push(Trace {
            name: tr.name,
            imu,
            reference,
        });
    }
    let config = StepDetectorConfig::default();
    let scorer = |r: usize, p: Option<&Perturbation>, rng: &mut Rng| -> Result<Scored, String> {
        let tr = &traces[r];
        let imu = match p {
            Some(p) => perturb(&tr.imu, p, rng).unwrap_or_else(|| tr.imu.clone()),
            None => tr.imu.clone(),
        };
        let samples: Vec<AccelSample> = (0..imu.len())
            .map(|k| AccelSample {
                t_s: imu.t_s[k],
                accel_mps2: imu.accel[k],
            })
            .collect();
        // A time stretch moves the strikes with the clock.
        let reference: Vec<f64> = match p {
            Some(Perturbation::Speed { factor }) => {
                let t0 = tr.imu.t_s[0];
                tr.reference
                    .iter()
                    .map(|t| t0 + (t - t0) / factor)
                    .collect()
            }
            _ => tr.reference.clone(),
        };
        let det = detect(config, &samples);
        // Timestamps not after the last accepted one are refused at the door.
        let mut last = f64::NEG_INFINITY;
        let mut refused = 0u64;
        for s in &samples {
            if s.t_s <= last {
                refused += 1;
            } else {
                last = s.t_s;
            }
        }
        Ok((score(&det, &reference).count_error_pct.abs(), refused))
    };
    let (baseline, cases) = measure(traces.len(), cases, "perturb steps", scorer)?;
    Ok(Report {
        engine: Engine::Steps,
        metric: "|step count error| against the alternation-checked reference (eval steps), %",
        decimals: 2,
        aggregate: Aggregate::Median,
        recordings: traces.iter().map(|t| t.name.clone()).collect(),
        baseline,
        cases,
        notes: vec![format!(
            "Data: {} (Oxford Step Counter). The default detector; refused samples: timestamps not after their predecessor (jitter).",
            dir.display()
        )],
    })
}
