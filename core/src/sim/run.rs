//! Simulated run: truth trajectory, GNSS fixes with disturbances and outages, pedometer.
//! (API fixed; implementation in progress.)

use crate::pace::{GnssFix, PaceSample, StepSample};

/// How the simulated pedometer reports steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepReport {
    /// Cumulative integer count once per second (watch / Android TYPE_STEP_COUNTER style).
    CountEverySecond,
    /// One event per detected step.
    Events,
    /// Cadence (steps/min) once per second (foot pod / FIT style).
    CadenceEverySecond,
}

/// What to simulate. Fields are public so tests can build variants.
#[derive(Clone, Debug, PartialEq)]
pub struct RunScenario {
    pub seed: u64,
    pub duration_s: f64,
    pub gnss_interval_s: f64,
    pub origin_lat_deg: f64,
    pub origin_lon_deg: f64,
    pub step_report: StepReport,
    /// Urban-canyon / forest bursts of correlated GNSS error.
    pub disturbances: bool,
    /// GNSS outages (no fixes) of 1–3 minutes.
    pub outages: bool,
    /// Standing stops (traffic lights).
    pub stops: bool,
    /// Whether fixes carry a horizontal accuracy.
    pub report_accuracy: bool,
}

/// True state at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TruthSample {
    pub t_s: f64,
    pub east_m: f64,
    pub north_m: f64,
    pub speed_mps: f64,
    pub distance_m: f64,
    pub cadence_spm: f64,
    pub step_length_m: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZoneKind {
    Disturbance,
    Outage,
    Stop,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zone {
    pub kind: ZoneKind,
    pub start_s: f64,
    pub end_s: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct SimulatedRun {
    pub scenario: RunScenario,
    /// Truth every 0.1 s.
    pub truth: Vec<TruthSample>,
    pub fixes: Vec<GnssFix>,
    pub steps: Vec<StepSample>,
    pub zones: Vec<Zone>,
}

impl RunScenario {
    /// The built-in demo: 40 min with intervals, stops, disturbance zones and outages.
    pub fn demo(seed: u64) -> Self {
        Self {
            seed,
            duration_s: 2400.0,
            gnss_interval_s: 1.0,
            origin_lat_deg: 50.2945,
            origin_lon_deg: 18.6714,
            step_report: StepReport::CountEverySecond,
            disturbances: true,
            outages: true,
            stops: true,
            report_accuracy: true,
        }
    }
}

impl SimulatedRun {
    /// Fixes and step samples merged in time order (steps first at equal times).
    pub fn samples(&self) -> Vec<PaceSample> {
        let mut out = Vec::with_capacity(self.fixes.len() + self.steps.len());
        let (mut i, mut j) = (0, 0);
        while i < self.fixes.len() || j < self.steps.len() {
            let take_step = match (self.fixes.get(i), self.steps.get(j)) {
                (Some(f), Some(s)) => s.t_s() <= f.t_s,
                (None, Some(_)) => true,
                _ => false,
            };
            if take_step {
                out.push(PaceSample::Steps(self.steps[j]));
                j += 1;
            } else {
                out.push(PaceSample::Fix(self.fixes[i]));
                i += 1;
            }
        }
        out
    }

    /// Truth at time `t` (linear interpolation, clamped to the run).
    pub fn truth_at(&self, t: f64) -> TruthSample {
        let Some(first) = self.truth.first() else {
            return TruthSample::default();
        };
        let dt = if self.truth.len() > 1 { self.truth[1].t_s - first.t_s } else { 1.0 };
        let x = ((t - first.t_s) / dt).max(0.0);
        let i = (x.floor() as usize).min(self.truth.len() - 1);
        let j = (i + 1).min(self.truth.len() - 1);
        let f = (x - i as f64).clamp(0.0, 1.0);
        let (a, b) = (self.truth[i], self.truth[j]);
        let l = |u: f64, v: f64| u + f * (v - u);
        TruthSample {
            t_s: t,
            east_m: l(a.east_m, b.east_m),
            north_m: l(a.north_m, b.north_m),
            speed_mps: l(a.speed_mps, b.speed_mps),
            distance_m: l(a.distance_m, b.distance_m),
            cadence_spm: l(a.cadence_spm, b.cadence_spm),
            step_length_m: l(a.step_length_m, b.step_length_m),
        }
    }

    /// Whether `t` lies in a zone of the given kind.
    pub fn in_zone(&self, t: f64, kind: ZoneKind) -> bool {
        self.zones
            .iter()
            .any(|z| z.kind == kind && t >= z.start_s && t < z.end_s)
    }
}

/// Simulate a run. Deterministic for a given scenario.
pub fn simulate_run(scenario: &RunScenario) -> SimulatedRun {
    SimulatedRun {
        scenario: scenario.clone(),
        truth: Vec::new(),
        fixes: Vec::new(),
        steps: Vec::new(),
        zones: Vec::new(),
    }
}
