//! Walking direction from a phone carried anywhere ([`WalkingDirection`]): where the
//! phone points (the AHRS attitude, tilt-corrected, its yaw corrected by the
//! magnetometer or GNSS) × how it is carried (the walking direction in the body
//! frame), averaged over each step. docs/phone.md ("Pedestrian dead reckoning")
//! explains the loops. Azimuths: radians clockwise from north in (−π, π].

mod calibration;
mod carrying;
mod gap;
mod hard_iron;
mod history;
mod magnetic;
mod snapshot;
mod stride;
mod tilt;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use self::calibration::CalibrationFilter;
use self::carrying::{Carrying, MIN_AZIMUTH_NORM};
use self::gap::{Bridged, GapBridge};
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
    /// The heading across dropped samples.
    gaps: GapBridge,
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
            gaps: GapBridge::default(),
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
    /// specific force (accelerometer, gravity included) in that ENU frame, the
    /// magnetometer reading in the body frame if any, and the gyroscope's rates in the
    /// body frame, rad/s, when the orientation is the gyroscope's own (an AHRS run
    /// here): the yaw correction then bridges the heading across dropped samples
    /// (`gap`); an orientation from outside is taken as it is across them.
    pub fn push_sample(
        &mut self,
        t_s: f64,
        q_enu: &UnitQuaternion<f64>,
        force_enu_mps2: [f64; 3],
        mag_body_ut: Option<[f64; 3]>,
        gyro_body_rads: Option<[f64; 3]>,
    ) {
        let interval_s = t_s - self.last_t_s;
        let dt = self.advance_clock(t_s);
        let q_before = self.quat();
        let (q_enu, lin_acc_enu_mps2) = self.tilt.correct(dt, q_enu, force_enu_mps2);
        self.q = [q_enu.w, q_enu.i, q_enu.j, q_enu.k];
        let up_body = q_enu.inverse_transform_vector(&Vector3::z());
        if self.carrying.follow_up(dt, up_body) {
            self.calibration.forget_offset();
        }
        if let Some(w) = gyro_body_rads {
            let rate_up = up_body.dot(&Vector3::from(w));
            if self.gaps.is_gap(interval_s) {
                self.bridge_gap(t_s, interval_s, rate_up, &q_before, &q_enu);
            } else {
                self.gaps.push_rate(rate_up);
            }
        }
        let field = self.yaw.push(dt, &q_enu, &up_body, mag_body_ut);
        if let Some(b) = field.and_then(|u| self.gaps.push_field(t_s, dt, u)) {
            self.apply_bridge(b);
        }
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

    /// A gap of `interval_s` ended with this sample (`rate_up` about the vertical,
    /// rad/s; the tilt-corrected orientation before and after it): μ takes the AHRS's
    /// yaw error over the gap against the trapezoid of the rates now, the field's view
    /// of it once the field after the gap is seen (`gap`).
    fn bridge_gap(
        &mut self,
        t_s: f64,
        interval_s: f64,
        rate_up: f64,
        q_before: &UnitQuaternion<f64>,
        q_after: &UnitQuaternion<f64>,
    ) {
        let (rows0, rows1) = (history::enu_rows(q_before), history::enu_rows(q_after));
        // The walking direction's turn if known, else that of the body axis nearest
        // the horizontal.
        let f = if self.carrying.forward_known {
            self.carrying.forward_body
        } else {
            let up = q_before.inverse_transform_vector(&Vector3::z());
            let i = (0..3)
                .min_by(|&a, &b| up[a].abs().total_cmp(&up[b].abs()))
                .unwrap_or(0);
            std::array::from_fn(|k| if k == i { 1.0 } else { 0.0 })
        };
        let ((e0, n0), (e1, n1)) = (history::project(&rows0, f), history::project(&rows1, f));
        let ahrs_turn = wrap(e1.atan2(n1) - e0.atan2(n0));
        let (earlier, mu_step) = self.gaps.on_gap(t_s, interval_s, rate_up, ahrs_turn);
        if let Some(b) = earlier {
            self.apply_bridge(b);
        }
        self.yaw.mu_rad = wrap(self.yaw.mu_rad + mu_step);
    }

    /// A field correction of μ found after the gap it belongs to: μ now and in the
    /// attitude history from the gap on.
    fn apply_bridge(&mut self, b: Bridged) {
        self.yaw.mu_rad = wrap(self.yaw.mu_rad + b.mu_step_rad);
        self.history.shift_mu_since(b.t_s, b.mu_step_rad);
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
