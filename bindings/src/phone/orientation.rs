//! `OrientationFilter` at the FFI: orientation (attitude and heading) from a phone's or
//! watch's gyroscope, accelerometer and optional magnetometer (core:
//! `stridekit_core::ahrs`; accuracy against optical motion capture in
//! `docs/orientation.md`).
//!
//! IMU samples cross the FFI packed, as the same 80-byte little-endian records as
//! `PhoneNavigator.pushImuPacked` (ten f64: `t_s, gyro_x, gyro_y, gyro_z (rad/s),
//! accel_x, accel_y, accel_z (m/s², gravity included), mag_x, mag_y, mag_z (µT; NaN
//! when there is no magnetometer)`, device axes as the platform reports them).
//! Estimates are in East-North-Up (or North-East-Down), body = device axes.

use std::sync::{Arc, Mutex, MutexGuard};

use stridekit_core::ahrs as core;

use crate::packed::imu_samples;
use crate::phone::navigator::{push_each, RejectedImuSample};

/// Which orientation filter runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum OrientationAlgorithm {
    /// The default: inclination from the accelerometer averaged in an almost-inertial
    /// frame, heading from the magnetometer on its own with disturbance rejection,
    /// gyroscope bias learned at rest and in motion.
    Decoupled,
    /// Madgwick's filter with Fusion-style rejection and recovery (the default before
    /// this filter); its gain is `madgwickGain`, its other settings the core's.
    Madgwick,
}

/// Earth frame of the outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum OrientationFrame {
    /// x East, y North, z Up.
    Enu,
    /// x North, y East, z Down.
    Ned,
}

/// Settings of an [`OrientationFilter`]. The literal defaults below are the core's
/// (`AhrsSettings::default()`); `orientationSettingsDefault()` returns the same record
/// from the core, and a test checks that both agree. Times in seconds; a time constant
/// of null switches that correction off where noted. `algorithm` and `frame` have no
/// literal default (uniffi 0.32 cannot give enum fields one): the core's are
/// `DECOUPLED` and `ENU`.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct OrientationSettings {
    pub algorithm: OrientationAlgorithm,
    pub frame: OrientationFrame,
    /// Averaging time of the accelerometer in the almost-inertial frame, s.
    #[uniffi(default = 3.0)]
    pub accel_time_constant_s: f64,
    /// Time constant of the heading correction from the magnetometer, s.
    #[uniffi(default = 10.0)]
    pub mag_time_constant_s: f64,
    /// Time constant of the gyroscope bias learned in motion, s (null: off, the default).
    #[uniffi(default = None)]
    pub motion_bias_time_constant_s: Option<f64>,
    /// Random walk of the gyroscope bias, rad/s/√s (0.003°/s/√s).
    #[uniffi(default = 0.00005235987755982989)]
    pub bias_random_walk: f64,
    /// How well motion alone tells the bias, rad/s (0.05°/s).
    #[uniffi(default = 0.0008726646259971648)]
    pub motion_bias_accuracy_rads: f64,
    /// Time constant of the bias about the vertical from the heading corrections, s
    /// (null: off).
    #[uniffi(default = None)]
    pub heading_bias_time_constant_s: Option<f64>,
    /// Rest: gyroscope deviation from its 0.5 s mean below this, rad/s (2°/s).
    #[uniffi(default = 0.03490658503988659)]
    pub rest_gyro_rads: f64,
    /// Rest: accelerometer deviation from its 0.5 s mean below this, m/s².
    #[uniffi(default = 0.5)]
    pub rest_accel_mps2: f64,
    /// Rest must last this long, s.
    #[uniffi(default = 1.5)]
    pub rest_time_s: f64,
    /// Time constant of the bias estimate at rest, s.
    #[uniffi(default = 2.0)]
    pub rest_bias_time_constant_s: f64,
    /// Largest bias estimated, rad/s (2°/s).
    #[uniffi(default = 0.03490658503988659)]
    pub max_bias_rads: f64,
    /// Magnetic disturbance: |m| off the learned field by more than this share.
    #[uniffi(default = 0.1)]
    pub mag_norm_threshold: f64,
    /// Magnetic disturbance: dip off the learned dip by more than this, rad (10°).
    #[uniffi(default = 0.17453292519943295)]
    pub mag_dip_threshold_rad: f64,
    /// After a disturbance, the field must look undisturbed this long, s.
    #[uniffi(default = 0.5)]
    pub mag_min_undisturbed_s: f64,
    /// A disturbance longer than this becomes the new local field, s.
    #[uniffi(default = 60.0)]
    pub mag_max_rejection_s: f64,
    /// Largest magnetometer offset (hard iron) learned online, per axis, µT; 0: off
    /// (readings the app or the OS calibrated itself).
    #[uniffi(default = 200.0)]
    pub mag_offset_max_ut: f64,
    /// Madgwick's gain β, rad/s (used with `algorithm = MADGWICK`).
    #[uniffi(default = 0.1)]
    pub madgwick_gain: f64,
    /// Gyroscope full-scale range, rad/s (2000°/s); readings beyond 98 % are clipped.
    #[uniffi(default = 34.906585039886586)]
    pub gyro_range_rads: f64,
    /// Learn the gyroscope bias.
    #[uniffi(default = true)]
    pub bias_estimation: bool,
    /// Local gravity, m/s².
    #[uniffi(default = 9.80665)]
    pub gravity_mps2: f64,
    /// A longer sample interval restarts the filter from that sample, s.
    #[uniffi(default = 1.0)]
    pub max_gap_s: f64,
}

