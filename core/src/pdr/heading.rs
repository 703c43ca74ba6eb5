//! Walking direction from a phone carried anywhere.
//!
//! A phone's own heading (where its top points) says little about where its owner
//! walks: in a front pocket the screen faces the thigh, in a bag it can point anywhere.
//! What every placement shares is the body's motion. Walking makes the horizontal
//! acceleration oscillate mostly along the walking direction (the centre of mass
//! brakes and pushes once per step) and less across it (sway). So, in the earth frame:
//!
//! 1. **Axis per stride**: principal axis of the horizontal linear acceleration over
//!    a stride (two steps), by a 2×2 covariance eigen-decomposition; an axis, i.e. an
//!    angle modulo π, with a quality = how much more variance lies along it than across.
//! 2. **Turns between strides**: the phone's angular rate about the vertical (earth
//!    frame), integrated. It is defined in every orientation (a yaw angle is not for an
//!    upright phone) and follows turns within a step.
//! 3. **Complementary fusion**: the walking azimuth follows the gyro and is pulled
//!    towards each stride's axis (the candidate of the two directions closest to the
//!    current estimate), weighted by the stride's quality.
//! 4. **Forward or backward**: the axis leaves a 180° ambiguity. It is resolved by a GNSS
//!    course when one is available (`observe_course`), and otherwise kept by continuity.
//!    At start without GNSS, the inverted-pendulum cue is used: when walking, forward
//!    speed is highest when the body is lowest, so forward acceleration is
//!    anti-correlated with vertical velocity (for running, a spring-mass gait, the sign
//!    flips; cadence above `RUNNING_STEP_HZ` selects it).
//!
//! Azimuths are radians clockwise from north in (−π, π]; east = sin, north = cos.
//! The heading offset of the phone (walking azimuth − phone azimuth) is an output.

use std::f64::consts::PI;

use crate::snapshot::{Reader, SnapshotError, Writer};

/// Step frequency above which the gait is taken as running (spring-mass), Hz.
pub const RUNNING_STEP_HZ: f64 = 2.4;
/// Gain of the pull towards a stride's axis at full quality (per stride).
const AXIS_GAIN: f64 = 0.3;
/// Strides whose along/across variance ratio is below this carry no direction.
const MIN_AXIS_RATIO: f64 = 1.5;
/// Learning rate of the stride-axis bias from GNSS courses.
const AXIS_BIAS_GAIN: f64 = 0.2;

/// Wrap an axis difference (defined modulo π) to (−π/2, π/2].
fn wrap_axis(a: f64) -> f64 {
    let x = wrap(2.0 * a) / 2.0;
    if x <= -0.5 * PI {
        x + PI
    } else {
        x
    }
}

/// Wrap an angle to (−π, π].
pub fn wrap(a: f64) -> f64 {
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
    /// Vertical velocity (integrated vertical acceleration, mean removed later) and its
    /// products with the horizontal components, for the forward/backward cue.
    vz: f64,
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

    /// Sign of the covariance between acceleration along azimuth `az` and vertical
    /// velocity (mean removed).
    fn forward_vz_cov(&self, az: f64) -> f64 {
        let (s, c) = az.sin_cos();
        let n = self.n.max(1.0);
        let a_mean = (s * self.se + c * self.sn) / n;
        let vz_mean = self.svz / n;
        (s * self.sevz + c * self.snvz) / n - a_mean * vz_mean
    }
}

/// Estimates the walking azimuth and the phone's heading offset.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkingDirection {
    azimuth_rad: f64,
    known: bool,
    /// Sign fixed by GNSS (or by a confident cue) rather than assumed.
    sign_resolved: bool,
    stride: StrideStats,
    steps_in_stride: u32,
    vz_mps: f64,
    last_t_s: f64,
    phone_azimuth_rad: f64,
    offset_rad: f64,
    /// Systematic difference between GNSS course and the stride axis (body motion is
    /// not exactly fore-aft in every placement: a pocket also sees the thigh's swing),
    /// learned while GNSS is good, applied to every stride axis.
    axis_bias_rad: f64,
    /// Stride axes since the last course, as doubled-angle sums (axes are modulo π).
    axis_sum_cos2: f64,
    axis_sum_sin2: f64,
}

impl Default for WalkingDirection {
    fn default() -> Self {
        Self::new()
    }
}

impl WalkingDirection {
    pub fn new() -> Self {
        Self {
            azimuth_rad: 0.0,
            known: false,
            sign_resolved: false,
            stride: StrideStats::default(),
            steps_in_stride: 0,
            vz_mps: 0.0,
            last_t_s: f64::NAN,
            phone_azimuth_rad: f64::NAN,
            offset_rad: f64::NAN,
            axis_bias_rad: 0.0,
            axis_sum_cos2: 0.0,
            axis_sum_sin2: 0.0,
        }
    }

    /// Walking azimuth, radians clockwise from north, once known.
    pub fn azimuth_rad(&self) -> Option<f64> {
        self.known.then_some(self.azimuth_rad)
    }

