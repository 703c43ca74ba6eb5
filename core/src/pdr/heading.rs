//! Walking direction from a phone carried anywhere.
//!
//! The walking direction is split into two parts that change at very different rates:
//!
//! 1. **Where the phone points** (its attitude): the AHRS gives it at every sample,
//!    tilt from the accelerometer, yaw integrated from the gyroscope. The gyro-integrated
//!    yaw drifts (gyroscope bias about the vertical), so the azimuth of the AHRS frame
//!    itself carries a slowly varying correction `μ` (AHRS azimuth − true azimuth):
//!    - with a magnetometer, `μ` is tracked from the tilt-compensated magnetic field
//!      (the AHRS tilt, the raw field minus an online hard-iron estimate) by a
//!      second-order loop (offset and drift rate), with samples whose field strength
//!      or dip departs from the learned ones rejected. Its time constants balance the
//!      gyroscope's drift against the field's disturbances: 120 s and 480 s for a
//!      gyroscope whose bias the platform removes (Android `TYPE_GYROSCOPE`, iOS
//!      device motion: a residual of ~0.01°/s), 10 s and 40 s for a raw one
//!      (~0.5°/s). A loop of τ lags a drift b by b·τ and passes a disturbance of
//!      spread σ and correlation time T by about σ·√(T / 2τ); indoors (σ ≈ 15°,
//!      T ≈ 5 s: steel passed at walking speed) the sum is least at τ ≈ 140 s for the
//!      first and ≈ 10 s for the second;
//!    - without one, `μ` only follows its learned drift rate; GNSS teaches that rate
//!      (the gyroscope bias about the vertical) while fixes are good.
//! 2. **How the phone is carried**: the walking direction expressed in the phone's
//!    body frame, a unit vector `forward_body` (the heading offset of the phone, in 3-D:
//!    it stays meaningful for an upright phone in a pocket, whose yaw angle is not, and
//!    a limb swing, a rotation about the body's lateral axis, leaves its azimuth
//!    unchanged). It is
//!    - *set* by a personal calibration when there is one ([`WalkingDirection::set_carrying`]),
//!      else, for a phone held in front to be read (screen up, portrait), *the top
//!      edge*: the walker goes where it points (`top_edge_if_read`),
//!      else *initialised* from the body's motion: walking makes the horizontal acceleration
//!      oscillate mostly along the walking direction, so the principal axis of the
//!      earth-frame horizontal linear acceleration over a stride (2×2 covariance) gives
//!      the axis; the forward/backward sign comes from the gait phase (inverted
//!      pendulum: forward acceleration is anti-correlated with vertical velocity when
//!      walking; correlated for a spring-mass running gait, cadence above
//!      `RUNNING_STEP_HZ`), or, after a carrying change, from continuity with the last
//!      walking direction; then the stride axes are averaged into it (gain 1/n down
//!      to 0.1: the carrying is constant until it changes);
//!    - *calibrated* by GNSS: the angle between the GNSS displacement and the
//!      dead-reckoned displacement over the same stretch (≥ 15 m) rotates it (and
//!      resolves a wrong sign once);
//!    - *held* once calibrated, through GNSS outages: the stride axis is only used
//!      again after a carrying change, detected as a lasting jump (> 0.6 rad) of the
//!      gravity direction in the body frame.
//!
//! Walking azimuth = azimuth of `q · forward_body` − `μ`, averaged over each step.
//! Steps reach the walking direction late (the detector confirms a bout before it
//! releases its steps, seconds after the first of them), so the attitude is kept as a
//! short history (16 s of 0.2 s slots: Σ of the east and north rows of the body → ENU
//! rotation, and μ): [`WalkingDirection::azimuth_between`] gives the walking azimuth
//! over any recent step span for the current carrying estimate, so a step gets the
//! direction of its own time, and the steps released before the carrying was known
//! (the first stride of a walk) can still be placed.
//!
//! The attitude comes from outside this module (the navigator's AHRS, or an external
//! orientation through `PhoneNavigator::push_imu_with_attitude`): a better orientation
//! filter drops in without changes here.
//!
//! Azimuths are radians clockwise from north in (−π, π]; east = sin, north = cos.

use std::f64::consts::PI;

use nalgebra::{Matrix4, Quaternion, UnitQuaternion, Vector3, Vector4};