impl From<core::AhrsSettings> for OrientationSettings {
    fn from(s: core::AhrsSettings) -> Self {
        let d = s.decoupled;
        Self {
            algorithm: match s.algorithm {
                core::AhrsAlgorithm::Decoupled => OrientationAlgorithm::Decoupled,
                core::AhrsAlgorithm::Madgwick => OrientationAlgorithm::Madgwick,
            },
            frame: match s.frame {
                core::EarthFrame::Enu => OrientationFrame::Enu,
                core::EarthFrame::Ned => OrientationFrame::Ned,
            },
            accel_time_constant_s: d.accel_time_constant_s,
            mag_time_constant_s: d.mag_time_constant_s,
            motion_bias_time_constant_s: d
                .motion_bias_time_constant_s
                .is_finite()
                .then_some(d.motion_bias_time_constant_s),
            bias_random_walk: d.bias_random_walk,
            motion_bias_accuracy_rads: d.motion_bias_accuracy_rads,
            heading_bias_time_constant_s: d
                .heading_bias_time_constant_s
                .is_finite()
                .then_some(d.heading_bias_time_constant_s),
            rest_gyro_rads: d.rest_gyro_rads,
            rest_accel_mps2: d.rest_accel_mps2,
            rest_time_s: d.rest_time_s,
            rest_bias_time_constant_s: d.rest_bias_time_constant_s,
            max_bias_rads: d.max_bias_rads,
            mag_norm_threshold: d.mag_norm_threshold,
            mag_dip_threshold_rad: d.mag_dip_threshold_rad,
            mag_min_undisturbed_s: d.mag_min_undisturbed_s,
            mag_max_rejection_s: d.mag_max_rejection_s,
            mag_offset_max_ut: d.mag_offset_max_ut,
            madgwick_gain: s.gain,
            gyro_range_rads: s.gyro_range_rads,
            bias_estimation: s.bias_estimation,
            gravity_mps2: s.gravity_mps2,
            max_gap_s: s.max_gap_s,
        }
    }
}

impl TryFrom<OrientationSettings> for core::AhrsSettings {
    type Error = OrientationError;
    fn try_from(r: OrientationSettings) -> Result<Self, OrientationError> {
        let base = match r.algorithm {
            OrientationAlgorithm::Decoupled => core::AhrsSettings::default(),
            OrientationAlgorithm::Madgwick => core::AhrsSettings::madgwick(),
        };
        let s = core::AhrsSettings {
            frame: match r.frame {
                OrientationFrame::Enu => core::EarthFrame::Enu,
                OrientationFrame::Ned => core::EarthFrame::Ned,
            },
            decoupled: core::DecoupledSettings {
                accel_time_constant_s: r.accel_time_constant_s,
                mag_time_constant_s: r.mag_time_constant_s,
                motion_bias_time_constant_s: r.motion_bias_time_constant_s.unwrap_or(f64::INFINITY),
                bias_random_walk: r.bias_random_walk,
                motion_bias_accuracy_rads: r.motion_bias_accuracy_rads,
                heading_bias_time_constant_s: r
                    .heading_bias_time_constant_s
                    .unwrap_or(f64::INFINITY),
                rest_gyro_rads: r.rest_gyro_rads,
                rest_accel_mps2: r.rest_accel_mps2,
                rest_time_s: r.rest_time_s,
                rest_bias_time_constant_s: r.rest_bias_time_constant_s,
                max_bias_rads: r.max_bias_rads,
                mag_norm_threshold: r.mag_norm_threshold,
                mag_dip_threshold_rad: r.mag_dip_threshold_rad,
                mag_min_undisturbed_s: r.mag_min_undisturbed_s,
                mag_max_rejection_s: r.mag_max_rejection_s,
                mag_offset_max_ut: r.mag_offset_max_ut,
            },
            gain: r.madgwick_gain,
            gyro_range_rads: r.gyro_range_rads,
            bias_estimation: r.bias_estimation,
            gravity_mps2: r.gravity_mps2,
            max_gap_s: r.max_gap_s,
            ..base
        };
        s.validate()
            .map_err(|e| OrientationError::InvalidSettings {
                reason: e.to_string(),
            })?;
        Ok(s)
    }
}

