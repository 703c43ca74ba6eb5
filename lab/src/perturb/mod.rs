//! `stridekit eval perturb`: the perturbation bench. Every development recording of
//! an engine replayed under controlled, seeded perturbations ([`kinds`]: vibration,
//! magnetometer offsets and drifts, gyroscope bias steps and scale errors, sample
//! rate, jitter, dropped bursts, clipping, other walking speeds), each swept over a
//! range, with the engine's default configuration; per recording the error against
//! the unperturbed one ([`report`]). A held-out recording meets such conditions; the
//! worst cases here are the failure modes to fix in the engines.

pub mod foot;
pub mod imu;
pub mod kinds;
pub mod orientation;
pub mod pace;
pub mod pdr;
pub mod report;
pub mod steps;

use std::path::Path;

use stridekit_sim::Rng;

pub use self::kinds::{sweep, Perturbation};
pub use self::report::{render, Report};

/// The engines the bench replays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// The default AHRS on the BROAD trials.
    Orientation,
    /// The foot navigator on the VICON trials.
    Foot,
    /// The step detector on the Oxford traces.
    Steps,
    /// The phone navigator on the indoor walks.
    Pdr,
    /// The pace tracker on the real runs (GNSS and cadence streams).
    Pace,
}

impl Engine {
    pub const ALL: [Engine; 5] = [
        Engine::Orientation,
        Engine::Foot,
        Engine::Steps,
        Engine::Pdr,
        Engine::Pace,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Engine::Orientation => "orientation",
            Engine::Foot => "foot",
            Engine::Steps => "steps",
            Engine::Pdr => "pdr",
            Engine::Pace => "pace",
        }
    }

    /// The shared-data folder of its development recordings.
    pub fn data_folder(self) -> &'static str {
        match self {
            Engine::Orientation => "orientation/broad",
            Engine::Foot => "foot/pyshoe-vicon",
            Engine::Steps => "steps/oxford",
            Engine::Pdr => "phone-indoor",
            Engine::Pace => "pace/original",
        }
    }
}

/// Options of `stridekit eval perturb`.
#[derive(Clone, Debug)]
pub struct PerturbArgs {
    pub engine: Engine,
    /// The recordings.
    pub data: std::path::PathBuf,
    /// One level per kind.
    pub quick: bool,
}

/// The sweep of one engine, computed.
pub fn run(args: &PerturbArgs) -> Result<Report, String> {
    let cases = sweep(args.engine, args.quick);
    let dir: &Path = &args.data;
    match args.engine {
        Engine::Orientation => orientation::sweep(dir, &cases),
        Engine::Foot => foot::sweep(dir, &cases),
        Engine::Steps => steps::sweep(dir, &cases),
        Engine::Pdr => pdr::sweep(dir, &cases),
        Engine::Pace => pace::sweep(dir, &cases),
    }
}

/// The seed of one (recording, perturbation) pair: fixed, different for each.
pub fn seed(recording: usize, case: usize) -> u64 {
    0x5eed_0000_0000_0000 ^ ((recording as u64) << 20) ^ (case as u64).wrapping_mul(0x9e37_79b9)
}

/// What one replay gave: the error and the samples refused.
pub type Scored = (f64, u64);

/// Every recording unperturbed and under every case, in parallel over the cores:
/// `score(recording index, perturbation or None, rng)`. Fills the report's baseline
/// and cases.
pub fn measure(
    n_recordings: usize,
    cases: &[Perturbation],
    what: &str,
    score: impl Fn(usize, Option<&Perturbation>, &mut Rng) -> Result<Scored, String> + Sync,
) -> Result<(Vec<f64>, Vec<report::Case>), String> {
    let jobs: Vec<(usize, Option<usize>)> = (0..n_recordings)
        .flat_map(|r| std::iter::once((r, None)).chain((0..cases.len()).map(move |c| (r, Some(c)))))
        .collect();
    let pb = crate::progress::bar(jobs.len(), what);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: std::sync::Mutex<Vec<Option<Result<Scored, String>>>> =
        std::sync::Mutex::new(vec![None; jobs.len()]);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let j = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&(r, c)) = jobs.get(j) else { break };
                let mut rng = Rng::new(seed(r, c.map_or(usize::MAX >> 1, |c| c)));
                let out = score(r, c.map(|c| &cases[c]), &mut rng);
                pb.inc(1);
                if let Ok(mut v) = results.lock() {
                    v[j] = Some(out);
                }
            });
        }
    });
    pb.finish_and_clear();
    let results = results
        .into_inner()
        .map_err(|_| "a sweep thread panicked")?;
    let mut baseline = vec![f64::NAN; n_recordings];
    let mut out: Vec<report::Case> = cases
        .iter()
        .map(|p| report::Case {
            perturbation: *p,
            errors: vec![f64::NAN; n_recordings],
            refused: 0,
        })
        .collect();
    for (&(r, c), res) in jobs.iter().zip(results) {
        let (e, refused) = res.ok_or("a sweep job did not run")??;
        match c {
            None => baseline[r] = e,
            Some(c) => {
                out[c].errors[r] = e;
                out[c].refused += refused;
            }
        }
    }
    Ok((baseline, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_differ_by_recording_and_case() {
        let mut s: Vec<u64> = (0..50)
            .flat_map(|r| (0..60).map(move |c| seed(r, c)))
            .collect();
        let n = s.len();
        s.sort();
        s.dedup();
        assert_eq!(s.len(), n);
    }
}