use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Step frequency above which the gait is taken as running (spring-mass), Hz.
pub const RUNNING_STEP_HZ: f64 = 2.4;
/// Held to be read: body-frame up (low-passed) with its screen-normal component at
/// least this (screen within 60° of facing up) ...
const READ_POSE_UP_Z: f64 = 0.5;
/// ... and its top-edge component at least this: the top edge at most ~17° below the
/// bottom edge. A reader tilts the screen towards the face, so the edge away from them
/// is the higher one; a phone held upside down (top edge towards the walker) and
/// tilted like that has its top edge lower, and is not taken ...
const READ_POSE_UP_Y: f64 = -0.3;
/// ... and the stride axis within ~60° of the phone's long side (portrait).
const READ_POSE_AXIS_Y: f64 = 0.5;
/// Gain of the pull towards a stride's axis at full quality (per stride), before
/// GNSS calibrated the carrying.
const AXIS_GAIN: f64 = 0.3;
/// Least gain of the stride-axis average (≈ 10 strides of memory).
const AXIS_MIN_GAIN: f64 = 0.1;
/// Strides whose along/across variance ratio is below this carry no direction.
const MIN_AXIS_RATIO: f64 = 1.5;
/// Magnetic yaw loop: offset and rate time constants, s, for a raw gyroscope ...
const MAG_TAU_RAW_GYRO_S: f64 = 10.0;
const MAG_RATE_TAU_RAW_GYRO_S: f64 = 40.0;
/// ... and for one whose bias the platform removes (see the module docs).
const MAG_TAU_CALIBRATED_GYRO_S: f64 = 120.0;
const MAG_RATE_TAU_CALIBRATED_GYRO_S: f64 = 480.0;
/// A field sample is rejected when its strength or dip departs from the learned ones
/// by more than this (µT, rad).
const MAG_GATE_UT: f64 = 6.0;
const MAG_GATE_DIP_RAD: f64 = 0.14;
/// Time constant of the learned field strength and dip, s.
const MAG_REF_TAU_S: f64 = 60.0;
/// Hard-iron sphere fit: forgetting time constant, s, and ridge towards zero, µT²
/// (an offset along a direction the field never swept stays near zero).
const HARD_IRON_TAU_S: f64 = 900.0;
const HARD_IRON_RIDGE_UT2: f64 = 4.0;
/// Samples of the fit before its solution is used.
const HARD_IRON_MIN_N: f64 = 1000.0;
/// Carrying change: body-frame gravity direction low-passed fast and slow, s; a
/// difference above this angle, rad, is a new carrying.
const UP_FAST_TAU_S: f64 = 2.0;
const UP_SLOW_TAU_S: f64 = 20.0;
const CARRY_CHANGE_RAD: f64 = 0.6;
/// Time constant of the mean earth-frame specific force that corrects the AHRS tilt, s.
const TILT_TAU_S: f64 = 3.0;
/// Standard gravity, m/s².
const GRAVITY_MPS2: f64 = 9.80665;
/// Attitude history for step azimuths: slot length, s, and slots kept (16 s: longer
/// than the step detector's longest release delay, a bout confirmed after its
/// buffered candidates).
const SLOT_S: f64 = 0.2;
pub const HISTORY_SLOTS: usize = 80;
/// Calibration from GNSS stretches (a Kalman filter on the azimuth error and, without
/// a magnetometer, its drift rate): prior σ of the carrying azimuth, rad, and of the
/// drift rate, rad/s; random walks of both, rad²/s and rad²/s³.
const CAL_OFFSET_SIGMA0_RAD: f64 = 0.5;
const CAL_RATE_SIGMA0_RADS: f64 = 0.02;
const CAL_OFFSET_Q: f64 = 1e-4;
const CAL_RATE_Q: f64 = 1e-11;

const CAL_P0: [f64; 3] = [
    CAL_OFFSET_SIGMA0_RAD * CAL_OFFSET_SIGMA0_RAD,
    0.0,
    CAL_RATE_SIGMA0_RADS * CAL_RATE_SIGMA0_RADS,
];

/// Wrap an angle to (−π, π]: one add for the sum or difference of two wrapped
/// angles, the general remainder otherwise.
#[inline]
pub fn wrap(a: f64) -> f64 {
    if a > -PI && a <= PI {
        a
    } else if a > PI && a <= 3.0 * PI {
        a - 2.0 * PI
    } else if a <= -PI && a > -3.0 * PI {
        a + 2.0 * PI
    } else {
        wrap_any(a)
    }
}

fn wrap_any(a: f64) -> f64 {
    let mut x = (a + PI).rem_euclid(2.0 * PI) - PI;
    if x <= -PI {
        x += 2.0 * PI;
    }
    x
}

/// Accumulated horizontal acceleration statistics over one stride.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct StrideStats {
    n: f64,
    se: f64,
    sn: f64,
    see: f64,
    snn: f64,
    sen: f64,
    /// Vertical velocity (integrated vertical acceleration) and its products with the
    /// horizontal components, for the forward/backward cue.
    svz: f64,
    sevz: f64,
    snvz: f64,
}

impl StrideStats {
    fn add(&mut self, e: f64, n: f64, vz: f64) {
        self.n += 1.0;
        self.se += e;
        self.sn += n;
        self.see += e * e;
        self.snn += n * n;
        self.sen += e * n;
        self.svz += vz;
        self.sevz += e * vz;
        self.snvz += n * vz;
    }

    /// Principal axis azimuth (mod π) and the along/across variance ratio.
    fn axis(&self) -> Option<(f64, f64)> {
        if self.n < 8.0 {
            return None;
        }
        let (me, mn) = (self.se / self.n, self.sn / self.n);
        let cee = self.see / self.n - me * me;
        let cnn = self.snn / self.n - mn * mn;
        let cen = self.sen / self.n - me * mn;
        let tr = cee + cnn;
        let det = cee * cnn - cen * cen;
        let disc = (0.25 * tr * tr - det).max(0.0).sqrt();
        let (l1, l2) = (0.5 * tr + disc, (0.5 * tr - disc).max(1e-12));
        // Eigenvector of l1: angle of (e, n) measured as an azimuth (from north, cw).
        let az = 0.5 * (2.0 * cen).atan2(cnn - cee);
        Some((az, l1 / l2))
    }

