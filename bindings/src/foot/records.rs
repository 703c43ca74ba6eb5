//! Estimates and batch results (the samples are `crate::packed::ImuSample`, packed in
//! the 6-axis layout of `crate::packed`).

use stridekit_core::foot as core;

use super::*;

/// A vector in the local level East-North-Up frame.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct EnuVector {
    pub east: f64,
    pub north: f64,
    pub up: f64,
}

impl From<[f64; 3]> for EnuVector {
    fn from(v: [f64; 3]) -> Self {
        Self {
            east: v[0],
            north: v[1],
            up: v[2],
        }
    }
}

/// A vector in body axes (x forward, y left, z up).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct BodyVector {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl From<[f64; 3]> for BodyVector {
    fn from(v: [f64; 3]) -> Self {
        Self {
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }
}

/// A unit quaternion.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct Quaternion {
    pub w: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// One stride: from one stance onset of the instrumented foot to the next.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct FootStride {
    /// Time of the stance onset that ends the stride, s.
    pub t_s: f64,
    /// Horizontal distance between the two stance onsets, m.
    pub length_m: f64,
    /// Time between them, s.
    pub duration_s: f64,
    /// `length_m / duration_s`, m/s.
    pub speed_mps: f64,
    /// Height change, m (up positive); zero on a stride taken as level.
    pub climb_m: f64,
    /// Height the level-floor constraint took off at the end of this stride, m (0 when
    /// the stride was not taken as level; `FootConfig.levelStrideMaxGrade`).
    pub levelled_m: f64,
}

impl From<core::Stride> for FootStride {
    fn from(s: core::Stride) -> Self {
        Self {
            t_s: s.t_s,
            length_m: s.length_m,
            duration_s: s.duration_s,
            speed_mps: s.speed_mps,
            climb_m: s.climb_m,
            levelled_m: s.levelled_m,
        }
    }
}

/// Where the foot is after one sample. Frame: local level East-North-Up, origin where
/// the navigator started, yaw 0 = body +x pointing East at start (set
/// `FootConfig.initialYawRad` for a known heading).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct FootEstimate {
    /// Time of the sample this estimate is for (the pipeline lags the newest input
    /// by `delaySamples()`), s.
    pub t_s: f64,
    pub position_m: EnuVector,
    pub velocity_mps: EnuVector,
    /// Orientation body → ENU.
    pub quaternion: Quaternion,
    /// ZYX Euler angles, rad: roll about body x, pitch about body y, yaw about up
    /// (counter-clockwise from East).
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    /// Heading of body +x, clockwise from North, 0..2π.
    pub heading_rad: f64,
    /// 1-σ of position and velocity per ENU axis.
    pub position_std_m: EnuVector,
    pub velocity_std_mps: EnuVector,
    /// 1-σ of the tilt about East and about North, rad.
    pub tilt_east_std_rad: f64,
    pub tilt_north_std_rad: f64,
    /// 1-σ of the heading, rad.
    pub heading_std_rad: f64,
    /// Bias estimates, body axes.
    pub accel_bias_mps2: BodyVector,
    pub gyro_bias_rads: BodyVector,
    /// The foot is still: a zero-velocity update was applied.
    pub stance: bool,
    /// Strides counted so far and the sum of their horizontal lengths, m.
    pub strides: i64,
    pub distance_m: f64,
    /// The stride that ended on this sample (null on every other sample).
    pub stride: Option<FootStride>,
    /// The sample hit the configured sensor range.
    pub saturated: bool,
    /// The time step before this sample exceeded `maxGapS`.
    pub gap: bool,
}

impl From<core::FootEstimate> for FootEstimate {
    fn from(e: core::FootEstimate) -> Self {
        Self {
            t_s: e.t_s,
            position_m: e.position_m.into(),
            velocity_mps: e.velocity_mps.into(),
            quaternion: Quaternion {
                w: e.quaternion[0],
                x: e.quaternion[1],
                y: e.quaternion[2],
                z: e.quaternion[3],
            },
            roll_rad: e.roll_rad,
            pitch_rad: e.pitch_rad,
            yaw_rad: e.yaw_rad,
            heading_rad: e.heading_rad,
            position_std_m: e.position_std_m.into(),
            velocity_std_mps: e.velocity_std_mps.into(),
            tilt_east_std_rad: e.tilt_std_rad[0],
            tilt_north_std_rad: e.tilt_std_rad[1],
            heading_std_rad: e.heading_std_rad,
            accel_bias_mps2: e.accel_bias_mps2.into(),
            gyro_bias_rads: e.gyro_bias_rads.into(),
            stance: e.stance,
            strides: i64::try_from(e.strides).unwrap_or(i64::MAX),
            distance_m: e.distance_m,
            stride: e.stride.map(Into::into),
            saturated: e.saturated,
            gap: e.gap,
        }
    }
}

/// Which estimates a batch push returns (each one crossing the FFI costs ~300 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum FootOutput {
    /// Every estimate produced (one per accepted sample once aligned, after the delay).
    All,
    /// Only the estimates on which a stride ended (`stride` not null).
    StrideEnds,
    /// None: only `latest`.
    LatestOnly,
}

/// A sample a batch rejected; the rest of the batch was still processed.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct FootRejectedSample {
    /// Position of the sample in the batch (record in a packed buffer), from 0.
    pub index: i32,
    pub error: FootError,
    /// The same as a sentence, for logs (the field every engine's rejected sample
    /// has: `reason`).
    pub reason: String,
}

/// What a batch push produced.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct FootBatchResult {
    /// Samples accepted (the batch minus the rejected ones).
    pub accepted: i32,
    /// Estimates the engine produced during the batch (returned or not).
    pub produced: i32,
    /// The estimates selected by the `FootOutput` argument, in time order.
    pub estimates: Vec<FootEstimate>,
    /// Rejected samples, in batch order.
    pub rejected: Vec<FootRejectedSample>,
    /// The newest estimate after the batch (what `estimate()` returns; null before
    /// the alignment is complete).
    pub latest: Option<FootEstimate>,
}
