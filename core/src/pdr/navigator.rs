//! `PhoneNavigator`: pedestrian dead reckoning with a phone, corrected by GNSS.
//!
//! Per IMU sample: the AHRS ([`crate::ahrs`], run as an IMU filter: tilt from the
//! accelerometer, yaw from the gyroscope) gives the orientation and the linear
//! acceleration in the earth frame; the step detector ([`crate::stepdetect`]) finds
//! steps in the raw acceleration; the walking direction ([`super::heading`]) combines
//! the orientation, the magnetometer (when given: it corrects the AHRS yaw) and how the
//! phone is carried. Per step: the phone's vertical displacement over the step
//! ([`super::VerticalHistory`], from the attitude) and the step-length estimator
//! ([`crate::steplength`], by default the inverted pendulum) give a length, and the
//! position advances by it along the step's walking direction. GNSS
//! fixes, when pushed, anchor the local East-North-Up frame (at the first fix),
//! correct the position (a 2-D Kalman update weighted by the fix's accuracy against
//! the dead-reckoning uncertainty), calibrate step length, and calibrate how the phone
//! is carried: the angle between the GNSS displacement and the dead-reckoned one over
//! the same stretch (≥ 15 m) rotates the walking direction's carrying estimate.
//!
//! Before the first fix, positions are relative to where the navigator started;
//! at the first fix the track is re-expressed around it. Without any GNSS (indoors)
//! it dead-reckons from where it started. Each step is placed with the walking
//! direction over its own span (steps are released by the detector up to seconds
//! late); steps released before the walking direction is known are held and placed
//! once it is. [`PhoneNavigator::recent_steps`] gives the placed steps (the
//! trajectory at step times). A personal [`PdrCalibration`] (step-length model,
//! carrying) can be loaded and is kept in the snapshot; the orientation can come
//! from outside ([`PhoneNavigator::push_imu_with_attitude`]) instead of the AHRS.
//! Separate accelerometer, gyroscope and magnetometer events (what a phone delivers)
//! go in through [`PhoneNavigator::push_event`], merged by [`crate::imu::ImuMerger`].

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::ahrs::{Ahrs, AhrsError, AhrsSettings, EarthFrame, ImuSample};
use crate::batch::{self, Batch};
use crate::geo::LocalFrame;
use crate::imu::{ImuEvent, ImuMerger, MergeConfig, MergeCounts, MergeError, SensorKind};
use crate::input::{self, InputError, Stream, TimeGuard};
use crate::pace::GnssFix;
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stats::{CHI2_99_2DOF, RADIUS68_TO_SIGMA};
use crate::stepdetect::{StepDetectError, StepDetector, StepDetectorConfig, StepEvent, StepOrigin};
use crate::steplength::{StepLengthConfig, StepLengthError, StepLengthEstimator, StepLengthModel};

use super::calibration::{CalibrationError, PdrCalibration};
use super::heading::WalkingDirection;
use super::scale::StepScale;
use super::vertical::VerticalHistory;

const SNAPSHOT_KIND: u8 = 5;
/// Version 11: the walking direction's bridge of the heading across dropped samples;
/// version 10: each deferred and recent step's origin (seen or filled by the detector);
/// version 9: the step lengths' scale from GNSS stretches (8: the event merger; 7: the
/// walking direction's `gyro_calibrated` flag; 6: the vertical history
/// and each step's vertical displacement; 5: gait initiation in the step-length state;
/// 4: the input layer's time state per stream; 3 added the attitude history, deferred
/// and recent steps).
const SNAPSHOT_VERSION: u16 = 11;
/// Steps waiting for the carrying to be known, and recent placed steps kept.
const DEFERRED_STEPS: usize = 32;
pub const RECENT_STEPS: usize = 32;
/// Span of a step whose duration is unknown (first of a bout) or implausibly long, s.
const DEFAULT_STEP_S: f64 = 0.55;
const MAX_STEP_S: f64 = 2.0;
/// Per-axis σ assumed for a fix without accuracy, m, and the least σ of any fix, m.
const DEFAULT_FIX_SIGMA_M: f64 = 5.0;
const MIN_FIX_SIGMA_M: f64 = 0.5;
/// Dead-reckoning position noise per step: share of the step length along track
/// (step-length error) and walking-direction uncertainty across it, rad.
const STEP_LENGTH_REL_SIGMA: f64 = 0.05;
const DIRECTION_SIGMA_RAD: f64 = 0.08;
/// A GNSS stretch (displacement compared with dead reckoning) needs this much
/// displacement and time between fixes (m, s).
const COURSE_MIN_DISTANCE_M: f64 = 15.0;
const COURSE_MIN_TIME_S: f64 = 5.0;
/// ... and no longer than this (a longer gap restarts the stretch), s.
const COURSE_MAX_TIME_S: f64 = 60.0;
/// Fixes with a worse accuracy give no stretch, m.
const COURSE_MAX_ACCURACY_M: f64 = 15.0;
/// ... nor a stretch whose dead-reckoned displacement is under this share of the GNSS
/// one (no walk to compare).
const COURSE_MIN_DR_SHARE: f64 = 0.5;

