//! Simulated phone IMU (accelerometer, gyroscope, magnetometer) and GNSS while a
//! person walks, runs, stands, shakes the phone, rides a vehicle or cycles.
//!
//! Deterministic: everything comes from [`PhoneScenario::seed`] through the in-tree
//! [`Rng`], one independent stream per sub-model.
//!
//! Models (see [`simulate_phone`]):
//! - **gait**: per-person step-length factor (0.92–1.08 unless given); nominal step
//!   length `0.37 + 0.26·v` walking (≈ 0.71 m at 1.84 steps/s for 1.3 m/s); running
//!   at a nearly constant cadence `2.75 + 0.12·(v − 3)` steps/s, so step length
//!   carries the speed (≈ 1.09 m at 2.75 steps/s for 3 m/s, 1.39 m at 4 m/s: what
//!   the real runs in `../shared/data/pace` show); speed wanders ±4 %
//!   within a segment; each step's length varies ~2 %; step duration = length /
//!   speed, so frequency and length stay consistent with speed;
//! - **body acceleration** (world frame) over each step: vertical centre-of-mass
//!   oscillation `A_v·cos(2πφ)` with the inverted-pendulum amplitude
//!   `A_v = 0.7·L²(2πF)²/(16·leg)` (grows with step length and frequency: this is
//!   what makes SV and a_max − a_min carry step length), forward surge `0.4·A_v`,
//!   lateral sway at the stride frequency, and a heel-strike transient (decaying
//!   18 Hz oscillation, τ = 25 ms) of amplitude `~A_v`, each with ~10 % per-step
//!   variation; all scaled by placement gains (a bag damps, a pocket amplifies
//!   impacts);
//! - **orientation**: placement-dependent nominal attitude relative to the walking
//!   direction, a random per-run offset (≤ 15°), slow wander (a few degrees), and for
//!   pockets, armband and swinging arm a limb swing at the stride frequency whose
//!   tangential and centripetal accelerations are added;
//! - **sensors**: accelerometer = C_bw·(a + g·up) + bias + noise (m/s²); gyroscope
//!   from the orientation's rate (finite difference) + bias + noise (rad/s);
//!   magnetometer = C_bw·B_earth (≈ 48 µT, dip ≈ 66°) + hard iron + noise (µT), with
//!   optional disturbance bursts and a steel vehicle body;
//! - **non-walking**: `Standing` (tiny sway), `Shaking` (3–6 Hz, 1.5–3 cm hand
//!   shake with rotation), `Vehicle` (speed oscillation, 12–25 Hz vibration, road
//!   bumps, turns with ≤ 2.5 m/s² lateral acceleration), `Cycling` (pedalling leg
//!   swing, road vibration): no heel strikes;
//! - **GNSS** (optional): 1 Hz fixes, white 0.5 m + Gauss–Markov 1.5 m / 60 s per
//!   axis, accuracy reports 3–5 m, none inside the scenario's outages.
//!
//! Truth: every heel strike (time, length of the step it ends; the first heel strike
//! of a bout ends no step: length 0, duration `NaN`), position and heading at 10 Hz.
//! A bout (consecutive walking/running segments) keeps its gait across segment
//! changes; the last step of a bout is not completed (the person stops).

use nalgebra::{Quaternion, Rotation3, UnitQuaternion, Vector3};

use super::rng::Rng;
use stridekit_core::pdr::NavigatorConfig;
use stridekit_core::placement::Placement;
use stridekit_core::stepdetect::{StepEvent, StepOrigin};

/// Standard gravity, m/s².
pub const GRAVITY_MPS2: f64 = 9.80665;

/// Where the phone is carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhonePlacement {
    InHand,
    FrontPocket,
    BackPocket,
    Bag,
    NeckPouch,
    Armband,
    SwingingArm,
}

impl PhonePlacement {
    pub const ALL: [PhonePlacement; 7] = [
        PhonePlacement::InHand,
        PhonePlacement::FrontPocket,
        PhonePlacement::BackPocket,
        PhonePlacement::Bag,
        PhonePlacement::NeckPouch,
        PhonePlacement::Armband,
        PhonePlacement::SwingingArm,
    ];

    /// (impact gain, pattern gain, swing amplitude walking rad, swing radius m).
    fn gains(self) -> (f64, f64, f64, f64) {
        match self {
            PhonePlacement::InHand => (0.7, 0.9, 0.0, 0.0),
            PhonePlacement::FrontPocket => (1.3, 1.1, 0.35, 0.3),
            PhonePlacement::BackPocket => (1.2, 1.0, 0.3, 0.25),
            PhonePlacement::Bag => (0.5, 0.7, 0.0, 0.0),
            PhonePlacement::NeckPouch => (0.8, 0.95, 0.0, 0.0),
            PhonePlacement::Armband => (0.9, 1.0, 0.25, 0.25),
            PhonePlacement::SwingingArm => (0.8, 1.0, 0.5, 0.6),
        }
    }

    /// Nominal attitude of the phone body in the walking frame (x forward, y left,
    /// z up) as (roll, pitch, yaw) for `Rotation3::from_euler_angles`.
    fn nominal(self) -> (f64, f64, f64) {
        let d = std::f64::consts::PI / 180.0;
        match self {
            // Screen up, top forward, tilted 30° towards the user.
            PhonePlacement::InHand => (30.0 * d, 0.0, -90.0 * d),
            // Upright (long axis vertical), screen against the thigh.
            PhonePlacement::FrontPocket => (90.0 * d, 0.0, -90.0 * d),
            PhonePlacement::BackPocket => (90.0 * d, 0.0, 90.0 * d),
            PhonePlacement::Bag => (0.0, 0.0, 0.0),
            PhonePlacement::NeckPouch => (90.0 * d, 0.0, -90.0 * d),
            PhonePlacement::Armband => (90.0 * d, 0.0, 0.0),
            PhonePlacement::SwingingArm => (90.0 * d, 0.0, 0.0),
        }
    }
}

