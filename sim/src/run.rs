//! Simulated run: truth trajectory, GNSS fixes with disturbances and outages, pedometer.
//!
//! Everything is generated from `RunScenario::seed` with the in-tree [`Rng`], so the
//! same scenario gives bit-identical output on every platform.
//!
//! Models (see [`simulate_run`]):
//! - truth at 10 Hz (integrated at 100 Hz): warm-up ~2.8 m/s, interval sets
//!   (4.0–4.8 m/s fast, 2.6–3.0 m/s easy) and steady blocks (3.0–3.6 m/s), cool-down
//!   walk ~1.4 m/s; optional standing stops; raised-cosine speed transitions with
//!   peak acceleration 0.9 m/s²; heading = Gauss–Markov curvature random walk plus
//!   street-corner turns (radius ≥ 8 m and ≥ v²/2.5);
//! - gait: step length 0.45 + 0.20·v running (v ≥ 2.2), 0.37 + 0.26·v walking
//!   (v ≤ 2.0), smooth blend, ±3 % slow per-run factor, ~2 % step-to-step jitter;
//! - pedometer: ~1 % missed steps, ~10 ms timing jitter, never a step while stopped;
//! - GNSS: white 0.6 m + Gauss–Markov 1.5 m / 60 s per axis; disturbance zones with an
//!   extra Gauss–Markov error of 4–10 m / 3–10 s and 5–15 m multipath jumps; outages
//!   without fixes; optimistic accuracy reports inside disturbance zones.

