//! One wrapper per engine so three kinds of target share one driver:
//!
//! - `sequence`: a stream of samples decoded from the input (see [`crate::bytes`]),
//!   with snapshot → restore swaps at points the input picks. Asserts no panic, every
//!   estimate finite or absent, and snapshot → restore → snapshot identical.
//! - `restore`: the input as a snapshot; if accepted, the engine's estimate is finite,
//!   its own snapshot round-trips and it takes further samples.
//! - `restore_sealed`: the input as a snapshot body behind a valid header and CRC, so
//!   mutations reach the field decoding.

use stridekit_core::ahrs::{Ahrs, AhrsSettings, ImuSample};
use stridekit_core::foot::{FootConfig, FootNavigator, FootSample};
use stridekit_core::odometry::{OdometryConfig, PhoneOdometry};
use stridekit_core::pace::{GnssFix, PaceConfig, PaceEstimate, PaceTracker, StepSample};
use stridekit_core::pdr::{NavEstimate, NavigatorConfig, PhoneNavigator};
use stridekit_core::placement::{AccelSample, PlacementClassifier};
use stridekit_core::snapshot::crc32;
use stridekit_core::stepdetect::{StepDetector, StepEvent, StepOrigin};
use stridekit_core::steplength::{StepLengthConfig, StepLengthEstimator, StepLengthModel};

use crate::bytes::Bytes;

/// Samples decoded per input at most (keeps every execution short).
const MAX_SAMPLES: usize = 4_000;
/// Byte that asks for a snapshot → restore swap instead of a sample.
const SWAP: u8 = 0xFF;

const GRAVITY: [f64; 3] = [0.0, 0.0, 9.81];
const FIELD_UT: [f64; 3] = [20.0, 0.0, -40.0];

pub trait Engine: Sized {
    /// A default-configured engine at the start of a session.
    fn fresh() -> Self;
    /// Decode one sample from `b` and push it; check what the push returned.
    fn feed(&mut self, b: &mut Bytes);
    /// The current estimate is finite or absent.
    fn check(&self);
    fn snapshot(&self) -> Vec<u8>;
    fn restore(bytes: &[u8]) -> Result<Self, String>;
}

fn finite(v: f64, what: &str) {
    assert!(v.is_finite(), "{what} is not finite: {v}");
}

fn finite_opt(v: Option<f64>, what: &str) {
    if let Some(v) = v {
        finite(v, what);
    }
}

/// snapshot → restore → snapshot gives the same bytes; returns the restored engine.
fn round_trip<E: Engine>(e: &E) -> E {
    let snap = e.snapshot();
    let back = E::restore(&snap).unwrap_or_else(|err| panic!("own snapshot refused: {err}"));
    assert!(
        back.snapshot() == snap,
        "snapshot → restore → snapshot differs"
    );
    back
}

pub fn sequence<E: Engine>(data: &[u8]) {
    let mut e = E::fresh();
    let mut b = Bytes::new(data);
    let mut n = 0;
    while !b.is_empty() && n < MAX_SAMPLES {
        if b.take_if(SWAP) {
            e = round_trip(&e);
        }
        e.feed(&mut b);
        e.check();
        n += 1;
    }
    round_trip(&e);
}

pub fn restore<E: Engine>(data: &[u8]) {
    if let Ok(mut e) = E::restore(data) {
        e.check();
        let mut e2 = round_trip(&e);
        // Nominal samples (an exhausted cursor) must still be taken without harm.
        let mut b = Bytes::new(&[]);
        for _ in 0..50 {
            e.feed(&mut b);
            e.check();
        }
        round_trip(&e);
        e2.feed(&mut Bytes::new(&[]));
        e2.check();
    }
}

