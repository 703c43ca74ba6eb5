//! `stridekit soak`: hours of simulated 200 Hz IMU and 1 Hz GNSS through every engine,
//! each engine twice: `A` runs unsplit, `B` is replaced by `restore(B.snapshot())`
//! every simulated minute. After every push the outputs of A and B must be identical
//! bit for bit and finite; resident memory is read every simulated hour.
//!
//! The input is generated in segments (10-minute phone walks with seeds `seed + k`,
//! shifted by `k · 600 s`; foot-mounted walks chained in time), so memory does not
//! grow with the duration.

use std::time::Instant;

use stridekit_core::ahrs::{Ahrs, AhrsOutput, AhrsSettings, ImuSample};
use stridekit_core::foot::{FootConfig, FootEstimate, FootNavigator, FootSample};
use stridekit_core::geo::LocalFrame;
use stridekit_core::odometry::{OdometryConfig, OdometryEstimate, PhoneOdometry};
use stridekit_core::pace::{GnssFix, PaceConfig, PaceEstimate, PaceTracker};
use stridekit_core::pdr::{NavEstimate, NavigatorConfig, PhoneNavigator};
use stridekit_core::placement::{PlacementClassifier, PlacementEstimate};
use stridekit_core::stepdetect::{StepDetector, StepEvent};
use stridekit_core::steplength::{StepLengthConfig, StepLengthEstimator, StepLengthModel};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario};
use stridekit_sim::{simulate_foot, FootScenario};

/// Simulated seconds between two snapshot/restore cycles of the B copies.
const RESTORE_EVERY_S: f64 = 60.0;
/// Length of one phone segment, s.
const PHONE_SEGMENT_S: f64 = 600.0;
/// IMU rate of both simulators, Hz.
const RATE_HZ: f64 = 200.0;
/// RSS growth after the first hour still called flat, MiB.
const FLAT_MIB: f64 = 5.0;
/// Laps of the foot simulator's 20 m × 10 m loop per segment (about 9.4 minutes).
const FOOT_LAPS: u32 = 12;
/// Approximate duration of one foot lap, s.
const FOOT_LAP_S: f64 = 47.0;

/// What to run.
#[derive(Clone, Copy, Debug)]
pub struct SoakArgs {
    pub hours: f64,
    pub seed: u64,
}

/// Counts of one engine.
#[derive(Clone, Debug, Default)]
pub struct EngineStats {
    pub name: &'static str,
    /// Inputs pushed into each copy.
    pub pushes: u64,
    /// Pushes whose outputs differed between A and B (bits, or `Ok` vs `Err`).
    pub mismatches: u64,
    pub first_mismatch_t_s: Option<f64>,
    /// Pushes with a NaN or infinite number in an output of either copy.
    pub non_finite: u64,
    pub first_non_finite_t_s: Option<f64>,
    /// Inputs the engine refused (counted on A).
    pub rejected: u64,
    /// Snapshot/restore cycles of B, and those where B's snapshot differed from A's
    /// or the restore failed.
    pub restores: u64,
    pub snapshot_mismatches: u64,
    /// Size of A's final snapshot, bytes.
    pub snapshot_bytes: usize,
    /// Wall time spent in the engine (both copies, comparisons, restores), s.
    pub wall_s: f64,
}

/// Memory reading at the end of a simulated hour.
#[derive(Clone, Copy, Debug)]
pub struct HourMark {
    pub hour: f64,
    pub wall_s: f64,
    pub rss_kib: Option<u64>,
}

/// What a soak found.
#[derive(Clone, Debug, Default)]
pub struct SoakReport {
    pub hours: f64,
    pub seed: u64,
    pub engines: Vec<EngineStats>,
    pub marks: Vec<HourMark>,
    pub wall_s: f64,
    /// Wall time spent simulating the input, s.
    pub sim_s: f64,
    pub phone_imu_samples: u64,
    pub phone_fixes: u64,
    pub foot_samples: u64,
    pub peak_kib: Option<u64>,
    pub rss_end_kib: Option<u64>,
}

impl SoakReport {
    pub fn mismatches(&self) -> u64 {
        self.engines
            .iter()
            .map(|e| e.mismatches + e.snapshot_mismatches)
            .sum()
    }

    pub fn non_finite(&self) -> u64 {
        self.engines.iter().map(|e| e.non_finite).sum()
    }

    /// RSS after the first simulated hour, KiB (`None` for shorter soaks).
    pub fn rss_hour1_kib(&self) -> Option<u64> {
        self.marks
            .iter()
            .find(|m| m.hour >= 1.0 - 1e-9)
            .and_then(|m| m.rss_kib)
    }