/// Why the navigator rejected an input, a configuration or a snapshot (its state is
/// unchanged).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NavError {
    /// An IMU sample or a fix was refused at the door (see [`crate::input`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The AHRS settings are not usable.
    #[error(transparent)]
    Ahrs(AhrsError),
    /// The step detector's configuration is not usable.
    #[error(transparent)]
    Steps(StepDetectError),
    /// The step-length configuration is not usable.
    #[error(transparent)]
    StepLength(StepLengthError),
    /// A calibration could not be read or applied.
    #[error("calibration: {0}")]
    Calibration(#[from] CalibrationError),
    /// An external attitude quaternion is not of unit norm.
    #[error("attitude quaternion: norm {norm} is not 1")]
    Attitude { norm: f64 },
    /// A snapshot could not be restored.
    #[error("cannot restore navigator snapshot: {0}")]
    Snapshot(#[from] SnapshotError),
    /// The event merger's settings are not usable.
    #[error(transparent)]
    Merge(MergeError),
}

impl From<MergeError> for NavError {
    fn from(e: MergeError) -> Self {
        match e {
            MergeError::Input(e) => Self::Input(e),
            MergeError::Snapshot(s) => Self::Snapshot(s),
            e => Self::Merge(e),
        }
    }
}

impl From<AhrsError> for NavError {
    fn from(e: AhrsError) -> Self {
        match e {
            AhrsError::Input(e) => Self::Input(e),
            AhrsError::Snapshot(s) => Self::Snapshot(s),
            e => Self::Ahrs(e),
        }
    }
}

impl From<StepDetectError> for NavError {
    fn from(e: StepDetectError) -> Self {
        match e {
            StepDetectError::Input(e) => Self::Input(e),
            StepDetectError::Snapshot(s) => Self::Snapshot(s),
            e => Self::Steps(e),
        }
    }
}

impl From<StepLengthError> for NavError {
    fn from(e: StepLengthError) -> Self {
        match e {
            StepLengthError::Input(e) => Self::Input(e),
            StepLengthError::Snapshot(s) => Self::Snapshot(s),
            e => Self::StepLength(e),
        }
    }
}

/// Configuration of a [`PhoneNavigator`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavigatorConfig {
    pub ahrs: AhrsSettings,
    pub detector: StepDetectorConfig,
    pub step_length_model: StepLengthModel,
    pub step_length: StepLengthConfig,
    /// The platform removes the gyroscope's bias (Android `TYPE_GYROSCOPE`, iOS
    /// `CMDeviceMotion.rotationRate`; not `TYPE_GYROSCOPE_UNCALIBRATED` or raw
    /// `CMGyroData`). Then the magnetometer corrects the heading slowly (time constant
    /// 120 s) and the field's disturbances indoors stay out of it; `false` for a raw
    /// gyroscope, whose drift needs the fast loop (10 s). Default `true`.
    pub gyro_calibrated: bool,
    /// How separate sensor events ([`PhoneNavigator::push_event`]) become IMU samples.
    pub merge: MergeConfig,
}