/// What the person does during a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhoneActivity {
    Walking {
        speed_mps: f64,
    },
    Running {
        speed_mps: f64,
    },
    Standing,
    /// The phone shaken in the hand while standing.
    Shaking,
    /// Riding a car or bus with the phone.
    Vehicle {
        speed_mps: f64,
    },
    Cycling {
        speed_mps: f64,
    },
}

impl PhoneActivity {
    /// Whether this activity has heel strikes.
    pub fn has_steps(&self) -> bool {
        matches!(
            self,
            PhoneActivity::Walking { .. } | PhoneActivity::Running { .. }
        )
    }

    fn speed(&self) -> f64 {
        let v = match *self {
            PhoneActivity::Walking { speed_mps } => speed_mps.clamp(0.5, 2.2),
            PhoneActivity::Running { speed_mps } => speed_mps.clamp(1.8, 7.0),
            PhoneActivity::Vehicle { speed_mps } => speed_mps.clamp(1.0, 40.0),
            PhoneActivity::Cycling { speed_mps } => speed_mps.clamp(1.0, 15.0),
            PhoneActivity::Standing | PhoneActivity::Shaking => 0.0,
        };
        if v.is_finite() {
            v
        } else {
            0.0
        }
    }
}

/// One segment of a scenario.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhoneSegment {
    pub activity: PhoneActivity,
    pub duration_s: f64,
}

/// What to simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct PhoneScenario {
    pub seed: u64,
    pub placement: PhonePlacement,
    /// IMU rate, Hz (clamped to 50–500).
    pub sample_rate_hz: f64,
    /// 1-σ timestamp jitter, seconds (clamped so timestamps keep increasing); the
    /// sample is taken at the jittered time.
    pub timestamp_jitter_s: f64,
    pub segments: Vec<PhoneSegment>,
    /// Step-length factor of the person (1 = population law); `None`: drawn from the
    /// seed in 0.92–1.08.
    pub person_factor: Option<f64>,
    /// Magnetic disturbance bursts (steel, electronics) besides vehicle bodies.
    pub magnetic_disturbances: bool,
    /// Simulate 1 Hz GNSS fixes.
    pub gnss: bool,
    /// GNSS outages (start, end), seconds: no fixes inside.
    pub gnss_outages: Vec<(f64, f64)>,
    /// Turns (start s, duration s, angle rad clockwise) replacing the random ones
    /// (e.g. a closed loop); the slow heading wander stays.
    pub turns: Option<Vec<(f64, f64, f64)>>,
}

impl PhoneScenario {
    /// A walk of `duration_s` at `speed_mps` with the phone at `placement`, 100 Hz,
    /// GNSS on.
    pub fn walk(seed: u64, placement: PhonePlacement, speed_mps: f64, duration_s: f64) -> Self {
        Self {
            seed,
            placement,
            sample_rate_hz: 100.0,
            timestamp_jitter_s: 0.0,
            segments: vec![PhoneSegment {
                activity: PhoneActivity::Walking { speed_mps },
                duration_s,
            }],
            person_factor: None,
            magnetic_disturbances: false,
            gnss: true,
            gnss_outages: Vec::new(),
            turns: None,
        }
    }

    /// A tour of every activity: walk, stand, shake, walk, run, cycle, vehicle, walk.
    pub fn tour(seed: u64, placement: PhonePlacement) -> Self {
        let seg = |activity, duration_s| PhoneSegment {
            activity,
            duration_s,
        };
        Self {
            segments: vec![
                seg(PhoneActivity::Walking { speed_mps: 1.3 }, 60.0),
                seg(PhoneActivity::Standing, 20.0),
                seg(PhoneActivity::Shaking, 15.0),
                seg(PhoneActivity::Walking { speed_mps: 1.5 }, 40.0),
                seg(PhoneActivity::Running { speed_mps: 3.0 }, 40.0),
                seg(PhoneActivity::Cycling { speed_mps: 5.0 }, 40.0),
                seg(PhoneActivity::Vehicle { speed_mps: 12.0 }, 60.0),
                seg(PhoneActivity::Walking { speed_mps: 1.2 }, 30.0),
            ],
            magnetic_disturbances: true,
            ..Self::walk(seed, placement, 1.3, 0.0)
        }
    }
}

/// One IMU sample in the phone's body frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuSample {
    pub t_s: f64,
    /// Specific force, gravity included, m/s².
    pub accel_mps2: [f64; 3],
    pub gyro_radps: [f64; 3],
    pub mag_ut: [f64; 3],
}

impl ImuSample {
    /// Acceleration magnitude, m/s².
    pub fn accel_norm_mps2(&self) -> f64 {
        let a = self.accel_mps2;
        (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
    }
}

/// A true heel strike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrueStep {
    pub t_s: f64,
    /// Length of the step that ends at this heel strike, metres.
    pub length_m: f64,
    /// Time since the previous heel strike of the same bout (`NaN` for the first).
    pub duration_s: f64,
    /// Index of the scenario segment.
    pub segment: usize,
}

/// Truth every 0.1 s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhoneTruth {
    pub t_s: f64,
    pub east_m: f64,
    pub north_m: f64,
    /// Direction of travel, radians clockwise from north.
    pub heading_rad: f64,
    pub speed_mps: f64,
    /// Distance travelled (walking, running, cycling and vehicle), metres.
    pub distance_m: f64,
    /// Attitude of the phone: body → ENU rotation as a unit quaternion `[w, x, y, z]`.
    pub attitude_wxyz: [f64; 4],
}

