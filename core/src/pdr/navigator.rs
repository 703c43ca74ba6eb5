//! `PhoneNavigator`: pedestrian dead reckoning with a phone, corrected by GNSS.
//!
//! Per IMU sample: the AHRS ([`crate::ahrs`]) gives the orientation and the linear
//! acceleration in the earth frame; the step detector ([`crate::stepdetect`]) finds
//! steps in the raw acceleration; the walking direction ([`super::heading`]) follows
//! the body's motion, not the phone's pointing. Per step: the step-length estimator
//! ([`crate::steplength`]) gives a length, and the position advances by it along the
//! walking direction. GNSS fixes, when pushed, anchor the local East-North-Up frame
//! (at the first fix), correct the position (a 2-D Kalman update weighted by the
//! fix's accuracy against the dead-reckoning uncertainty), calibrate step length, and
//! give the walking direction its course.
//!
//! Before the first fix, positions are relative to where the navigator started;
//! at the first fix the track is re-expressed around it.

use nalgebra::Vector3;

use crate::ahrs::{Ahrs, AhrsError, AhrsSettings, EarthFrame, ImuSample};
use crate::geo::LocalFrame;
use crate::pace::GnssFix;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stepdetect::{StepDetectError, StepDetector, StepDetectorConfig, StepEvent};
use crate::steplength::{StepLengthConfig, StepLengthError, StepLengthEstimator, StepLengthModel};

use super::heading::WalkingDirection;

const SNAPSHOT_KIND: u8 = 5;
const SNAPSHOT_VERSION: u16 = 1;
/// 68 % radius of a circular 2-D Gaussian is 1.515 σ per axis.
const RADIUS68_TO_SIGMA: f64 = 1.0 / 1.515;
/// Per-axis σ assumed for a fix without accuracy, m.
const DEFAULT_FIX_SIGMA_M: f64 = 5.0;
/// Dead-reckoning position noise per step: share of the step length along track
/// (step-length error) and walking-direction uncertainty across it, rad.
const STEP_LENGTH_REL_SIGMA: f64 = 0.05;
const DIRECTION_SIGMA_RAD: f64 = 0.08;
/// A GNSS course needs this much displacement and time between fixes (m, s).
const COURSE_MIN_DISTANCE_M: f64 = 10.0;
const COURSE_MIN_TIME_S: f64 = 5.0;
/// ... and a walking direction that turned less than this meanwhile, rad.
const COURSE_MAX_TURN_RAD: f64 = 0.35;
/// Weight of one GNSS course in the walking direction.
const COURSE_WEIGHT: f64 = 0.3;
/// Fixes with a worse accuracy give no course, m.
const COURSE_MAX_ACCURACY_M: f64 = 15.0;

