//! Outage evaluation of step-length models on the phone simulator, shared by
//! `stridekit eval steplength` and the regression tests.
//!
//! Protocol: the simulated person walks/runs with good GNSS for the calibration
//! period; every step (the simulator's true heel strikes with the features computed
//! from its acceleration, see [`SimulatedPhone::step_events`]) and every fix is fed
//! to the estimator. Then GNSS is lost for 5 minutes: the distance is the sum of the
//! step lengths the estimator returns for the steps in the outage, compared with the
//! sum of the true lengths of the same steps (detector errors are left out: the
//! detector is evaluated on its own).

use stridekit_core::steplength::{StepLengthConfig, StepLengthEstimator, StepLengthModel};
use stridekit_sim::phone::{
    simulate_phone, PhoneActivity, PhonePlacement, PhoneScenario, PhoneSegment, SimulatedPhone,
};

/// Length of the simulated GNSS outage, seconds.
pub const OUTAGE_S: f64 = 300.0;

/// A named speed mix: calibration segments, then outage segments.
#[derive(Clone, Debug, PartialEq)]
pub struct Mix {
    pub name: &'static str,
    pub calibration: Vec<PhoneSegment>,
    /// Must last [`OUTAGE_S`] in total.
    pub outage: Vec<PhoneSegment>,
}

fn walk(v: f64, min: f64) -> PhoneSegment {
    PhoneSegment {
        activity: PhoneActivity::Walking { speed_mps: v },
        duration_s: 60.0 * min,
    }
}

fn run(v: f64, min: f64) -> PhoneSegment {
    PhoneSegment {
        activity: PhoneActivity::Running { speed_mps: v },
        duration_s: 60.0 * min,
    }
}

/// The evaluation mixes (8 minutes of calibration each).
pub fn mixes() -> Vec<Mix> {
    vec![
        Mix {
            name: "steady walk 1.3 m/s",
            calibration: vec![walk(1.3, 8.0)],
            outage: vec![walk(1.3, 5.0)],
        },
        Mix {
            name: "varied walk 1.1–1.6 m/s",
            calibration: vec![walk(1.1, 3.0), walk(1.5, 3.0), walk(1.3, 2.0)],
            outage: vec![walk(1.2, 2.5), walk(1.6, 2.5)],
        },
        Mix {
            name: "calibrated at 1.2, outage brisk 1.7 m/s",
            calibration: vec![walk(1.2, 8.0)],
            outage: vec![walk(1.7, 5.0)],
        },
        Mix {
            name: "run 2.8–3.4 m/s",
            calibration: vec![run(2.8, 4.0), run(3.4, 4.0)],
            outage: vec![run(3.1, 5.0)],
        },
        Mix {
            name: "walk + run",
            calibration: vec![walk(1.3, 4.0), run(3.0, 4.0)],
            outage: vec![walk(1.4, 2.5), run(3.3, 2.5)],
        },
    ]
}

/// The scenario of a mix for one seed and placement (100 Hz, GNSS off during the
/// outage).
pub fn scenario(mix: &Mix, seed: u64, placement: PhonePlacement) -> PhoneScenario {
    let mut segments = mix.calibration.clone();
    segments.extend(mix.outage.iter().copied());
    let t_cal: f64 = mix.calibration.iter().map(|s| s.duration_s).sum();
    PhoneScenario {
        segments,
        gnss_outages: vec![(t_cal, t_cal + OUTAGE_S + 1.0)],
        ..PhoneScenario::walk(seed, placement, 1.3, 0.0)
    }
}

/// Result of one model on one simulated outage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutageResult {
    pub true_distance_m: f64,
    pub estimated_distance_m: f64,
    /// Signed error, percent.
    pub error_pct: f64,
    /// 20-step fits accepted during calibration.
    pub fits: u32,
    pub converged: bool,
}

/// Feed a simulated walk to a new estimator: fixes before `t_cal_s`, every step;
/// sum step lengths over `[t_cal_s, t_cal_s + OUTAGE_S)`.
pub fn outage_error(
    sim: &SimulatedPhone,
    model: StepLengthModel,
    config: StepLengthConfig,
    t_cal_s: f64,
) -> OutageResult {
    let events = sim.step_events();
    let mut est = match StepLengthEstimator::new(model, config) {
        Ok(e) => e,
        Err(_) => {
            return OutageResult {
                true_distance_m: f64::NAN,
                estimated_distance_m: f64::NAN,
                error_pct: f64::NAN,
                fits: 0,
                converged: false,
            }
        }
    };
    let mut fi = 0;
    let (mut est_m, mut true_m) = (0.0, 0.0);
    let t_end = t_cal_s + OUTAGE_S;
    for (e, s) in events.iter().zip(&sim.steps) {
        while let Some(f) = sim.fixes.get(fi) {
            if f.t_s > e.t_s || f.t_s >= t_cal_s {
                break;
            }
            // Simulated fixes are valid by construction.
            let _ = est.push_gnss_fix(f.t_s, f.east_m, f.north_m, Some(f.accuracy_m));
            fi += 1;
        }
        let l = est.push_step(e).unwrap_or(f64::NAN);
        if e.t_s >= t_cal_s && e.t_s < t_end {
            est_m += l;
            true_m += s.length_m;
        }
    }
    let c = est.calibration();
    OutageResult {
        true_distance_m: true_m,
        estimated_distance_m: est_m,
        error_pct: 100.0 * (est_m - true_m) / true_m,
        fits: c.fits,
        converged: c.converged,
    }
}

