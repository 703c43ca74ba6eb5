//! The perturbations of the bench and the sweep of each engine: what is changed in a
//! recording, by how much, and which engines' inputs it applies to. Each level is a
//! fixed number; the random parts (directions, phases, burst positions) come from a
//! seed per recording and perturbation, so a run repeats exactly.

use super::Engine;

/// Standard gravity, m/s² (clip levels are given in g).
pub const G0_MPS2: f64 = 9.80665;

/// One controlled change of a recording.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Perturbation {
    /// Vibration on the accelerometer (peak amplitude, m/s²) with the gyroscope ripple
    /// and tilt that the same shaking of a rigid device implies: at one frequency
    /// (`hz: Some`) or broadband, 10–200 Hz (`hz: None`, RMS amplitude).
    Vibration { hz: Option<f64>, mps2: f64 },
    /// A constant magnetometer offset (hard iron) in a random body direction, µT.
    MagOffset { ut: f64 },
    /// A magnetometer offset growing linearly from 0 to `ut` over the recording.
    MagDrift { ut: f64 },
    /// A magnet the device passes: an extra field of `ut` fixed in the earth frame (it
    /// does not turn with the device), switched on and off smoothly, 5–60 s per pass.
    MagPass { ut: f64 },
    /// The gyroscope bias jumps by `dps` (°/s, random direction) a third of the way in.
    GyroBiasStep { dps: f64 },
    /// Gyroscope scale error of ±`pct` % per axis (random signs).
    GyroScale { pct: f64 },
    /// Linearly interpolated onto a grid of `hz` (pace: GNSS fixes thinned to at most
    /// `hz`).
    Rate { hz: f64 },
    /// Timestamps jittered by a Gaussian of σ = `share` × the mean spacing, values
    /// unchanged, order kept (a sample no longer after its predecessor is refused).
    Jitter { share: f64 },
    /// `share` of the time dropped in bursts of `min_s`–`max_s` s.
    Bursts { share: f64, min_s: f64, max_s: f64 },
    /// Accelerometer axes clipped at ±`g` g.
    ClipAccel { g: f64 },
    /// Gyroscope axes clipped at ±`dps` °/s.
    ClipGyro { dps: f64 },
    /// Time-stretched copy: the same path walked `factor` times as fast (angular
    /// rates × factor, linear acceleration × factor², gravity kept), resampled to the
    /// recording's rate.
    Speed { factor: f64 },
}

impl Perturbation {
    /// The kind (one per-recording table each).
    pub fn kind(&self) -> &'static str {
        match self {
            Perturbation::Vibration { hz: Some(_), .. } => "vibration, sinusoidal",
            Perturbation::Vibration { hz: None, .. } => "vibration, broadband 10–200 Hz",
            Perturbation::MagOffset { .. } => "magnetometer offset",
            Perturbation::MagDrift { .. } => "magnetometer drift",
            Perturbation::MagPass { .. } => "magnet passed (earth-fixed field)",
            Perturbation::GyroBiasStep { .. } => "gyroscope bias step",
            Perturbation::GyroScale { .. } => "gyroscope scale error",
            Perturbation::Rate { .. } => "sample rate",
            Perturbation::Jitter { .. } => "timestamp jitter",
            Perturbation::Bursts { .. } => "dropped bursts",
            Perturbation::ClipAccel { .. } => "accelerometer clipped",
            Perturbation::ClipGyro { .. } => "gyroscope clipped",
            Perturbation::Speed { .. } => "walking speed (time-stretched)",
        }
    }

    /// The level, short.
    pub fn level(&self) -> String {
        match *self {
            Perturbation::Vibration { hz: Some(f), mps2 } => format!("{f:.0} Hz, {mps2} m/s²"),
            Perturbation::Vibration { hz: None, mps2 } => format!("{mps2} m/s² RMS"),
            Perturbation::MagOffset { ut }
            | Perturbation::MagDrift { ut }
            | Perturbation::MagPass { ut } => format!("{ut} µT"),
            Perturbation::GyroBiasStep { dps } => format!("{dps} °/s"),
            Perturbation::GyroScale { pct } => format!("±{pct} %"),
            Perturbation::Rate { hz } => format!("{hz} Hz"),
            Perturbation::Jitter { share } => format!("σ {share} × spacing"),
            Perturbation::Bursts {
                share,
                min_s,
                max_s,
            } => {
                format!("{:.0} % in {min_s}–{max_s} s", share * 100.0)
            }
            Perturbation::ClipAccel { g } => format!("±{g} g"),
            Perturbation::ClipGyro { dps } => format!("±{dps} °/s"),
            Perturbation::Speed { factor } => format!("× {factor}"),
        }
    }

    /// Kind and level, for lists.
    pub fn label(&self) -> String {
        format!("{}: {}", self.kind(), self.level())
    }
}