    /// Highest RSS from hour 1 on (every later hourly reading and the end), KiB.
    pub fn rss_max_after_hour1_kib(&self) -> Option<u64> {
        let h1 = self.marks.iter().position(|m| m.hour >= 1.0 - 1e-9)?;
        self.marks[h1..]
            .iter()
            .filter_map(|m| m.rss_kib)
            .chain(self.rss_end_kib)
            .max()
    }

    /// RSS growth after hour 1 (highest later reading − hour 1), MiB.
    pub fn rss_growth_mib(&self) -> Option<f64> {
        match (self.rss_hour1_kib(), self.rss_max_after_hour1_kib()) {
            (Some(a), Some(b)) => Some((b as f64 - a as f64) / 1024.0),
            _ => None,
        }
    }

    pub fn memory_flat(&self) -> Option<bool> {
        self.rss_growth_mib().map(|g| g < FLAT_MIB)
    }

    pub fn ok(&self) -> bool {
        self.mismatches() == 0 && self.non_finite() == 0 && self.memory_flat() != Some(false)
    }

    /// The summary printed at the end.
    pub fn summary(&self) -> String {
        let mib =
            |k: Option<u64>| k.map_or("n/a".into(), |k| format!("{:.1} MiB", k as f64 / 1024.0));
        let mut s = String::new();
        s.push_str(&format!(
            "soak: {} simulated h, seed {}: wall time {:.1} s ({:.1} s simulating input)\n",
            self.hours, self.seed, self.wall_s, self.sim_s
        ));
        s.push_str(&format!(
            "input: {} phone IMU samples (200 Hz), {} GNSS fixes (1 Hz), {} foot IMU samples (200 Hz)\n",
            self.phone_imu_samples, self.phone_fixes, self.foot_samples
        ));
        s.push_str(&format!(
            "memory: peak (VmHWM) {}, RSS at hour 1 {}, highest after {}, at the end {}",
            mib(self.peak_kib),
            mib(self.rss_hour1_kib()),
            mib(self.rss_max_after_hour1_kib()),
            mib(self.rss_end_kib)
        ));
        match self.rss_growth_mib() {
            Some(g) => s.push_str(&format!(
                " (growth {g:+.2} MiB after hour 1: {})\n",
                if g < FLAT_MIB { "flat" } else { "NOT FLAT" }
            )),
            None => s.push_str(" (flatness needs at least 1 h)\n"),
        }
        s.push_str(
            "| engine | pushes per copy | rejected | restores | mismatches | snapshot mismatches | non-finite | snapshot bytes | wall s | µs per push per copy |\n",
        );
        s.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for e in &self.engines {
            s.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.2} |\n",
                e.name,
                e.pushes,
                e.rejected,
                e.restores,
                e.mismatches,
                e.snapshot_mismatches,
                e.non_finite,
                e.snapshot_bytes,
                e.wall_s,
                e.wall_s * 1e6 / (2 * e.pushes.max(1)) as f64
            ));
        }
        for e in &self.engines {
            if let Some(t) = e.first_mismatch_t_s {
                s.push_str(&format!("{}: first mismatch at t = {t:.3} s\n", e.name));
            }
            if let Some(t) = e.first_non_finite_t_s {
                s.push_str(&format!(
                    "{}: first non-finite output at t = {t:.3} s\n",
                    e.name
                ));
            }
        }
        s.push_str(&format!(
            "result: {} mismatches, {} non-finite outputs: {}\n",
            self.mismatches(),
            self.non_finite(),
            if self.ok() { "PASS" } else { "FAIL" }
        ));
        s
    }
}

// ------------------------------------------------------------------ comparison

/// Bit-exact comparison and finiteness of two outputs.
#[derive(Default)]
struct Cmp {
    differ: bool,
    non_finite: bool,
}

impl Cmp {
    fn f(&mut self, a: f64, b: f64) {
        self.differ |= a.to_bits() != b.to_bits();
        self.non_finite |= !a.is_finite() || !b.is_finite();
    }
    /// A number documented as possibly NaN: bits only.
    fn f_nan_ok(&mut self, a: f64, b: f64) {
        self.differ |= a.to_bits() != b.to_bits();
    }
    fn fs(&mut self, a: &[f64], b: &[f64]) {
        for (x, y) in a.iter().zip(b) {
            self.f(*x, *y);
        }
    }
    fn of(&mut self, a: Option<f64>, b: Option<f64>) {
        match (a, b) {
            (Some(x), Some(y)) => self.f(x, y),
            (None, None) => {}
            _ => self.differ = true,
        }
    }
    fn eq<T: PartialEq>(&mut self, a: &T, b: &T) {
        self.differ |= a != b;
    }
    fn opt<T>(&mut self, a: &Option<T>, b: &Option<T>, each: impl Fn(&mut Self, &T, &T)) {
        match (a, b) {
            (Some(x), Some(y)) => each(self, x, y),
            (None, None) => {}
            _ => self.differ = true,
        }
    }
}