impl Default for NavigatorConfig {
    fn default() -> Self {
        Self {
            ahrs: AhrsSettings::default(),
            detector: StepDetectorConfig::default(),
            // The inverted pendulum: the phone's rise and fall over a step follows
            // its length when the walker shortens steps at the same cadence (slowing
            // down, turning, indoors), which the cadence-driven linear prior cannot,
            // and more closely than Weinberg's acceleration range (docs/lab/2026-12-06-phone-history.md).
            step_length_model: StepLengthModel::Pendulum,
            step_length: StepLengthConfig::default(),
            gyro_calibrated: true,
            merge: MergeConfig::default(),
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
    /// Factor on every step length since GNSS disagreed with them (1 until then):
    /// the GNSS displacement over stretches of ≥ 15 m against the dead-reckoned one
    /// (docs/phone.md, "Cross-check with GNSS").
    pub step_scale: f64,
    /// GNSS and the step lengths disagree by more than a factor of 1.35 now (two
    /// stretches in a row); the scale is being corrected.
    pub step_scale_disagrees: bool,
}

/// A step placed on the track: where it ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NavStep {
    /// Time of the step (the detector's heel strike), s.
    pub t_s: f64,
    /// Position after the step, ENU, m (same frame as [`NavEstimate`]).
    pub east_m: f64,
    pub north_m: f64,
    pub length_m: f64,
    /// Walking azimuth over the step, radians clockwise from north.
    pub azimuth_rad: f64,
    /// Peak-to-peak vertical displacement of the phone over the step, m (what the
    /// pendulum step length uses; NaN when it could not be measured).
    pub vertical_displacement_m: f64,
    /// Whether the detector saw the step or filled it in at the walk's cadence
    /// (across dropped samples, a weak step, a pause between bouts of one walk).
    pub origin: StepOrigin,
}

/// A detected step waiting for the walking direction to be known.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PendingStep {
    t0_s: f64,
    t1_s: f64,
    length_m: f64,
    vertical_displacement_m: f64,
    origin: StepOrigin,
}

/// Pedestrian dead reckoning with a phone.
#[derive(Clone, Debug)]
pub struct PhoneNavigator {
    config: NavigatorConfig,
    ahrs: Ahrs,
    detector: StepDetector,
    lengths: StepLengthEstimator,
    direction: WalkingDirection,
    /// The vertical specific force of recent samples (the pendulum step length).
    vertical: VerticalHistory,
    frame: Option<LocalFrame>,
    east_m: f64,
    north_m: f64,
    pos_var_m2: f64,
    distance_m: f64,
    steps: u64,
    last_step_length_m: f64,
    /// Newest input of either stream, s (NaN before any).
    last_t_s: f64,
    /// Time state of the IMU and the GNSS stream.
    imu_time: TimeGuard,
    fix_time: TimeGuard,
    /// Dead-reckoned position without GNSS corrections, m.
    dr_east_m: f64,
    dr_north_m: f64,
    /// Where the current GNSS stretch starts.
    course_anchor: CourseAnchor,
    /// Steps detected before the walking direction was known: placed once it is
    /// (at their own times, from the attitude history).
    deferred: Ring<PendingStep, DEFERRED_STEPS>,
    /// The latest placed steps and how many were placed in all.
    recent: Ring<NavStep, RECENT_STEPS>,
    placed: u64,
    /// The personal calibration loaded, if any.
    calibration: Option<PdrCalibration>,
    /// The step lengths' scale that GNSS stretches taught (`super::scale`).
    scale: StepScale,
    /// Separate sensor events to IMU samples ([`Self::push_event`]).
    merger: ImuMerger,
}

/// The start of a GNSS stretch (see `observe_course`); all NaN before the first.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CourseAnchor {
    t_s: f64,
    /// The fix, local ENU, m.
    fix_east_m: f64,
    fix_north_m: f64,
    /// The dead-reckoned position at that time, m.
    dr_east_m: f64,
    dr_north_m: f64,
}

impl CourseAnchor {
    const NONE: Self = Self {
        t_s: f64::NAN,
        fix_east_m: f64::NAN,
        fix_north_m: f64::NAN,
        dr_east_m: f64::NAN,
        dr_north_m: f64::NAN,
    };
}

/// Where a sample's orientation comes from: the navigator's AHRS integrating the
/// gyroscope (whose heading the walking direction bridges across dropped samples), or
/// the caller ([`PhoneNavigator::push_imu_with_attitude`], taken as it is).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Attitude {
    Gyroscope,
    Outside,
}

/// NED → ENU rotation (swaps north and east, flips the vertical).
/// (A half turn about the horizontal axis between north and east.)
fn ned_to_enu() -> UnitQuaternion<f64> {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    UnitQuaternion::new_unchecked(Quaternion::new(0.0, h, h, 0.0))
}