    /// Covariance between acceleration along azimuth `az` and vertical velocity.
    fn forward_vz_cov(&self, az: f64) -> f64 {
        let (s, c) = az.sin_cos();
        let n = self.n.max(1.0);
        let a_mean = (s * self.se + c * self.sn) / n;
        let vz_mean = self.svz / n;
        (s * self.sevz + c * self.snvz) / n - a_mean * vz_mean
    }

    fn to_array(self) -> [f64; 9] {
        [
            self.n, self.se, self.sn, self.see, self.snn, self.sen, self.svz, self.sevz, self.snvz,
        ]
    }

    fn from_array(v: &[f64]) -> Self {
        Self {
            n: v[0],
            se: v[1],
            sn: v[2],
            see: v[3],
            snn: v[4],
            sen: v[5],
            svz: v[6],
            sevz: v[7],
            snvz: v[8],
        }
    }
}

/// Online hard-iron (constant field offset in the body frame) estimate: least-squares
/// sphere fit `|m − h|² = const`, i.e. `2 m·h + c = |m|²`, with forgetting and a ridge.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct HardIron {
    /// Upper triangle of Σ x xᵀ for x = (2m, 1): 10 values, then Σ x |m|²: 4 values.
    sums: [f64; 14],
    h_ut: [f64; 3],
}

impl HardIron {
    fn add(&mut self, m: &[f64; 3]) {
        let x = [2.0 * m[0], 2.0 * m[1], 2.0 * m[2], 1.0];
        let y = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
        let s = &mut self.sums;
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                s[k] += x[i] * x[j];
                k += 1;
            }
        }
        for i in 0..4 {
            s[10 + i] += x[i] * y;
        }
    }

    /// Forget (factor `decay`) and re-solve.
    fn solve(&mut self, decay: f64) {
        for s in self.sums.iter_mut() {
            *s *= decay;
        }
        let s = &self.sums;
        let n = s[9];
        if n < HARD_IRON_MIN_N {
            return;
        }
        let mut a = Matrix4::zeros();
        let mut k = 0;
        for i in 0..4 {
            for j in i..4 {
                a[(i, j)] = s[k];
                a[(j, i)] = s[k];
                k += 1;
            }
        }
        let ridge = 4.0 * n * HARD_IRON_RIDGE_UT2;
        for i in 0..3 {
            a[(i, i)] += ridge;
        }
        let b = Vector4::new(s[10], s[11], s[12], s[13]);
        if let Some(x) = a.cholesky().map(|c| c.solve(&b)) {
            let h = [x[0], x[1], x[2]];
            if h.iter().all(|v| v.is_finite() && v.abs() < 100.0) {
                self.h_ut = h;
            }
        }
    }
}

/// One slot of the attitude history: Σ over its samples of the east and north rows
/// of `R(q)` (body → ENU) and the yaw correction μ at its end, so that the azimuth
/// of any body-frame vector averaged over a time span can be computed later.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Slot {
    t0_s: f64,
    t1_s: f64,
    rows: [f64; 6],
    n: f64,
    mu_rad: f64,
}

impl Slot {
    /// Σ over the slot of the horizontal ENU direction of body vector `f`, with the
    /// yaw correction applied (azimuth − μ).
    fn horizontal(&self, f: [f64; 3]) -> (f64, f64) {
        let r = &self.rows;
        let e = r[0] * f[0] + r[1] * f[1] + r[2] * f[2];
        let n = r[3] * f[0] + r[4] * f[1] + r[5] * f[2];
        let (s, c) = self.mu_rad.sin_cos();
        (c * e - s * n, s * e + c * n)
    }
}

/// Estimates the walking azimuth and the phone's heading offset.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkingDirection {
    /// Latest walking azimuth (per sample), once known.
    azimuth_rad: f64,
    known: bool,
    /// Attitude history (see [`Slot`]).
    history: Ring<Slot, HISTORY_SLOTS>,
    /// AHRS azimuth − true azimuth, and its drift rate, rad, rad/s.
    mu_rad: f64,
    mu_rate_rads: f64,
    mu_known: bool,
    mag_seen: bool,
    /// The gyroscope's bias is removed by the platform (the magnetic loop is slow).
    gyro_calibrated: bool,
    /// Learned field strength, µT, and dip, rad.
    mag_ref_ut: f64,
    dip_ref_rad: f64,
    mag_ref_known: bool,
    hard_iron: HardIron,
    /// Walking direction in the body frame (how the phone is carried).
    forward_body: [f64; 3],
    forward_known: bool,
    /// `forward_body` calibrated by GNSS (held from then on).
    calibrated: bool,
    /// Covariance of the calibration filter (azimuth error, drift-rate error):
    /// p00, p01, p11.
    cal_p: [f64; 3],
    /// Body-frame up, low-passed fast and slow (carrying change detection).
    up_fast: [f64; 3],
    up_slow: [f64; 3],
    up_known: bool,
    /// Orientation (body → ENU) of the latest sample after the tilt correction,
    /// `[w, x, y, z]`.
    q: [f64; 4],
    /// Mean specific force in the AHRS earth frame (low-passed), m/s²: its tilt from
    /// the vertical is the AHRS's mean tilt error while walking.
    mean_force_enu: [f64; 3],
    stride: StrideStats,
    steps_in_stride: u32,
    /// Stride axes averaged into the carrying since it was initialised.
    axis_strides: f64,
    vz_mps: f64,
    last_t_s: f64,
    last_stride_t_s: f64,
}