fn cmp_pace(c: &mut Cmp, a: &PaceEstimate, b: &PaceEstimate) {
    c.f(a.t_s, b.t_s);
    c.f(a.speed_mps, b.speed_mps);
    c.of(a.pace_s_per_km, b.pace_s_per_km);
    c.of(a.speed_std_mps, b.speed_std_mps);
    c.of(a.cadence_spm, b.cadence_spm);
    c.of(a.step_length_m, b.step_length_m);
    c.f(a.gnss_weight, b.gnss_weight);
    c.f(a.distance_m, b.distance_m);
    c.eq(&a.source, &b.source);
}

fn cmp_ahrs(c: &mut Cmp, a: &AhrsOutput, b: &AhrsOutput) {
    c.f(a.t_s, b.t_s);
    c.eq(&a.frame, &b.frame);
    c.fs(&a.quaternion, &b.quaternion);
    c.fs(
        &[a.roll_rad, a.pitch_rad, a.yaw_rad, a.heading_rad],
        &[b.roll_rad, b.pitch_rad, b.yaw_rad, b.heading_rad],
    );
    c.fs(&a.gravity_body_mps2, &b.gravity_body_mps2);
    c.fs(&a.linear_accel_body_mps2, &b.linear_accel_body_mps2);
    c.fs(&a.linear_accel_earth_mps2, &b.linear_accel_earth_mps2);
    c.fs(&a.gyro_bias_rads, &b.gyro_bias_rads);
    c.eq(&a.flags, &b.flags);
}

fn cmp_step(c: &mut Cmp, a: &StepEvent, b: &StepEvent) {
    c.f(a.t_s, b.t_s);
    // NaN for the first step of a bout (documented).
    c.f_nan_ok(a.duration_s, b.duration_s);
    c.differ |= a.duration_s == f64::INFINITY || a.duration_s < 0.0;
    c.fs(
        &[a.accel_variance_m2ps4, a.accel_max_mps2, a.accel_min_mps2],
        &[b.accel_variance_m2ps4, b.accel_max_mps2, b.accel_min_mps2],
    );
    c.eq(&a.origin, &b.origin);
}

fn cmp_nav(c: &mut Cmp, a: &NavEstimate, b: &NavEstimate) {
    c.fs(
        &[a.t_s, a.east_m, a.north_m, a.position_std_m, a.distance_m],
        &[b.t_s, b.east_m, b.north_m, b.position_std_m, b.distance_m],
    );
    c.of(a.lat_deg, b.lat_deg);
    c.of(a.lon_deg, b.lon_deg);
    c.of(a.walking_azimuth_rad, b.walking_azimuth_rad);
    c.of(a.heading_offset_rad, b.heading_offset_rad);
    c.eq(&a.steps, &b.steps);
    c.of(a.step_length_m, b.step_length_m);
}

fn cmp_foot(c: &mut Cmp, a: &FootEstimate, b: &FootEstimate) {
    c.f(a.t_s, b.t_s);
    c.fs(&a.position_m, &b.position_m);
    c.fs(&a.velocity_mps, &b.velocity_mps);
    c.fs(&a.quaternion, &b.quaternion);
    c.fs(
        &[a.roll_rad, a.pitch_rad, a.yaw_rad, a.heading_rad],
        &[b.roll_rad, b.pitch_rad, b.yaw_rad, b.heading_rad],
    );
    c.fs(&a.position_std_m, &b.position_std_m);
    c.fs(&a.velocity_std_mps, &b.velocity_std_mps);
    c.fs(&a.tilt_std_rad, &b.tilt_std_rad);
    c.f(a.heading_std_rad, b.heading_std_rad);
    c.fs(&a.accel_bias_mps2, &b.accel_bias_mps2);
    c.fs(&a.gyro_bias_rads, &b.gyro_bias_rads);
    c.eq(&a.stance, &b.stance);
    c.eq(&a.strides, &b.strides);
    c.f(a.distance_m, b.distance_m);
    c.opt(&a.stride, &b.stride, |c, x, y| {
        c.fs(&x.values(), &y.values())
    });
    c.eq(&a.saturated, &b.saturated);
    c.eq(&a.gap, &b.gap);
}

fn cmp_placement(c: &mut Cmp, a: &PlacementEstimate, b: &PlacementEstimate) {
    c.f(a.t_s, b.t_s);
    c.eq(&a.placement, &b.placement);
    c.f(a.confidence, b.confidence);
    c.fs(&a.probabilities, &b.probabilities);
    c.fs(&a.window_probabilities, &b.window_probabilities);
    c.eq(&a.windows, &b.windows);
}

