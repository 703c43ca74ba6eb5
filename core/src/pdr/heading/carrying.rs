//! How the phone is carried: the walking direction as a unit vector in the body frame.
//! Set by a calibration, else the top edge of a phone held to be read, else the stride
//! axis with the gait cue for its sign; averaged over strides until GNSS calibrates it,
//! then held until a lasting jump of the body-frame gravity direction (a new carrying).

use std::f64::consts::PI;

use nalgebra::{UnitQuaternion, Vector3};

use super::stride::StrideStats;
use super::WalkingDirection;
use crate::angle::wrap;
use crate::vec3;

/// Step frequency above which the gait is taken as running (spring-mass), Hz.
pub(super) const RUNNING_STEP_HZ: f64 = 2.4;
/// Held to be read: body-frame up (low-passed) with its screen-normal component at
/// least this (screen within 60° of facing up) ...
const READ_POSE_UP_Z: f64 = 0.5;
/// ... its top-edge component at least this (top edge at most ~17° below the bottom
/// edge: a reader tilts the screen towards the face; upside down is not taken) ...
const READ_POSE_UP_Y: f64 = -0.3;
/// ... and the stride axis within ~60° of the phone's long side (portrait).
const READ_POSE_AXIS_Y: f64 = 0.5;
/// Gain of the pull towards a stride's axis at full quality (per stride), before
/// GNSS calibrated the carrying.
const AXIS_GAIN: f64 = 0.3;
/// Least gain of the stride-axis average (≈ 10 strides of memory).
const AXIS_MIN_GAIN: f64 = 0.1;
/// Strides whose along/across variance ratio is below this carry no direction ...
const MIN_AXIS_RATIO: f64 = 1.5;
/// ... and their quality is full this many times `MIN_AXIS_RATIO` above it.
const AXIS_QUALITY_SPAN: f64 = 4.0;
/// Carrying change: body-frame up low-passed fast and slow, s; a difference above
/// this angle, rad, is a new carrying.
const UP_FAST_TAU_S: f64 = 2.0;
const UP_SLOW_TAU_S: f64 = 20.0;
const CARRY_CHANGE_RAD: f64 = 0.6;
/// Vectors shorter than this have no direction (normalisation).
const MIN_NORM: f64 = 1e-12;
/// A horizontal part shorter than this has no azimuth (the vector is vertical).
pub(super) const MIN_AZIMUTH_NORM: f64 = 1e-6;

/// `v` normalised; +z for a null vector.
pub(super) fn unit(v: [f64; 3]) -> Vector3<f64> {
    Vector3::from(vec3::unit(v, MIN_NORM).unwrap_or([0.0, 0.0, 1.0]))
}

/// The carrying estimate and the gravity direction that tells when it changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Carrying {
    /// Walking direction in the body frame.
    pub(super) forward_body: [f64; 3],
    pub(super) forward_known: bool,
    /// `forward_body` calibrated by GNSS or set (held from then on).
    pub(super) calibrated: bool,
    /// Stride axes averaged into the carrying since it was initialised.
    pub(super) axis_strides: f64,
    /// Body-frame up, low-passed fast and slow (carrying change detection).
    pub(super) up_fast: [f64; 3],
    pub(super) up_slow: [f64; 3],
    pub(super) up_known: bool,
}

impl Default for Carrying {
    fn default() -> Self {
        Self {
            forward_body: [1.0, 0.0, 0.0],
            forward_known: false,
            calibrated: false,
            axis_strides: 0.0,
            up_fast: [0.0, 0.0, 1.0],
            up_slow: [0.0, 0.0, 1.0],
            up_known: false,
        }
    }
}

impl Carrying {
    /// Set the carrying (a personal calibration): held as if GNSS had calibrated it.
    pub(super) fn set(&mut self, forward_body: [f64; 3]) {
        self.forward_body = unit(forward_body).into();
        self.forward_known = true;
        self.calibrated = true;
    }

    /// One sample of the body-frame up `dt` after the previous; `true` when its
    /// lasting jump says the phone is carried another way (the estimate is dropped).
    pub(super) fn follow_up(&mut self, dt: f64, up_body: Vector3<f64>) -> bool {
        if !self.up_known {
            self.up_fast = up_body.into();
            self.up_slow = up_body.into();
            self.up_known = true;
            return false;
        }
        let kf = dt / UP_FAST_TAU_S;
        let ks = dt / UP_SLOW_TAU_S;
        let fast = Vector3::from(self.up_fast) + (up_body - Vector3::from(self.up_fast)) * kf;
        let slow = Vector3::from(self.up_slow) + (fast - Vector3::from(self.up_slow)) * ks;
        self.up_fast = fast.into();
        self.up_slow = slow.into();
        let (f, s) = (unit(self.up_fast), unit(self.up_slow));
        if f.dot(&s) < CARRY_CHANGE_RAD.cos() {
            self.up_slow = self.up_fast;
            self.forward_known = false;
            self.calibrated = false;
            return true;
        }
        false
    }

    /// Rotate `forward_body` so that its azimuth grows by `delta` (clockwise), about the
    /// (slow) body-frame up.
    pub(super) fn rotate(&mut self, delta: f64) {
        let k = unit(self.up_fast);
        let v = Vector3::from(self.forward_body);
        let (s, c) = (-delta).sin_cos();
        let r = v * c + k.cross(&v) * s + k * (k.dot(&v) * (1.0 - c));
        self.forward_body = r.try_normalize(MIN_NORM).unwrap_or(v).into();
    }