impl PhoneNavigator {
    pub fn new(config: NavigatorConfig) -> Result<Self, NavError> {
        Ok(Self {
            ahrs: Ahrs::new(config.ahrs)?,
            detector: StepDetector::new(config.detector)?,
            lengths: StepLengthEstimator::new(config.step_length_model, config.step_length)?,
            config,
            direction: WalkingDirection::with_gyro_calibrated(config.gyro_calibrated),
            vertical: VerticalHistory::new(),
            frame: None,
            east_m: 0.0,
            north_m: 0.0,
            pos_var_m2: 0.0,
            distance_m: 0.0,
            steps: 0,
            last_step_length_m: f64::NAN,
            last_t_s: f64::NAN,
            imu_time: TimeGuard::new(Stream::Imu),
            fix_time: TimeGuard::new(Stream::Gnss),
            dr_east_m: 0.0,
            dr_north_m: 0.0,
            course_anchor: CourseAnchor::NONE,
            deferred: Ring::new(),
            recent: Ring::new(),
            placed: 0,
            calibration: None,
            scale: StepScale::new(),
            merger: ImuMerger::new(config.merge)?,
        })
    }

    /// A navigator with a personal calibration loaded (see [`Self::set_calibration`]).
    pub fn with_calibration(
        config: NavigatorConfig,
        calibration: &PdrCalibration,
    ) -> Result<Self, NavError> {
        let mut n = Self::new(config)?;
        n.set_calibration(calibration)?;
        Ok(n)
    }

    /// Load a personal calibration: the step-length model starts from it (its online
    /// GNSS calibration restarts from there) and, when it has one, the carrying
    /// direction. Best done before the first sample; the state is unchanged on error.
    pub fn set_calibration(&mut self, c: &PdrCalibration) -> Result<(), NavError> {
        c.validate()?;
        let lengths = StepLengthEstimator::calibrated(
            c.step_length_model,
            self.config.step_length,
            c.step_length_theta,
            c.step_length_sigma,
        )?;
        self.lengths = lengths;
        self.config.step_length_model = c.step_length_model;
        if let Some(f) = c.carrying_body {
            self.direction.set_carrying(f);
        }
        self.calibration = Some(*c);
        Ok(())
    }

    /// The personal calibration loaded, if any.
    pub fn calibration(&self) -> Option<&PdrCalibration> {
        self.calibration.as_ref()
    }

    pub fn config(&self) -> &NavigatorConfig {
        &self.config
    }

    /// Checks shared by both IMU entry points, before anything changes.
    fn check_imu(&self, s: &ImuSample) -> Result<(), NavError> {
        // The door: the whole sample is checked once here (the sub-engines check the
        // same limits again); then the detector's check (its g-units heuristic) runs
        // without side effects, so a rejection by either engine leaves both untouched
        // (the AHRS rejects before changing anything too).
        self.imu_time.check(s.t_s)?;
        input::gyro(&s.gyro_rads)?;
        input::accel(&s.accel_mps2)?;
        if let Some(m) = &s.mag_ut {
            input::mag(m)?;
        }
        self.detector.check_sample(s.t_s, s.accel_mps2)?;
        Ok(())
    }

