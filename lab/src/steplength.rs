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
    simulate_phone, PhoneActivity, PhoneEvent, PhonePlacement, PhoneScenario, PhoneSegment,
    SimulatedPhone,
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
    use stridekit_core::pace::{PaceConfig, PaceTracker, StepSample};
    use stridekit_core::stepdetect::StepDetector;

    let Ok(mut tracker) = PaceTracker::new(PaceConfig::default()) else {
        return TrackerOutage::NAN;
    };
    let mut detector = StepDetector::default();
    let mut scored = OutageScore::new(t_cal_s, 0.0);
    for ev in sim.timeline(&sim_frame()) {
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
                scored.read(sim, s.t_s, &tracker);
            }
        }
    }
    scored.finish(sim)
}

/// The first seconds of a session carried over are not scored: its step detector
/// confirms the first bout after a few steps (speed 0 until then, the same with or
/// without the accelerometer model), s.
pub const CARRIED_WARM_UP_S: f64 = 10.0;

/// A calibration carried to a session without GNSS: the tracker of session 1 gets
/// the fixes and the raw acceleration of the calibration period and exports its
/// [`PaceCalibration`](stridekit_core::PaceCalibration); a new tracker, configured
/// with it, gets only the raw acceleration of the outage (the same simulated person
/// and phone the next day on a treadmill or an indoor track: no fix at all). With
/// `accel_model` false the export's accelerometer model is removed, so session 2 is
/// paced by the line at the cadence (what the calibration held before the model was
/// carried). `None` if session 1 learned nothing.
pub fn carried_outage(
    sim: &SimulatedPhone,
    t_cal_s: f64,
    accel_model: bool,
) -> Option<TrackerOutage> {
    use stridekit_core::pace::{PaceConfig, PaceTracker};

    let mut first = PaceTracker::new(PaceConfig::default()).ok()?;
    let mut second: Option<PaceTracker> = None;
    let mut scored = OutageScore::new(t_cal_s, CARRIED_WARM_UP_S);
    for ev in sim.timeline(&sim_frame()) {
        match (ev, &mut second) {
            (PhoneEvent::Fix(f), None) => {
                let _ = first.push_fix(&f);
            }
            (PhoneEvent::Imu(s), None) if s.t_s < t_cal_s => {
                let _ = first.push_accel(s.t_s, s.accel_mps2);
            }
            (PhoneEvent::Imu(s), slot) => {
                let tracker = match slot {
                    Some(t) => t,
                    None => {
                        let mut cal = first.calibration()?;
                        if !accel_model {
                            cal.accel_model = None;
                        }
                        slot.insert(
                            PaceTracker::new(PaceConfig {
                                calibration: Some(cal),
                                ..PaceConfig::default()
                            })
                            .ok()?,
                        )
                    }
                };
                let _ = tracker.push_accel(s.t_s, s.accel_mps2);
                scored.read(sim, s.t_s, tracker);
            }
            (PhoneEvent::Fix(_), Some(_)) => {}
        }
    }
    Some(scored.finish(sim))
}

fn sim_frame() -> stridekit_core::geo::LocalFrame {
    stridekit_core::geo::LocalFrame::new(51.5, -0.1, 0.0)
}

impl TrackerOutage {
    const NAN: Self = Self {
        speed_rmse_mps: f64::NAN,
        distance_error_pct: f64::NAN,
    };
}

/// Speed error once a second and the distance over `[start_s, end_s)`.
struct OutageScore {
    start_s: f64,
    end_s: f64,
    next_read: f64,
    se: f64,
    n: usize,
    d0: f64,
    d1: f64,
}

impl OutageScore {
    /// The outage that starts at `t_cal_s`, scored from `skip_s` after its start.
    fn new(t_cal_s: f64, skip_s: f64) -> Self {
        Self {
            start_s: t_cal_s + skip_s,
            end_s: t_cal_s + OUTAGE_S,
            next_read: t_cal_s + skip_s,
            se: 0.0,
            n: 0,
            d0: f64::NAN,
            d1: f64::NAN,
        }
    }

    /// After a sample at `t_s`.
    fn read(&mut self, sim: &SimulatedPhone, t_s: f64, tracker: &stridekit_core::PaceTracker) {
        if t_s < self.start_s || t_s >= self.end_s {
            return;
        }
        let Some(est) = tracker.estimate() else {
            return;
        };
        if t_s >= self.next_read {
            if self.d0.is_nan() {
                self.d0 = est.distance_m;
            }
            let truth = sim.truth_at(t_s).speed_mps;
            self.se += (est.speed_mps - truth).powi(2);
            self.n += 1;
            self.next_read += 1.0;
        }
        self.d1 = est.distance_m;
    }

    fn finish(&self, sim: &SimulatedPhone) -> TrackerOutage {
        let true_m = sim.truth_at(self.end_s).distance_m - sim.truth_at(self.start_s).distance_m;
        TrackerOutage {
            speed_rmse_mps: (self.se / self.n.max(1) as f64).sqrt(),
            distance_error_pct: 100.0 * ((self.d1 - self.d0) - true_m) / true_m,
        }
    }
}