    /// Whether the forward/backward ambiguity was resolved by GNSS.
    pub fn sign_resolved(&self) -> bool {
        self.sign_resolved
    }

    /// Walking azimuth minus the phone's azimuth, radians (how the phone is carried).
    pub fn heading_offset_rad(&self) -> Option<f64> {
        (self.known && self.offset_rad.is_finite()).then_some(self.offset_rad)
    }

    /// One IMU sample in the earth frame: linear acceleration east/north/up (gravity
    /// removed), the angular rate about the vertical (rad/s, counter-clockwise seen
    /// from above, i.e. the ENU z component), and the phone's own azimuth if known.
    pub fn push_sample(
        &mut self,
        t_s: f64,
        lin_acc_enu_mps2: [f64; 3],
        yaw_rate_up_rads: f64,
        phone_azimuth_rad: Option<f64>,
    ) {
        let dt = if self.last_t_s.is_finite() {
            (t_s - self.last_t_s).clamp(0.0, 0.1)
        } else {
            0.0
        };
        self.last_t_s = t_s;
        // A counter-clockwise (positive up) rotation decreases a clockwise azimuth.
        if self.known {
            self.azimuth_rad = wrap(self.azimuth_rad - yaw_rate_up_rads * dt);
        }
        // Vertical velocity, leaky to stay bounded (time constant ~1 s).
        self.vz_mps = self.vz_mps * (1.0 - dt) + lin_acc_enu_mps2[2] * dt;
        self.stride
            .add(lin_acc_enu_mps2[0], lin_acc_enu_mps2[1], self.vz_mps);
        if let Some(p) = phone_azimuth_rad {
            self.phone_azimuth_rad = p;
            if self.known {
                self.offset_rad = wrap(self.azimuth_rad - p);
            }
        }
    }