/// One evaluated case: mix, seed, placement, and the result per model (in the
/// order of `models`).
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub mix: &'static str,
    pub seed: u64,
    pub placement: PhonePlacement,
    pub results: Vec<OutageResult>,
}

/// Run every mix for seeds `1..=seeds`, the placement cycling with the seed and mix.
pub fn run_cases(seeds: u64, models: &[StepLengthModel], config: StepLengthConfig) -> Vec<Case> {
    let mut out = Vec::new();
    for (mi, mix) in mixes().iter().enumerate() {
        let t_cal: f64 = mix.calibration.iter().map(|s| s.duration_s).sum();
        for seed in 1..=seeds {
            let placement = PhonePlacement::ALL[(seed as usize + mi) % PhonePlacement::ALL.len()];
            let sim = simulate_phone(&scenario(mix, seed, placement));
            let results = models
                .iter()
                .map(|&m| outage_error(&sim, m, config, t_cal))
                .collect();
            out.push(Case {
                mix: mix.name,
                seed,
                placement,
                results,
            });
        }
    }
    out
}

/// The pace tracker through the same outage, fed the simulated phone's raw
/// accelerometer ([`PaceTracker::push_accel`]: its own detector, and the feature step
/// length of `stridekit_core::pace`'s accelerometer input) or only the steps that
/// detector finds ([`StepSample::Event`], what a platform step detector gives): speed
/// RMSE against the truth over the outage (one reading a second) and the distance
/// error of the outage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackerOutage {
    pub speed_rmse_mps: f64,
    pub distance_error_pct: f64,
}

/// Run the pace tracker over a simulated mix with raw acceleration (`accel` true) or
/// with the detected step events only.
pub fn tracker_outage(sim: &SimulatedPhone, t_cal_s: f64, accel: bool) -> TrackerOutage {
    use stridekit_core::geo::LocalFrame;
    use stridekit_core::pace::{PaceConfig, PaceTracker, StepSample};
    use stridekit_core::stepdetect::StepDetector;
    use stridekit_sim::phone::PhoneEvent;

    let nan = TrackerOutage {
        speed_rmse_mps: f64::NAN,
        distance_error_pct: f64::NAN,
    };
    let Ok(mut tracker) = PaceTracker::new(PaceConfig::default()) else {
        return nan;
    };
    let mut detector = StepDetector::default();
    let frame = LocalFrame::new(51.5, -0.1, 0.0);
    let t_end = t_cal_s + OUTAGE_S;
    let (mut next_read, mut se, mut n) = (t_cal_s, 0.0, 0usize);
    let (mut d0, mut d1) = (f64::NAN, f64::NAN);
    for ev in sim.timeline(&frame) {
        match ev {
            PhoneEvent::Fix(f) => {
                let _ = tracker.push_fix(&f);
            }
            PhoneEvent::Imu(s) => {
                if accel {
                    let _ = tracker.push_accel(s.t_s, s.accel_mps2);
                } else {
                    if let Ok(Some(e)) = detector.push_accel(s.t_s, s.accel_mps2) {
                        let _ = tracker.push_steps(&StepSample::Event { t_s: e.t_s });
                    }
                    while let Some(e) = detector.pop_step() {
                        let _ = tracker.push_steps(&StepSample::Event { t_s: e.t_s });
                    }
                }
                if s.t_s >= next_read && s.t_s < t_end {
                    if let Some(est) = tracker.estimate() {
                        if d0.is_nan() {
                            d0 = est.distance_m;
                        }
                        let truth = sim.truth_at(s.t_s).speed_mps;
                        se += (est.speed_mps - truth).powi(2);
                        n += 1;
                    }
                    next_read += 1.0;
                }
                if s.t_s < t_end {
                    if let Some(est) = tracker.estimate() {
                        d1 = est.distance_m;
                    }
                }
            }
        }
    }
    let true_m = sim.truth_at(t_end).distance_m - sim.truth_at(t_cal_s).distance_m;
    TrackerOutage {
        speed_rmse_mps: (se / n.max(1) as f64).sqrt(),
        distance_error_pct: 100.0 * ((d1 - d0) - true_m) / true_m,
    }
}