impl Default for WalkingDirection {
    fn default() -> Self {
        Self::new()
    }
}

fn unit(v: [f64; 3]) -> Vector3<f64> {
    Vector3::from(v)
        .try_normalize(1e-12)
        .unwrap_or(Vector3::z())
}

impl WalkingDirection {
    /// For a gyroscope whose bias the platform removes (the default of
    /// `NavigatorConfig`).
    pub fn new() -> Self {
        Self::with_gyro_calibrated(true)
    }

    /// `gyro_calibrated`: the platform removes the gyroscope's bias (Android
    /// `TYPE_GYROSCOPE`, iOS device motion), so the magnetic loop can be slow and keep
    /// the field's disturbances out of the heading; `false` for a raw gyroscope, whose
    /// drift the loop must follow.
    pub fn with_gyro_calibrated(gyro_calibrated: bool) -> Self {
        Self {
            gyro_calibrated,
            azimuth_rad: 0.0,
            known: false,
            history: Ring::new(),
            mu_rad: 0.0,
            mu_rate_rads: 0.0,
            mu_known: false,
            mag_seen: false,
            mag_ref_ut: 0.0,
            dip_ref_rad: 0.0,
            mag_ref_known: false,
            hard_iron: HardIron::default(),
            forward_body: [1.0, 0.0, 0.0],
            forward_known: false,
            calibrated: false,
            cal_p: CAL_P0,
            up_fast: [0.0, 0.0, 1.0],
            up_slow: [0.0, 0.0, 1.0],
            up_known: false,
            q: [1.0, 0.0, 0.0, 0.0],
            mean_force_enu: [0.0, 0.0, GRAVITY_MPS2],
            stride: StrideStats::default(),
            steps_in_stride: 0,
            axis_strides: 0.0,
            vz_mps: 0.0,
            last_t_s: f64::NAN,
            last_stride_t_s: f64::NAN,
        }
    }

    /// Set how the phone is carried (the walking direction in the body frame, e.g. a
    /// personal calibration): held like a GNSS-calibrated carrying until a carrying
    /// change; GNSS can still refine it.
    pub fn set_carrying(&mut self, forward_body: [f64; 3]) {
        let v = unit(forward_body);
        self.forward_body = v.into();
        self.forward_known = true;
        self.calibrated = true;
        self.cal_p = CAL_P0;
    }

    /// Walking azimuth, radians clockwise from north, once known.
    pub fn azimuth_rad(&self) -> Option<f64> {
        self.known.then_some(self.azimuth_rad)
    }

    /// Whether GNSS calibrated how the phone is carried (sign included).
    pub fn sign_resolved(&self) -> bool {
        self.calibrated
    }

    /// Walking azimuth minus the phone's azimuth, radians (how the phone is carried);
    /// the phone's azimuth is that of `heading_axis_body` (e.g. body +y, the top edge
    /// of a phone in the Android / iOS device frame).
    pub fn heading_offset_rad(&self, heading_axis_body: [f64; 3]) -> Option<f64> {
        if !self.known {
            return None;
        }
        let v = self.quat() * Vector3::from(heading_axis_body);
        (v.x.hypot(v.y) > 1e-6).then(|| wrap(self.azimuth_rad - (v.x.atan2(v.y) - self.mu_rad)))
    }

    /// Whether the magnetic loop takes the gyroscope's bias as removed by the platform.
    pub fn gyro_calibrated(&self) -> bool {
        self.gyro_calibrated
    }

    /// Estimated hard-iron offset of the magnetometer, body frame, µT.
    pub fn hard_iron_ut(&self) -> [f64; 3] {
        self.hard_iron.h_ut
    }

    /// The walking direction in the phone's body frame, once known (how it is carried).
    pub fn forward_body(&self) -> Option<[f64; 3]> {
        self.forward_known.then_some(self.forward_body)
    }

    /// Orientation (body → ENU) of the latest sample after the tilt correction,
    /// `[w, x, y, z]` (azimuths in it are still offset by the yaw correction).
    pub fn orientation(&self) -> [f64; 4] {
        self.q
    }

    /// Correction of the AHRS azimuth (AHRS − true), rad, and its drift rate, rad/s.
    pub fn yaw_correction(&self) -> (f64, f64) {
        (self.mu_rad, self.mu_rate_rads)
    }