/// The core's default settings.
#[uniffi::export]
pub fn orientation_settings_default() -> OrientationSettings {
    core::AhrsSettings::default().into()
}

/// What the filter did with the latest sample and why (all false in steady motion).
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Record)]
pub struct OrientationFlags {
    /// The filter (re)started from this sample (first sample, or after a gap).
    pub reinitialised: bool,
    /// Still converging from the (re)start.
    pub initialising: bool,
    /// The gyroscope clipped; re-converging from accelerometer and magnetometer.
    pub angular_rate_recovery: bool,
    /// No accelerometer correction (Madgwick: linear acceleration rejected).
    pub accel_rejected: bool,
    /// Madgwick's acceleration recovery.
    pub accel_recovery: bool,
    /// The magnetometer did not correct the heading on this sample.
    pub mag_rejected: bool,
    /// The field was rejected for too long: the current field became the learned one.
    pub mag_recovery: bool,
    /// The gyroscope bias is being learned at rest.
    pub bias_learning: bool,
    /// The device is at rest.
    pub at_rest: bool,
    /// The gyroscope bias is being learned in motion.
    pub bias_motion: bool,
    /// The field's magnitude or dip is off the learned Earth field.
    pub mag_disturbed: bool,
    /// The heading follows the gyroscope alone on this sample.
    pub heading_held: bool,
    /// The magnetometer offset (hard iron) is still being learned: the heading may be
    /// off by several degrees until the device has turned about two axes.
    pub mag_calibrating: bool,
}

impl From<core::AhrsFlags> for OrientationFlags {
    fn from(f: core::AhrsFlags) -> Self {
        Self {
            reinitialised: f.reinitialised,
            initialising: f.initialising,
            angular_rate_recovery: f.angular_rate_recovery,
            accel_rejected: f.accel_rejected,
            accel_recovery: f.accel_recovery,
            mag_rejected: f.mag_rejected,
            mag_recovery: f.mag_recovery,
            bias_learning: f.bias_learning,
            at_rest: f.at_rest,
            bias_motion: f.bias_motion,
            mag_disturbed: f.mag_disturbed,
            heading_held: f.heading_held,
            mag_calibrating: f.mag_calibrating,
        }
    }
}

/// The orientation after a sample. Vectors in the earth frame (`frame`) unless named
/// `body`.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct OrientationEstimate {
    pub t_s: f64,
    /// Orientation body → earth, [w, x, y, z]: v_earth = q ⊗ v_body ⊗ q*.
    pub quaternion: Vec<f64>,
    /// ZYX Euler angles of `quaternion`, rad.
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    /// Compass heading, clockwise from magnetic north, 0..2π (ENU: of the device's +y
    /// axis, as Android's azimuth; NED: of +x). Relative to the start without a
    /// magnetometer.
    pub heading_rad: f64,
    /// What a still accelerometer would read, body axes, m/s².
    pub gravity_body_mps2: Vec<f64>,
    /// Acceleration with gravity removed, body axes and earth frame, m/s².
    pub linear_accel_body_mps2: Vec<f64>,
    pub linear_accel_earth_mps2: Vec<f64>,
    /// Estimated gyroscope bias (already subtracted), rad/s, body axes.
    pub gyro_bias_rads: Vec<f64>,
    pub flags: OrientationFlags,
}