fn cmp_odometry(c: &mut Cmp, a: &OdometryEstimate, b: &OdometryEstimate) {
    c.f(a.t_s, b.t_s);
    c.fs(&a.velocity_mps, &b.velocity_mps);
    c.fs(&a.regressed_mps, &b.regressed_mps);
    c.fs(&a.position_m, &b.position_m);
    let (fa, fb) = (&a.features, &b.features);
    c.fs(
        &[fa.t_start_s, fa.t_end_s, fa.yaw_rad],
        &[fb.t_start_s, fb.t_end_s, fb.yaw_rad],
    );
    c.fs(&fa.scalars, &fb.scalars);
    for (x, y) in fa.vectors.iter().zip(&fb.vectors) {
        c.fs(x, y);
    }
    c.eq(&a.regressor_placement, &b.regressor_placement);
    c.eq(&a.detected_placement, &b.detected_placement);
    c.f(a.placement_confidence, b.placement_confidence);
}

// ------------------------------------------------------------------ engine pairs

/// Snapshot and restore of an engine.
trait Engine: Sized {
    fn snap(&self) -> Vec<u8>;
    fn from_snap(bytes: &[u8]) -> Result<Self, String>;
}

macro_rules! engine {
    ($($t:ty),*) => {$(
        impl Engine for $t {
            fn snap(&self) -> Vec<u8> {
                self.snapshot()
            }
            fn from_snap(bytes: &[u8]) -> Result<Self, String> {
                <$t>::restore(bytes).map_err(|e| e.to_string())
            }
        }
    )*};
}

engine!(
    PaceTracker,
    Ahrs,
    StepDetector,
    StepLengthEstimator,
    PhoneNavigator,
    FootNavigator,
    PlacementClassifier,
    PhoneOdometry
);

/// The unsplit copy `a` and the copy `b` restored from its own snapshot every minute.
struct Pair<E> {
    a: E,
    b: E,
    next_restore_t_s: f64,
    stats: EngineStats,
}

impl<E: Engine> Pair<E> {
    fn new(name: &'static str, make: impl Fn() -> E) -> Self {
        Self {
            a: make(),
            b: make(),
            next_restore_t_s: RESTORE_EVERY_S,
            stats: EngineStats {
                name,
                ..EngineStats::default()
            },
        }
    }

    /// Restores B when a minute boundary has been passed before the input at `t_s`.
    fn maybe_restore(&mut self, t_s: f64) {
        if t_s < self.next_restore_t_s {
            return;
        }
        while self.next_restore_t_s <= t_s {
            self.next_restore_t_s += RESTORE_EVERY_S;
        }
        self.stats.restores += 1;
        let snap = self.b.snap();
        if snap != self.a.snap() {
            self.stats.snapshot_mismatches += 1;
            self.stats.first_mismatch_t_s.get_or_insert(t_s);
        }
        match E::from_snap(&snap) {
            Ok(b) => self.b = b,
            Err(e) => {
                if self.stats.snapshot_mismatches < 3 {
                    eprintln!("{}: restore failed at t = {t_s}: {e}", self.stats.name);
                }
                self.stats.snapshot_mismatches += 1;
                self.stats.first_mismatch_t_s.get_or_insert(t_s);
            }
        }
    }

    /// Pushes one input (time `t_s`) into both copies with `push` and compares what
    /// `push` returned with `cmp`; returns A's output
    /// (`None` when A refused the input).
    fn step<O, Er: PartialEq + std::fmt::Display>(
        &mut self,
        t_s: f64,
        push: impl Fn(&mut E) -> Result<O, Er>,
        cmp: impl Fn(&mut Cmp, &O, &O),
    ) -> Option<O> {
        self.maybe_restore(t_s);
        let ra = push(&mut self.a);
        let rb = push(&mut self.b);
        self.stats.pushes += 1;
        let mut c = Cmp::default();
        match (&ra, &rb) {
            (Ok(x), Ok(y)) => cmp(&mut c, x, y),
            (Err(x), Err(y)) => {
                self.stats.rejected += 1;
                if self.stats.rejected <= 3 {
                    eprintln!("{}: input at t = {t_s} rejected: {x}", self.stats.name);
                }
                c.differ |= x != y;
            }
            (Err(x), Ok(_)) | (Ok(_), Err(x)) => {
                self.stats.rejected += 1;
                eprintln!(
                    "{}: only one copy rejected the input at t = {t_s}: {x}",
                    self.stats.name
                );
                c.differ = true;
            }
        }
        if c.differ {
            self.stats.mismatches += 1;
            self.stats.first_mismatch_t_s.get_or_insert(t_s);
        }
        if c.non_finite {
            self.stats.non_finite += 1;
            self.stats.first_non_finite_t_s.get_or_insert(t_s);
        }
        ra.ok()
    }