    fn quat(&self) -> UnitQuaternion<f64> {
        let [w, x, y, z] = self.q;
        UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z))
    }

    /// The azimuth (AHRS frame) of the phone's top edge when the phone is held in
    /// front to be read — screen facing up ([`READ_POSE_UP_Z`]), top edge not below the
    /// bottom edge by more than ~17° ([`READ_POSE_UP_Y`]), portrait: the stride axis at
    /// `axis_ahrs` within ~60° of the long side ([`READ_POSE_AXIS_Y`]). A phone held
    /// to be read points where its walker goes (on issue 13's 287 real walks the
    /// walking direction is within ±9° of the top edge for half the legs, ±20° for
    /// 80 %), more closely than one stride's axis and gait cue tell (with them, 341 of
    /// 1 499 legs were dead-reckoned backwards). `None` in any other pose (pocket, bag,
    /// swinging hand, landscape): the stride axis and the gait cue decide there.
    fn top_edge_if_read(&self, axis_ahrs: f64) -> Option<f64> {
        let up = unit(self.up_fast);
        if up.z < READ_POSE_UP_Z || up.y < READ_POSE_UP_Y {
            return None;
        }
        let q = self.quat();
        let u = Vector3::new(axis_ahrs.sin(), axis_ahrs.cos(), 0.0);
        if q.inverse_transform_vector(&u).y.abs() < READ_POSE_AXIS_Y {
            return None;
        }
        let top = q.transform_vector(&Vector3::new(0.0, 1.0, 0.0));
        (top.x.hypot(top.y) > 1e-6).then(|| top.x.atan2(top.y))
    }

    /// Rotate `forward_body` so that its azimuth grows by `delta` (clockwise), about the
    /// (slow) body-frame up.
    fn rotate_forward(&mut self, delta: f64) {
        let k = unit(self.up_fast);
        let v = Vector3::from(self.forward_body);
        let (s, c) = (-delta).sin_cos();
        let r = v * c + k.cross(&v) * s + k * (k.dot(&v) * (1.0 - c));
        self.forward_body = r.try_normalize(1e-12).unwrap_or(v).into();
    }

    /// One IMU sample: the orientation body → ENU from the AHRS, the measured
    /// specific force (accelerometer, gravity included) in that ENU frame, and the
    /// magnetometer reading in the body frame if any.
    pub fn push_sample(
        &mut self,
        t_s: f64,
        q_enu: &UnitQuaternion<f64>,
        force_enu_mps2: [f64; 3],
        mag_body_ut: Option<[f64; 3]>,
    ) {
        let dt = if self.last_t_s.is_finite() {
            (t_s - self.last_t_s).clamp(0.0, 0.1)
        } else {
            0.0
        };
        self.last_t_s = t_s;
        if !self.last_stride_t_s.is_finite() {
            self.last_stride_t_s = t_s;
        }
        // Tilt correction: over strides the body's acceleration averages out, so the
        // mean specific force in the earth frame is vertical; the AHRS's systematic
        // tilt error while walking (its accelerometer correction follows the median
        // rather than the mean of the asymmetric gait accelerations) shows as a tilt
        // of that mean, which is rotated away.
        let k_tilt = dt / TILT_TAU_S;
        let f_enu = force_enu_mps2;
        for (m, f) in self.mean_force_enu.iter_mut().zip(f_enu) {
            *m += k_tilt * (f - *m);
        }
        // Shortest rotation taking the mean force's direction a to up:
        // q ∝ (1 + a_z, a × z) = (1 + a_z, a_y, −a_x, 0).
        let mf = Vector3::from(self.mean_force_enu);
        let g = mf.norm();
        let fix = if g > 1.0 && mf.z > 0.0 {
            let a = mf / g;
            UnitQuaternion::from_quaternion(Quaternion::new(1.0 + a.z, a.y, -a.x, 0.0))
        } else {
            UnitQuaternion::identity()
        };
        let q_enu = &(fix * q_enu);
        let lin = fix * Vector3::from(f_enu) - Vector3::new(0.0, 0.0, g.max(1.0));
        let lin_acc_enu_mps2 = [lin.x, lin.y, lin.z];
        self.q = [q_enu.w, q_enu.i, q_enu.j, q_enu.k];
        let up_b = q_enu.inverse_transform_vector(&Vector3::z());

        // Carrying change: a lasting jump of the body-frame gravity direction.
        if !self.up_known {
            self.up_fast = up_b.into();
            self.up_slow = up_b.into();
            self.up_known = true;
        } else {
            let kf = dt / UP_FAST_TAU_S;
            let ks = dt / UP_SLOW_TAU_S;
            let fast = Vector3::from(self.up_fast) + (up_b - Vector3::from(self.up_fast)) * kf;
            let slow = Vector3::from(self.up_slow) + (fast - Vector3::from(self.up_slow)) * ks;
            self.up_fast = fast.into();
            self.up_slow = slow.into();
            let (f, s) = (unit(self.up_fast), unit(self.up_slow));
            if f.dot(&s) < CARRY_CHANGE_RAD.cos() {
                self.up_slow = self.up_fast;
                self.forward_known = false;
                self.calibrated = false;
                self.cal_p[0] = CAL_P0[0];
            }
        }

        // Magnetometer: azimuth of magnetic north in the AHRS frame.
        match mag_body_ut {
            Some(m) => {
                let h = self.hard_iron.h_ut;
                let mc = Vector3::new(m[0] - h[0], m[1] - h[1], m[2] - h[2]);
                let n = mc.norm();
                if n > 1.0 {
                    let dip = (mc.dot(&up_b) / n).clamp(-1.0, 1.0).asin();
                    if !self.mag_ref_known {
                        self.mag_ref_ut = n;
                        self.dip_ref_rad = dip;
                        self.mag_ref_known = true;
                    }
                    let ok = (n - self.mag_ref_ut).abs() < MAG_GATE_UT
                        && (dip - self.dip_ref_rad).abs() < MAG_GATE_DIP_RAD;
                    let k = dt / MAG_REF_TAU_S;
                    self.mag_ref_ut += k * (n - self.mag_ref_ut);
                    self.dip_ref_rad += k * (dip - self.dip_ref_rad);
                    let me = q_enu * mc;
                    if ok {
                        self.hard_iron.add(&m);
                    }
                    if ok && me.x.hypot(me.y) > 1.0 {
                        let meas = me.x.atan2(me.y);
                        if !self.mag_seen {
                            self.mu_rad = meas;
                            self.mu_known = true;
                        } else {
                            let e = wrap(meas - self.mu_rad);
                            let (tau, rate_tau) = if self.gyro_calibrated {
                                (MAG_TAU_CALIBRATED_GYRO_S, MAG_RATE_TAU_CALIBRATED_GYRO_S)
                            } else {
                                (MAG_TAU_RAW_GYRO_S, MAG_RATE_TAU_RAW_GYRO_S)
                            };
                            self.mu_rad += dt * e / tau;
                            self.mu_rate_rads += dt * e / (rate_tau * rate_tau);
                        }
                        self.mag_seen = true;
                    }
                }
            }
            None => {
                if !self.mu_known {
                    self.mu_rad = 0.0;
                    self.mu_known = true;
                }
            }
        }
        self.mu_rad = wrap(self.mu_rad + self.mu_rate_rads * dt);

        // Vertical velocity, leaky to stay bounded (time constant ~1 s).
        self.vz_mps = self.vz_mps * (1.0 - dt) + lin_acc_enu_mps2[2] * dt;
        self.stride
            .add(lin_acc_enu_mps2[0], lin_acc_enu_mps2[1], self.vz_mps);

        // Attitude history: rows east and north of R (body → ENU); the slot keeps
        // the yaw correction μ (it moves over tens of seconds, not within a slot).
        let (w, x, y, z) = (q_enu.w, q_enu.i, q_enu.j, q_enu.k);
        let rows = [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ];
        match self.history.newest_mut() {
            Some(slot) if t_s - slot.t0_s < SLOT_S && t_s >= slot.t0_s => {
                for (a, b) in slot.rows.iter_mut().zip(rows) {
                    *a += b;
                }
                slot.n += 1.0;
                slot.t1_s = t_s;
                slot.mu_rad = self.mu_rad;
            }
            _ => self.history.push(Slot {
                t0_s: t_s,
                t1_s: t_s,
                rows,
                n: 1.0,
                mu_rad: self.mu_rad,
            }),
        }

        // Walking azimuth of this sample.
        if self.forward_known {
            let f = self.forward_body;
            let e = rows[0] * f[0] + rows[1] * f[1] + rows[2] * f[2];
            let n = rows[3] * f[0] + rows[4] * f[1] + rows[5] * f[2];
            if e.hypot(n) > 0.2 {
                self.azimuth_rad = wrap(e.atan2(n) - self.mu_rad);
                self.known = true;
            }
        }
    }

    /// The walking azimuth averaged over `t0_s..=t1_s` (a step), from the attitude
    /// history and the current carrying estimate; `None` while the carrying is
    /// unknown. Spans older than the history use its oldest slot, spans in a gap the
    /// nearest slot.
    pub fn azimuth_between(&self, t0_s: f64, t1_s: f64) -> Option<f64> {
        if !self.forward_known || self.history.is_empty() {
            return None;
        }
        let f = self.forward_body;
        let (mut e, mut n, mut w) = (0.0, 0.0, 0.0);
        let len = self.history.len();
        for i in 0..len {
            let Some(s) = self.history.get(i) else {
                continue;
            };
            // A slot spans from its start to the next slot's start (the newest: to
            // its last sample).
            let end = self
                .history
                .get(i + 1)
                .map_or(s.t1_s, |next| next.t0_s.min(s.t0_s + SLOT_S));
            let span = (end - s.t0_s).max(1e-9);
            let overlap = (end.min(t1_s) - s.t0_s.max(t0_s)).max(0.0);
            if overlap <= 0.0 && !(s.t0_s <= t1_s && t1_s <= end) {
                continue;
            }
            let k = (overlap / span).max(1e-6) / s.n;
            let (se, sn) = s.horizontal(f);
            e += k * se;
            n += k * sn;
            w += k;
        }
        if w == 0.0 {
            // Outside the history: the nearest slot.
            let s = if self.history.get(0).is_some_and(|s| t1_s < s.t0_s) {
                self.history.get(0)
            } else {
                self.history.newest()
            }?;
            (e, n) = s.horizontal(f);
            w = s.n;
        }
        (e.hypot(n) > 0.2 * w).then(|| e.atan2(n))
    }

    /// A step was detected (its azimuth: [`azimuth_between`](Self::azimuth_between)).
    /// Every second step closes a stride: the hard-iron fit is re-solved, and until GNSS
    /// calibrated the carrying, the stride's axis updates it. `step_hz` selects the
    /// walking or running cue for the forward direction.
    pub fn push_step(&mut self, step_hz: f64) {
        self.steps_in_stride += 1;
        if self.steps_in_stride < 2 {
            return;
        }
        self.steps_in_stride = 0;
        let stats = std::mem::take(&mut self.stride);
        if self.last_t_s.is_finite() && self.last_stride_t_s.is_finite() {
            let span = (self.last_t_s - self.last_stride_t_s).max(0.0);
            self.hard_iron.solve((-span / HARD_IRON_TAU_S).exp());
        }
        self.last_stride_t_s = self.last_t_s;
        if self.calibrated {
            return;
        }
        let Some((axis_ahrs, ratio)) = stats.axis() else {
            return;
        };
        if ratio < MIN_AXIS_RATIO {
            return;
        }
        let quality = ((ratio - MIN_AXIS_RATIO) / (4.0 * MIN_AXIS_RATIO)).clamp(0.0, 1.0);
        let axis = wrap(axis_ahrs - self.mu_rad);
        // Held to be read: the walker walks where the top edge points.
        let top_edge = self.top_edge_if_read(axis_ahrs);
        if !self.forward_known {
            let dir_ahrs = top_edge.unwrap_or_else(|| {
                let forward_is_axis = if self.known {
                    // After a carrying change: continuity with the last direction.
                    wrap(axis - self.azimuth_rad).abs() <= 0.5 * PI
                } else {
                    // Gait cue: walking → forward acceleration is anti-correlated with
                    // vertical velocity; running → correlated.
                    let cov = stats.forward_vz_cov(axis_ahrs);
                    if step_hz > RUNNING_STEP_HZ {
                        cov > 0.0
                    } else {
                        cov < 0.0
                    }
                };
                if forward_is_axis {
                    axis_ahrs
                } else {
                    axis_ahrs + PI
                }
            });
            let u = Vector3::new(dir_ahrs.sin(), dir_ahrs.cos(), 0.0);
            self.forward_body = self.quat().inverse_transform_vector(&u).into();
            self.forward_known = true;
            self.axis_strides = 1.0;
            return;
        }
        // The top edge, or of the axis' two directions the one nearer the current
        // estimate.
        let target = match top_edge {
            Some(top) => wrap(top - self.mu_rad),
            None if wrap(axis - self.azimuth_rad).abs() > 0.5 * PI => wrap(axis + PI),
            None => axis,
        };
        // The carrying is constant until it changes (detected above): average the
        // stride axes (gain 1/n), down to a floor that follows slow changes.
        let gain = (1.0 / (self.axis_strides + 1.0)).clamp(AXIS_MIN_GAIN, AXIS_GAIN);
        self.axis_strides += quality;
        self.rotate_forward(gain * quality * wrap(target - self.azimuth_rad));
    }

    /// GNSS says the dead-reckoned displacement over a stretch of `window_s` seconds
    /// was `err_rad` anticlockwise of the true one (true azimuth − dead-reckoned
    /// azimuth), with a 1-σ of `sigma_rad`. A wrong forward sign is resolved once; a
    /// Kalman filter on the azimuth error (and, without a magnetometer, on the drift
    /// rate of the gyro-integrated yaw, which the stretch's mean error lags by half its
    /// length) rotates the carrying and corrects the drift rate.
    pub fn observe_rotation(&mut self, err_rad: f64, window_s: f64, sigma_rad: f64) {
        if !self.forward_known || !err_rad.is_finite() || sigma_rad.is_nan() || sigma_rad <= 0.0 {
            return;
        }
        let mut err = wrap(err_rad);
        if !self.calibrated && err.abs() > 0.5 * PI {
            self.rotate_forward(PI);
            err = wrap(err - PI);
        }
        self.calibrated = true;
        let t = if window_s.is_finite() {
            window_s.max(0.0)
        } else {
            0.0
        };
        let use_rate = !self.mag_seen;
        let [mut p00, mut p01, mut p11] = self.cal_p;
        if !use_rate {
            p01 = 0.0;
            p11 = 0.0;
        }
        // Predict over the stretch: offset += rate · t.
        p00 += 2.0 * t * p01 + t * t * p11 + CAL_OFFSET_Q * t;
        p01 += t * p11;
        if use_rate {
            p11 += CAL_RATE_Q * t;
        }
        // The stretch's mean error = offset − rate · t/2 (both as errors now).
        let h1 = if use_rate { -0.5 * t } else { 0.0 };
        let s = p00 + 2.0 * h1 * p01 + h1 * h1 * p11 + sigma_rad * sigma_rad;
        let k0 = (p00 + h1 * p01) / s;
        let k1 = (p01 + h1 * p11) / s;
        // Update and apply: the error states go back to zero.
        let (ph0, ph1) = (p00 + h1 * p01, p01 + h1 * p11);
        p00 -= k0 * ph0;
        p01 -= k0 * ph1;
        p11 -= k1 * ph1;
        self.cal_p = [p00, p01, p11];
        self.rotate_forward(k0 * err);
        if use_rate {
            // True azimuth = AHRS azimuth − μ: a growing error wants μ to grow slower.
            self.mu_rate_rads -= k1 * err;
        }
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.f64s(&[
            self.azimuth_rad,
            self.mu_rad,
            self.mu_rate_rads,
            self.mag_ref_ut,
            self.dip_ref_rad,
            self.vz_mps,
            self.last_t_s,
            self.last_stride_t_s,
        ]);
        w.f64s(&self.mean_force_enu);
        w.f64s(&self.cal_p);
        w.f64s(&self.hard_iron.sums);
        w.f64s(&self.hard_iron.h_ut);
        w.f64s(&self.forward_body);
        w.f64s(&self.up_fast);
        w.f64s(&self.up_slow);
        w.f64s(&self.q);
        w.f64s(&self.stride.to_array());
        for b in [
            self.known,
            self.mu_known,
            self.mag_seen,
            self.mag_ref_known,
            self.forward_known,
            self.calibrated,
            self.up_known,
            self.gyro_calibrated,
        ] {
            w.bool(b);
        }
        w.u64(self.steps_in_stride as u64);
        w.f64(self.axis_strides);
        w.u64(self.history.len() as u64);
        for s in self.history.iter() {
            w.f64s(&[s.t0_s, s.t1_s, s.n, s.mu_rad]);
            w.f64s(&s.rows);
        }
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 8];
        r.f64s(&mut v[..6])?;
        // NaN before the first sample / stride.
        v[6] = r.f64_or_nan()?;
        v[7] = r.f64_or_nan()?;
        let mut mean_force_enu = [0.0; 3];
        r.f64s(&mut mean_force_enu)?;
        let mut cal_p = [0.0; 3];
        r.f64s(&mut cal_p)?;
        let mut hard_iron = HardIron::default();
        r.f64s(&mut hard_iron.sums)?;
        r.f64s(&mut hard_iron.h_ut)?;
        let mut forward_body = [0.0; 3];
        r.f64s(&mut forward_body)?;
        let mut up_fast = [0.0; 3];
        r.f64s(&mut up_fast)?;
        let mut up_slow = [0.0; 3];
        r.f64s(&mut up_slow)?;
        let mut q = [0.0; 4];
        r.f64s(&mut q)?;
        let mut stride = [0.0; 9];
        r.f64s(&mut stride)?;
        let mut b = [false; 8];
        for x in b.iter_mut() {
            *x = r.bool()?;
        }
        let steps_in_stride = r.len(2)? as u32;
        let axis_strides = r.f64()?;
        let mut history = Ring::new();
        for _ in 0..r.len(HISTORY_SLOTS)? {
            let mut h = [0.0; 4];
            r.f64s(&mut h)?;
            let mut rows = [0.0; 6];
            r.f64s(&mut rows)?;
            // A slot of n ≥ 1 samples within the time limits, its rows sums of n
            // unit-vector components, its μ an angle.
            let t_ok = |t: f64| t.abs() <= crate::input::limits::MAX_ABS_T_S + 1.0;
            if !(t_ok(h[0]) && t_ok(h[1]) && (1.0..=1e9).contains(&h[2]) && h[3].abs() <= 100.0)
                || rows.iter().any(|x| x.abs() > h[2] * 1.01)
            {
                return Err(SnapshotError::Invalid("walking direction history"));
            }
            history.push(Slot {
                t0_s: h[0],
                t1_s: h[1],
                n: h[2],
                mu_rad: h[3],
                rows,
            });
        }
        let qn = q.iter().map(|x| x * x).sum::<f64>();
        if (qn - 1.0).abs() >= 1e-6 {
            return Err(SnapshotError::Invalid("walking direction orientation"));
        }
        use crate::input::limits::{MAX_ABS_T_S, MAX_ACCEL_NORM_MPS2, MAX_MAG_UT};
        let mag_max = MAX_MAG_UT * 3f64.sqrt();
        let within = |xs: &[f64], max: f64| xs.iter().all(|x| x.abs() <= max);
        // Angles, rates, a vertical speed, the field's magnitude and dip, unit
        // vectors, forces within the door's limits, sums that forgetting keeps
        // bounded, a covariance.
        let checks = [
            within(&[v[0], v[1]], 100.0),
            v[2].abs() <= 1.0,
            (0.0..=mag_max).contains(&v[3]),
            v[4].abs() <= 4.0,
            v[5].abs() <= 1e3,
            [v[6], v[7]]
                .iter()
                .all(|t| t.is_nan() || t.abs() <= MAX_ABS_T_S + 1.0),
            (0.0..=1e9).contains(&axis_strides),
            within(&mean_force_enu, MAX_ACCEL_NORM_MPS2),
            cal_p[0] >= 0.0 && cal_p[2] >= 0.0 && within(&cal_p, 1e6),
            within(&hard_iron.sums, 1e20) && within(&hard_iron.h_ut, mag_max),
            within(&forward_body, 1.5) && within(&up_fast, 1.5) && within(&up_slow, 1.5),
            (0.0..=1e7).contains(&stride[0]) && within(&stride[1..], 1e12),
        ];
        let ok = checks.iter().all(|ok| *ok);
        if !ok {
            return Err(SnapshotError::Invalid("walking direction state"));
        }
        Ok(Self {
            azimuth_rad: v[0],
            history,
            mu_rad: v[1],
            mu_rate_rads: v[2],
            mag_ref_ut: v[3],
            dip_ref_rad: v[4],
            vz_mps: v[5],
            last_t_s: v[6],
            last_stride_t_s: v[7],
            mean_force_enu,
            cal_p,
            hard_iron,
            forward_body,
            up_fast,
            up_slow,
            q,
            stride: StrideStats::from_array(&stride),
            known: b[0],
            mu_known: b[1],
            mag_seen: b[2],
            mag_ref_known: b[3],
            forward_known: b[4],
            calibrated: b[5],
            up_known: b[6],
            gyro_calibrated: b[7],
            steps_in_stride,
            axis_strides,
        })
    }
}