use super::rng::Rng;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::{GnssFix, PaceSample, StepSample};

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
    /// Whether fixes carry a receiver (Doppler) speed with its accuracy. Off in the
    /// demo: the paper's method and most activity files have positions only.
    pub receiver_speed: bool,
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
            receiver_speed: false,
        }
    }

    /// Like [`demo`](Self::demo) but with clean GNSS: no disturbance zones, no
    /// outages (standing stops stay).
    pub fn clean(seed: u64) -> Self {
        Self {
            disturbances: false,
            outages: false,
            ..Self::demo(seed)
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
        let dt = if self.truth.len() > 1 {
            self.truth[1].t_s - first.t_s
        } else {
            1.0
        };
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
    let d = if scenario.duration_s.is_finite() {
        scenario.duration_s.max(0.0)
    } else {
        0.0
    };
    let seed = scenario.seed;
    let mut prof_rng = stream(seed, 1);
    let mut zone_rng = stream(seed, 2);

    let mut segs = plan_segments(&mut prof_rng, d);
    let mut zones = plan_zones(&mut zone_rng, scenario, d, &mut segs);
    zones.sort_by(|a, b| a.zone.start_s.total_cmp(&b.zone.start_s));

    let profile = Profile::new(segs, &mut prof_rng);
    let gait = Gait::new(&mut stream(seed, 3));
    let (truth, true_steps) = integrate_truth(&profile, &gait, &mut stream(seed, 4), d);

    let stop_zones: Vec<Zone> = zones
        .iter()
        .map(|z| z.zone)
        .filter(|z| z.kind == ZoneKind::Stop)
        .collect();
    let detected = detect_steps(&true_steps, &stop_zones, &mut stream(seed, 5));
    let steps = report_steps(&detected, scenario.step_report, d, &mut stream(seed, 6));

    let mut run = SimulatedRun {
        scenario: scenario.clone(),
        truth,
        fixes: Vec::new(),
        steps,
        zones: zones.iter().map(|z| z.zone).collect(),
    };
    run.fixes = simulate_fixes(&run, &zones, d, &mut stream(seed, 7));
    if scenario.receiver_speed {
        add_receiver_speed(&mut run, &mut stream(seed, 8));
    }
    run
}

/// Doppler speed: accurate in the open (0.1 m/s), degraded in disturbance zones
/// (0.6 m/s), never negative (a receiver reports |v|), with a reported accuracy that
/// is honest in the open and optimistic in zones. Drawn from its own random stream,
/// so positions and steps are the same with or without it.
fn add_receiver_speed(run: &mut SimulatedRun, rng: &mut Rng) {
    for i in 0..run.fixes.len() {
        let t = run.fixes[i].t_s;
        let disturbed = run.in_zone(t, ZoneKind::Disturbance);
        let (sigma, reported) = if disturbed { (0.6, 0.4) } else { (0.1, 0.15) };
        let v = (run.truth_at(t).speed_mps + sigma * rng.normal()).abs();
        run.fixes[i].speed_mps = Some(v);
        run.fixes[i].speed_accuracy_mps = Some(reported);
    }
}

// ---------------------------------------------------------------------------------
// Constants of the models.

/// Truth output rate, Hz.
const TRUTH_HZ: f64 = 10.0;
/// Integration sub-steps per truth sample (100 Hz internal integration).
const SUBSTEPS: usize = 10;
/// Peak acceleration of the raised-cosine speed transitions, m/s².
const RAMP_ACCEL_MPS2: f64 = 0.9;
/// Margin between a stop and a pace-segment boundary, s (keeps ramps apart).
const STOP_MARGIN_S: f64 = 20.0;
/// Minimum gap between any two zones, s.
const ZONE_GAP_S: f64 = 10.0;
/// No disturbance or outage starts before this time, s.
const QUIET_START_S: f64 = 120.0;
/// Curvature random walk (Gauss–Markov in distance): σ (1/m) and correlation length (m).
const KAPPA_SIGMA: f64 = 0.004;
const KAPPA_LEN_M: f64 = 60.0;
/// GNSS error model.
const GNSS_WHITE_SIGMA_M: f64 = 0.6;
const GNSS_BG_SIGMA_M: f64 = 1.5;
const GNSS_BG_TAU_S: f64 = 60.0;
/// Ramp of the disturbance envelope at zone edges, s.
const DIST_EDGE_S: f64 = 5.0;
/// Fraction of steps the pedometer misses.
const STEP_MISS_PROB: f64 = 0.01;

/// An independent random stream per sub-model, so tuning one leaves the others alone.
fn stream(seed: u64, k: u64) -> Rng {
    Rng::new(seed ^ k.wrapping_mul(0xD1B5_4A32_D192_ED03).rotate_left(23))
}

fn cosramp(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    0.5 - 0.5 * (std::f64::consts::PI * x).cos()
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Duration of a raised-cosine transition by `dv` with peak acceleration RAMP_ACCEL_MPS2.
fn ramp_time(dv: f64) -> f64 {
    (std::f64::consts::FRAC_PI_2 * dv.abs() / RAMP_ACCEL_MPS2).max(2.0)
}

// ---------------------------------------------------------------------------------
// Pace profile.

#[derive(Clone, Copy, Debug)]
struct Seg {
    start: f64,
    end: f64,
    v: f64,
    stop: bool,
}

/// Append a constant-speed segment of `dur` s ending at most at `limit`; pieces
/// shorter than 60 s are merged into their neighbour so speed ramps never overlap.
fn add_seg(segs: &mut Vec<Seg>, t: &mut f64, limit: f64, v: f64, dur: f64) {
    if *t >= limit {
        return;
    }
    let mut end = (*t + dur).min(limit);
    if limit - end < 60.0 {
        end = limit;
    }
    if end - *t < 60.0 {
        if let Some(last) = segs.last_mut() {
            last.end = end;
            *t = end;
            return;
        }
    }
    segs.push(Seg {
        start: *t,
        end,
        v,
        stop: false,
    });
    *t = end;
}

/// Warm-up, a mix of interval sets and steady blocks, cool-down walk.
fn plan_segments(rng: &mut Rng, d: f64) -> Vec<Seg> {
    let mut segs = Vec::new();
    let warm = rng.range(300.0, 480.0).min(0.2 * d);
    let cool = rng.range(150.0, 240.0).min(0.1 * d);
    let main_end = d - cool;
    let mut t = 0.0;
    let warm_v = rng.range(2.7, 2.9);
    add_seg(&mut segs, &mut t, main_end.max(warm), warm_v, warm);
    let mut had_intervals = false;
    while t < main_end {
        if !had_intervals || rng.uniform() < 0.55 {
            had_intervals = true;
            let reps = 2 + (rng.uniform() * 3.0) as usize;
            for _ in 0..reps {
                let (v, dur) = (rng.range(4.0, 4.8), rng.range(120.0, 180.0));
                add_seg(&mut segs, &mut t, main_end, v, dur);
                let (v, dur) = (rng.range(2.6, 3.0), rng.range(60.0, 120.0));
                add_seg(&mut segs, &mut t, main_end, v, dur);
            }
        } else {
            let (v, dur) = (rng.range(3.0, 3.6), rng.range(180.0, 420.0));
            add_seg(&mut segs, &mut t, main_end, v, dur);
        }
    }
    let cool_v = rng.range(1.3, 1.5);
    if d > t {
        // The cool-down walk always gets its own segment (even if short).
        segs.push(Seg {
            start: t,
            end: d,
            v: cool_v,
            stop: false,
        });
    }
    if segs.is_empty() {
        segs.push(Seg {
            start: 0.0,
            end: d,
            v: warm_v,
            stop: false,
        });
    }
    segs
}

/// Split the segment holding `[s, e)` into before / stop / after. Returns false if the
/// stop is not at least STOP_MARGIN_S inside one moving segment.
fn insert_stop(segs: &mut Vec<Seg>, s: f64, e: f64) -> bool {
    let Some(i) = segs
        .iter()
        .position(|g| !g.stop && g.start + STOP_MARGIN_S <= s && e + STOP_MARGIN_S <= g.end)
    else {
        return false;
    };
    let g = segs[i];
    let before = Seg { end: s, ..g };
    let stop = Seg {
        start: s,
        end: e,
        v: 0.0,
        stop: true,
    };
    let after = Seg { start: e, ..g };
    segs.splice(i..=i, [before, stop, after]);
    true
}

struct Profile {
    segs: Vec<Seg>,
    /// Small smooth speed fluctuation: (amplitude, angular frequency, phase).
    wobble: [(f64, f64, f64); 2],
}

impl Profile {
    fn new(segs: Vec<Seg>, rng: &mut Rng) -> Self {
        let tau = std::f64::consts::TAU;
        let w1 = (0.012, tau / rng.range(60.0, 150.0), rng.range(0.0, tau));
        let w2 = (0.008, tau / rng.range(20.0, 50.0), rng.range(0.0, tau));
        Self {
            segs,
            wobble: [w1, w2],
        }
    }

    /// True speed at `t`; `cur` is a cursor into the segments (t must not decrease).
    fn speed(&self, t: f64, cur: &mut usize) -> f64 {
        while *cur + 1 < self.segs.len() && t >= self.segs[*cur].end {
            *cur += 1;
        }
        let Some(&g) = self.segs.get(*cur) else {
            return 0.0;
        };
        if g.stop {
            return 0.0;
        }
        let prev = if *cur == 0 {
            0.0
        } else {
            self.segs[*cur - 1].v
        };
        let mut v = g.v;
        let t_in = ramp_time(g.v - prev);
        if t < g.start + t_in {
            v = prev + (g.v - prev) * cosramp((t - g.start) / t_in);
        }
        if self.segs.get(*cur + 1).is_some_and(|n| n.stop) {
            let t_out = ramp_time(g.v);
            let t0 = g.end - t_out;
            if t > t0 {
                v = v.min(g.v * (1.0 - cosramp((t - t0) / t_out)));
            }
        }
        let f: f64 = self
            .wobble
            .iter()
            .map(|&(a, w, p)| a * (w * t + p).sin())
            .sum();
        (v * (1.0 + f)).max(0.0)
    }
}

// ---------------------------------------------------------------------------------
// Gait.

struct Gait {
    /// Per-run constant part and two slow sinusoids of the ±3 % step-length factor.
    a0: f64,
    slow: [(f64, f64, f64); 2],
}

impl Gait {
    fn new(rng: &mut Rng) -> Self {
        let tau = std::f64::consts::TAU;
        Self {
            a0: rng.range(-1.0, 1.0),
            slow: [
                (0.35, tau / rng.range(300.0, 900.0), rng.range(0.0, tau)),
                (0.25, tau / rng.range(120.0, 300.0), rng.range(0.0, tau)),
            ],
        }
    }

    /// Nominal step length at speed `v`: walking law below 2.0 m/s, running law above
    /// 2.2 m/s, smooth blend between.
    fn law(v: f64) -> f64 {
        let walk = 0.37 + 0.26 * v;
        let run = 0.45 + 0.20 * v;
        walk + (run - walk) * smoothstep((v - 2.0) / 0.2)
    }

    /// Step length at `t`, speed `v`, with the slow per-run factor.
    fn step_length(&self, t: f64, v: f64) -> f64 {
        let s: f64 = self
            .slow
            .iter()
            .map(|&(a, w, p)| a * (w * t + p).sin())
            .sum();
        Self::law(v) * (1.0 + 0.03 * (0.4 * self.a0 + s))
    }
}

// ---------------------------------------------------------------------------------
// Truth integration (100 Hz internally, 10 Hz out) and true step instants.

fn integrate_truth(
    profile: &Profile,
    gait: &Gait,
    rng: &mut Rng,
    d: f64,
) -> (Vec<TruthSample>, Vec<f64>) {
    let n = (d * TRUTH_HZ + 1e-9).floor() as usize;
    let dt = 1.0 / (TRUTH_HZ * SUBSTEPS as f64);
    let mut truth = Vec::with_capacity(n + 1);
    let mut steps = Vec::with_capacity((d * 3.0) as usize + 16);
    let mut cur = 0usize;

    let tau = std::f64::consts::TAU;
    let mut heading = rng.range(0.0, tau);
    let mut kappa = KAPPA_SIGMA * rng.normal();
    let (mut east, mut north, mut dist) = (0.0f64, 0.0f64, 0.0f64);
    let mut next_turn_m = rng.range(150.0, 600.0);
    let (mut turn_left, mut turn_k) = (0.0f64, 0.0f64);
    let mut phase = 0.0;
    let mut threshold = step_threshold(rng);

    let sample = |t: f64, v: f64, e: f64, nn: f64, dist: f64| {
        let l = gait.step_length(t, v);
        TruthSample {
            t_s: t,
            east_m: e,
            north_m: nn,
            speed_mps: v,
            distance_m: dist,
            cadence_spm: 60.0 * v / l,
            step_length_m: l,
        }
    };

    for i in 0..=n {
        let t_i = i as f64 / TRUTH_HZ;
        let v_i = profile.speed(t_i, &mut cur);
        truth.push(sample(t_i, v_i, east, north, dist));
        if i == n {
            break;
        }
        for k in 0..SUBSTEPS {
            let t0 = t_i + k as f64 * dt;
            let t1 = t0 + dt;
            let v = profile.speed(t0 + 0.5 * dt, &mut cur);
            let ds = v * dt;
            // Curvature: Gauss–Markov random walk in distance plus street-corner turns.
            let a = (-ds / KAPPA_LEN_M).exp();
            kappa = a * kappa + KAPPA_SIGMA * (1.0 - a * a).sqrt() * rng.normal();
            if turn_left <= 0.0 && dist >= next_turn_m {
                let angle = rng.range(50.0f64, 100.0).to_radians();
                let sign = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
                let radius = rng.range(8.0f64, 15.0).max(v * v / 2.5);
                turn_left = angle;
                turn_k = sign / radius;
            }
            let mut dh = kappa * ds;
            if turn_left > 0.0 {
                let turn = (turn_k.abs() * ds).min(turn_left);
                dh += turn * turn_k.signum();
                turn_left -= turn;
                if turn_left <= 0.0 {
                    next_turn_m = dist + rng.range(150.0, 600.0);
                }
            }
            let h_mid = heading + 0.5 * dh;
            east += ds * h_mid.sin();
            north += ds * h_mid.cos();
            heading += dh;
            dist += ds;
            // Step phase.
            if v > 0.0 {
                let c = v / gait.step_length(t0 + 0.5 * dt, v);
                phase += c * dt;
                while phase >= threshold {
                    let over = (phase - threshold) / c;
                    steps.push((t1 - over).max(t0));
                    phase -= threshold;
                    threshold = step_threshold(rng);
                }
            }
        }
    }
    (truth, steps)
}

/// Phase needed for the next step: 1 ± ~2 % step-to-step length jitter.
fn step_threshold(rng: &mut Rng) -> f64 {
    (1.0 + 0.02 * rng.normal()).clamp(0.92, 1.08)
}

// ---------------------------------------------------------------------------------
// Pedometer.

/// Detected step instants: ~1 % missed, ~10 ms timing jitter, never inside a stop.
fn detect_steps(true_steps: &[f64], stops: &[Zone], rng: &mut Rng) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(true_steps.len());
    for &t in true_steps {
        let miss = rng.uniform() < STEP_MISS_PROB;
        let jitter = (0.010 * rng.normal()).clamp(-0.03, 0.03);
        if miss {
            continue;
        }
        let mut tj = (t + jitter).max(0.0);
        if let Some(z) = stops.iter().find(|z| tj >= z.start_s && tj < z.end_s) {
            tj = (z.start_s - 1e-3).max(0.0);
        }
        if let Some(&last) = out.last() {
            tj = tj.max(last + 1e-3);
        }
        out.push(tj);
    }
    out
}

fn report_steps(detected: &[f64], how: StepReport, d: f64, rng: &mut Rng) -> Vec<StepSample> {
    let seconds = (d + 1e-9).floor() as usize;
    match how {
        StepReport::Events => detected
            .iter()
            .map(|&t_s| StepSample::Event { t_s })
            .collect(),
        StepReport::CountEverySecond => {
            let offset = 10_000 + (rng.uniform() * 40_000.0) as u64;
            let mut j = 0usize;
            (0..=seconds)
                .map(|s| {
                    let t_s = s as f64;
                    while j < detected.len() && detected[j] <= t_s {
                        j += 1;
                    }
                    StepSample::Count {
                        t_s,
                        steps: offset + j as u64,
                    }
                })
                .collect()
        }
        StepReport::CadenceEverySecond => {
            let (mut lo, mut hi) = (0usize, 0usize);
            (1..=seconds)
                .map(|s| {
                    let t_s = s as f64;
                    while hi < detected.len() && detected[hi] <= t_s {
                        hi += 1;
                    }
                    while lo < hi && detected[lo] <= t_s - 2.0 {
                        lo += 1;
                    }
                    let spm = if hi >= lo + 2 {
                        let span = detected[hi - 1] - detected[lo];
                        (60.0 * (hi - lo - 1) as f64 / span).round()
                    } else {
                        0.0
                    };
                    StepSample::Cadence {
                        t_s,
                        steps_per_min: spm,
                    }
                })
                .collect()
        }
    }
}

// ---------------------------------------------------------------------------------
// Zones.

/// A zone plus the GNSS error parameters of a disturbance zone.
#[derive(Clone, Debug)]
struct ZonePlan {
    zone: Zone,
    /// Correlated error σ (m) and τ (s) inside a disturbance zone.
    sigma_m: f64,
    tau_s: f64,
    /// Multipath jumps: (start, end, east offset, north offset).
    jumps: Vec<(f64, f64, f64, f64)>,
}

fn free(placed: &[ZonePlan], s: f64, e: f64) -> bool {
    placed
        .iter()
        .all(|p| e + ZONE_GAP_S <= p.zone.start_s || s >= p.zone.end_s + ZONE_GAP_S)
}

/// Pick a start for a zone of length `len` in `[lo, hi]` that does not touch any
/// placed zone and satisfies `ok`; None after a bounded number of tries.
fn place(
    rng: &mut Rng,
    len: f64,
    lo: f64,
    hi: f64,
    placed: &[ZonePlan],
    mut ok: impl FnMut(f64, f64) -> bool,
) -> Option<(f64, f64)> {
    if hi - lo < len {
        return None;
    }
    for _ in 0..500 {
        let s = rng.range(lo, hi - len);
        let e = s + len;
        if free(placed, s, e) && ok(s, e) {
            return Some((s, e));
        }
    }
    None
}

fn plan_zones(rng: &mut Rng, sc: &RunScenario, d: f64, segs: &mut Vec<Seg>) -> Vec<ZonePlan> {
    let mut placed: Vec<ZonePlan> = Vec::new();
    let scale = (d / 2400.0).min(1.0);
    let plain = |kind, s, e| ZonePlan {
        zone: Zone {
            kind,
            start_s: s,
            end_s: e,
        },
        sigma_m: 0.0,
        tau_s: 1.0,
        jumps: Vec::new(),
    };
    let hi = d - ZONE_GAP_S;
    if sc.outages {
        let n = ((2.0 + (rng.uniform() * 2.0).floor()) * scale).round() as usize;
        for k in 0..n {
            let len = if k == 0 {
                rng.range(150.0, 180.0)
            } else {
                rng.range(60.0, 180.0)
            };
            if let Some((s, e)) = place(rng, len, QUIET_START_S, hi, &placed, |_, _| true) {
                placed.push(plain(ZoneKind::Outage, s, e));
            }
        }
    }
    if sc.stops {
        let n = 2 + (rng.uniform() * 3.0) as usize;
        for _ in 0..n {
            let len = rng.range(15.0, 45.0);
            let segs_now: &Vec<Seg> = segs;
            let fits = |s: f64, e: f64| {
                segs_now
                    .iter()
                    .any(|g| !g.stop && g.start + STOP_MARGIN_S <= s && e + STOP_MARGIN_S <= g.end)
            };
            if let Some((s, e)) = place(rng, len, 150.0, d - 30.0, &placed, fits) {
                if insert_stop(segs, s, e) {
                    placed.push(plain(ZoneKind::Stop, s, e));
                }
            }
        }
    }
    if sc.disturbances {
        let n = (rng.range(4.0, 9.0).floor() * scale).round().max(1.0) as usize;
        for _ in 0..n {
            let len = rng.range(20.0, 90.0);
            let sigma_m = rng.range(4.0, 10.0);
            let tau_s = rng.range(3.0, 10.0);
            let Some((s, e)) = place(rng, len, QUIET_START_S, hi, &placed, |_, _| true) else {
                continue;
            };
            let n_jumps = (len / 40.0).floor() as usize + usize::from(rng.uniform() < 0.5);
            let jumps = (0..n_jumps)
                .map(|_| {
                    let dur = rng.range(2.0, 6.0);
                    let js = rng.range(s, e - dur);
                    let mag = rng.range(5.0, 15.0);
                    let dir = rng.range(0.0, std::f64::consts::TAU);
                    (js, js + dur, mag * dir.sin(), mag * dir.cos())
                })
                .collect();
            placed.push(ZonePlan {
                sigma_m,
                tau_s,
                jumps,
                ..plain(ZoneKind::Disturbance, s, e)
            });
        }
    }
    placed
}

// ---------------------------------------------------------------------------------
// GNSS.

/// One step of a unit-variance first-order Gauss–Markov process.
fn gm_step(x: f64, dt: f64, tau: f64, rng: &mut Rng) -> f64 {
    let a = (-dt.max(0.0) / tau).exp();
    a * x + (1.0 - a * a).sqrt() * rng.normal()
}

fn simulate_fixes(run: &SimulatedRun, zones: &[ZonePlan], d: f64, rng: &mut Rng) -> Vec<GnssFix> {
    let sc = &run.scenario;
    let interval = if sc.gnss_interval_s.is_finite() && sc.gnss_interval_s > 0.0 {
        sc.gnss_interval_s
    } else {
        1.0
    };
    let frame = LocalFrame::new(sc.origin_lat_deg, sc.origin_lon_deg, 0.0);
    let tau = std::f64::consts::TAU;
    let hills = [
        (6.0, tau / rng.range(600.0, 1000.0), rng.range(0.0, tau)),
        (4.0, tau / rng.range(300.0, 600.0), rng.range(0.0, tau)),
    ];
    let ground = |e: f64, n: f64| {
        250.0
            + hills[0].0 * (hills[0].1 * e + hills[0].2).sin()
            + hills[1].0 * (hills[1].1 * n + hills[1].2).sin()
    };

    let n_fix = (d / interval + 1e-9).floor() as usize;
    let mut fixes = Vec::with_capacity(n_fix + 1);
    // Unit-variance Gauss–Markov states.
    let (mut bg_e, mut bg_n, mut bg_u) = (rng.normal(), rng.normal(), rng.normal());
    let (mut dz_e, mut dz_n) = (0.0, 0.0);
    let mut acc_clean = rng.normal();
    let mut acc_zone = rng.normal();
    let mut cur_zone: Option<usize> = None;
    let mut in_outage = false;
    let mut t_prev = 0.0;

    for k in 0..=n_fix {
        let t = (k as f64 * interval + rng.range(-0.005, 0.005)).clamp(0.0, d);
        let dt = t - t_prev;
        t_prev = t;
        bg_e = gm_step(bg_e, dt, GNSS_BG_TAU_S, rng);
        bg_n = gm_step(bg_n, dt, GNSS_BG_TAU_S, rng);
        bg_u = gm_step(bg_u, dt, GNSS_BG_TAU_S, rng);
        acc_clean = gm_step(acc_clean, dt, 60.0, rng);
        acc_zone = gm_step(acc_zone, dt, 8.0, rng);
        let (w_e, w_n, w_u) = (rng.normal(), rng.normal(), rng.normal());

        let zone_idx = zones
            .iter()
            .position(|z| z.zone.kind != ZoneKind::Stop && t >= z.zone.start_s && t < z.zone.end_s);
        let zone = zone_idx.map(|i| &zones[i]);
        if zone.is_some_and(|z| z.zone.kind == ZoneKind::Outage) {
            in_outage = true;
            cur_zone = None;
            continue;
        }
        if in_outage {
            // Reacquisition after an outage: a new constellation, a new slow error.
            in_outage = false;
            bg_e = rng.normal();
            bg_n = rng.normal();
        }
        let mut env = 0.0;
        let (mut jump_e, mut jump_n) = (0.0, 0.0);
        let mut sigma_z = 0.0;
        if let Some(z) = zone {
            if cur_zone != zone_idx {
                dz_e = rng.normal();
                dz_n = rng.normal();
            } else {
                dz_e = gm_step(dz_e, dt, z.tau_s, rng);
                dz_n = gm_step(dz_n, dt, z.tau_s, rng);
            }
            env = smoothstep((t - z.zone.start_s).min(z.zone.end_s - t) / DIST_EDGE_S);
            sigma_z = z.sigma_m * env;
            for &(js, je, de, dn) in &z.jumps {
                if t >= js && t < je {
                    jump_e += de;
                    jump_n += dn;
                }
            }
        }
        cur_zone = zone_idx;

        let tr = run.truth_at(t);
        let err_e = GNSS_WHITE_SIGMA_M * w_e + GNSS_BG_SIGMA_M * bg_e + sigma_z * dz_e + jump_e;
        let err_n = GNSS_WHITE_SIGMA_M * w_n + GNSS_BG_SIGMA_M * bg_n + sigma_z * dz_n + jump_n;
        let (lat, lon) = frame.to_geodetic(tr.east_m + err_e, tr.north_m + err_n);
        let alt = ground(tr.east_m, tr.north_m) + 2.0 * bg_u + 0.8 * w_u;
        let mut fix = GnssFix::new(t, lat, lon);
        fix.alt_m = Some(alt);
        if sc.report_accuracy {
            let clean = (4.0 + 0.6 * acc_clean).clamp(3.0, 5.5);
            // The receiver's own idea of its error inside a zone: about the median size
            // of the Gaussian part, times a wandering optimism factor, blind to multipath
            // jumps. With the 8 m floor it under-reports the real error ~40 % of the time
            // (about 3 times in 4 when the real error exceeds 8 m).
            let sigma_axis =
                (GNSS_WHITE_SIGMA_M.powi(2) + GNSS_BG_SIGMA_M.powi(2) + sigma_z.powi(2)).sqrt();
            let seen = (1.18 * sigma_axis).hypot(0.5 * jump_e.hypot(jump_n));
            let zone_acc = (seen * (0.3 * acc_zone).exp()).clamp(8.0, 25.0);
            let acc = clean + (zone_acc - clean) * env;
            fix.horizontal_accuracy_m = Some((acc * 10.0).round() / 10.0);
        }
        fixes.push(fix);
    }
    fixes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix_error(run: &SimulatedRun, f: &GnssFix) -> f64 {
        let s = &run.scenario;
        let frame = LocalFrame::new(s.origin_lat_deg, s.origin_lon_deg, 0.0);
        let p = frame.to_enu(f.lat_deg, f.lon_deg, 0.0);
        let tr = run.truth_at(f.t_s);
        (p[0] - tr.east_m).hypot(p[1] - tr.north_m)
    }

    fn rms(xs: &[f64]) -> f64 {
        (xs.iter().map(|x| x * x).sum::<f64>() / xs.len().max(1) as f64).sqrt()
    }

    fn zones_of(run: &SimulatedRun, kind: ZoneKind) -> Vec<Zone> {
        run.zones
            .iter()
            .copied()
            .filter(|z| z.kind == kind)
            .collect()
    }

    #[test]
    fn deterministic_from_seed() {
        let a = simulate_run(&RunScenario::demo(7));
        let b = simulate_run(&RunScenario::demo(7));
        assert_eq!(a, b);
        let c = simulate_run(&RunScenario::demo(8));
        assert_ne!(a.fixes, c.fixes);
        assert_ne!(a.steps, c.steps);
        assert_ne!(a.zones, c.zones);
        assert_ne!(a.truth.last(), c.truth.last());
        for how in [StepReport::Events, StepReport::CadenceEverySecond] {
            let sc = RunScenario {
                step_report: how,
                ..RunScenario::demo(7)
            };
            assert_eq!(simulate_run(&sc), simulate_run(&sc));
        }
    }

    #[test]
    fn demo_scenario_shape() {
        let sc = RunScenario::demo(1);
        assert_eq!(sc.duration_s, 2400.0);
        let run = simulate_run(&sc);
        assert_eq!(run.truth.len(), 24_001);
        assert_eq!(run.truth[0].t_s, 0.0);
        assert!((run.truth.last().unwrap().t_s - 2400.0).abs() < 1e-9);
        for w in run.truth.windows(2) {
            assert!((w[1].t_s - w[0].t_s - 0.1).abs() < 1e-9);
        }
        assert_eq!(run.truth[0].east_m, 0.0);
        assert_eq!(run.truth[0].north_m, 0.0);
        let clean = RunScenario::clean(1);
        assert!(!clean.disturbances && !clean.outages && clean.stops);
        assert_eq!(clean.duration_s, 2400.0);
    }

    #[test]
    fn pace_profile_is_plausible() {
        for seed in 0..8 {
            let run = simulate_run(&RunScenario::demo(seed));
            let at = |t: f64| run.truth_at(t).speed_mps;
            let max = run.truth.iter().map(|s| s.speed_mps).fold(0.0, f64::max);
            assert!((4.0..=5.0).contains(&max), "seed {seed}: max {max}");
            assert!((2.6..=3.0).contains(&at(60.0)), "warm-up {}", at(60.0));
            assert!(
                (1.2..=1.6).contains(&at(2395.0)),
                "cool-down {}",
                at(2395.0)
            );
            for w in run.truth.windows(2) {
                let acc = (w[1].speed_mps - w[0].speed_mps) / 0.1;
                assert!(acc.abs() <= 1.0, "seed {seed} t {}: accel {acc}", w[0].t_s);
            }
            // Lateral acceleration from the path (v · heading rate) stays plausible.
            let h = |a: &TruthSample, b: &TruthSample| {
                (b.east_m - a.east_m).atan2(b.north_m - a.north_m)
            };
            for w in run.truth.windows(3) {
                if w[0].speed_mps < 1.0 || w[2].speed_mps < 1.0 {
                    continue;
                }
                let mut dh = h(&w[1], &w[2]) - h(&w[0], &w[1]);
                dh = (dh + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                let lat = w[1].speed_mps * dh / 0.1;
                assert!(lat.abs() < 3.5, "seed {seed} t {}: lateral {lat}", w[1].t_s);
            }
        }
    }

    #[test]
    fn truth_is_consistent() {
        for seed in 0..4 {
            let run = simulate_run(&RunScenario::demo(seed));
            let integral: f64 = run
                .truth
                .windows(2)
                .map(|w| 0.5 * (w[0].speed_mps + w[1].speed_mps) * (w[1].t_s - w[0].t_s))
                .sum();
            let dist = run.truth.last().unwrap().distance_m;
            assert!(
                (dist - integral).abs() < 0.005 * integral,
                "{dist} vs {integral}"
            );
            let path: f64 = run
                .truth
                .windows(2)
                .map(|w| (w[1].east_m - w[0].east_m).hypot(w[1].north_m - w[0].north_m))
                .sum();
            assert!((path - dist).abs() < 0.005 * dist, "{path} vs {dist}");
            let stops = zones_of(&run, ZoneKind::Stop);
            assert!((2..=4).contains(&stops.len()), "{stops:?}");
            for s in &run.truth {
                assert!(s.speed_mps >= 0.0);
                if run.in_zone(s.t_s, ZoneKind::Stop) {
                    assert_eq!(s.speed_mps, 0.0, "t {}", s.t_s);
                    assert_eq!(s.cadence_spm, 0.0, "t {}", s.t_s);
                } else if s.speed_mps > 2.2 {
                    let c = s.cadence_spm;
                    assert!((140.0..=215.0).contains(&c), "t {} cadence {c}", s.t_s);
                    let l = 0.45 + 0.20 * s.speed_mps;
                    assert!((s.step_length_m / l - 1.0).abs() <= 0.031);
                }
                if s.speed_mps > 0.0 {
                    let v = s.step_length_m * s.cadence_spm / 60.0;
                    assert!((v - s.speed_mps).abs() < 1e-9);
                }
            }
            for w in run.truth.windows(2) {
                assert!(w[1].distance_m >= w[0].distance_m);
            }
            // Walking cool-down: ~0.73 m steps at 1.4 m/s.
            let end = run.truth.last().unwrap();
            assert!((0.65..=0.8).contains(&end.step_length_m), "{end:?}");
        }
    }

    #[test]
    fn steps_follow_cadence_and_never_while_stopped() {
        for seed in 0..3 {
            let events = simulate_run(&RunScenario {
                step_report: StepReport::Events,
                ..RunScenario::demo(seed)
            });
            let counts = simulate_run(&RunScenario::demo(seed));
            let cadence = simulate_run(&RunScenario {
                step_report: StepReport::CadenceEverySecond,
                ..RunScenario::demo(seed)
            });
            // Expected steps: integral of the true cadence.
            let expected: f64 = events
                .truth
                .windows(2)
                .map(|w| (w[0].cadence_spm + w[1].cadence_spm) / 120.0 * 0.1)
                .sum();
            let n_events = events.steps.len() as f64;
            let ratio = n_events / expected;
            assert!((0.975..=1.0).contains(&ratio), "seed {seed}: {ratio}");
            for s in &events.steps {
                assert!(matches!(s, StepSample::Event { .. }));
                assert!(
                    !events.in_zone(s.t_s(), ZoneKind::Stop),
                    "step at {}",
                    s.t_s()
                );
            }
            // Counts: every whole second, non-zero offset, same total as the events.
            let StepSample::Count {
                t_s: 0.0,
                steps: first,
            } = counts.steps[0]
            else {
                panic!("{:?}", counts.steps[0]);
            };
            assert!(first >= 10_000);
            assert_eq!(counts.steps.len(), 2401);
            let StepSample::Count { steps: last, .. } = *counts.steps.last().unwrap() else {
                panic!()
            };
            assert_eq!((last - first) as f64, n_events);
            for z in zones_of(&counts, ZoneKind::Stop) {
                let inside: Vec<u64> = counts
                    .steps
                    .iter()
                    .filter(|s| s.t_s() >= z.start_s && s.t_s() < z.end_s)
                    .map(|s| match *s {
                        StepSample::Count { steps, .. } => steps,
                        _ => unreachable!(),
                    })
                    .collect();
                assert!(inside.len() >= 14);
                assert!(inside.windows(2).all(|w| w[0] == w[1]), "{z:?} {inside:?}");
                // A watch reports 0 cadence a couple of seconds into a stop.
                for s in &cadence.steps {
                    if s.t_s() >= z.start_s + 2.5 && s.t_s() < z.end_s {
                        assert!(
                            matches!(s, StepSample::Cadence { steps_per_min, .. } if *steps_per_min == 0.0)
                        );
                    }
                }
            }
            // Reported cadence tracks the truth when running steadily.
            let mut errs = Vec::new();
            for s in &cadence.steps {
                let StepSample::Cadence { t_s, steps_per_min } = *s else {
                    panic!()
                };
                assert_eq!(steps_per_min, steps_per_min.round());
                let tr = cadence.truth_at(t_s - 1.0);
                if tr.speed_mps > 2.5
                    && (cadence.truth_at(t_s - 2.0).speed_mps - tr.speed_mps).abs() < 0.02
                {
                    errs.push(steps_per_min / tr.cadence_spm - 1.0);
                }
            }
            let mean = errs.iter().sum::<f64>() / errs.len() as f64;
            assert!(
                errs.len() > 1000 && mean.abs() < 0.01,
                "{} {mean}",
                errs.len()
            );
            assert!(rms(&errs) < 0.05, "{}", rms(&errs));
        }
    }

    #[test]
    fn gnss_error_statistics() {
        for seed in 0..6 {
            let run = simulate_run(&RunScenario::demo(seed));
            let (mut clean, mut dist) = (Vec::new(), Vec::new());
            let (mut under, mut zone_fixes) = (0usize, 0usize);
            for f in &run.fixes {
                let e = fix_error(&run, f);
                let acc = f.horizontal_accuracy_m.unwrap();
                assert!(f.alt_m.is_some_and(|a| (220.0..=280.0).contains(&a)));
                assert!(f.speed_mps.is_none() && f.speed_accuracy_mps.is_none());
                if run.in_zone(f.t_s, ZoneKind::Disturbance) {
                    dist.push(e);
                    zone_fixes += 1;
                    under += usize::from(acc < e);
                    assert!((3.0..=25.0).contains(&acc), "{acc}");
                    let deep = run
                        .zones
                        .iter()
                        .any(|z| f.t_s >= z.start_s + DIST_EDGE_S && f.t_s < z.end_s - DIST_EDGE_S);
                    if deep {
                        assert!((8.0..=25.0).contains(&acc), "{acc}");
                    }
                } else {
                    clean.push(e);
                    assert!((3.0..=5.5).contains(&acc), "{acc}");
                }
            }
            let (rc, rd) = (rms(&clean), rms(&dist));
            assert!((1.0..=3.0).contains(&rc), "seed {seed}: clean rms {rc}");
            assert!(
                rd > 2.5 * rc && rd > 6.0,
                "seed {seed}: disturbed rms {rd} vs {rc}"
            );
            let frac = under as f64 / zone_fixes as f64;
            assert!(
                (0.25..=0.6).contains(&frac),
                "seed {seed}: under-reported {frac}"
            );
        }
        // Accuracy optional.
        let run = simulate_run(&RunScenario {
            report_accuracy: false,
            ..RunScenario::demo(3)
        });
        assert!(run.fixes.iter().all(|f| f.horizontal_accuracy_m.is_none()));
    }

    #[test]
    fn zones_are_separate_and_late() {
        for seed in 0..20 {
            let run = simulate_run(&RunScenario::demo(seed));
            for w in run.zones.windows(2) {
                assert!(w[0].start_s <= w[1].start_s);
                assert!(w[0].end_s <= w[1].start_s, "seed {seed}: {w:?}");
            }
            for z in &run.zones {
                assert!(z.end_s <= 2400.0);
                match z.kind {
                    ZoneKind::Disturbance => {
                        assert!(
                            z.start_s >= 120.0 && (20.0..=90.0).contains(&(z.end_s - z.start_s))
                        )
                    }
                    ZoneKind::Outage => {
                        assert!(
                            z.start_s >= 120.0 && (60.0..=180.0).contains(&(z.end_s - z.start_s))
                        )
                    }
                    ZoneKind::Stop => assert!((15.0..=45.0).contains(&(z.end_s - z.start_s))),
                }
            }
            let n_d = zones_of(&run, ZoneKind::Disturbance).len();
            let outages = zones_of(&run, ZoneKind::Outage);
            assert!((4..=8).contains(&n_d), "seed {seed}: {n_d}");
            assert!((2..=3).contains(&outages.len()), "seed {seed}: {outages:?}");
            assert!(outages.iter().any(|z| z.end_s - z.start_s >= 150.0));
            for f in &run.fixes {
                assert!(!run.in_zone(f.t_s, ZoneKind::Outage), "fix at {}", f.t_s);
            }
            // Fixes otherwise every second.
            let covered: f64 = outages.iter().map(|z| z.end_s - z.start_s).sum();
            let expected = 2401.0 - covered;
            assert!((run.fixes.len() as f64 - expected).abs() <= 4.0);
        }
        let run = simulate_run(&RunScenario::clean(5));
        assert!(run.zones.iter().all(|z| z.kind == ZoneKind::Stop));
        assert_eq!(run.fixes.len(), 2401);
    }

    #[test]
    fn streams_are_time_ordered() {
        for how in [
            StepReport::CountEverySecond,
            StepReport::Events,
            StepReport::CadenceEverySecond,
        ] {
            let run = simulate_run(&RunScenario {
                step_report: how,
                ..RunScenario::demo(11)
            });
            assert!(run.fixes.windows(2).all(|w| w[0].t_s < w[1].t_s));
            assert!(run.steps.windows(2).all(|w| w[0].t_s() < w[1].t_s()));
            for f in &run.fixes {
                assert!((f.t_s - f.t_s.round()).abs() <= 0.005 && f.t_s >= 0.0);
            }
            let samples = run.samples();
            assert_eq!(samples.len(), run.fixes.len() + run.steps.len());
            assert!(samples.windows(2).all(|w| w[0].t_s() <= w[1].t_s()));
        }
    }

    #[test]
    fn other_durations_and_rates() {
        let sc = RunScenario {
            duration_s: 600.0,
            gnss_interval_s: 0.5,
            ..RunScenario::demo(4)
        };
        let run = simulate_run(&sc);
        assert_eq!(run.truth.len(), 6001);
        assert!(run.fixes.windows(2).all(|w| w[0].t_s < w[1].t_s));
        assert!(run.zones.iter().all(|z| z.end_s <= 600.0));
        let empty = simulate_run(&RunScenario {
            duration_s: 0.0,
            ..RunScenario::demo(4)
        });
        assert_eq!(empty.truth.len(), 1);
    }
}