    /// One IMU sample (sensor frame; the AHRS settings say how to remap it).
    pub fn push_imu(&mut self, s: &ImuSample) -> Result<(), NavError> {
        self.check_imu(s)?;
        // The AHRS runs without the magnetometer: the walking direction corrects its
        // yaw from the field itself (see `super::heading`).
        self.ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, None)?;
        let q_enu = self.ahrs.quaternion().map(|[w, x, y, z]| {
            let q = UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z));
            match self.config.ahrs.frame {
                EarthFrame::Enu => q,
                EarthFrame::Ned => ned_to_enu() * q,
            }
        });
        self.advance(s, q_enu, Attitude::Gyroscope)
    }

    /// One IMU sample (the engine contract's form of [`push_imu`](Self::push_imu)):
    /// the estimate after it.
    pub fn push(&mut self, s: &ImuSample) -> Result<Option<NavEstimate>, NavError> {
        self.push_imu(s)?;
        Ok(self.estimate())
    }

    /// Many IMU samples in order: one estimate per accepted sample (as
    /// [`push`](Self::push)); bad samples are skipped and reported.
    pub fn push_batch(&mut self, samples: &[ImuSample]) -> Batch<NavEstimate, NavError> {
        batch::run(samples, |s| self.push(s))
    }

    /// One IMU sample with the orientation from elsewhere instead of the internal
    /// AHRS: `q_body_to_enu` = `[w, x, y, z]` rotating the (remapped) body frame into
    /// East-North-Up — e.g. a better orientation filter, or the platform's fused
    /// orientation (Android's rotation vector is exactly this). The magnetometer, if
    /// given, still drives the yaw correction; pass none when the attitude already
    /// has an absolute heading. The internal AHRS does not advance.
    pub fn push_imu_with_attitude(
        &mut self,
        s: &ImuSample,
        q_body_to_enu: [f64; 4],
    ) -> Result<(), NavError> {
        self.check_imu(s)?;
        let [w, x, y, z] = q_body_to_enu;
        let n = (w * w + x * x + y * y + z * z).sqrt();
        if !(n.is_finite() && (n - 1.0).abs() < 1e-3) {
            return Err(NavError::Attitude { norm: n });
        }
        let q = UnitQuaternion::new_normalize(Quaternion::new(w, x, y, z));
        self.advance(s, Some(q), Attitude::Outside)
    }

    /// One sensor event (accelerometer, gyroscope or magnetometer, each with its own
    /// time): merged into IMU samples by the rule of [`crate::imu`], each pushed as
    /// by [`push_imu`](Self::push_imu) as soon as it is complete. A refused event
    /// (bad value, time not increasing within its stream, an accelerometer in g, an
    /// accelerometer event before an IMU sample pushed directly) changes nothing.
    pub fn push_event(&mut self, e: &ImuEvent) -> Result<(), NavError> {
        if e.kind == SensorKind::Accelerometer {
            self.imu_time.check(e.t_s)?;
            self.detector.check_sample(e.t_s, e.values)?;
        }
        self.merger.check(e)?;
        self.with_merger(|m, push| m.push(e, push))?;
        Ok(())
    }

    /// Push every IMU sample the merger still holds back (waiting for later
    /// gyroscope or magnetometer events): the end of a recording, a session that
    /// stops. Events pushed afterwards merge as before.
    pub fn flush_events(&mut self) {
        self.with_merger(|m, push| {
            m.flush(push);
            Ok(())
        })
        .expect("flush refuses nothing");
    }

    /// What the event merger did so far.
    pub fn merge_counts(&self) -> MergeCounts {
        self.merger.counts()
    }

    /// Run `f` on the merger with a sink that pushes each released sample; samples
    /// the navigator refuses (an app that mixes direct IMU samples with events) are
    /// counted in [`MergeCounts::refused`].
    fn with_merger<R>(
        &mut self,
        f: impl FnOnce(&mut ImuMerger, &mut dyn FnMut(ImuSample)) -> Result<R, InputError>,
    ) -> Result<R, InputError> {
        // The merger is moved out for the call (its placeholder holds no memory).
        let mut merger = std::mem::take(&mut self.merger);
        let mut refused = 0;
        let r = f(&mut merger, &mut |s| {
            if self.push_imu(&s).is_err() {
                refused += 1;
            }
        });
        merger.count_refused(refused);
        self.merger = merger;
        r
    }

    /// Detector, walking direction and steps for an accepted sample with its
    /// orientation (body → ENU), if known yet, and where that came from.
    fn advance(
        &mut self,
        s: &ImuSample,
        q_enu: Option<UnitQuaternion<f64>>,
        source: Attitude,
    ) -> Result<(), NavError> {
        let first = self.detector.push_accel(s.t_s, s.accel_mps2)?;
        self.imu_time.accept(s.t_s);
        self.last_t_s = if self.last_t_s.is_nan() {
            s.t_s
        } else {
            self.last_t_s.max(s.t_s)
        };
        if let Some(q_enu) = q_enu {
            let remap = &self.config.ahrs.axis_remap;
            let force = q_enu * Vector3::from(remap.apply(s.accel_mps2));
            self.vertical.push(s.t_s, force.z);
            let mag = s.mag_ut.map(|m| remap.apply(m));
            let gyro = (source == Attitude::Gyroscope).then(|| remap.apply(s.gyro_rads));
            self.direction
                .push_sample(s.t_s, &q_enu, force.into(), mag, gyro);
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
        let span = if step.duration_s.is_finite() && step.duration_s <= MAX_STEP_S {
            step.duration_s
        } else {
            DEFAULT_STEP_S
        };
        // The phone's rise and fall over the step (NaN when the history lacks it, or
        // implausible: the estimator then uses its prior length).
        let h = self
            .vertical
            .displacement_range_m(step.t_s - span, step.t_s);
        let step = StepEvent {
            vertical_displacement_m: if (0.0..=input::limits::MAX_STEP_VERTICAL_M).contains(&h) {
                h
            } else {
                f64::NAN
            },
            ..*step
        };
        // The model's length, times the scale GNSS taught when it disagreed.
        let length = self.lengths.push_step(&step)? * self.scale.factor();
        self.direction
            .push_step(if hz.is_finite() { hz } else { 1.8 });
        self.steps = self.steps.saturating_add(1);
        self.last_step_length_m = length;
        self.distance_m += length;
        let pending = PendingStep {
            t0_s: step.t_s - span,
            t1_s: step.t_s,
            length_m: length,
            vertical_displacement_m: step.vertical_displacement_m,
            origin: step.origin,
        };
        if self.direction.forward_body().is_none() {
            // The carrying is not known yet (a walk's first stride): place the step
            // once it is, at its own time.
            self.deferred.push(pending);
            return Ok(());
        }
        while let Some(p) = self.deferred.pop_front() {
            self.place(p);
        }
        self.place(pending);
        Ok(())
    }

    /// Move the position by one step along the walking azimuth over its span.
    fn place(&mut self, p: PendingStep) {
        let Some(az) = self.direction.azimuth_between(p.t0_s, p.t1_s) else {
            return;
        };
        let length = p.length_m;
        let (de, dn) = (length * az.sin(), length * az.cos());
        self.east_m += de;
        self.north_m += dn;
        self.dr_east_m += de;
        self.dr_north_m += dn;
        self.pos_var_m2 +=
            (STEP_LENGTH_REL_SIGMA * length).powi(2) + (DIRECTION_SIGMA_RAD * length).powi(2);
        self.placed = self.placed.saturating_add(1);
        self.recent.push(NavStep {
            t_s: p.t1_s,
            east_m: self.east_m,
            north_m: self.north_m,
            length_m: length,
            azimuth_rad: az,
            vertical_displacement_m: p.vertical_displacement_m,
            origin: p.origin,
        });
    }

    /// The latest placed steps (at most [`RECENT_STEPS`], oldest first) and how many
    /// steps were placed in all: a caller that remembers the count reads the new ones.
    pub fn recent_steps(&self) -> (impl DoubleEndedIterator<Item = NavStep> + '_, u64) {
        (self.recent.iter(), self.placed)
    }

    /// The steps placed after the first `placed` (a count [`recent_steps`](Self::recent_steps)
    /// gave earlier), oldest first, as far as they are still kept (the newest
    /// [`RECENT_STEPS`]): read them after each push and remember the new count.
    pub fn steps_since(&self, placed: u64) -> impl Iterator<Item = NavStep> + '_ {
        let new = usize::try_from(self.placed.saturating_sub(placed)).unwrap_or(usize::MAX);
        self.recent
            .iter()
            .skip(self.recent.len().saturating_sub(new))
    }

    /// One GNSS fix: anchors the frame at the first one, then corrects the position,
    /// calibrates step length and the walking direction.
    pub fn push_fix(&mut self, fix: &GnssFix) -> Result<NavEstimate, NavError> {
        self.fix_time.check(fix.t_s)?;
        input::gnss_fix(fix)?;
        let sigma = self.fix_sigma_m(fix);
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
        let r_eff = if nis > CHI2_99_2DOF {
            r * nis / CHI2_99_2DOF
        } else {
            r
        };
        let k = self.pos_var_m2 / (self.pos_var_m2 + r_eff);
        self.east_m += k * de;
        self.north_m += k * dn;
        self.pos_var_m2 *= 1.0 - k;
        self.observe_course(fix, p);
        self.fix_time.accept(fix.t_s);
        self.last_t_s = if self.last_t_s.is_nan() {
            fix.t_s
        } else {
            self.last_t_s.max(fix.t_s)
        };
        Ok(self.current())
    }

    /// Per-axis σ of a fix, m.
    fn fix_sigma_m(&self, fix: &GnssFix) -> f64 {
        fix.horizontal_accuracy_m.map_or(DEFAULT_FIX_SIGMA_M, |a| {
            (a * RADIUS68_TO_SIGMA).max(MIN_FIX_SIGMA_M)
        })
    }

    /// The walking direction learns how the phone is carried (and its forward sign)
    /// from the angle between the GNSS and the dead-reckoned displacements over a
    /// stretch of ≥ 15 m.
    fn observe_course(&mut self, fix: &GnssFix, p: [f64; 3]) {
        let good = fix
            .horizontal_accuracy_m
            .is_none_or(|a| a <= COURSE_MAX_ACCURACY_M);
        let CourseAnchor {
            t_s: t0,
            fix_east_m: e0,
            fix_north_m: n0,
            dr_east_m: de0,
            dr_north_m: dn0,
        } = self.course_anchor;
        let anchor = CourseAnchor {
            t_s: fix.t_s,
            fix_east_m: p[0],
            fix_north_m: p[1],
            dr_east_m: self.dr_east_m,
            dr_north_m: self.dr_north_m,
        };
        if !good || !t0.is_finite() || fix.t_s - t0 > COURSE_MAX_TIME_S {
            self.course_anchor = anchor;
            return;
        }
        let (ge, gn) = (p[0] - e0, p[1] - n0);
        let g = ge.hypot(gn);
        if g < COURSE_MIN_DISTANCE_M || fix.t_s - t0 < COURSE_MIN_TIME_S {
            return;
        }
        let (de, dn) = (self.dr_east_m - de0, self.dr_north_m - dn0);
        self.scale.observe(g, de.hypot(dn));
        if de.hypot(dn) > COURSE_MIN_DR_SHARE * g {
            // Azimuth of GNSS minus azimuth of dead reckoning (clockwise positive); its
            // σ from the two fixes' accuracy across the baseline.
            let err = (ge * dn - gn * de).atan2(ge * de + gn * dn);
            let sigma = std::f64::consts::SQRT_2 * self.fix_sigma_m(fix) / g;
            self.direction.observe_rotation(err, fix.t_s - t0, sigma);
        }
        self.course_anchor = anchor;
    }

    /// The walking-direction estimator (diagnostics: carrying, yaw correction).
    pub fn walking_direction(&self) -> &WalkingDirection {
        &self.direction
    }

    /// The AHRS orientation of the latest sample (body → AHRS earth frame),
    /// `[w, x, y, z]`.
    pub fn orientation(&self) -> Option<[f64; 4]> {
        self.ahrs.quaternion()
    }

    /// Where the pedestrian is now: `None` before the first accepted input. Before
    /// the first GNSS fix the position is relative to where the navigator started
    /// (0, 0 at the first IMU sample, east/north of the AHRS's heading reference);
    /// at the first fix the frame is re-anchored at the fix (the position becomes
    /// 0, 0 there and `lat_deg`/`lon_deg` appear).
    pub fn estimate(&self) -> Option<NavEstimate> {
        (!self.last_t_s.is_nan()).then(|| self.current())
    }

    fn current(&self) -> NavEstimate {
        let geo = self.frame.map(|f| f.to_geodetic(self.east_m, self.north_m));
        NavEstimate {
            t_s: self.last_t_s,
            east_m: self.east_m,
            north_m: self.north_m,
            position_std_m: self.pos_var_m2.sqrt(),
            lat_deg: geo.map(|g| g.0),
            lon_deg: geo.map(|g| g.1),
            walking_azimuth_rad: self.direction.azimuth_rad(),
            // The phone's heading as the AHRS defines it: body +y (top edge) in ENU,
            // body +x in NED.
            heading_offset_rad: self
                .direction
                .heading_offset_rad(match self.config.ahrs.frame {
                    EarthFrame::Enu => [0.0, 1.0, 0.0],
                    EarthFrame::Ned => [1.0, 0.0, 0.0],
                }),
            steps: self.steps,
            distance_m: self.distance_m,
            step_length_m: self
                .last_step_length_m
                .is_finite()
                .then_some(self.last_step_length_m),
            step_scale: self.scale.factor(),
            step_scale_disagrees: self.scale.disagrees(),
        }
    }
}

mod snapshot;