impl From<core::AhrsOutput> for OrientationEstimate {
    fn from(o: core::AhrsOutput) -> Self {
        Self {
            t_s: o.t_s,
            quaternion: o.quaternion.to_vec(),
            roll_rad: o.roll_rad,
            pitch_rad: o.pitch_rad,
            yaw_rad: o.yaw_rad,
            heading_rad: o.heading_rad,
            gravity_body_mps2: o.gravity_body_mps2.to_vec(),
            linear_accel_body_mps2: o.linear_accel_body_mps2.to_vec(),
            linear_accel_earth_mps2: o.linear_accel_earth_mps2.to_vec(),
            gyro_bias_rads: o.gyro_bias_rads.to_vec(),
            flags: o.flags.into(),
        }
    }
}

crate::error::engine_error! {
    /// Why the filter rejected an input, settings, a buffer or a snapshot (Kotlin
    /// `OrientationException`, Swift `OrientationError`): the typed input causes every
    /// engine shares, then its own. A rejected sample changes nothing.
    pub enum OrientationError {
        /// A sample was refused for a reason other than the input checks (a vector
        /// without three components, ...).
        #[error("IMU sample rejected: {reason}")]
        InvalidSample { reason: String },
        /// A setting is out of range.
        #[error("invalid orientation settings: {reason}")]
        InvalidSettings { reason: String },
        /// Snapshot bytes could not be restored.
        #[error("cannot restore snapshot: {reason}")]
        InvalidSnapshot { reason: String },
        /// A packed buffer is not a whole number of 80-byte records.
        #[error("invalid packed buffer: {reason}")]
        InvalidBuffer { reason: String },
        /// A bug inside stridekit (a caught panic). The filter stays usable.
        #[error("internal error in stridekit: {reason}")]
        Internal { reason: String },
    }
}

fn guard<T>(f: impl FnOnce() -> Result<T, OrientationError>) -> Result<T, OrientationError> {
    crate::error::guard_with(f, |reason| OrientationError::Internal { reason })
}

/// Which estimates a batch push returns (each one crossing the FFI costs ~250 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum OrientationOutput {
    /// One estimate per accepted sample.
    All,
    /// None: only `latest`.
    LatestOnly,
}

/// What a packed push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct OrientationBatchResult {
    /// Samples accepted (the batch minus the rejected ones).
    pub accepted: i32,
    /// Estimates produced during the batch: one per accepted sample once the filter has an orientation (returned or not).
    pub produced: i32,
    /// Per accepted sample (with `OrientationOutput.ALL`), else empty.
    pub estimates: Vec<OrientationEstimate>,
    /// Samples rejected (by index in the buffer, with the reason); the rest went in.
    pub rejected: Vec<RejectedImuSample>,
    /// The estimate after the batch (null before the first accepted sample).
    pub latest: Option<OrientationEstimate>,
}

/// Orientation filter. Safe to call from several threads (calls serialise).
#[derive(Debug, uniffi::Object)]
pub struct OrientationFilter {
    inner: Mutex<core::Ahrs>,
}

impl OrientationFilter {
    fn lock(&self) -> MutexGuard<'_, core::Ahrs> {
        crate::error::lock(&self.inner)
    }
}

#[uniffi::export]
impl OrientationFilter {
    /// A filter with the given settings.
    #[uniffi::constructor]
    pub fn new(settings: OrientationSettings) -> Result<Arc<Self>, OrientationError> {
        guard(|| {
            let s: core::AhrsSettings = settings.try_into()?;
            let a = core::Ahrs::new(s).map_err(|e| OrientationError::InvalidSettings {
                reason: e.to_string(),
            })?;
            Ok(Arc::new(Self {
                inner: Mutex::new(a),
            }))
        })
    }