/// A simulated GNSS fix in the local ENU frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhoneFix {
    pub t_s: f64,
    pub east_m: f64,
    pub north_m: f64,
    pub accuracy_m: f64,
}

/// Output of [`simulate_phone`].
#[derive(Clone, Debug, PartialEq)]
pub struct SimulatedPhone {
    pub scenario: PhoneScenario,
    /// (start, end) of every segment, seconds.
    pub segment_times: Vec<(f64, f64)>,
    pub samples: Vec<ImuSample>,
    pub steps: Vec<TrueStep>,
    pub truth: Vec<PhoneTruth>,
    pub fixes: Vec<PhoneFix>,
    /// The person's step-length factor used.
    pub person_factor: f64,
}

/// One input of a simulated phone recording (see [`SimulatedPhone::timeline`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhoneEvent<'a> {
    Imu(&'a ImuSample),
    Fix(stridekit_core::pace::GnssFix),
}

impl SimulatedPhone {
    /// The IMU samples and the GNSS fixes (as WGS84 fixes through `frame`, with their
    /// accuracy) merged in time order, as an app would push them: a fix goes before
    /// the IMU sample with the same time; fixes after the last sample are left out.
    pub fn timeline(&self, frame: &stridekit_core::geo::LocalFrame) -> Vec<PhoneEvent<'_>> {
        let mut out = Vec::with_capacity(self.samples.len() + self.fixes.len());
        let mut fixes = self.fixes.iter().peekable();
        for s in &self.samples {
            while let Some(f) = fixes.next_if(|f| f.t_s <= s.t_s) {
                let (lat, lon) = frame.to_geodetic(f.east_m, f.north_m);
                out.push(PhoneEvent::Fix(
                    stridekit_core::pace::GnssFix::new(f.t_s, lat, lon).with_accuracy(f.accuracy_m),
                ));
            }
            out.push(PhoneEvent::Imu(s));
        }
        out
    }

    /// Step events at the true heel strikes with the features a detector would
    /// compute over each step (previous heel strike, this one] from the simulated
    /// acceleration magnitude, and the vertical displacement a navigator would
    /// measure over it (the accelerometer rotated by the true attitude, the nearest
    /// 10 Hz truth row). Duration is `NaN` for the first step of a bout.
    pub fn step_events(&self) -> Vec<StepEvent> {
        let mut out = Vec::with_capacity(self.steps.len());
        let mut i = 0;
        let mut prev_t = f64::NEG_INFINITY;
        let mut vertical = stridekit_core::pdr::VerticalHistory::new();
        let (mut k, mut m) = (0, 0);
        for s in &self.steps {
            while k < self.samples.len() && self.samples[k].t_s <= s.t_s {
                let x = &self.samples[k];
                while m + 1 < self.truth.len()
                    && (self.truth[m + 1].t_s - x.t_s).abs() <= (self.truth[m].t_s - x.t_s).abs()
                {
                    m += 1;
                }
                if let Some(tr) = self.truth.get(m) {
                    let [w, qx, qy, qz] = tr.attitude_wxyz;
                    let q = UnitQuaternion::new_unchecked(Quaternion::new(w, qx, qy, qz));
                    vertical.push(x.t_s, (q * Vector3::from(x.accel_mps2)).z);
                }
                k += 1;
            }
            let t0 = if s.duration_s.is_finite() {
                s.t_s - s.duration_s
            } else {
                // First step of a bout: features over the preceding half second.
                s.t_s - 0.5
            };
            let t0 = t0.max(prev_t);
            while i < self.samples.len() && self.samples[i].t_s <= t0 {
                i += 1;
            }
            let (mut n, mut sum, mut sum2) = (0.0, 0.0, 0.0);
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            let mut j = i;
            while j < self.samples.len() && self.samples[j].t_s <= s.t_s {
                let a = self.samples[j].accel_norm_mps2();
                n += 1.0;
                sum += a;
                sum2 += a * a;
                lo = lo.min(a);
                hi = hi.max(a);
                j += 1;
            }
            let (var, lo, hi) = if n > 0.0 {
                let m = sum / n;
                ((sum2 / n - m * m).max(0.0), lo, hi)
            } else {
                (0.0, GRAVITY_MPS2, GRAVITY_MPS2)
            };
            out.push(StepEvent {
                t_s: s.t_s,
                duration_s: s.duration_s,
                accel_variance_m2ps4: var,
                accel_max_mps2: hi,
                accel_min_mps2: lo,
                vertical_displacement_m: vertical.displacement_range_m(t0, s.t_s),
                origin: StepOrigin::Detected,
            });
            prev_t = s.t_s;
        }
        out
    }

    /// Truth at `t` (linear interpolation, clamped).
    pub fn truth_at(&self, t: f64) -> PhoneTruth {
        let Some(first) = self.truth.first() else {
            return PhoneTruth::default();
        };
        let x = ((t - first.t_s) / TRUTH_DT_S).max(0.0);
        let i = (x.floor() as usize).min(self.truth.len() - 1);
        let j = (i + 1).min(self.truth.len() - 1);
        let f = (x - i as f64).clamp(0.0, 1.0);
        let (a, b) = (self.truth[i], self.truth[j]);
        let l = |u: f64, v: f64| u + f * (v - u);
        PhoneTruth {
            t_s: t,
            east_m: l(a.east_m, b.east_m),
            north_m: l(a.north_m, b.north_m),
            heading_rad: a.heading_rad,
            speed_mps: l(a.speed_mps, b.speed_mps),
            distance_m: l(a.distance_m, b.distance_m),
            attitude_wxyz: a.attitude_wxyz,
        }
    }

    /// Index of the segment holding `t`.
    pub fn segment_at(&self, t: f64) -> Option<usize> {
        self.segment_times
            .iter()
            .position(|&(s, e)| t >= s && t < e)
    }
}