/// `body` behind the header of `E`'s own snapshots (magic, kind, version, length) and
/// a valid CRC.
pub fn sealed<E: Engine>(body: &[u8]) -> Vec<u8> {
    let own = E::fresh().snapshot();
    let mut out = own[..7].to_vec();
    let total = (11 + body.len() + 4) as u32;
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(body);
    let crc = crc32(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

pub fn restore_sealed<E: Engine>(body: &[u8]) {
    restore::<E>(&sealed::<E>(body));
}

/// A snapshot body of `E` after a plausible random session (a fuzz seed).
pub fn seed_body<E: Engine>(seed: u64, samples: usize) -> Vec<u8> {
    let bytes = plausible_bytes(seed, samples * 40);
    let mut e = E::fresh();
    let mut b = Bytes::new(&bytes);
    for _ in 0..samples {
        e.feed(&mut b);
    }
    let snap = e.snapshot();
    snap[11..snap.len() - 4].to_vec()
}

/// Bytes that decode to plausible values and regular times only.
pub fn plausible_bytes(seed: u64, n: usize) -> Vec<u8> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 32) % 200) as u8
        })
        .collect()
}

// ------------------------------------------------------------------ pace

pub struct Pace {
    e: PaceTracker,
    t_fix: f64,
    t_steps: f64,
    t_accel: f64,
    steps: u64,
}

fn check_pace(p: &PaceEstimate) {
    finite(p.t_s, "pace t_s");
    finite(p.speed_mps, "speed");
    finite(p.distance_m, "distance");
    finite(p.gnss_weight, "gnss weight");
    finite_opt(p.pace_s_per_km, "pace");
    finite_opt(p.speed_std_mps, "speed std");
    finite_opt(p.cadence_spm, "cadence");
    finite_opt(p.step_length_m, "step length");
}

fn fix(b: &mut Bytes, t: f64) -> GnssFix {
    let mut f = GnssFix::new(t, 47.0 + b.value(0.0, 1e-4), 8.0 + b.value(0.0, 1e-4));
    if b.bool() {
        f.horizontal_accuracy_m = Some(b.value(5.0, 2.0));
    }
    if b.bool() {
        f.speed_mps = Some(b.value(3.0, 1.0));
        f.speed_accuracy_mps = Some(b.value(0.5, 0.2));
    }
    if b.bool() {
        f.alt_m = Some(b.value(400.0, 10.0));
    }
    f
}