    /// Final check: the two copies end in the same state.
    fn finish(mut self) -> EngineStats {
        let (sa, sb) = (self.a.snap(), self.b.snap());
        if sa != sb {
            self.stats.snapshot_mismatches += 1;
        }
        self.stats.snapshot_bytes = sa.len();
        self.stats
    }
}

/// Options compared with a per-item function.
fn cmp_opt<T>(each: fn(&mut Cmp, &T, &T)) -> impl Fn(&mut Cmp, &Option<T>, &Option<T>) {
    move |c, a, b| c.opt(a, b, each)
}

fn cmp_unit(_: &mut Cmp, _: &(), _: &()) {}

// ------------------------------------------------------------------ input

/// One phone segment: IMU samples and fixes with soak times, merged in time order.
struct PhoneChunk {
    imu: Vec<ImuSample>,
    /// (fix as pushed, east, north, accuracy) with the segment's position offset.
    fixes: Vec<(GnssFix, f64, f64, f64)>,
    /// `true`: the next fix; `false`: the next IMU sample.
    order: Vec<bool>,
    /// Where the segment's walk ended (soak frame), m.
    end_en: (f64, f64),
}

fn phone_chunk(
    seed: u64,
    k: u64,
    t0: f64,
    duration_s: f64,
    offset: (f64, f64),
    frame: &LocalFrame,
) -> PhoneChunk {
    let placement = PhonePlacement::ALL[(k % PhonePlacement::ALL.len() as u64) as usize];
    let speed = 1.1 + 0.1 * (k % 5) as f64;
    let mut scenario = PhoneScenario::walk(seed.wrapping_add(k), placement, speed, duration_s);
    scenario.sample_rate_hz = RATE_HZ;
    let sim = simulate_phone(&scenario);
    let imu: Vec<ImuSample> = sim
        .samples
        .iter()
        .filter(|s| s.t_s < duration_s)
        .map(|s| ImuSample {
            t_s: t0 + s.t_s,
            gyro_rads: s.gyro_radps,
            accel_mps2: s.accel_mps2,
            mag_ut: Some(s.mag_ut),
        })
        .collect();
    let fixes: Vec<_> = sim
        .fixes
        .iter()
        .filter(|f| f.t_s < duration_s)
        .map(|f| {
            let (e, n) = (f.east_m + offset.0, f.north_m + offset.1);
            let (lat, lon) = frame.to_geodetic(e, n);
            let fix = GnssFix::new(t0 + f.t_s, lat, lon).with_accuracy(f.accuracy_m);
            (fix, e, n, f.accuracy_m)
        })
        .collect();
    // As SimulatedPhone::timeline: a fix before the IMU sample with the same time.
    let mut order = Vec::with_capacity(imu.len() + fixes.len());
    let mut fi = 0;
    for s in &imu {
        while fi < fixes.len() && fixes[fi].0.t_s <= s.t_s {
            order.push(true);
            fi += 1;
        }
        order.push(false);
    }
    order.extend(std::iter::repeat_n(true, fixes.len() - fi));
    let end = sim
        .truth
        .last()
        .map_or((0.0, 0.0), |t| (t.east_m, t.north_m));
    PhoneChunk {
        imu,
        fixes,
        order,
        end_en: (end.0 + offset.0, end.1 + offset.1),
    }
}

/// Resident set size and its high-water mark from /proc/self/status, KiB.
pub fn memory_kib() -> (Option<u64>, Option<u64>) {
    let Ok(s) = std::fs::read_to_string("/proc/self/status") else {
        return (None, None);
    };
    let field = |name: &str| {
        s.lines().find(|l| l.starts_with(name)).and_then(|l| {
            l[name.len()..]
                .trim()
                .trim_end_matches("kB")
                .trim()
                .parse()
                .ok()
        })
    };
    (field("VmRSS:"), field("VmHWM:"))
}

// ------------------------------------------------------------------ the soak

/// The eight engines of the soak, each as an A/B pair.
struct Engines {
    pace: Pair<PaceTracker>,
    ahrs: Pair<Ahrs>,
    steps: Pair<StepDetector>,
    length: Pair<StepLengthEstimator>,
    nav: Pair<PhoneNavigator>,
    placement: Pair<PlacementClassifier>,
    odometry: Pair<PhoneOdometry>,
    foot: Pair<FootNavigator>,
}

/// Where the chained foot-mounted walks stand.
#[derive(Default)]
struct FootClock {
    t_s: f64,
    walks: u64,
}