const TRUTH_DT_S: f64 = 0.1;
/// Internal integration step of the truth track, seconds.
const TRUTH_SUBSTEPS: usize = 10;

/// An independent random stream per sub-model.
fn stream(seed: u64, k: u64) -> Rng {
    Rng::new(seed ^ k.wrapping_mul(0x9E6C_63D0_676A_9A99).rotate_left(17) ^ 0x5048_4F4E)
}

fn cosramp(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    0.5 - 0.5 * (std::f64::consts::PI * x).cos()
}

/// Sum of sinusoids `Σ a·sin(w·t + p)` (smooth, deterministic in t).
#[derive(Clone, Copy, Debug)]
struct Wobble([(f64, f64, f64); 3]);

impl Wobble {
    fn new(rng: &mut Rng, amp: f64, period_lo_s: f64, period_hi_s: f64) -> Self {
        let tau = std::f64::consts::TAU;
        let mut w = [(0.0, 0.0, 0.0); 3];
        for (k, c) in w.iter_mut().enumerate() {
            *c = (
                amp / (k as f64 + 1.0),
                tau / rng.range(period_lo_s, period_hi_s),
                rng.range(0.0, tau),
            );
        }
        Self(w)
    }
    fn at(&self, t: f64) -> f64 {
        self.0.iter().map(|&(a, w, p)| a * (w * t + p).sin()).sum()
    }
    /// Integral from 0 to t.
    fn integral(&self, t: f64) -> f64 {
        self.0
            .iter()
            .map(|&(a, w, p)| a / w * (p.cos() - (w * t + p).cos()))
            .sum()
    }
}

/// A turn: heading changes by `angle` over `dur` starting at `t0`.
#[derive(Clone, Copy, Debug)]
struct Turn {
    t0: f64,
    dur: f64,
    angle: f64,
}

/// A heel strike scheduled in the gait plan, with its per-step variation.
#[derive(Clone, Copy, Debug)]
struct PlannedStep {
    t_s: f64,
    /// Duration until the next heel strike of the bout (or the segment end).
    next_dur_s: f64,
    length_m: f64,
    amp_gain: f64,
    impact_gain: f64,
    /// Index within the bout (for the stride phase).
    k: usize,
    running: bool,
    /// Whether a heel strike ends this step (false for the last of a bout).
    ends: bool,
    /// Start of the bout (first segment start), seconds.
    bout_start: f64,
}

/// Simulate the phone's sensors. Deterministic for a given scenario.
/// The phone navigator's configuration for these simulated sensors: the default, with
/// the gyroscope said to be raw (its bias, 0.01 rad/s per axis, is not removed as a
/// platform's calibrated gyroscope's is), so the magnetic loop follows its drift.
pub fn navigator_config() -> NavigatorConfig {
    NavigatorConfig {
        gyro_calibrated: false,
        ..NavigatorConfig::default()
    }
}

