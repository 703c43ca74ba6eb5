//! Walking direction from a phone carried anywhere ([`WalkingDirection`]): where the
//! phone points (the AHRS attitude, tilt-corrected, its yaw corrected by the
//! magnetometer or GNSS) × how it is carried (the walking direction in the body
//! frame), averaged over each step. docs/phone.md ("Pedestrian dead reckoning")
//! explains the loops. Azimuths: radians clockwise from north in (−π, π].

mod calibration;
mod carrying;
mod hard_iron;
mod history;
mod magnetic;
mod snapshot;
mod stride;
mod tilt;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use self::calibration::CalibrationFilter;
use self::carrying::{Carrying, MIN_AZIMUTH_NORM};
use self::hard_iron::HARD_IRON_TAU_S;
use self::history::{AttitudeHistory, MIN_HORIZONTAL_SHARE};
use self::magnetic::YawCorrection;
use self::stride::Stride;
use self::tilt::TiltCorrection;
use crate::angle::wrap;

/// Longest time step of the loops, s: a longer gap between samples counts as this.
const MAX_DT_S: f64 = 0.1;

/// Estimates the walking azimuth and the phone's heading offset.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkingDirection {
    /// Latest walking azimuth (per sample), rad, once `known`.
    azimuth_rad: f64,
    known: bool,
    /// Orientation (body → ENU) of the latest sample after the tilt correction,
    /// `[w, x, y, z]`.
    q: [f64; 4],
    tilt: TiltCorrection,
    /// μ = AHRS azimuth − true azimuth, its drift rate, the magnetometer's part.
    yaw: YawCorrection,
    /// How the phone is carried.
    carrying: Carrying,
    /// GNSS calibration of the carrying (and of μ's drift rate).
    calibration: CalibrationFilter,
    stride: Stride,
    history: AttitudeHistory,
    /// Time of the latest sample and of the latest stride's end, s (NaN before).
    last_t_s: f64,
    last_stride_t_s: f64,
}