impl Engines {
    fn new() -> Self {
        Engines {
            pace: Pair::new("pace::PaceTracker", || {
                PaceTracker::new(PaceConfig::default()).expect("default pace config")
            }),
            ahrs: Pair::new("ahrs::Ahrs", || {
                Ahrs::new(AhrsSettings::default()).expect("default AHRS settings")
            }),
            steps: Pair::new("stepdetect::StepDetector", StepDetector::default),
            length: Pair::new("steplength::StepLengthEstimator", || {
                StepLengthEstimator::new(StepLengthModel::Linear, StepLengthConfig::default())
                    .expect("default step-length config")
            }),
            nav: Pair::new("pdr::PhoneNavigator", || {
                PhoneNavigator::new(NavigatorConfig::default()).expect("default navigator config")
            }),
            placement: Pair::new(
                "placement::PlacementClassifier",
                PlacementClassifier::shipped,
            ),
            odometry: Pair::new("odometry::PhoneOdometry", || {
                PhoneOdometry::shipped(OdometryConfig::default()).expect("shipped odometry model")
            }),
            foot: Pair::new("foot::FootNavigator", || {
                FootNavigator::new(FootConfig::default()).expect("default foot config")
            }),
        }
    }

    /// One phone segment through the seven phone engines, in the soak's fixed order.
    fn feed_phone(&mut self, chunk: &PhoneChunk) {
        self.feed_pace(chunk);
        self.feed_ahrs(chunk);
        let detected = self.feed_steps(chunk);
        self.feed_length(chunk, &detected);
        self.feed_nav(chunk);
        self.feed_placement(chunk);
        self.feed_odometry(chunk);
    }

    /// Pace: fixes and raw accelerometer; the estimate after every push.
    fn feed_pace(&mut self, chunk: &PhoneChunk) {
        let t = Instant::now();
        let (mut ii, mut fi) = (0, 0);
        for &is_fix in &chunk.order {
            if is_fix {
                let f = &chunk.fixes[fi].0;
                fi += 1;
                self.pace.step(f.t_s, |p| p.push_fix(f), cmp_pace);
            } else {
                let s = &chunk.imu[ii];
                ii += 1;
                self.pace.step(
                    s.t_s,
                    |p| {
                        p.push_accel(s.t_s, s.accel_mps2)
                            .map(|()| p.estimate().expect("a sample was accepted"))
                    },
                    cmp_pace,
                );
            }
        }
        self.pace.stats.wall_s += t.elapsed().as_secs_f64();
    }