    /// A filter with the default settings (the decoupled filter, ENU).
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(
                core::Ahrs::new(core::AhrsSettings::default())
                    .expect("the core default settings are valid"),
            ),
        })
    }

    /// A filter continuing exactly where `snapshot()` was taken (also snapshots of
    /// the previous format, which restore as the Madgwick filter).
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, OrientationError> {
        guard(|| {
            let a =
                core::Ahrs::restore(&snapshot).map_err(|e| OrientationError::InvalidSnapshot {
                    reason: match e {
                        core::AhrsError::Snapshot(s) => s.to_string(),
                        e => e.to_string(),
                    },
                })?;
            Ok(Arc::new(Self {
                inner: Mutex::new(a),
            }))
        })
    }

    /// The settings in use.
    pub fn settings(&self) -> OrientationSettings {
        (*self.lock().settings()).into()
    }

    /// Push IMU samples packed as 80-byte little-endian records of ten f64 `t_s,
    /// accel_x, accel_y, accel_z (m/s²), gyro_x, gyro_y, gyro_z (rad/s), mag_x, mag_y,
    /// mag_z (µT, NaN: none)` (`packImuSamples` builds them). A buffer that is not a
    /// whole number of records is refused as a whole; otherwise bad records are skipped
    /// and reported, and the result equals pushing only the good ones.
    pub fn push_imu_packed(
        &self,
        data: Vec<u8>,
        output: OrientationOutput,
    ) -> Result<OrientationBatchResult, OrientationError> {
        guard(|| {
            let samples =
                imu_samples(&data).map_err(|reason| OrientationError::InvalidBuffer { reason })?;
            let mut a = self.lock();
            let mut estimates = Vec::new();
            let b = push_each(samples, |s| {
                a.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)?;
                // An estimate once the filter has an orientation.
                let produced = a.quaternion().is_some();
                if produced && output == OrientationOutput::All {
                    estimates.extend(a.output().map(OrientationEstimate::from));
                }
                Ok::<_, core::AhrsError>(produced)
            });
            Ok(OrientationBatchResult {
                accepted: b.accepted,
                produced: b.produced,
                estimates,
                rejected: b.rejected,
                latest: a.output().map(Into::into),
            })
        })
    }

    /// One sample (`mag` null without a magnetometer); a typed error leaves the filter
    /// unchanged. Prefer `pushImuPacked` for streams: one call costs ~20 µs.
    pub fn push(
        &self,
        t_s: f64,
        gyro_rads: Vec<f64>,
        accel_mps2: Vec<f64>,
        mag_ut: Option<Vec<f64>>,
    ) -> Result<OrientationEstimate, OrientationError> {
        guard(|| {
            let v3 = |v: &[f64], what: &str| -> Result<[f64; 3], OrientationError> {
                <[f64; 3]>::try_from(v).map_err(|_| OrientationError::InvalidSample {
                    reason: format!("{what} must have 3 components, got {}", v.len()),
                })
            };
            let g = v3(&gyro_rads, "gyro_rads")?;
            let acc = v3(&accel_mps2, "accel_mps2")?;
            let m = mag_ut.as_deref().map(|m| v3(m, "mag_ut")).transpose()?;
            let mut a = self.lock();
            a.update(t_s, g, acc, m).map_err(|e| match e {
                core::AhrsError::Input(e) => OrientationError::from(e),
                e => OrientationError::InvalidSample {
                    reason: e.to_string(),
                },
            })?;
            a.output()
                .map(Into::into)
                .ok_or_else(|| OrientationError::Internal {
                    reason: "no output after an accepted sample".into(),
                })
        })
    }

    /// The estimate after the latest accepted sample (null before the first).
    pub fn estimate(&self) -> Option<OrientationEstimate> {
        self.lock().output().map(Into::into)
    }

    /// The whole state as bytes (versioned, checksummed; restores bit-exactly).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(n: usize) -> Vec<u8> {
        crate::packed::pack_imu((0..n).map(|i| {
            let x = i as f64 * 0.01;
            core::ImuSample {
                t_s: x,
                gyro_rads: [0.3 * x.sin(), 0.2 * (1.3 * x).cos(), 0.1],
                accel_mps2: [0.5 * (2.0 * x).sin(), 0.3, 9.7],
                mag_ut: (i % 3 != 0).then_some([20.0 * (0.5 * x).cos(), 5.0, -40.0]),
            }
        }))
    }

    #[test]
    fn settings_defaults_agree_with_the_core_and_round_trip() {
        let d = orientation_settings_default();
        let core: core::AhrsSettings = d.clone().try_into().unwrap();
        assert_eq!(core, core::AhrsSettings::default());
        assert_eq!(OrientationSettings::from(core), d);
        // The record's literal defaults (used by the Kotlin/Swift constructors).
        let c = core::AhrsSettings::default();
        let dd = c.decoupled;
        assert_eq!(
            (
                dd.accel_time_constant_s,
                dd.mag_time_constant_s,
                dd.motion_bias_time_constant_s,
                dd.bias_random_walk,
                dd.motion_bias_accuracy_rads,
                dd.heading_bias_time_constant_s,
            ),
            (
                3.0,
                10.0,
                f64::INFINITY,
                0.00005235987755982989,
                0.0008726646259971648,
                f64::INFINITY
            )
        );
        assert_eq!(
            (
                dd.rest_gyro_rads,
                dd.rest_accel_mps2,
                dd.rest_time_s,
                dd.rest_bias_time_constant_s,
                dd.max_bias_rads,
            ),
            (0.03490658503988659, 0.5, 1.5, 2.0, 0.03490658503988659)
        );
        assert_eq!(
            (
                dd.mag_norm_threshold,
                dd.mag_dip_threshold_rad,
                dd.mag_min_undisturbed_s,
                dd.mag_max_rejection_s,
                dd.mag_offset_max_ut,
            ),
            (0.1, 0.17453292519943295, 0.5, 60.0, 200.0)
        );
        assert_eq!(
            (
                c.gain,
                c.gyro_range_rads,
                c.bias_estimation,
                c.gravity_mps2,
                c.max_gap_s
            ),
            (0.1, 34.906585039886586, true, 9.80665, 1.0)
        );
        assert_eq!(c.algorithm, core::AhrsAlgorithm::Decoupled);
        assert_eq!(c.frame, core::EarthFrame::Enu);
        // Madgwick through the record: the core's Madgwick settings with the gain.
        let m = OrientationSettings {
            algorithm: OrientationAlgorithm::Madgwick,
            madgwick_gain: 0.12,
            ..d.clone()
        };
        let mc: core::AhrsSettings = m.try_into().unwrap();
        assert_eq!(
            mc,
            core::AhrsSettings {
                gain: 0.12,
                ..core::AhrsSettings::madgwick()
            }
        );
        let bad = OrientationSettings {
            accel_time_constant_s: -1.0,
            ..d
        };
        assert!(matches!(
            OrientationFilter::new(bad),
            Err(OrientationError::InvalidSettings { .. })
        ));
    }

    #[test]
    fn packed_batches_equal_the_core_and_rejections_are_reported() {
        let data = samples(3000);
        // The core, sample by sample.
        let mut reference = core::Ahrs::new(core::AhrsSettings::default()).unwrap();
        let mut want = Vec::new();
        for r in imu_samples(&data).unwrap() {
            reference
                .update(r.t_s, r.gyro_rads, r.accel_mps2, r.mag_ut)
                .unwrap();
            want.push(OrientationEstimate::from(reference.output().unwrap()));
        }
        let f = OrientationFilter::with_defaults();
        let mut got = Vec::new();
        for chunk in data.chunks(80 * 700) {
            let r = f
                .push_imu_packed(chunk.to_vec(), OrientationOutput::All)
                .unwrap();
            assert!(r.rejected.is_empty());
            assert_eq!(r.latest.as_ref(), r.estimates.last());
            got.extend(r.estimates);
        }
        assert_eq!(got, want);
        assert_eq!(f.snapshot(), reference.snapshot());
        // A restored filter continues identically.
        let again = OrientationFilter::restore(f.snapshot()).unwrap();
        let more = samples(3100)[3000 * 80..].to_vec();
        let a = f
            .push_imu_packed(more.clone(), OrientationOutput::LatestOnly)
            .unwrap();
        let b = again
            .push_imu_packed(more, OrientationOutput::LatestOnly)
            .unwrap();
        assert_eq!(a, b);
        assert!(a.estimates.is_empty() && a.accepted == 100);
        // Bad records are skipped and reported; a ragged buffer is refused whole.
        let mut bad = samples(10);
        bad[80 * 3 + 8..80 * 3 + 16].copy_from_slice(&f64::NAN.to_le_bytes());
        let g = OrientationFilter::with_defaults();
        let r = g
            .push_imu_packed(bad, OrientationOutput::LatestOnly)
            .unwrap();
        assert_eq!(r.accepted, 9);
        assert_eq!(r.rejected.len(), 1);
        assert_eq!(r.rejected[0].index, 3);
        assert!(matches!(
            g.push_imu_packed(vec![0; 81], OrientationOutput::All),
            Err(OrientationError::InvalidBuffer { .. })
        ));
        assert!(matches!(
            OrientationFilter::restore(vec![1, 2, 3]),
            Err(OrientationError::InvalidSnapshot { .. })
        ));
        assert!(matches!(
            g.push(0.0, vec![0.0; 2], vec![0.0, 0.0, 9.8], None),
            Err(OrientationError::InvalidSample { .. })
        ));
        // A time not after the previous sample's: the shared typed cause.
        assert!(matches!(
            g.push(0.0, vec![0.0; 3], vec![0.0, 0.0, 9.8], None),
            Err(OrientationError::TimeNotIncreasing { .. })
        ));
        let e = g
            .push(10.0, vec![0.0; 3], vec![0.0, 0.0, 9.8], None)
            .unwrap();
        assert_eq!(e.quaternion.len(), 4);
    }
}