pub fn simulate_phone(scenario: &PhoneScenario) -> SimulatedPhone {
    let rate = if scenario.sample_rate_hz.is_finite() {
        scenario.sample_rate_hz.clamp(50.0, 500.0)
    } else {
        100.0
    };
    let seed = scenario.seed;
    let mut person_rng = stream(seed, 1);
    let person_factor = scenario
        .person_factor
        .filter(|f| f.is_finite() && *f > 0.3 && *f < 3.0)
        .unwrap_or_else(|| person_rng.range(0.92, 1.08));
    let leg_m = person_rng.range(0.85, 0.95) * person_factor;

    // Segments.
    let mut segment_times = Vec::with_capacity(scenario.segments.len());
    let mut t = 0.0;
    for s in &scenario.segments {
        let d = if s.duration_s.is_finite() {
            s.duration_s.max(0.0)
        } else {
            0.0
        };
        segment_times.push((t, t + d));
        t += d;
    }
    let total_s = t;

    // Gait plan: heel strikes per walking/running segment.
    let mut gait_rng = stream(seed, 2);
    let mut plan: Vec<PlannedStep> = Vec::new();
    let mut steps: Vec<TrueStep> = Vec::new();
    let speed_wobble = Wobble::new(&mut gait_rng, 0.025, 20.0, 90.0);
    // Bouts: maximal runs of consecutive walking/running segments; the gait goes on
    // across segment changes inside a bout.
    let mut si = 0;
    while si < scenario.segments.len() {
        if !scenario.segments[si].activity.has_steps() {
            si += 1;
            continue;
        }
        let mut last = si;
        while last + 1 < scenario.segments.len() && scenario.segments[last + 1].activity.has_steps()
        {
            last += 1;
        }
        let (bout_start, bout_end) = (segment_times[si].0, segment_times[last].1);
        let mut t = bout_start + gait_rng.range(0.2, 0.5);
        let mut k = 0;
        let mut seg_i = si;
        let first = plan.len();
        while t < bout_end - 0.05 {
            while seg_i < last && t >= segment_times[seg_i].1 {
                seg_i += 1;
            }
            let act = scenario.segments[seg_i].activity;
            let running = matches!(act, PhoneActivity::Running { .. });
            let v = act.speed() * (1.0 + speed_wobble.at(t));
            let law = if running {
                // Runners speed up mostly by longer steps at a nearly constant
                // cadence (as in the real runs of ../shared/data/pace).
                v / (2.75 + 0.12 * (v - 3.0)).max(2.3)
            } else {
                0.37 + 0.26 * v
            };
            let length = law * person_factor * (1.0 + 0.02 * gait_rng.normal());
            let dur = length / v;
            let prev = (k > 0).then(|| plan[plan.len() - 1]);
            steps.push(TrueStep {
                t_s: t,
                length_m: prev.map_or(0.0, |p| p.length_m),
                duration_s: prev.map_or(f64::NAN, |p| t - p.t_s),
                segment: seg_i,
            });
            plan.push(PlannedStep {
                t_s: t,
                next_dur_s: dur,
                length_m: length,
                amp_gain: (1.0 + 0.08 * gait_rng.normal()).max(0.5),
                impact_gain: (1.0 + 0.15 * gait_rng.normal()).max(0.3),
                k,
                running,
                ends: true,
                bout_start,
            });
            t += dur;
            k += 1;
        }
        // The last planned step of a bout is not completed (no heel strike ends it).
        if plan.len() > first {
            if let Some(p) = plan.last_mut() {
                p.ends = false;
            }
        }
        si = last + 1;
    }

    // Heading: smooth wander plus turns (walking and vehicles turn more).
    let mut head_rng = stream(seed, 3);
    let heading0 = head_rng.range(0.0, std::f64::consts::TAU);
    let heading_wobble = Wobble::new(&mut head_rng, 0.02, 40.0, 120.0);
    let mut turns = Vec::new();
    let mut tt = head_rng.range(60.0, 120.0);
    if let Some(given) = &scenario.turns {
        turns.extend(
            given
                .iter()
                .filter(|t| t.0.is_finite() && t.1.is_finite() && t.1 > 0.0 && t.2.is_finite())
                .map(|&(t0, dur, angle)| Turn { t0, dur, angle }),
        );
        tt = f64::INFINITY;
    }
    while tt < total_s {
        let angle = head_rng.range(0.6, 1.6) * if head_rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        // Peak lateral acceleration of the turn (v·π/2·angle/dur) at most 2.5 m/s².
        let v_turn = segment_times
            .iter()
            .position(|&(s0, s1)| tt >= s0 && tt < s1)
            .map_or(0.0, |k| 1.15 * scenario.segments[k].activity.speed());
        let dur = head_rng
            .range(3.0, 6.0)
            .max(std::f64::consts::FRAC_PI_2 * angle.abs() * v_turn / 2.5);
        turns.push(Turn { t0: tt, dur, angle });
        tt += dur + head_rng.range(60.0, 150.0);
    }
    let heading_at = |t: f64| -> f64 {
        let mut h = heading0 + heading_wobble.integral(t);
        for tr in &turns {
            h += tr.angle * cosramp((t - tr.t0) / tr.dur);
        }
        h
    };
    let heading_rate_at = |t: f64| -> f64 {
        let mut r = heading_wobble.at(t);
        for tr in &turns {
            let x = (t - tr.t0) / tr.dur;
            if (0.0..=1.0).contains(&x) {
                r += tr.angle * 0.5 * std::f64::consts::PI / tr.dur
                    * (std::f64::consts::PI * x).sin();
            }
        }
        r
    };

    // Vehicle / cycling speed profile.
    let mut veh_rng = stream(seed, 4);
    let veh_wobble = Wobble::new(&mut veh_rng, 0.15, 15.0, 40.0);
    let segment_index = |t: f64, cur: &mut usize| -> Option<usize> {
        while *cur + 1 < segment_times.len() && t >= segment_times[*cur].1 {
            *cur += 1;
        }
        segment_times
            .get(*cur)
            .filter(|&&(s, e)| t >= s && t < e)
            .map(|_| *cur)
    };
    let plan_index = |t: f64, cur: &mut usize| -> Option<usize> {
        while *cur + 1 < plan.len() && plan[*cur + 1].t_s <= t {
            *cur += 1;
        }
        plan.get(*cur).filter(|p| p.t_s <= t).map(|_| *cur)
    };
    // Speed at t (truth).
    let speed_at = |t: f64, seg_cur: &mut usize, plan_cur: &mut usize| -> f64 {
        let Some(si) = segment_index(t, seg_cur) else {
            return 0.0;
        };
        match scenario.segments[si].activity {
            PhoneActivity::Walking { .. } | PhoneActivity::Running { .. } => {
                match plan_index(t, plan_cur) {
                    Some(pi) => {
                        let p = plan[pi];
                        // Earlier bouts' last steps have `ends == false`.
                        if p.ends && t < p.t_s + p.next_dur_s {
                            p.length_m / p.next_dur_s
                        } else {
                            0.0
                        }
                    }
                    None => 0.0,
                }
            }
            PhoneActivity::Vehicle { .. } | PhoneActivity::Cycling { .. } => {
                let v = scenario.segments[si].activity.speed();
                let (s0, s1) = segment_times[si];
                let ramp = cosramp((t - s0) / 5.0).min(cosramp((s1 - t) / 5.0));
                v * (1.0 + veh_wobble.at(t)) * ramp
            }
            _ => 0.0,
        }
    };

    // Truth track.
    let n_truth = (total_s / TRUTH_DT_S).floor() as usize + 1;
    let mut truth = Vec::with_capacity(n_truth);
    let (mut e, mut n, mut dist) = (0.0, 0.0, 0.0);
    let (mut sc, mut pc) = (0, 0);
    let h_int = TRUTH_DT_S / TRUTH_SUBSTEPS as f64;
    for i in 0..n_truth {
        let t = i as f64 * TRUTH_DT_S;
        if i > 0 {
            for k in 0..TRUTH_SUBSTEPS {
                let tm = t - TRUTH_DT_S + (k as f64 + 0.5) * h_int;
                let v = speed_at(tm, &mut sc, &mut pc);
                let h = heading_at(tm);
                e += v * h.sin() * h_int;
                n += v * h.cos() * h_int;
                dist += v * h_int;
            }
        }
        truth.push(PhoneTruth {
            t_s: t,
            east_m: e,
            north_m: n,
            heading_rad: heading_at(t).rem_euclid(std::f64::consts::TAU),
            speed_mps: speed_at(t, &mut sc, &mut pc),
            distance_m: dist,
            attitude_wxyz: [1.0, 0.0, 0.0, 0.0],
        });
    }
    // Step lengths: the truth integrates the same piecewise-constant speed, so the
    // steps' lengths sum to the walked distance.

    // Orientation: nominal + per-run offset + slow wander.
    let mut ori_rng = stream(seed, 5);
    let placement = scenario.placement;
    let (r0, p0, y0) = if placement == PhonePlacement::Bag {
        (
            ori_rng.range(-std::f64::consts::PI, std::f64::consts::PI),
            ori_rng.range(-1.5, 1.5),
            ori_rng.range(-std::f64::consts::PI, std::f64::consts::PI),
        )
    } else {
        placement.nominal()
    };
    let off = 0.26;
    let nominal = Rotation3::from_euler_angles(r0, p0, y0)
        * Rotation3::from_euler_angles(
            ori_rng.range(-off, off),
            ori_rng.range(-off, off),
            ori_rng.range(-off, off),
        );
    let wander = [
        Wobble::new(&mut ori_rng, 0.05, 5.0, 30.0),
        Wobble::new(&mut ori_rng, 0.05, 5.0, 30.0),
        Wobble::new(&mut ori_rng, 0.05, 5.0, 30.0),
    ];
    let shake_axis = Vector3::new(ori_rng.normal(), ori_rng.normal(), ori_rng.normal())
        .try_normalize(1e-9)
        .unwrap_or(Vector3::x());
    let shake_freq = Wobble::new(&mut ori_rng, 0.6, 2.0, 6.0);
    let (impact_gain, pattern_gain, swing0, swing_r) = placement.gains();
    let mut bump_rng = stream(seed, 6);
    let mut bumps = Vec::new();
    for (si, seg) in scenario.segments.iter().enumerate() {
        if matches!(
            seg.activity,
            PhoneActivity::Vehicle { .. } | PhoneActivity::Cycling { .. }
        ) {
            let (s0, s1) = segment_times[si];
            let mut tb = s0 + bump_rng.range(0.5, 4.0);
            while tb < s1 {
                bumps.push((tb, bump_rng.range(1.5, 4.0)));
                tb += bump_rng.range(1.0, 6.0);
            }
        }
    }
    let mut mag_rng = stream(seed, 7);
    let mut mag_bursts = Vec::new();
    if scenario.magnetic_disturbances {
        let mut tb = mag_rng.range(10.0, 40.0);
        while tb < total_s {
            let v = Vector3::new(mag_rng.normal(), mag_rng.normal(), mag_rng.normal()) * 10.0;
            mag_bursts.push((tb, mag_rng.range(1.0, 4.0), v));
            tb += mag_rng.range(20.0, 60.0);
        }
    }
    let vehicle_field = Vector3::new(mag_rng.normal(), mag_rng.normal(), mag_rng.normal()) * 12.0;
    let hard_iron = Vector3::new(mag_rng.normal(), mag_rng.normal(), mag_rng.normal()) * 4.0;
    let earth_enu = Vector3::new(0.0, 20.0, -44.0);

    // Phone attitude (body → walking frame, and body → ENU) and limb-swing state.
    struct Pose {
        c_enu_b: Rotation3<f64>,
        /// Limb swing angle, rate and acceleration (rad, rad/s, rad/s²) and radius.
        swing: (f64, f64, f64),
    }
    let pose_at = |t: f64, seg_cur: &mut usize, plan_cur: &mut usize| -> Pose {
        let si = segment_index(t, seg_cur);
        let act = si.map(|i| scenario.segments[i].activity);
        let heading = heading_at(t);
        // Swing: stride phase for walking/running, pedalling for cycling.
        let mut swing = (0.0, 0.0, 0.0);
        match act {
            Some(PhoneActivity::Walking { .. } | PhoneActivity::Running { .. }) => {
                if let Some(pi) = plan_index(t, plan_cur) {
                    let p = plan[pi];
                    let phase = ((t - p.t_s) / p.next_dur_s).clamp(0.0, 1.0);
                    let psi = std::f64::consts::PI * (p.k as f64 + phase);
                    let w = std::f64::consts::PI / p.next_dur_s;
                    let a = swing0 * if p.running { 1.4 } else { 1.0 };
                    swing = (a * psi.sin(), a * w * psi.cos(), -a * w * w * psi.sin());
                }
            }
            Some(PhoneActivity::Cycling { .. }) => {
                let pocket = matches!(
                    placement,
                    PhonePlacement::FrontPocket | PhonePlacement::BackPocket
                );
                let a = if pocket { 0.4 } else { 0.05 };
                let w = std::f64::consts::TAU * 1.3;
                let psi = w * t;
                swing = (a * psi.sin(), a * w * psi.cos(), -a * w * w * psi.sin());
            }
            _ => {}
        }
        let mut extra = Rotation3::identity();
        if act == Some(PhoneActivity::Shaking) {
            let f = 4.5 * (1.0 + 0.3 * shake_freq.at(t));
            let ang = 0.3 * (std::f64::consts::TAU * f * t).sin();
            extra = Rotation3::from_scaled_axis(shake_axis * ang);
        }
        let wobble =
            Rotation3::from_euler_angles(wander[0].at(t), wander[1].at(t), wander[2].at(t));
        // Walking frame → ENU: x forward, y left, z up.
        let c_enu_w =
            Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2 - heading);
        let c_w_b =
            Rotation3::from_axis_angle(&Vector3::y_axis(), swing.0) * nominal * wobble * extra;
        Pose {
            c_enu_b: c_enu_w * c_w_b,
            swing,
        }
    };

    // Truth attitude.
    {
        let (mut sc, mut pc) = (0, 0);
        for tr in truth.iter_mut() {
            let q = nalgebra::UnitQuaternion::from_rotation_matrix(
                &pose_at(tr.t_s, &mut sc, &mut pc).c_enu_b,
            );
            tr.attitude_wxyz = [q.w, q.i, q.j, q.k];
        }
    }

    // IMU samples.
    let mut noise_rng = stream(seed, 8);
    let mut jitter_rng = stream(seed, 9);
    let accel_bias =
        Vector3::new(noise_rng.normal(), noise_rng.normal(), noise_rng.normal()) * 0.05;
    let gyro_bias = Vector3::new(noise_rng.normal(), noise_rng.normal(), noise_rng.normal()) * 0.01;
    let dt = 1.0 / rate;
    let n_samples = (total_s * rate).floor() as usize;
    let jitter = if scenario.timestamp_jitter_s.is_finite() {
        scenario.timestamp_jitter_s.max(0.0)
    } else {
        0.0
    };
    let mut samples = Vec::with_capacity(n_samples);
    let (mut sc, mut pc) = (0, 0);
    let (mut sc2, mut pc2) = (0, 0);
    let mut vib_rng = stream(seed, 10);
    let mut bump_cur = 0;
    for i in 0..n_samples {
        let mut shake_enu = Vector3::zeros();
        let j = if jitter > 0.0 {
            (jitter * jitter_rng.normal()).clamp(-0.3 * dt, 0.3 * dt)
        } else {
            0.0
        };
        let t = (i as f64 * dt + j).max(0.0);
        let si = segment_index(t, &mut sc);
        let act = si.map(|k| scenario.segments[k].activity);
        let pose = pose_at(t, &mut sc, &mut pc);
        // World-frame (walking frame) acceleration of the body.
        let mut a_w = Vector3::zeros(); // forward, left, up
        match act {
            Some(PhoneActivity::Walking { .. } | PhoneActivity::Running { .. }) => {
                if let Some(pi) = plan_index(t, &mut pc) {
                    let p = plan[pi];
                    let s0 = si.map_or(f64::INFINITY, |k| segment_times[k].0);
                    if p.t_s >= p.bout_start && p.bout_start <= s0 && t < p.t_s + p.next_dur_s {
                        let phase = ((t - p.t_s) / p.next_dur_s).clamp(0.0, 1.0);
                        let f = 1.0 / p.next_dur_s;
                        let om = std::f64::consts::TAU * f;
                        let av = 0.7 * p.length_m * p.length_m * om * om / (16.0 * leg_m)
                            * pattern_gain
                            * p.amp_gain;
                        let ph = std::f64::consts::TAU * phase;
                        a_w.z += av * ph.cos();
                        a_w.x += -0.4 * av * ph.sin();
                        let stride = std::f64::consts::PI * (p.k as f64 + phase);
                        a_w.y += 0.25 * av * stride.cos();
                        // Heel-strike transient.
                        let tau = 0.025;
                        let ti = t - p.t_s;
                        if ti < 8.0 * tau {
                            let imp = av * impact_gain * p.impact_gain * (ti / tau).min(1.0);
                            let osc = (std::f64::consts::TAU * 18.0 * ti).cos();
                            a_w.z += imp * (-ti / tau).exp() * osc;
                            a_w.x -= 0.3 * imp * (-ti / tau).exp() * osc;
                        }
                    }
                }
            }
            Some(PhoneActivity::Vehicle { .. } | PhoneActivity::Cycling { .. }) => {
                let k = si.unwrap_or(0);
                let v_now = speed_at(t, &mut sc2, &mut pc2);
                let (s0, s1) = segment_times[k];
                let vmax = scenario.segments[k].activity.speed();
                let h = 1e-3;
                let v_next = {
                    let ramp = cosramp((t + h - s0) / 5.0).min(cosramp((s1 - t - h) / 5.0));
                    vmax * (1.0 + veh_wobble.at(t + h)) * ramp
                };
                a_w.x += (v_next - v_now) / h;
                a_w.y += v_now * heading_rate_at(t);
                let vehicle = matches!(act, Some(PhoneActivity::Vehicle { .. }));
                let vib = if vehicle { 0.3 } else { 0.2 };
                a_w.z += vib * (std::f64::consts::TAU * 17.0 * t).sin()
                    + 0.5 * vib * (std::f64::consts::TAU * 23.3 * t).sin()
                    + vib * vib_rng.normal();
                if !vehicle {
                    a_w.z += 0.5 * (std::f64::consts::TAU * 2.6 * t).sin();
                }
                while bump_cur + 1 < bumps.len() && bumps[bump_cur].0 + 1.0 < t {
                    bump_cur += 1;
                }
                for &(tb, amp) in bumps.iter().skip(bump_cur).take(2) {
                    let x = t - tb;
                    if (0.0..1.0).contains(&x) {
                        a_w.z += amp * (-x / 0.12).exp() * (std::f64::consts::TAU * 8.0 * x).sin();
                    }
                }
            }
            Some(PhoneActivity::Shaking) => {
                let f = 4.5 * (1.0 + 0.3 * shake_freq.at(t));
                let om = std::f64::consts::TAU * f;
                let amp_m = 0.015 + 0.01 * (0.5 + 0.5 * (0.37 * t).sin());
                // Hand shake along a fixed body axis, expressed in ENU.
                shake_enu = pose.c_enu_b * shake_axis * (-amp_m * om * om * (om * t).sin());
            }
            Some(PhoneActivity::Standing) => {
                a_w.x += 0.03 * (std::f64::consts::TAU * 0.3 * t).sin();
                a_w.y += 0.03 * (std::f64::consts::TAU * 0.23 * t).sin();
            }
            None => {}
        }
        // Limb swing: pivot above the phone, radius r (forward/up plane).
        if swing_r > 0.0 {
            let (th, w, al) = pose.swing;
            a_w.x += swing_r * (al * th.cos() - w * w * th.sin());
            a_w.z += swing_r * (al * th.sin() + w * w * th.cos());
        }
        let heading = heading_at(t);
        let c_enu_w =
            Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2 - heading);
        let a_enu = c_enu_w * a_w + shake_enu + Vector3::new(0.0, 0.0, GRAVITY_MPS2);
        let f_b = pose.c_enu_b.inverse() * a_enu;
        let vehicle_mag = if matches!(act, Some(PhoneActivity::Vehicle { .. })) {
            vehicle_field
        } else {
            Vector3::zeros()
        };
        let mut s = (sc, pc);
        let p2 = pose_at(t + 1e-3, &mut s.0, &mut s.1);
        samples.push(finish_sample(
            t,
            f_b,
            &mut noise_rng,
            accel_bias,
            gyro_bias,
            &earth_enu,
            hard_iron,
            &mag_bursts,
            vehicle_mag,
            (pose.c_enu_b, p2.c_enu_b),
        ));
    }

    // GNSS.
    let mut fixes = Vec::new();
    if scenario.gnss {
        let mut g = stream(seed, 11);
        let (white, bg, tau) = (0.5, 1.5, 60.0);
        let phi: f64 = (-1.0f64 / tau).exp();
        let q = bg * (1.0 - phi * phi).sqrt();
        let (mut be, mut bn) = (bg * g.normal(), bg * g.normal());
        let mut t = 0.0;
        while t <= total_s {
            be = phi * be + q * g.normal();
            bn = phi * bn + q * g.normal();
            let (we, wn) = (white * g.normal(), white * g.normal());
            let acc = g.range(3.0, 5.0);
            let out = scenario.gnss_outages.iter().any(|&(s, e)| t >= s && t < e);
            if !out {
                let tr = truth_at_vec(&truth, t);
                fixes.push(PhoneFix {
                    t_s: t,
                    east_m: tr.0 + be + we,
                    north_m: tr.1 + bn + wn,
                    accuracy_m: (acc * 10.0).round() / 10.0,
                });
            }
            t += 1.0;
        }
    }

    SimulatedPhone {
        scenario: scenario.clone(),
        segment_times,
        samples,
        steps,
        truth,
        fixes,
        person_factor,
    }
}