    /// AHRS: every IMU sample with the magnetometer; flags and output.
    fn feed_ahrs(&mut self, chunk: &PhoneChunk) {
        let t = Instant::now();
        for s in &chunk.imu {
            self.ahrs.step(
                s.t_s,
                |a| {
                    a.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)
                        .map(|flags| (flags, a.output()))
                },
                |c, x: &(_, Option<AhrsOutput>), y| {
                    c.eq(&x.0, &y.0);
                    c.opt(&x.1, &y.1, cmp_ahrs);
                },
            );
        }
        self.ahrs.stats.wall_s += t.elapsed().as_secs_f64();
    }

    /// Step detector; returns A's steps, which feed the step-length estimator.
    fn feed_steps(&mut self, chunk: &PhoneChunk) -> Vec<StepEvent> {
        let t = Instant::now();
        let mut detected = Vec::new();
        for s in &chunk.imu {
            if let Some(Some(e)) = self.steps.step(
                s.t_s,
                |d| d.push_accel(s.t_s, s.accel_mps2),
                cmp_opt(cmp_step),
            ) {
                detected.push(e);
            }
        }
        self.steps.stats.wall_s += t.elapsed().as_secs_f64();
        detected
    }

    /// Step length: fixes (ENU) and detected steps in time order.
    fn feed_length(&mut self, chunk: &PhoneChunk, detected: &[StepEvent]) {
        let t = Instant::now();
        let mut fi = 0;
        for e in detected {
            while fi < chunk.fixes.len() && chunk.fixes[fi].0.t_s <= e.t_s {
                self.length_fix(chunk.fixes[fi]);
                fi += 1;
            }
            self.length
                .step(e.t_s, |l| l.push_step(e), |c, x: &f64, y| c.f(*x, *y));
        }
        for &fix in &chunk.fixes[fi..] {
            self.length_fix(fix);
        }
        self.length.stats.wall_s += t.elapsed().as_secs_f64();
    }

    fn length_fix(&mut self, (f, east, north, acc): (GnssFix, f64, f64, f64)) {
        self.length.step(
            f.t_s,
            |l| l.push_gnss_fix(f.t_s, east, north, Some(acc)),
            cmp_unit,
        );
    }

    /// Phone navigator: IMU and fixes; the estimate after every push.
    fn feed_nav(&mut self, chunk: &PhoneChunk) {
        let t = Instant::now();
        let (mut ii, mut fi) = (0, 0);
        for &is_fix in &chunk.order {
            if is_fix {
                let f = &chunk.fixes[fi].0;
                fi += 1;
                self.nav.step(f.t_s, |n| n.push_fix(f), cmp_nav);
            } else {
                let s = &chunk.imu[ii];
                ii += 1;
                self.nav.step(s.t_s, |n| n.push(s), cmp_opt(cmp_nav));
            }
        }
        self.nav.stats.wall_s += t.elapsed().as_secs_f64();
    }

    /// Placement classifier: accelerometer.
    fn feed_placement(&mut self, chunk: &PhoneChunk) {
        let t = Instant::now();
        for s in &chunk.imu {
            self.placement
                .step(s.t_s, |p| p.push(&s.into()), cmp_opt(cmp_placement));
        }
        self.placement.stats.wall_s += t.elapsed().as_secs_f64();
    }

    /// Learned odometry: IMU with magnetometer.
    fn feed_odometry(&mut self, chunk: &PhoneChunk) {
        let t = Instant::now();
        for s in &chunk.imu {
            let o = ImuSample {
                t_s: s.t_s,
                accel_mps2: s.accel_mps2,
                gyro_rads: s.gyro_rads,
                mag_ut: s.mag_ut,
            };
            self.odometry
                .step(s.t_s, |p| p.push(&o), cmp_opt(cmp_odometry));
        }
        self.odometry.stats.wall_s += t.elapsed().as_secs_f64();
    }

    /// Foot navigator: foot-mounted walks chained in time up to `until_s`.
    fn feed_foot(
        &mut self,
        clock: &mut FootClock,
        until_s: f64,
        args: &SoakArgs,
        report: &mut SoakReport,
    ) {
        let total_s = args.hours * 3600.0;
        while clock.t_s < until_s {
            let remaining = total_s - clock.t_s;
            let laps = ((remaining / FOOT_LAP_S).ceil() as u32).clamp(1, FOOT_LAPS);
            let mut sc = FootScenario::walk(args.seed.wrapping_add(1_000_000 + clock.walks), laps);
            sc.sample_rate_hz = RATE_HZ;
            sc.start_t_s = clock.t_s;
            clock.walks += 1;
            let t_sim = Instant::now();
            let sim = simulate_foot(&sc);
            report.sim_s += t_sim.elapsed().as_secs_f64();
            let t = Instant::now();
            let mut last = clock.t_s;
            for s in sim.samples.iter().filter(|s| s.t_s < total_s) {
                let s: FootSample = *s;
                self.foot.step(s.t_s, |n| n.push(&s), cmp_opt(cmp_foot));
                last = s.t_s;
                report.foot_samples += 1;
            }
            self.foot.stats.wall_s += t.elapsed().as_secs_f64();
            clock.t_s = if sim.samples.last().is_some_and(|s| s.t_s < total_s) {
                last + 1.0 / RATE_HZ
            } else {
                total_s
            };
        }
    }

    /// Mismatches, snapshot mismatches and non-finite outputs so far, all engines.
    fn bad(&self) -> u64 {
        self.all_stats()
            .iter()
            .map(|s| s.mismatches + s.snapshot_mismatches + s.non_finite)
            .sum()
    }

    fn all_stats(&self) -> [&EngineStats; 8] {
        [
            &self.pace.stats,
            &self.ahrs.stats,
            &self.steps.stats,
            &self.length.stats,
            &self.nav.stats,
            &self.placement.stats,
            &self.odometry.stats,
            &self.foot.stats,
        ]
    }

    fn finish(self) -> Vec<EngineStats> {
        vec![
            self.pace.finish(),
            self.ahrs.finish(),
            self.steps.finish(),
            self.length.finish(),
            self.nav.finish(),
            self.placement.finish(),
            self.odometry.finish(),
            self.foot.finish(),
        ]
    }
}