impl Default for WalkingDirection {
    fn default() -> Self {
        Self::new()
    }
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
            azimuth_rad: 0.0,
            known: false,
            q: [1.0, 0.0, 0.0, 0.0],
            tilt: TiltCorrection::default(),
            yaw: YawCorrection::new(gyro_calibrated),
            carrying: Carrying::default(),
            calibration: CalibrationFilter::default(),
            stride: Stride::default(),
            history: AttitudeHistory::default(),
            last_t_s: f64::NAN,
            last_stride_t_s: f64::NAN,
        }
    }

    /// Set how the phone is carried (the walking direction in the body frame, e.g. a
    /// personal calibration): held like a GNSS-calibrated carrying until a carrying
    /// change; GNSS can still refine it.
    pub fn set_carrying(&mut self, forward_body: [f64; 3]) {
        self.carrying.set(forward_body);
        self.calibration = CalibrationFilter::default();
    }

    /// Walking azimuth, radians clockwise from north, once known.
    pub fn azimuth_rad(&self) -> Option<f64> {
        self.known.then_some(self.azimuth_rad)
    }

    /// Whether GNSS calibrated how the phone is carried (sign included).
    pub fn sign_resolved(&self) -> bool {
        self.carrying.calibrated
    }

    /// Walking azimuth minus the phone's azimuth, radians (how the phone is carried);
    /// the phone's azimuth is that of `heading_axis_body` (e.g. body +y, the top edge
    /// of a phone in the Android / iOS device frame).
    pub fn heading_offset_rad(&self, heading_axis_body: [f64; 3]) -> Option<f64> {
        if !self.known {
            return None;
        }
        let v = self.quat() * Vector3::from(heading_axis_body);
        (v.x.hypot(v.y) > MIN_AZIMUTH_NORM)
            .then(|| wrap(self.azimuth_rad - (v.x.atan2(v.y) - self.yaw.mu_rad)))
    }

    /// Whether the magnetic loop takes the gyroscope's bias as removed by the platform.
    pub fn gyro_calibrated(&self) -> bool {
        self.yaw.gyro_calibrated
    }

    /// Estimated hard-iron offset of the magnetometer, body frame, µT.
    pub fn hard_iron_ut(&self) -> [f64; 3] {
        self.yaw.hard_iron.h_ut
    }

    /// The walking direction in the phone's body frame, once known (how it is carried).
    pub fn forward_body(&self) -> Option<[f64; 3]> {
        self.carrying
            .forward_known
            .then_some(self.carrying.forward_body)
    }

    /// Orientation (body → ENU) of the latest sample after the tilt correction,
    /// `[w, x, y, z]` (azimuths in it are still offset by the yaw correction).
    pub fn orientation(&self) -> [f64; 4] {
        self.q
    }

    /// Correction of the AHRS azimuth (AHRS − true), rad, and its drift rate, rad/s.
    pub fn yaw_correction(&self) -> (f64, f64) {
        (self.yaw.mu_rad, self.yaw.mu_rate_rads)
    }

    fn quat(&self) -> UnitQuaternion<f64> {
        let [w, x, y, z] = self.q;
        UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z))
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
        let dt = self.advance_clock(t_s);
        let (q_enu, lin_acc_enu_mps2) = self.tilt.correct(dt, q_enu, force_enu_mps2);
        self.q = [q_enu.w, q_enu.i, q_enu.j, q_enu.k];
        let up_body = q_enu.inverse_transform_vector(&Vector3::z());
        if self.carrying.follow_up(dt, up_body) {
            self.calibration.forget_offset();
        }
        self.yaw.push(dt, &q_enu, &up_body, mag_body_ut);
        self.stride.push(dt, lin_acc_enu_mps2);
        let rows = history::enu_rows(&q_enu);
        self.history.push(t_s, rows, self.yaw.mu_rad);
        self.update_azimuth(&rows);
    }

    /// The walking azimuth averaged over `t0_s..=t1_s` (a step), from the attitude
    /// history and the current carrying estimate; `None` while the carrying is
    /// unknown. Spans older than the history use its oldest slot, spans in a gap the
    /// nearest slot.
    pub fn azimuth_between(&self, t0_s: f64, t1_s: f64) -> Option<f64> {
        if !self.carrying.forward_known {
            return None;
        }
        self.history
            .azimuth_between(self.carrying.forward_body, t0_s, t1_s)
    }

    /// A step was detected (its azimuth: [`azimuth_between`](Self::azimuth_between)).
    /// Every second step closes a stride: the hard-iron fit is re-solved, and until GNSS
    /// calibrated the carrying, the stride's axis updates it. `step_hz` selects the
    /// walking or running cue for the forward direction.
    pub fn push_step(&mut self, step_hz: f64) {
        let Some(stats) = self.stride.push_step() else {
            return;
        };
        self.resolve_hard_iron();
        self.learn_carrying(&stats, step_hz);
    }

    /// The time step since the previous sample, capped (0 for the first).
    fn advance_clock(&mut self, t_s: f64) -> f64 {
        let dt = if self.last_t_s.is_finite() {
            (t_s - self.last_t_s).clamp(0.0, MAX_DT_S)
        } else {
            0.0
        };
        self.last_t_s = t_s;
        if !self.last_stride_t_s.is_finite() {
            self.last_stride_t_s = t_s;
        }
        dt
    }

    /// Forget the hard-iron fit over the stride's span and re-solve it.
    fn resolve_hard_iron(&mut self) {
        if self.last_t_s.is_finite() && self.last_stride_t_s.is_finite() {
            let span = (self.last_t_s - self.last_stride_t_s).max(0.0);
            self.yaw.hard_iron.solve((-span / HARD_IRON_TAU_S).exp());
        }
        self.last_stride_t_s = self.last_t_s;
    }

    /// The walking azimuth of this sample (rows of its R, body → ENU), once the
    /// carrying is known and not vertical.
    fn update_azimuth(&mut self, rows: &[f64; 6]) {
        if !self.carrying.forward_known {
            return;
        }
        let (e, n) = history::project(rows, self.carrying.forward_body);
        if e.hypot(n) > MIN_HORIZONTAL_SHARE {
            self.azimuth_rad = wrap(e.atan2(n) - self.yaw.mu_rad);
            self.known = true;
        }
    }
}