impl Engine for Pace {
    fn fresh() -> Self {
        Self {
            e: PaceTracker::new(PaceConfig::default()).expect("default config"),
            t_fix: 0.0,
            t_steps: 0.0,
            t_accel: 0.0,
            steps: 0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        match b.u8() % 8 {
            0..=2 => {
                let t = b.time(&mut self.t_fix, 1.0);
                if let Ok(est) = self.e.push_fix(&fix(b, t)) {
                    check_pace(&est);
                }
            }
            3 => {
                let t = b.time(&mut self.t_steps, 1.0);
                self.steps = match b.u8() {
                    255 => u64::from(b.u8()) << 40,
                    254 => 0,
                    k => self.steps + u64::from(k % 6),
                };
                let _ = self.e.push_steps(&StepSample::Count {
                    t_s: t,
                    steps: self.steps,
                });
            }
            4 => {
                let t = b.time(&mut self.t_steps, 0.35);
                let _ = self.e.push_steps(&StepSample::Event { t_s: t });
            }
            5 => {
                let t = b.time(&mut self.t_steps, 1.0);
                let spm = b.value(170.0, 20.0);
                let _ = self.e.push_steps(&StepSample::Cadence {
                    t_s: t,
                    steps_per_min: spm,
                });
            }
            _ => {
                let t = b.time(&mut self.t_accel, 0.01);
                let _ = self.e.push_accel(t, b.vec3(GRAVITY, 3.0));
            }
        }
    }
    fn check(&self) {
        if let Some(e) = self.e.estimate() {
            check_pace(&e);
        }
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        PaceTracker::restore(bytes)
            .map(|e| Self { e, ..Self::fresh() })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ AHRS

pub struct Orientation {
    e: Ahrs,
    t: f64,
}

pub(crate) fn imu(b: &mut Bytes, t: f64) -> ImuSample {
    ImuSample {
        t_s: t,
        gyro_rads: b.vec3([0.0; 3], 0.5),
        accel_mps2: b.vec3(GRAVITY, 1.5),
        mag_ut: if b.bool() {
            Some(b.vec3(FIELD_UT, 5.0))
        } else {
            None
        },
    }
}

impl Engine for Orientation {
    fn fresh() -> Self {
        Self {
            e: Ahrs::new(AhrsSettings::default()).expect("default settings"),
            t: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        let t = b.time(&mut self.t, 0.01);
        let s = imu(b, t);
        let _ = self.e.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut);
    }
    fn check(&self) {
        if let Some(q) = self.e.quaternion() {
            let n: f64 = q.iter().map(|v| v * v).sum();
            assert!((n - 1.0).abs() < 1e-6, "quaternion not unit: {q:?}");
        }
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        Ahrs::restore(bytes)
            .map(|e| Self { e, t: 0.0 })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ steps

pub struct Steps {
    e: StepDetector,
    t: f64,
}

fn check_event(ev: &StepEvent) {
    finite(ev.t_s, "step time");
    // NaN by design for the first step of a bout (no previous step to time it from).
    assert!(
        !ev.duration_s.is_infinite(),
        "step duration {}",
        ev.duration_s
    );
    finite(ev.accel_variance_m2ps4, "step variance");
}

impl Engine for Steps {
    fn fresh() -> Self {
        Self {
            e: StepDetector::default(),
            t: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        let t = b.time(&mut self.t, 0.01);
        if let Ok(Some(ev)) = self.e.push_accel(t, b.vec3(GRAVITY, 3.0)) {
            check_event(&ev);
        }
    }
    fn check(&self) {}
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        StepDetector::restore(bytes)
            .map(|e| Self { e, t: 0.0 })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ step length

pub struct StepLength {
    e: StepLengthEstimator,
    t_step: f64,
    t_fix: f64,
    east_m: f64,
}

impl Engine for StepLength {
    fn fresh() -> Self {
        Self {
            e: StepLengthEstimator::new(StepLengthModel::Linear, StepLengthConfig::default())
                .expect("default config"),
            t_step: 0.0,
            t_fix: 0.0,
            east_m: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        if b.u8() % 3 == 0 {
            let t = b.time(&mut self.t_fix, 1.0);
            self.east_m += b.value(1.3, 0.3);
            let acc = b.bool().then(|| b.value(5.0, 2.0));
            let north = b.value(0.0, 0.5);
            let _ = self.e.push_gnss_fix(t, self.east_m, north, acc);
        } else {
            let t = b.time(&mut self.t_step, 0.55);
            let ev = StepEvent {
                t_s: t,
                duration_s: b.value(0.55, 0.1),
                accel_variance_m2ps4: b.value(4.0, 2.0),
                accel_max_mps2: b.value(14.0, 3.0),
                accel_min_mps2: b.value(6.0, 2.0),
                vertical_displacement_m: b.value(0.07, 0.03),
                origin: StepOrigin::Detected,
            };
            if let Ok(l) = self.e.push_step(&ev) {
                assert!(l.is_finite() && l >= 0.0, "step length {l}");
            }
        }
    }
    fn check(&self) {}
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        StepLengthEstimator::restore(bytes)
            .map(|e| Self { e, ..Self::fresh() })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ PDR

pub struct Navigator {
    e: PhoneNavigator,
    t: f64,
    t_fix: f64,
}

fn check_nav(n: &NavEstimate) {
    finite(n.t_s, "nav t_s");
    finite(n.east_m, "east");
    finite(n.north_m, "north");
    finite(n.position_std_m, "position std");
    finite(n.distance_m, "distance");
    finite_opt(n.lat_deg, "lat");
    finite_opt(n.lon_deg, "lon");
    finite_opt(n.walking_azimuth_rad, "azimuth");
    finite_opt(n.heading_offset_rad, "heading offset");
}

impl Engine for Navigator {
    fn fresh() -> Self {
        Self {
            e: PhoneNavigator::new(NavigatorConfig::default()).expect("default config"),
            t: 0.0,
            t_fix: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        match b.u8() {
            0..=4 => {
                let t = b.time(&mut self.t_fix, 1.0);
                if let Ok(est) = self.e.push_fix(&fix(b, t)) {
                    check_nav(&est);
                }
            }
            5..=9 => {
                let t = b.time(&mut self.t, 0.01);
                let s = imu(b, t);
                let q = [
                    b.value(1.0, 0.1),
                    b.value(0.0, 0.1),
                    b.value(0.0, 0.1),
                    b.value(0.0, 0.1),
                ];
                let _ = self.e.push_imu_with_attitude(&s, q);
            }
            _ => {
                let t = b.time(&mut self.t, 0.01);
                let _ = self.e.push_imu(&imu(b, t));
            }
        }
    }
    fn check(&self) {
        if let Some(est) = self.e.estimate() {
            check_nav(&est);
        }
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        PhoneNavigator::restore(bytes)
            .map(|e| Self {
                e,
                t: 0.0,
                t_fix: 0.0,
            })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ foot

pub struct Foot {
    e: FootNavigator,
    t: f64,
}

impl Engine for Foot {
    fn fresh() -> Self {
        Self {
            // A small accelerometer alignment: the rotation at the door runs on every
            // sample (zero, the default, skips it); a gyroscope range, so the clipping
            // repair runs on fuzzed rates (none, the default, skips it).
            e: FootNavigator::new(FootConfig {
                accel_alignment_rad: [0.01, 0.02, -0.015],
                gyro_range_rads: Some(8.0),
                ..FootConfig::default()
            })
            .expect("valid config"),
            t: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        let t = b.time(&mut self.t, 0.005);
        let s = FootSample {
            t_s: t,
            accel_mps2: b.vec3(GRAVITY, 5.0),
            gyro_rads: b.vec3([0.0; 3], 2.0),
        };
        if let Ok(Some(est)) = self.e.push(&s) {
            assert!(est.is_finite(), "foot estimate {est:?}");
        }
    }
    fn check(&self) {
        if let Some(est) = self.e.estimate() {
            assert!(est.is_finite(), "foot estimate {est:?}");
        }
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        FootNavigator::restore(bytes)
            .map(|e| Self { e, t: 0.0 })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ placement

pub struct Placement {
    e: PlacementClassifier,
    t: f64,
}

impl Engine for Placement {
    fn fresh() -> Self {
        Self {
            e: PlacementClassifier::shipped(),
            t: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        let s = AccelSample {
            t_s: b.time(&mut self.t, 0.01),
            accel_mps2: b.vec3(GRAVITY, 3.0),
        };
        if let Ok(Some(est)) = self.e.push(&s) {
            finite(est.confidence, "placement confidence");
            assert!(est.probabilities.iter().all(|p| p.is_finite()));
        }
    }
    fn check(&self) {
        if let Some(est) = self.e.estimate() {
            assert!(est.probabilities.iter().all(|p| p.is_finite()));
        }
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        PlacementClassifier::restore(bytes)
            .map(|e| Self { e, t: 0.0 })
            .map_err(|e| e.to_string())
    }
}

// ------------------------------------------------------------------ odometry

pub struct Odometry {
    e: PhoneOdometry,
    t: f64,
}

impl Engine for Odometry {
    fn fresh() -> Self {
        Self {
            e: PhoneOdometry::shipped(OdometryConfig::default()).expect("shipped model"),
            t: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        let t = b.time(&mut self.t, 0.01);
        let s = imu(b, t);
        let s = ImuSample {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
            gyro_rads: s.gyro_rads,
            mag_ut: s.mag_ut,
        };
        if let Ok(Some(est)) = self.e.push(&s) {
            assert!(est.is_finite(), "odometry estimate {est:?}");
        }
    }
    fn check(&self) {
        if let Some(est) = self.e.estimate() {
            assert!(est.is_finite(), "odometry estimate {est:?}");
        }
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        PhoneOdometry::restore(bytes)
            .map(|e| Self { e, t: 0.0 })
            .map_err(|e| e.to_string())
    }
}