/// Runs the soak; `progress` gets one line per simulated hour.
pub fn run(args: &SoakArgs, mut progress: impl FnMut(&str)) -> SoakReport {
    let start = Instant::now();
    let total_s = args.hours * 3600.0;
    let frame = LocalFrame::new(47.0, 8.0, 0.0);
    let mut engines = Engines::new();
    let mut report = SoakReport {
        hours: args.hours,
        seed: args.seed,
        ..SoakReport::default()
    };
    let mut offset = (0.0, 0.0);
    let mut foot = FootClock::default();
    let mut next_hour = 1.0;
    let n_chunks = (total_s / PHONE_SEGMENT_S).ceil() as u64;
    for k in 0..n_chunks {
        let t0 = k as f64 * PHONE_SEGMENT_S;
        let dur = PHONE_SEGMENT_S.min(total_s - t0);
        let t_sim = Instant::now();
        let chunk = phone_chunk(args.seed, k, t0, dur, offset, &frame);
        report.sim_s += t_sim.elapsed().as_secs_f64();
        offset = chunk.end_en;
        report.phone_imu_samples += chunk.imu.len() as u64;
        report.phone_fixes += chunk.fixes.len() as u64;
        engines.feed_phone(&chunk);
        drop(chunk);
        let chunk_end = t0 + dur;
        engines.feed_foot(&mut foot, chunk_end, args, &mut report);
        let hours_done = chunk_end / 3600.0;
        if hours_done >= next_hour - 1e-9 || k + 1 == n_chunks {
            while next_hour <= hours_done + 1e-9 {
                next_hour += 1.0;
            }
            let line = mark_hour(&mut report, hours_done, start, engines.bad());
            progress(&line);
        }
    }
    report.engines = engines.finish();
    let (rss, hwm) = memory_kib();
    report.rss_end_kib = rss;
    report.peak_kib = hwm;
    report.wall_s = start.elapsed().as_secs_f64();
    report
}

/// Memory at a simulated hour (and at the end): recorded, and the progress line.
fn mark_hour(report: &mut SoakReport, hours_done: f64, start: Instant, bad: u64) -> String {
    let (rss, hwm) = memory_kib();
    let mark = HourMark {
        hour: hours_done,
        wall_s: start.elapsed().as_secs_f64(),
        rss_kib: rss,
    };
    report.marks.push(mark);
    let mib = |k: Option<u64>| k.map_or(f64::NAN, |k| k as f64 / 1024.0);
    format!(
        "simulated hour {:5.2}  wall {:7.1} s  RSS {:6.1} MiB  peak {:6.1} MiB  mismatches+non-finite {bad}",
        mark.hour,
        mark.wall_s,
        mib(rss),
        mib(hwm)
    )
}

/// `stridekit soak [--hours H] [--seed N]`: runs, prints, fails on any mismatch.
pub fn cmd(a: &SoakArgs) -> Result<(), String> {
    let a = *a;
    println!(
        "soak: {} simulated h of 200 Hz phone IMU + 1 Hz GNSS and 200 Hz foot IMU through 8 engines, B restored every {RESTORE_EVERY_S} s (seed {})",
        a.hours, a.seed
    );
    let report = run(&a, |line| println!("{line}"));
    print!("{}", report.summary());
    if report.ok() {
        Ok(())
    } else {
        Err(format!(
            "soak failed: {} mismatches, {} non-finite outputs, memory flat: {:?}",
            report.mismatches(),
            report.non_finite(),
            report.memory_flat()
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_soak_has_no_mismatch_and_no_nan() {
        let r = run(
            &SoakArgs {
                hours: 0.05,
                seed: 3,
            },
            |l| eprintln!("{l}"),
        );
        eprint!("{}", r.summary());
        assert_eq!(r.engines.len(), 8);
        for e in &r.engines {
            assert!(e.pushes > 0, "{}: nothing pushed", e.name);
            assert!(e.restores >= 2, "{}: {} restores", e.name, e.restores);
            assert_eq!(e.mismatches + e.snapshot_mismatches, 0, "{e:?}");
            assert_eq!(e.non_finite, 0, "{e:?}");
        }
        // 180 s at 200 Hz.
        assert_eq!(r.phone_imu_samples, 36_000);
        assert!(r.phone_fixes >= 179, "{}", r.phone_fixes);
        assert!(r.foot_samples >= 35_000, "{}", r.foot_samples);
        assert!(r.ok());
    }

    #[test]
    fn a_diverged_copy_is_caught() {
        // Bits, not values: -0.0 == 0.0 but differs.
        let mut c = Cmp::default();
        c.f(0.0, -0.0);
        assert!(c.differ && !c.non_finite);
        let mut c = Cmp::default();
        c.of(Some(1.0), Some(f64::NAN));
        assert!(c.differ && c.non_finite);
        // A B copy that lost its state is found by the output or snapshot checks.
        let mut p = Pair::new("steps", StepDetector::default);
        let sim = simulate_phone(&PhoneScenario::walk(2, PhonePlacement::InHand, 1.3, 90.0));
        for (i, s) in sim.samples.iter().enumerate() {
            if i == 3000 {
                p.b = StepDetector::default();
            }
            p.step(
                s.t_s,
                |d| d.push_accel(s.t_s, s.accel_mps2),
                cmp_opt(cmp_step),
            );
        }
        let stats = p.finish();
        assert!(
            stats.mismatches + stats.snapshot_mismatches > 0,
            "{stats:?}"
        );
        assert!(stats.first_mismatch_t_s.is_some_and(|t| t >= 30.0));
    }
}