/// The sweep of one engine: every perturbation its inputs can meet, each over a range
/// (`quick`: the middle level of each kind only).
pub fn sweep(engine: Engine, quick: bool) -> Vec<Perturbation> {
    use Perturbation as P;
    let mut kinds: Vec<Vec<Perturbation>> = Vec::new();
    let imu = matches!(engine, Engine::Orientation | Engine::Foot | Engine::Pdr);
    let accel = imu || engine == Engine::Steps;
    if accel {
        kinds.push(
            [10.0, 50.0, 200.0]
                .iter()
                .flat_map(|&f| {
                    [0.5, 2.0, 5.0].map(|a| P::Vibration {
                        hz: Some(f),
                        mps2: a,
                    })
                })
                .collect(),
        );
        kinds.push(
            [0.5, 2.0, 5.0]
                .map(|a| P::Vibration { hz: None, mps2: a })
                .to_vec(),
        );
    }
    if matches!(engine, Engine::Orientation | Engine::Pdr) {
        kinds.push(
            [2.0, 5.0, 10.0, 20.0]
                .map(|ut| P::MagOffset { ut })
                .to_vec(),
        );
        kinds.push([5.0, 10.0, 20.0].map(|ut| P::MagDrift { ut }).to_vec());
    }
    if imu {
        kinds.push(
            [0.5, 1.0, 2.0, 5.0]
                .map(|dps| P::GyroBiasStep { dps })
                .to_vec(),
        );
        kinds.push([1.0, 2.0, 5.0].map(|pct| P::GyroScale { pct }).to_vec());
    }
    match engine {
        Engine::Pace => {
            kinds.push([0.5, 0.2].map(|hz| P::Rate { hz }).to_vec());
            kinds.push([0.1, 0.25, 0.5].map(|share| P::Jitter { share }).to_vec());
            kinds.push(
                [0.05, 0.1, 0.2]
                    .map(|share| P::Bursts {
                        share,
                        min_s: 5.0,
                        max_s: 60.0,
                    })
                    .to_vec(),
            );
        }
        _ => {
            let rates: &[f64] = match engine {
                Engine::Steps => &[100.0, 50.0, 25.0],
                Engine::Pdr => &[25.0],
                _ => &[100.0, 50.0],
            };
            kinds.push(rates.iter().map(|&hz| P::Rate { hz }).collect());
            kinds.push([0.1, 0.25, 0.5].map(|share| P::Jitter { share }).to_vec());
            kinds.push(
                [0.05, 0.1, 0.2]
                    .map(|share| P::Bursts {
                        share,
                        min_s: 0.05,
                        max_s: 1.0,
                    })
                    .to_vec(),
            );
            kinds.push([2.0, 4.0, 8.0].map(|g| P::ClipAccel { g }).to_vec());
        }
    }
    if imu {
        kinds.push(
            [250.0, 500.0, 1000.0]
                .map(|dps| P::ClipGyro { dps })
                .to_vec(),
        );
    }
    if engine == Engine::Orientation {
        // Last, so the seeds of the kinds before it do not move.
        kinds.push([5.0, 10.0, 30.0].map(|ut| P::MagPass { ut }).to_vec());
    }
    if matches!(engine, Engine::Foot | Engine::Steps) {
        kinds.push(
            [0.7, 0.85, 1.2, 1.4]
                .map(|factor| P::Speed { factor })
                .to_vec(),
        );
    }
    if quick {
        kinds.into_iter().map(|k| k[k.len() / 2]).collect()
    } else {
        kinds.into_iter().flatten().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_engine_has_a_sweep_and_quick_takes_one_level_per_kind() {
        for e in Engine::ALL {
            let full = sweep(e, false);
            let quick = sweep(e, true);
            assert!(!quick.is_empty() && full.len() > quick.len(), "{e:?}");
            let mut kinds: Vec<&str> = quick.iter().map(|p| p.kind()).collect();
            kinds.dedup();
            assert_eq!(kinds.len(), quick.len(), "{e:?}: one level per kind");
        }
        assert!(!sweep(Engine::Steps, false).iter().any(|p| matches!(
            p,
            Perturbation::MagOffset { .. } | Perturbation::GyroScale { .. }
        )));
    }
}
