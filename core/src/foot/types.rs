//! Samples going into the foot navigator and the estimates coming out.

/// One IMU sample from the foot, sensor frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootSample {
    /// Time, seconds on the app's monotonic clock, strictly increasing.
    pub t_s: f64,
    /// Specific force, m/s², sensor axes (reads +9.8 along "up" at rest).
    pub accel_mps2: [f64; 3],
    /// Angular rate, rad/s, sensor axes.
    pub gyro_rads: [f64; 3],
}

/// A sample in body axes (after the axis remap), as the pipeline stages pass it on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct BodySample {
    pub t_s: f64,
    pub f: [f64; 3],
    pub w: [f64; 3],
    pub saturated: bool,
    /// Stance given from outside (labels, a pressure insole) instead of the detector.
    pub external: Option<bool>,
    /// Rotation over the interval ending here that the gyroscope's samples do not
    /// resolve, about each body axis, rad (`unresolved.rs`).
    pub unresolved_rad: [f64; 3],
    /// 1-σ of the specific force the accelerometer did not report (clipped axes),
    /// per body axis, m/s² (`accel_clip.rs`).
    pub clip_unknown_mps2: [f64; 3],
    /// A clipped impact's ‖f‖ as its flanks put it, given once its run is over (0:
    /// none), m/s² (`accel_clip.rs`): the gait intensity takes it for the sample's.
    pub impact_mps2: f64,
}

/// One stride: from one stance onset of the instrumented foot to the next.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stride {
    /// Time of the stance onset that ends the stride, s.
    pub t_s: f64,
    /// Horizontal distance between the two stance onsets, m.
    pub length_m: f64,
    /// Time between them, s.
    pub duration_s: f64,
    /// `length_m / duration_s`, m/s.
    pub speed_mps: f64,
    /// Height change, m (up positive): stairs. Zero on a stride taken as level.
    pub climb_m: f64,
    /// Height the level-floor constraint took off at the end of this stride, m (the
    /// filter's climb over a stride it took as level; 0 when the stride was not
    /// levelled: see [`FootConfig::level_stride_max_grade`](super::FootConfig)).
    pub levelled_m: f64,
}

impl Stride {
    /// Every number of the stride, in declaration order (`t_s`, `length_m`,
    /// `duration_s`, `speed_mps`, `climb_m`, `levelled_m`).
    pub fn values(&self) -> [f64; 6] {
        [
            self.t_s,
            self.length_m,
            self.duration_s,
            self.speed_mps,
            self.climb_m,
            self.levelled_m,
        ]
    }
}

/// Where the foot is, after one sample. Frame: local level East-North-Up with the
/// origin where the navigator started and yaw 0 = body +x pointing East at start
/// (set `FootConfig::initial_yaw_rad` to use a known heading).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootEstimate {
    /// Time of the sample this estimate is for (the pipeline lags the newest input by
    /// [`FootNavigator::delay_samples`](super::FootNavigator::delay_samples)), s.
    pub t_s: f64,
    /// Position, m, ENU.
    pub position_m: [f64; 3],
    /// Velocity, m/s, ENU.
    pub velocity_mps: [f64; 3],
    /// Orientation body → ENU, `[w, x, y, z]`.
    pub quaternion: [f64; 4],
    /// ZYX Euler angles, rad: roll about body x, pitch about body y, yaw about up
    /// (counter-clockwise from East).
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    /// Heading of body +x clockwise from North (the ENU y axis), 0..2π.
    pub heading_rad: f64,
    /// 1-σ of position and velocity per ENU axis.
    pub position_std_m: [f64; 3],
    pub velocity_std_mps: [f64; 3],
    /// 1-σ of the tilt (about East and North) and of the heading, rad.
    pub tilt_std_rad: [f64; 2],
    pub heading_std_rad: f64,
    /// Accelerometer and gyroscope bias estimates, body axes.
    pub accel_bias_mps2: [f64; 3],
    pub gyro_bias_rads: [f64; 3],
    /// The detector said the foot is still; a zero-velocity update was applied.
    pub stance: bool,
    /// Strides counted and the sum of their horizontal lengths, m.
    pub strides: u64,
    pub distance_m: f64,
    /// The stride that ended on this sample.
    pub stride: Option<Stride>,
    /// The sample hit the configured sensor range (no update in its window).
    pub saturated: bool,
    /// The time step before this sample exceeded `max_gap_s` (see the navigator docs).
    pub gap: bool,
}

impl FootEstimate {
    /// Every number in the estimate (and in its stride, if any) is finite. The
    /// navigator guarantees it; apps and tests can check it cheaply.
    pub fn is_finite(&self) -> bool {
        let scalars = [
            self.t_s,
            self.roll_rad,
            self.pitch_rad,
            self.yaw_rad,
            self.heading_rad,
            self.heading_std_rad,
            self.distance_m,
        ];
        let stride_ok = self
            .stride
            .is_none_or(|s| s.values().iter().all(|v| v.is_finite()));
        stride_ok
            && self
                .position_m
                .iter()
                .chain(&self.velocity_mps)
                .chain(&self.quaternion)
                .chain(&self.position_std_m)
                .chain(&self.velocity_std_mps)
                .chain(&self.tilt_std_rad)
                .chain(&self.accel_bias_mps2)
                .chain(&self.gyro_bias_rads)
                .chain(&scalars)
                .all(|v| v.is_finite())
    }
}