    /// The azimuth (AHRS frame) of the phone's top edge when the phone is held in
    /// front to be read — screen facing up, top edge not below the bottom edge by more
    /// than ~17°, portrait: the stride axis at `axis_ahrs` within ~60° of the long
    /// side. A phone held to be read points where its walker goes (docs/lab/2026-12-06-phone-history.md, "A
    /// phone held to be read walks towards its top edge"). `None` in any other pose
    /// (pocket, bag, swinging hand, landscape): the stride axis and the gait cue decide.
    fn top_edge_if_read(&self, q: &UnitQuaternion<f64>, axis_ahrs: f64) -> Option<f64> {
        let up = unit(self.up_fast);
        if up.z < READ_POSE_UP_Z || up.y < READ_POSE_UP_Y {
            return None;
        }
        let u = Vector3::new(axis_ahrs.sin(), axis_ahrs.cos(), 0.0);
        if q.inverse_transform_vector(&u).y.abs() < READ_POSE_AXIS_Y {
            return None;
        }
        let top = q.transform_vector(&Vector3::new(0.0, 1.0, 0.0));
        (top.x.hypot(top.y) > MIN_AZIMUTH_NORM).then(|| top.x.atan2(top.y))
    }

    /// The carrying from a first stride: walking along `dir_ahrs` (AHRS frame).
    fn initialise(&mut self, q: &UnitQuaternion<f64>, dir_ahrs: f64) {
        let u = Vector3::new(dir_ahrs.sin(), dir_ahrs.cos(), 0.0);
        self.forward_body = q.inverse_transform_vector(&u).into();
        self.forward_known = true;
        self.axis_strides = 1.0;
    }
}

impl WalkingDirection {
    /// A closed stride, until GNSS calibrated the carrying: its axis (or the top edge
    /// of a phone held to be read) initialises the carrying, or pulls it.
    pub(super) fn learn_carrying(&mut self, stats: &StrideStats, step_hz: f64) {
        if self.carrying.calibrated {
            return;
        }
        let Some((axis_ahrs, ratio)) = stats.axis() else {
            return;
        };
        if ratio < MIN_AXIS_RATIO {
            return;
        }
        let q = self.quat();
        let top_edge = self.carrying.top_edge_if_read(&q, axis_ahrs);
        if self.carrying.forward_known {
            self.pull_towards_axis(axis_ahrs, ratio, top_edge);
        } else {
            let dir_ahrs =
                top_edge.unwrap_or_else(|| self.forward_of_axis(stats, axis_ahrs, step_hz));
            self.carrying.initialise(&q, dir_ahrs);
        }
    }

    /// Which way along the stride axis is forward (AHRS frame): after a carrying
    /// change, continuity with the last walking direction; else the gait cue (walking:
    /// forward acceleration anti-correlated with vertical velocity; running:
    /// correlated).
    fn forward_of_axis(&self, stats: &StrideStats, axis_ahrs: f64, step_hz: f64) -> f64 {
        let forward_is_axis = if self.known {
            let axis = wrap(axis_ahrs - self.yaw.mu_rad);
            wrap(axis - self.azimuth_rad).abs() <= 0.5 * PI
        } else {
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
    }

    /// Pull the carrying towards the top edge, or of the stride axis' two directions
    /// the one nearer the current estimate. The carrying is constant until it changes:
    /// the stride axes are averaged (gain 1/n), down to a floor that follows slow changes.
    fn pull_towards_axis(&mut self, axis_ahrs: f64, ratio: f64, top_edge: Option<f64>) {
        let quality =
            ((ratio - MIN_AXIS_RATIO) / (AXIS_QUALITY_SPAN * MIN_AXIS_RATIO)).clamp(0.0, 1.0);
        let axis = wrap(axis_ahrs - self.yaw.mu_rad);
        let target = match top_edge {
            Some(top) => wrap(top - self.yaw.mu_rad),
            None if wrap(axis - self.azimuth_rad).abs() > 0.5 * PI => wrap(axis + PI),
            None => axis,
        };
        let gain = (1.0 / (self.carrying.axis_strides + 1.0)).clamp(AXIS_MIN_GAIN, AXIS_GAIN);
        self.carrying.axis_strides += quality;
        self.carrying
            .rotate(gain * quality * wrap(target - self.azimuth_rad));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lasting_jump_of_gravity_is_a_new_carrying() {
        let mut c = Carrying::default();
        c.set([0.0, 1.0, 0.0]);
        assert!(!c.follow_up(0.01, Vector3::z()));
        // Swaying by 0.3 rad for a second: the same carrying.
        let sway = Vector3::new(0.3f64.sin(), 0.0, 0.3f64.cos());
        for _ in 0..100 {
            assert!(!c.follow_up(0.01, sway));
        }
        // Turned by 1.2 rad for good: a new carrying within seconds.
        let turned = Vector3::new(1.2f64.sin(), 0.0, 1.2f64.cos());
        let at = (0..1000).position(|_| c.follow_up(0.01, turned)).unwrap();
        assert!((50..400).contains(&at), "{at}");
        assert!(!c.forward_known && !c.calibrated);
    }

    #[test]
    fn rotates_about_the_body_up() {
        let mut c = Carrying {
            up_fast: [0.0, 0.0, 2.0],
            forward_body: [0.0, 1.0, 0.0],
            ..Carrying::default()
        };
        // Clockwise seen from above: +y (north of a level phone) towards +x (east).
        c.rotate(0.5 * PI);
        let f = c.forward_body;
        assert!(
            (f[0] - 1.0).abs() < 1e-12 && f[1].abs() < 1e-12 && f[2] == 0.0,
            "{f:?}"
        );
    }
}