    /// A step was detected; every second step closes a stride and updates the axis.
    /// `step_hz` selects the walking or running cue for the forward direction.
    pub fn push_step(&mut self, step_hz: f64) {
        self.steps_in_stride += 1;
        if self.steps_in_stride < 2 {
            return;
        }
        self.steps_in_stride = 0;
        let stats = std::mem::take(&mut self.stride);
        let Some((axis, ratio)) = stats.axis() else {
            return;
        };
        if ratio < MIN_AXIS_RATIO {
            return;
        }
        let quality = ((ratio - MIN_AXIS_RATIO) / (4.0 * MIN_AXIS_RATIO)).clamp(0.0, 1.0);
        self.axis_sum_cos2 += quality * (2.0 * axis).cos();
        self.axis_sum_sin2 += quality * (2.0 * axis).sin();
        let axis = wrap(axis + self.axis_bias_rad);
        if !self.known {
            // Choose forward by the gait cue: walking → forward acceleration is
            // anti-correlated with vertical velocity; running → correlated.
            let cov = stats.forward_vz_cov(axis);
            let running = step_hz > RUNNING_STEP_HZ;
            let forward_is_axis = if running { cov > 0.0 } else { cov < 0.0 };
            self.azimuth_rad = if forward_is_axis {
                axis
            } else {
                wrap(axis + PI)
            };
            self.known = true;
            return;
        }
        // Of the axis' two directions, take the one nearer the current estimate.
        let mut target = axis;
        if wrap(target - self.azimuth_rad).abs() > 0.5 * PI {
            target = wrap(target + PI);
        }
        self.azimuth_rad =
            wrap(self.azimuth_rad + AXIS_GAIN * quality * wrap(target - self.azimuth_rad));
        if self.phone_azimuth_rad.is_finite() {
            self.offset_rad = wrap(self.azimuth_rad - self.phone_azimuth_rad);
        }
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        let s = &self.stride;
        w.f64s(&[
            self.azimuth_rad,
            s.n,
            s.se,
            s.sn,
            s.see,
            s.snn,
            s.sen,
            s.vz,
            s.svz,
        ]);
        w.f64s(&[
            s.sevz,
            s.snvz,
            self.vz_mps,
            self.last_t_s,
            self.phone_azimuth_rad,
        ]);
        w.f64s(&[
            self.offset_rad,
            self.axis_bias_rad,
            self.axis_sum_cos2,
            self.axis_sum_sin2,
        ]);
        w.bool(self.known);
        w.bool(self.sign_resolved);
        w.u64(self.steps_in_stride as u64);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 14];
        r.f64s(&mut v)?;
        Ok(Self {
            azimuth_rad: v[0],
            stride: StrideStats {
                n: v[1],
                se: v[2],
                sn: v[3],
                see: v[4],
                snn: v[5],
                sen: v[6],
                vz: v[7],
                svz: v[8],
                sevz: v[9],
                snvz: v[10],
            },
            vz_mps: v[11],
            last_t_s: v[12],
            phone_azimuth_rad: v[13],
            offset_rad: r.f64()?,
            axis_bias_rad: r.f64()?,
            axis_sum_cos2: r.f64()?,
            axis_sum_sin2: r.f64()?,
            known: r.bool()?,
            sign_resolved: r.bool()?,
            steps_in_stride: r.len(2)? as u32,
        })
    }

    /// A GNSS course over ground (azimuth, rad) while walking straight: resolves the
    /// forward/backward ambiguity and pulls the estimate towards it with `weight` (0..1).
    pub fn observe_course(&mut self, course_rad: f64, weight: f64) {
        if !course_rad.is_finite() {
            return;
        }
        let w = weight.clamp(0.0, 1.0);
        // Learn the stride-axis bias: course minus the mean stride axis since the
        // last course (both as axes, modulo π).
        if self.axis_sum_cos2.hypot(self.axis_sum_sin2) > 1.0 {
            let mean_axis = 0.5 * self.axis_sum_sin2.atan2(self.axis_sum_cos2);
            let diff = wrap_axis(course_rad - mean_axis);
            self.axis_bias_rad = wrap_axis(
                self.axis_bias_rad + AXIS_BIAS_GAIN * wrap_axis(diff - self.axis_bias_rad),
            );
        }
        self.axis_sum_cos2 = 0.0;
        self.axis_sum_sin2 = 0.0;
        if !self.known {
            self.azimuth_rad = wrap(course_rad);
            self.known = true;
        } else if wrap(course_rad - self.azimuth_rad).abs() > 0.5 * PI && !self.sign_resolved {
            // The axis was right, the sign wrong.
            self.azimuth_rad = wrap(self.azimuth_rad + PI);
        }
        self.sign_resolved = true;
        self.azimuth_rad = wrap(self.azimuth_rad + w * wrap(course_rad - self.azimuth_rad));
        if self.phone_azimuth_rad.is_finite() {
            self.offset_rad = wrap(self.azimuth_rad - self.phone_azimuth_rad);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Rng;

    /// Earth-frame linear acceleration of a walker heading `az` (inverted pendulum:
    /// forward acceleration = −k · vertical velocity) plus sway and noise.
    fn walk(
        wd: &mut WalkingDirection,
        rng: &mut Rng,
        t0: f64,
        seconds: f64,
        az_of_t: impl Fn(f64) -> f64,
        step_hz: f64,
    ) -> f64 {
        let fs = 100.0;
        let mut next_step = t0 + 1.0 / step_hz;
        let n = (seconds * fs) as usize;
        let mut t = t0;
        for i in 0..n {
            t = t0 + i as f64 / fs;
            let ph = 2.0 * PI * step_hz * (t - t0);
            let vz = 0.15 * ph.cos(); // vertical velocity of the body
            let a_up = -0.15 * 2.0 * PI * step_hz * ph.sin();
            let a_fwd = -2.0 * vz / 0.15 * 0.6 + 0.2 * rng.normal();
            let a_side = 0.4 * (0.5 * ph).sin() + 0.2 * rng.normal();
            let az = az_of_t(t);
            let (s, c) = az.sin_cos();
            let e = a_fwd * s + a_side * c;
            let nn = a_fwd * c - a_side * s;
            let rate = -(az_of_t(t + 0.01) - az_of_t(t)) / 0.01;
            wd.push_sample(t, [e, nn, a_up], rate, Some(wrap(az - 1.0)));
            if t >= next_step {
                wd.push_step(step_hz);
                next_step += 1.0 / step_hz;
            }
        }
        t
    }

    #[test]
    fn finds_the_walking_direction_and_the_phone_offset() {
        for az in [0.3, 2.0, -2.5] {
            let mut wd = WalkingDirection::new();
            let mut rng = Rng::new(1);
            walk(&mut wd, &mut rng, 0.0, 30.0, |_| az, 1.8);
            let est = wd.azimuth_rad().unwrap();
            assert!(wrap(est - az).abs() < 0.1, "{az}: {est}");
            assert!((wd.heading_offset_rad().unwrap() - 1.0).abs() < 0.1);
        }
    }

    #[test]
    fn follows_turns_and_gnss_fixes_the_sign() {
        let mut wd = WalkingDirection::new();
        let mut rng = Rng::new(2);
        // Straight north, then a 90° right turn over 3 s, then east.
        let az = |t: f64| {
            if t < 20.0 {
                0.0
            } else if t < 23.0 {
                0.5 * PI * (t - 20.0) / 3.0
            } else {
                0.5 * PI
            }
        };
        walk(&mut wd, &mut rng, 0.0, 40.0, az, 1.8);
        assert!(wrap(wd.azimuth_rad().unwrap() - 0.5 * PI).abs() < 0.12);
        // A GNSS course pointing the other way flips a wrong sign once.
        let mut wrong = WalkingDirection::new();
        wrong.push_sample(0.0, [0.0; 3], 0.0, None);
        wrong.observe_course(0.0, 0.5);
        assert!(wrong.sign_resolved());
        assert!(wrap(wrong.azimuth_rad().unwrap()).abs() < 1e-9);
    }

    #[test]
    fn wrap_is_in_range() {
        for a in [-10.0, -PI, 0.0, PI, 7.0] {
            let w = wrap(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
        }
    }
}