fn truth_at_vec(truth: &[PhoneTruth], t: f64) -> (f64, f64) {
    let x = (t / TRUTH_DT_S).max(0.0);
    let i = (x.floor() as usize).min(truth.len().saturating_sub(1));
    let j = (i + 1).min(truth.len().saturating_sub(1));
    let f = (x - i as f64).clamp(0.0, 1.0);
    match (truth.get(i), truth.get(j)) {
        (Some(a), Some(b)) => (
            a.east_m + f * (b.east_m - a.east_m),
            a.north_m + f * (b.north_m - a.north_m),
        ),
        _ => (0.0, 0.0),
    }
}

#[allow(clippy::too_many_arguments)]
fn finish_sample(
    t: f64,
    f_b: Vector3<f64>,
    rng: &mut Rng,
    accel_bias: Vector3<f64>,
    gyro_bias: Vector3<f64>,
    earth_enu: &Vector3<f64>,
    hard_iron: Vector3<f64>,
    bursts: &[(f64, f64, Vector3<f64>)],
    vehicle_mag: Vector3<f64>,
    (c0, c1): (Rotation3<f64>, Rotation3<f64>),
) -> ImuSample {
    let mut nv = |s: f64| Vector3::new(rng.normal(), rng.normal(), rng.normal()) * s;
    let acc = f_b + accel_bias + nv(0.03);
    let rel = c0.inverse() * c1;
    let omega = rel.scaled_axis() / 1e-3;
    let gyro = omega + gyro_bias + nv(0.004);
    let mut m_enu = *earth_enu;
    for &(tb, w, v) in bursts {
        let x = (t - tb) / w;
        if x.abs() < 3.0 {
            m_enu += v * (-0.5 * x * x).exp();
        }
    }
    let mag = c0.inverse() * m_enu + vehicle_mag + hard_iron + nv(0.3);
    ImuSample {
        t_s: t,
        accel_mps2: [acc.x, acc.y, acc.z],
        gyro_radps: [gyro.x, gyro.y, gyro.z],
        mag_ut: [mag.x, mag.y, mag.z],
    }
}

/// The simulator's placements in the SDK's placement classes (front and back pocket
/// are one class).
impl From<PhonePlacement> for Placement {
    fn from(p: PhonePlacement) -> Self {
        match p {
            PhonePlacement::InHand => Placement::InHand,
            PhonePlacement::FrontPocket | PhonePlacement::BackPocket => Placement::Pocket,
            PhonePlacement::Bag => Placement::Bag,
            PhonePlacement::NeckPouch => Placement::NeckPouch,
            PhonePlacement::Armband => Placement::Armband,
            PhonePlacement::SwingingArm => Placement::SwingingArm,
        }
    }
}

impl From<&ImuSample> for stridekit_core::odometry::ImuSample {
    fn from(s: &ImuSample) -> Self {
        Self {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
            gyro_rads: s.gyro_radps,
            mag_ut: Some(s.mag_ut),
        }
    }
}