/// Why the navigator rejected an input (its state is unchanged).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NavError {
    #[error("IMU sample: {0}")]
    Imu(#[from] AhrsError),
    #[error("step detection: {0}")]
    Steps(#[from] StepDetectError),
    #[error("step length: {0}")]
    StepLength(#[from] StepLengthError),
    #[error("GNSS fix: {field} = {value} is not valid ({expected})")]
    Fix {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
    #[error("cannot restore snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
}

/// Configuration of a [`PhoneNavigator`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavigatorConfig {
    pub ahrs: AhrsSettings,
    pub detector: StepDetectorConfig,
    pub step_length_model: StepLengthModel,
    pub step_length: StepLengthConfig,
}

impl Default for NavigatorConfig {
    fn default() -> Self {
        Self {
            ahrs: AhrsSettings::default(),
            detector: StepDetectorConfig::default(),
            step_length_model: StepLengthModel::Linear,
            step_length: StepLengthConfig::default(),
        }
    }
}

/// Where the pedestrian is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavEstimate {
    /// Time of the newest input, s.
    pub t_s: f64,
    /// Position in the local ENU frame (anchored at the first fix; before it, at the
    /// start), metres.
    pub east_m: f64,
    pub north_m: f64,
    /// 1-σ of the position per axis, metres.
    pub position_std_m: f64,
    /// WGS84 position once a fix anchored the frame.
    pub lat_deg: Option<f64>,
    pub lon_deg: Option<f64>,
    /// Walking direction, radians clockwise from north, once known.
    pub walking_azimuth_rad: Option<f64>,
    /// Walking direction minus the phone's heading, radians (how it is carried).
    pub heading_offset_rad: Option<f64>,
    /// Steps detected.
    pub steps: u64,
    /// Distance walked (sum of step lengths), metres.
    pub distance_m: f64,
    /// Length of the last step, metres.
    pub step_length_m: Option<f64>,
}

/// Pedestrian dead reckoning with a phone.
#[derive(Clone, Debug)]
pub struct PhoneNavigator {
    config: NavigatorConfig,
    ahrs: Ahrs,
    detector: StepDetector,
    lengths: StepLengthEstimator,
    direction: WalkingDirection,
    frame: Option<LocalFrame>,
    east_m: f64,
    north_m: f64,
    pos_var_m2: f64,
    distance_m: f64,
    steps: u64,
    last_step_length_m: f64,
    last_t_s: f64,
    last_fix_t_s: f64,
    /// Fix and walking azimuth where the current course baseline starts.
    course_anchor: (f64, f64, f64, f64),
}

fn check_fix(fix: &GnssFix) -> Result<(), NavError> {
    let bad = |field, value, expected| {
        Err(NavError::Fix {
            field,
            value,
            expected,
        })
    };
    if !fix.t_s.is_finite() {
        return bad("t_s", fix.t_s, "finite");
    }
    if fix.lat_deg.is_nan() || fix.lat_deg.abs() > 90.0 {
        return bad("lat_deg", fix.lat_deg, "−90..=90");
    }
    if fix.lon_deg.is_nan() || fix.lon_deg.abs() > 180.0 {
        return bad("lon_deg", fix.lon_deg, "−180..=180");
    }
    if let Some(a) = fix.horizontal_accuracy_m {
        if !(a.is_finite() && a >= 0.0) {
            return bad("horizontal_accuracy_m", a, "≥ 0");
        }
    }
    Ok(())
}

impl PhoneNavigator {
    pub fn new(config: NavigatorConfig) -> Result<Self, NavError> {
        Ok(Self {
            ahrs: Ahrs::new(config.ahrs)?,
            detector: StepDetector::new(config.detector)?,
            lengths: StepLengthEstimator::new(config.step_length_model, config.step_length)?,
            config,
            direction: WalkingDirection::new(),
            frame: None,
            east_m: 0.0,
            north_m: 0.0,
            pos_var_m2: 0.0,
            distance_m: 0.0,
            steps: 0,
            last_step_length_m: f64::NAN,
            last_t_s: f64::NAN,
            last_fix_t_s: f64::NAN,
            course_anchor: (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
        })
    }

    pub fn config(&self) -> &NavigatorConfig {
        &self.config
    }

    /// One IMU sample (sensor frame; the AHRS settings say how to remap it).
    pub fn push_imu(&mut self, s: &ImuSample) -> Result<(), NavError> {
        // Both engines check the same things (finite, increasing time, m/s²): the
        // detector's check runs first, without side effects, so a rejection by either
        // leaves both untouched (the AHRS rejects before changing anything too).
        self.detector.check_sample(s.t_s, s.accel_mps2)?;
        self.ahrs
            .update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)?;
        let first = self.detector.push(s.t_s, s.accel_mps2)?;
        self.last_t_s = s.t_s;
        if let Some(o) = self.ahrs.output() {
            let q = o.unit_quaternion();
            let w = Vector3::from(s.gyro_rads) - Vector3::from(o.gyro_bias_rads);
            let w_earth = q * w;
            let a = o.linear_accel_earth_mps2;
            let (lin_enu, rate_up) = match o.frame {
                EarthFrame::Enu => (a, w_earth.z),
                EarthFrame::Ned => ([a[1], a[0], -a[2]], -w_earth.z),
            };
            self.direction
                .push_sample(s.t_s, lin_enu, rate_up, Some(o.heading_rad));
        }
        if let Some(step) = first {
            self.on_step(&step)?;
        }
        while let Some(step) = self.detector.pop_step() {
            self.on_step(&step)?;
        }
        Ok(())
    }

    fn on_step(&mut self, step: &StepEvent) -> Result<(), NavError> {
        let hz = step.frequency_hz();
        self.direction
            .push_step(if hz.is_finite() { hz } else { 1.8 });
        let length = self.lengths.push_step(step)?;
        self.steps += 1;
        self.last_step_length_m = length;
        self.distance_m += length;
        if let Some(az) = self.direction.azimuth_rad() {
            self.east_m += length * az.sin();
            self.north_m += length * az.cos();
            self.pos_var_m2 +=
                (STEP_LENGTH_REL_SIGMA * length).powi(2) + (DIRECTION_SIGMA_RAD * length).powi(2);
        }
        Ok(())
    }

    /// One GNSS fix: anchors the frame at the first one, then corrects the position,
    /// calibrates step length and the walking direction.
    pub fn push_fix(&mut self, fix: &GnssFix) -> Result<NavEstimate, NavError> {
        check_fix(fix)?;
        if fix.t_s <= self.last_fix_t_s {
            return Err(NavError::Fix {
                field: "t_s",
                value: fix.t_s,
                expected: "after the previous fix",
            });
        }
        let sigma = fix
            .horizontal_accuracy_m
            .map_or(DEFAULT_FIX_SIGMA_M, |a| (a * RADIUS68_TO_SIGMA).max(0.5));
        let frame = match self.frame {
            Some(f) => f,
            None => {
                let f = LocalFrame::new(fix.lat_deg, fix.lon_deg, 0.0);
                self.frame = Some(f);
                self.east_m = 0.0;
                self.north_m = 0.0;
                self.pos_var_m2 = sigma * sigma;
                f
            }
        };
        let p = frame.to_enu(fix.lat_deg, fix.lon_deg, 0.0);
        self.lengths
            .push_gnss_fix(fix.t_s, p[0], p[1], fix.horizontal_accuracy_m)?;
        // Position: scalar-variance Kalman update, robust to outliers.
        let r = sigma * sigma;
        let (de, dn) = (p[0] - self.east_m, p[1] - self.north_m);
        let nis = (de * de + dn * dn) / (self.pos_var_m2 + r);
        let r_eff = if nis > 9.21 { r * nis / 9.21 } else { r };
        let k = self.pos_var_m2 / (self.pos_var_m2 + r_eff);
        self.east_m += k * de;
        self.north_m += k * dn;
        self.pos_var_m2 *= 1.0 - k;
        self.observe_course(fix, p);
        self.last_fix_t_s = fix.t_s;
        self.last_t_s = self.last_t_s.max(fix.t_s);
        Ok(self.estimate())
    }

    /// The walking direction learns its course (and its forward sign) from the GNSS
    /// displacement over a straight stretch.
    fn observe_course(&mut self, fix: &GnssFix, p: [f64; 3]) {
        let az_now = self.direction.azimuth_rad().unwrap_or(f64::NAN);
        let good = fix
            .horizontal_accuracy_m
            .is_none_or(|a| a <= COURSE_MAX_ACCURACY_M);
        let (t0, e0, n0, az0) = self.course_anchor;
        if !good || !t0.is_finite() {
            self.course_anchor = (fix.t_s, p[0], p[1], az_now);
            return;
        }
        let (de, dn) = (p[0] - e0, p[1] - n0);
        let d = de.hypot(dn);
        if d < COURSE_MIN_DISTANCE_M || fix.t_s - t0 < COURSE_MIN_TIME_S {
            return;
        }
        let turned = super::heading::wrap(az_now - az0).abs();
        if az_now.is_nan() || az0.is_nan() || turned < COURSE_MAX_TURN_RAD {
            self.direction.observe_course(de.atan2(dn), COURSE_WEIGHT);
        }
        self.course_anchor = (
            fix.t_s,
            p[0],
            p[1],
            self.direction.azimuth_rad().unwrap_or(f64::NAN),
        );
    }

    /// Where the pedestrian is now.
    pub fn estimate(&self) -> NavEstimate {
        let geo = self.frame.map(|f| f.to_geodetic(self.east_m, self.north_m));
        NavEstimate {
            t_s: self.last_t_s,
            east_m: self.east_m,
            north_m: self.north_m,
            position_std_m: self.pos_var_m2.sqrt(),
            lat_deg: geo.map(|g| g.0),
            lon_deg: geo.map(|g| g.1),
            walking_azimuth_rad: self.direction.azimuth_rad(),
            heading_offset_rad: self.direction.heading_offset_rad(),
            steps: self.steps,
            distance_m: self.distance_m,
            step_length_m: self
                .last_step_length_m
                .is_finite()
                .then_some(self.last_step_length_m),
        }
    }

    /// The whole state (sub-engines included) as bytes.
    pub fn snapshot(&self) -> Vec<u8> {
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.bytes(&self.ahrs.snapshot());
        w.bytes(&self.detector.snapshot());
        w.bytes(&self.lengths.snapshot());
        self.direction.write(&mut w);
        match self.frame {
            Some(f) => {
                w.bool(true);
                let (lat, lon, alt) = f.origin();
                w.f64s(&[lat, lon, alt]);
            }
            None => w.bool(false),
        }
        w.f64s(&[
            self.east_m,
            self.north_m,
            self.pos_var_m2,
            self.distance_m,
            self.last_step_length_m,
            self.last_t_s,
            self.last_fix_t_s,
            self.course_anchor.0,
            self.course_anchor.1,
            self.course_anchor.2,
            self.course_anchor.3,
        ]);
        w.u64(self.steps);
        w.finish()
    }

    /// A navigator continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, NavError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let ahrs = Ahrs::restore(r.bytes()?)?;
        let detector = StepDetector::restore(r.bytes()?)?;
        let lengths = StepLengthEstimator::restore(r.bytes()?)?;
        let direction = WalkingDirection::read(&mut r)?;
        let frame = if r.bool()? {
            let (lat, lon, alt) = (r.f64()?, r.f64()?, r.f64()?);
            if !(lat.abs() <= 90.0 && lon.abs() <= 180.0 && alt.is_finite()) {
                return Err(SnapshotError::Invalid("frame origin").into());
            }
            Some(LocalFrame::new(lat, lon, alt))
        } else {
            None
        };
        let mut v = [0.0; 11];
        r.f64s(&mut v)?;
        let steps = r.u64()?;
        r.end()?;
        let config = NavigatorConfig {
            ahrs: *ahrs.settings(),
            detector: *detector.config(),
            step_length_model: lengths.model(),
            step_length: *lengths.config(),
        };
        Ok(Self {
            config,
            ahrs,
            detector,
            lengths,
            direction,
            frame,
            east_m: v[0],
            north_m: v[1],
            pos_var_m2: v[2],
            distance_m: v[3],
            last_step_length_m: v[4],
            last_t_s: v[5],
            last_fix_t_s: v[6],
            course_anchor: (v[7], v[8], v[9], v[10]),
            steps,
        })
    }
}
