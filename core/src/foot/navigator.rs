//! [`FootNavigator`]: median pre-filter → zero-velocity detector → strapdown
//! mechanisation → 15-state error-state Kalman filter with zero-velocity updates.
//!
//! Pipeline and latency: the median filter and the detector both look at windows
//! centred on the sample they decide, so the estimate for a sample comes out
//! [`delay_samples`](FootNavigator::delay_samples) samples after it was pushed
//! (2 samples, 10 ms, at 200 Hz with the defaults).
//!
//! Start: the first [`FootConfig::alignment_s`] seconds must be a rest: roll and pitch
//! come from the mean specific force, local gravity from its magnitude, the gyroscope
//! bias from the mean rate (when enabled) and the sample rate from the timestamps
//! (the detector window in samples follows from it). Position starts at the origin,
//! yaw at [`FootConfig::initial_yaw_rad`].
//!
//! Bad input: a NaN/∞ field, a value no foot IMU reports, or a timestamp not after
//! the previous one is rejected with a typed error and changes nothing. Saturated
//! samples (at ≥ 99 % of a configured range) are used but no zero-velocity update
//! uses a window that contains one. A time step longer than `max_gap_s` is a gap: the
//! mechanisation integrates `max_gap_s` of it, the covariance is propagated over
//! that and its diagonal widened for the rest (position by 2 m/s × the gap), and the
//! estimate is flagged. Samples lost mid-swing (a step over 2.5 periods hiding more
//! than 2° of rotation) widen the attitude and velocity variances ([`Strapdown::lost`]).
//! Should the state ever become non-finite, the speed
//! absurd (> 50 m/s, a foot does not do that) or a bias estimate beyond any MEMS
//! sensor (‖b_a‖ > 5 m/s², ‖b_g‖ > 1 rad/s), the navigator keeps the state it had
//! before the sample (the covariance without its correlations), zeroes the velocity
//! and widens the velocity variance (counted in
//! [`divergence_resets`](FootNavigator::divergence_resets)) rather than returning
//! NaN. Variances are capped (1 000 km, 100 m/s, 1 rad tilt, π heading, 10 m/s²,
//! 1 rad/s, 1-σ) so that the covariance stays finite through any input.

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use super::accel_clip::{AccelCeiling, ClipRun, UNKNOWN_SHARE};
use super::clip::{AxisClip, AT_RANGE};
use super::config::{Correction, FootConfig, GyroTiming, MAX_DETECTOR_WINDOW};
use super::detect::{
    AdaptiveShoe, AdaptiveThresholds, FixedThresholds, ShoeDetector, SvmAdaptive, WindowStats,
    ZeroVelocityDetector, G_MPS2,
};
use super::ekf::{Cov, Noise, Strapdown, IA, IP, IV};
use super::error::FootError;
use super::hole::Hole;
use super::median::{MedianFilter, MAX_MEDIAN_WINDOW};
use super::still::StillFloor;
use super::svm::SvmModel;
use super::types::{BodySample, FootEstimate, FootSample, Stride};
use super::unresolved::Unresolved;
use super::zaru::Zaru;
use crate::ahrs::AxisRemap;
use crate::batch::{self, Batch, Counts};
use crate::input::{self, AccelUnits, Stream, TimeGuard};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::vec3;

/// Capacity of the sliding-maximum queue of the gait window.
const GAIT_CAP: usize = 1024;
/// An interval longer than this many sample periods has lost samples.
const LOST_INTERVALS: f64 = 2.5;
/// Across lost samples the trapezoid of the rates is trusted with a rotation up to
/// this, rad (2°); beyond, the attitude and velocity variances grow with what the
/// interval may hide ([`Strapdown::lost`]).
const LOST_BRIDGE_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;
/// Tilt error of a foot re-levelled from gravity at rest, rad (1°, as the start's
/// alignment).
const RELEVEL_TILT_RAD: f64 = std::f64::consts::PI / 180.0;
/// The sample rate [`FootConfig::zupt_gate_nis`] holds at, Hz (the rate it was chosen
/// at, the UofT trials'): at a lower rate a stance has fewer updates, each bounded
/// more loosely in proportion, so that a stance's pull per second does not depend on
/// the rate (at 50 Hz an under-sampled heel strike leaves a velocity error the
/// gated updates of a stance could not remove).
const ZUPT_GATE_RATE_HZ: f64 = 200.0;
/// Physical limits at the door.
/// Speed above which the state is considered diverged, m/s.
const MAX_SPEED_MPS: f64 = 50.0;
/// Bias estimates beyond what any MEMS IMU has also mean divergence.
const MAX_ACC_BIAS_MPS2: f64 = 5.0;
const MAX_GYRO_BIAS_RADS: f64 = 1.0;

/// A sample a batch push rejected, with its index in the batch.
pub type FootRejection = crate::batch::Rejected<FootError>;

/// The rotation `exp([α×])` (Rodrigues) as a matrix, `None` when `α` is zero (the
/// default: the door then skips it).
fn accel_rotation(alpha: &[f64; 3]) -> Option<Matrix3<f64>> {
    if alpha == &[0.0; 3] {
        return None;
    }
    let a = Vector3::from(*alpha);
    // sin θ / θ and (1 − cos θ) / θ² = ½ (sin(θ/2) / (θ/2))², by series near 0 (a
    // denormal angle must not divide 0 by 0).
    let sinc = |x: f64| {
        if x < 1e-4 {
            1.0 - x * x / 6.0
        } else {
            x.sin() / x
        }
    };
    let th = a.norm();
    let h = sinc(0.5 * th);
    let k = a.cross_matrix();
    Some(Matrix3::identity() + k * sinc(th) + k * k * (0.5 * h * h))
}

#[derive(Clone, Debug, Default, PartialEq)]
struct Alignment {
    n: u64,
    t_first: f64,
    t_last: f64,
    sum_f: [f64; 3],
    sum_w: [f64; 3],
}

#[derive(Clone, Debug, PartialEq)]
pub struct FootNavigator {
    config: FootConfig,
    noise: Noise,
    /// [`FootConfig::accel_alignment_rad`] as a matrix (`None`: zero), derived from it.
    accel_rotation: Option<Matrix3<f64>>,
    /// Time of the newest accepted raw sample.
    time: TimeGuard,
    units: AccelUnits,
    median: MedianFilter,
    /// Gyroscope clipping repair per sensor axis (with a configured range).
    clip: [AxisClip; 3],
    /// The rotation the raw rates do not resolve (before the clipping repair).
    unresolved: Unresolved,
    /// The accelerometer's ceiling per sensor axis and sign (`accel_clip`).
    accel_ceiling: AccelCeiling,
    /// Clipped runs per sensor axis, for the impact's peak (`accel_clip`).
    accel_runs: [ClipRun; 3],
    /// Filtered samples, newest last (detector window source).
    det: Ring<BodySample, MAX_DETECTOR_WINDOW>,
    /// Monotonic queue `(t, ‖f‖)` for the gait-window peak.
    gait: Ring<(f64, f64), GAIT_CAP>,
    /// The quietest detector windows of the last seconds (the detector's floor).
    still: StillFloor,
    align: Alignment,
    /// Detector window in samples, set at alignment (0 before).
    window: usize,
    rate_hz: f64,
    ins: Option<Strapdown>,
    /// Time of the last sample integrated (or of the last alignment sample).
    ins_t: f64,
    stance: bool,
    swing_start_t: f64,
    last_onset: Option<(f64, [f64; 3])>,
    /// The walker's turn rate and a hole waiting for a stance.
    hole: Hole,
    /// Stances re-levelled from gravity after a hole left the foot upside down.
    relevels: u64,
    /// Gyroscope bias jumps: the stillest still window of the current stance and
    /// the last unexplained still rate.
    zaru: Zaru,
    /// Bias jumps confirmed and taken (zero-angular-rate updates).
    bias_jumps: u64,
    strides: u64,
    distance_m: f64,
    resets: u64,
    latest: Option<FootEstimate>,
}

impl FootNavigator {
    pub fn new(config: FootConfig) -> Result<Self, FootError> {
        config.validate()?;
        let noise = Noise {
            acc_var_per_s: config.accel_noise_density.powi(2),
            gyro_var_per_s: config.gyro_noise_density.powi(2),
            acc_bias_var_per_s: config.accel_bias_walk.powi(2),
            gyro_bias_var_per_s: config.gyro_bias_walk.powi(2),
        };
        Ok(Self {
            accel_rotation: accel_rotation(&config.accel_alignment_rad),
            median: MedianFilter::new(config.median_window),
            clip: [AxisClip::new(); 3],
            unresolved: Unresolved::default(),
            accel_ceiling: AccelCeiling::default(),
            accel_runs: [ClipRun::default(); 3],
            config,
            noise,
            time: TimeGuard::new(Stream::Imu),
            units: AccelUnits::new(),
            det: Ring::new(),
            gait: Ring::new(),
            still: StillFloor::default(),
            align: Alignment::default(),
            window: 0,
            rate_hz: 0.0,
            ins: None,
            ins_t: f64::NEG_INFINITY,
            stance: true,
            swing_start_t: 0.0,
            last_onset: None,
            hole: Hole::default(),
            relevels: 0,
            zaru: Zaru::default(),
            bias_jumps: 0,
            strides: 0,
            distance_m: 0.0,
            resets: 0,
            latest: None,
        })
    }

    pub fn config(&self) -> &FootConfig {
        &self.config
    }

    /// Alignment is done and samples are being integrated.
    pub fn is_aligned(&self) -> bool {
        self.ins.is_some()
    }

    /// Sample rate measured during alignment, Hz (0 before).
    pub fn sample_rate_hz(&self) -> f64 {
        self.rate_hz
    }

    /// Detector window, samples (0 before alignment).
    pub fn detector_window(&self) -> usize {
        self.window
    }

    /// How many samples the estimates lag the newest input.
    pub fn delay_samples(&self) -> usize {
        self.median.delay() + self.window / 2
    }

    /// Stances re-levelled from gravity because samples lost mid-swing had left the
    /// attitude more than 90° from it.
    pub fn relevels(&self) -> u64 {
        self.relevels
    }

    /// The accelerometer's ceiling in use, m/s²: 99 % of
    /// [`FootConfig::accel_range_mps2`] when configured, else the lowest ceiling found
    /// in the data so far on any sensor axis and sign (`accel_clip.rs`), or `None`:
    /// no clipping seen. Samples at it count as clipped: their velocity variance grows
    /// by what they may hide, and the detector's gait intensity takes their impact's
    /// peak from its flanks.
    pub fn accel_ceiling_mps2(&self) -> Option<f64> {
        match self.config.accel_range_mps2 {
            Some(r) => Some(AT_RANGE * r),
            None => self.accel_ceiling.lowest_mps2(),
        }
    }

    /// Gyroscope bias jumps taken: two consecutive still stances whose rates agreed
    /// and that the bias estimate could not explain set it anew (zero-angular-rate
    /// updates; `zaru.rs`).
    pub fn bias_jumps(&self) -> u64 {
        self.bias_jumps
    }

    /// Times the divergence guard reset the velocity.
    pub fn divergence_resets(&self) -> u64 {
        self.resets
    }

    /// The newest estimate (None before alignment).
    pub fn estimate(&self) -> Option<FootEstimate> {
        self.latest
    }

    /// Check a sample at the door without changing anything.
    pub fn check(&self, s: &FootSample) -> Result<(), FootError> {
        self.check_inner(s).map(|_| ())
    }

    /// The door; returns the interval since the previous sample (`None` for the first)
    /// and the new mean |a| of the g-units check.
    fn check_inner(&self, s: &FootSample) -> Result<(Option<f64>, f64), FootError> {
        let dt = self.time.check(s.t_s)?;
        input::accel(&s.accel_mps2)?;
        input::gyro(&s.gyro_rads)?;
        Ok((dt, self.units.check(dt, vec3::norm(s.accel_mps2))?))
    }

    /// Push one sample. Returns the estimate of the sample the pipeline finished (the
    /// one [`delay_samples`](Self::delay_samples) back), or `None` while filling or
    /// aligning.
    pub fn push(&mut self, s: &FootSample) -> Result<Option<FootEstimate>, FootError> {
        self.push_inner(s, None)
    }

    /// Push one sample whose stance is known from outside (a pressure insole, labels
    /// of a data set): the detector is bypassed for it. Same output as [`push`](Self::push).
    pub fn push_with_stance(
        &mut self,
        s: &FootSample,
        stance: bool,
    ) -> Result<Option<FootEstimate>, FootError> {
        self.push_inner(s, Some(stance))
    }

    fn push_inner(
        &mut self,
        s: &FootSample,
        external: Option<bool>,
    ) -> Result<Option<FootEstimate>, FootError> {
        let (dt, mean) = self.check_inner(s)?;
        self.time.accept(s.t_s);
        self.units.accept(mean);
        let mut f = self.config.axis_remap.apply(s.accel_mps2);
        if let Some(r) = &self.accel_rotation {
            f = (r * Vector3::from(f)).into();
        }
        let dt_int = dt.unwrap_or(0.0).min(self.config.max_gap_s);
        let unresolved_rad = self
            .unresolved
            .push(self.config.axis_remap.apply(s.gyro_rads), dt_int);
        let mut gyro = s.gyro_rads;
        if let Some(range) = self.config.gyro_range_rads {
            // The rotation a clipped swing peak did not report (`clip`).
            let spread = u32::try_from(self.config.median_window).unwrap_or(1);
            for (g, c) in gyro.iter_mut().zip(self.clip.iter_mut()) {
                *g = c.push(s.t_s, *g, dt.unwrap_or(0.0), AT_RANGE * range, spread);
            }
        }
        let w = self.config.axis_remap.apply(gyro);
        // What clipped accelerometer axes did not report, and a clipped impact's peak
        // (`accel_clip`).
        let clipped = self
            .accel_ceiling
            .push(&s.accel_mps2, self.config.accel_range_mps2);
        let norm2 = vec3::dot(s.accel_mps2, s.accel_mps2);
        let mut impact_mps2 = 0.0_f64;
        let mut unknown = [0.0; 3];
        for (((run, &x), &c), u) in self
            .accel_runs
            .iter_mut()
            .zip(&s.accel_mps2)
            .zip(&clipped)
            .zip(unknown.iter_mut())
        {
            if let Some(peak) = run.push(x, c, norm2) {
                impact_mps2 = impact_mps2.max(peak);
            }
            if c {
                *u = UNKNOWN_SHARE * x.abs();
            }
        }
        let clip_unknown_mps2 = self.config.axis_remap.apply(unknown).map(f64::abs);
        let saturated = saturated(&s.accel_mps2, self.config.accel_range_mps2)
            || saturated(&s.gyro_rads, self.config.gyro_range_rads);
        let body = BodySample {
            t_s: s.t_s,
            f,
            w,
            saturated,
            external,
            unresolved_rad,
            clip_unknown_mps2,
            impact_mps2,
        };
        let Some(filtered) = self.median.push(body) else {
            return Ok(None);
        };
        Ok(self.after_median(filtered))
    }

    /// Push a batch. Bad samples are skipped and reported; the estimates (one per
    /// processed sample, after the pipeline delay) are returned in order.
    pub fn push_batch(&mut self, samples: &[FootSample]) -> Batch<FootEstimate, FootError> {
        batch::run(samples, |s| self.push(s))
    }

    /// As [`push_batch`](Self::push_batch), but `on_estimate` sees every estimate
    /// instead of it being kept: a long replay needs no memory for them, and a clean
    /// batch allocates nothing.
    pub fn push_batch_with(
        &mut self,
        samples: &[FootSample],
        on_estimate: impl FnMut(&FootEstimate),
    ) -> Counts<FootError> {
        batch::counted(samples, on_estimate, |s| self.push(s))
    }

    fn after_median(&mut self, s: BodySample) -> Option<FootEstimate> {
        self.det.push(s);
        let fnorm = vec3::norm(s.f).max(s.impact_mps2);
        while let Some(&(_, v)) = self.gait.newest().as_ref() {
            if v <= fnorm {
                self.gait.pop_back();
            } else {
                break;
            }
        }
        if self.gait.len() == GAIT_CAP {
            self.gait.pop_front();
        }
        self.gait.push((s.t_s, fnorm));
        let horizon = s.t_s - self.config.gait_window_s;
        while let Some((t, _)) = self.gait.get(0) {
            if t < horizon && self.gait.len() > 1 {
                self.gait.pop_front();
            } else {
                break;
            }
        }

        if self.ins.is_none() {
            self.accumulate_alignment(&s);
            return None;
        }
        if self.det.len() < self.window {
            return None;
        }
        let c = self.det.back(self.window / 2)?;
        if c.t_s <= self.ins_t {
            return None;
        }
        let stats = self.window_stats();
        self.still.push(c.t_s, &stats);
        let stats = self.still.apply(stats);
        Some(self.integrate(&c, &stats))
    }

    fn accumulate_alignment(&mut self, s: &BodySample) {
        let a = &mut self.align;
        if a.n == 0 {
            a.t_first = s.t_s;
        }
        a.n += 1;
        a.t_last = s.t_s;
        for i in 0..3 {
            a.sum_f[i] += s.f[i];
            a.sum_w[i] += s.w[i];
        }
        if a.t_last - a.t_first < self.config.alignment_s || a.n < 3 {
            return;
        }
        let n = a.n as f64;
        let mf = Vector3::new(a.sum_f[0] / n, a.sum_f[1] / n, a.sum_f[2] / n);
        let mw = Vector3::new(a.sum_w[0] / n, a.sum_w[1] / n, a.sum_w[2] / n);
        let rate = (n - 1.0) / (a.t_last - a.t_first);
        let mut win = (self.config.detector_window_s * rate).round() as usize;
        if win % 2 == 0 {
            win += 1;
        }
        self.window = win.clamp(3, MAX_DETECTOR_WINDOW);
        self.rate_hz = rate;
        let g = mf.norm().clamp(0.5 * G_MPS2, 1.5 * G_MPS2);
        let roll = mf.y.atan2(mf.z);
        let pitch = (-mf.x).atan2((mf.y * mf.y + mf.z * mf.z).sqrt());
        let q = UnitQuaternion::from_euler_angles(roll, pitch, self.config.initial_yaw_rad);
        let bg = if self.config.gyro_bias_from_alignment {
            mw
        } else {
            Vector3::zeros()
        };
        let c = &self.config;
        let tilt = 1.0_f64.to_radians();
        let std = [
            1e-3,
            1e-3,
            1e-3,
            1e-3,
            1e-3,
            1e-3,
            tilt,
            tilt,
            1e-4,
            c.initial_accel_bias_std_mps2,
            c.initial_accel_bias_std_mps2,
            c.initial_accel_bias_std_mps2,
            c.initial_gyro_bias_std_rads,
            c.initial_gyro_bias_std_rads,
            c.initial_gyro_bias_std_rads,
        ];
        self.ins = Some(Strapdown::new(
            q,
            g,
            bg,
            &std,
            Vector3::from(s.f),
            Vector3::from(s.w),
        ));
        self.ins_t = s.t_s;
        self.stance = true;
        self.last_onset = Some((s.t_s, [0.0; 3]));
    }

    fn window_stats(&self) -> WindowStats {
        let n = self.window;
        let g = self.ins.as_ref().map_or(G_MPS2, |i| i.g);
        let c = self.det.back(n / 2).unwrap_or_default();
        let mut mf = [0.0; 3];
        let mut mw = [0.0; 3];
        let mut sat = false;
        for k in 0..n {
            let s = self.det.back(k).unwrap_or_default();
            for i in 0..3 {
                mf[i] += s.f[i];
                mw[i] += s.w[i];
            }
            sat |= s.saturated;
        }
        let inv = 1.0 / n as f64;
        for i in 0..3 {
            mf[i] *= inv;
            mw[i] *= inv;
        }
        let mfn = vec3::norm(mf).max(1e-9);
        let u = [mf[0] / mfn, mf[1] / mfn, mf[2] / mfn];
        let mut vf = [0.0; 3];
        let mut vw = [0.0; 3];
        let mut shoe_a = 0.0;
        let mut shoe_w = 0.0;
        for k in 0..n {
            let s = self.det.back(k).unwrap_or_default();
            for i in 0..3 {
                let df = s.f[i] - mf[i];
                let dw = s.w[i] - mw[i];
                vf[i] += df * df;
                vw[i] += dw * dw;
                let r = s.f[i] - g * u[i];
                shoe_a += r * r;
                shoe_w += s.w[i] * s.w[i];
            }
        }
        let cn = vec3::norm(c.f);
        WindowStats {
            acc_norm_mps2: cn,
            acc_dev_mps2: (cn - g).abs(),
            gyro_norm_rads: vec3::norm(c.w),
            acc_std_mps2: vf.map(|v| (v * inv).sqrt()),
            gyro_std_rads: vw.map(|v| (v * inv).sqrt()),
            peak_acc_norm_mps2: self.gait.get(0).map_or(cn, |(_, v)| v),
            shoe_acc_ss: shoe_a,
            shoe_gyro_ss: shoe_w,
            // Filled in by the stillness floor (`StillFloor::apply`).
            still_acc_ms2_sq: 0.0,
            still_gyro_rads_sq: 0.0,
            n,
            saturated: sat,
        }
    }

    /// Whether the detector calls the window around the sample `delay` back stance
    /// (exposed for evaluations through [`FootEstimate::stance`]).
    fn detect(&self, stats: &WindowStats) -> bool {
        self.config.detector.is_stance(stats)
    }

    fn integrate(&mut self, c: &BodySample, stats: &WindowStats) -> FootEstimate {
        let stance = c.external.unwrap_or_else(|| self.detect(stats));
        let dt = c.t_s - self.ins_t;
        let gap = dt > self.config.max_gap_s;
        let dt_int = dt.min(self.config.max_gap_s);
        let correction = self.config.correction;
        let zupt_sigma = self.config.zupt_noise_mps;
        let noise = self.noise;
        let interval_mean = self.config.gyro_timing == GyroTiming::IntervalMean;
        // The bound per update, so that a stance pulls as much per second at any rate.
        let gate = self
            .config
            .zupt_gate_nis
            .map(|g| g * (ZUPT_GATE_RATE_HZ / self.rate_hz).max(1.0));
        let Some(ins) = self.ins.as_mut() else {
            return FootEstimate::default();
        };
        // What the divergence guard falls back to (the covariance only by its
        // diagonal: copying all of it every sample would cost more than the guard).
        let before = (ins.q, ins.p, ins.ba, ins.bg, ins.cov.diagonal());
        // Samples lost: the rotation the interval may hide, the larger rate on either
        // side times the interval, when it is more than the trapezoid can be trusted
        // with (the foot swings at up to 9 rad/s).
        let lost = self.rate_hz > 0.0 && dt * self.rate_hz > LOST_INTERVALS;
        let missed = if lost {
            ins.prev_w.norm().max(vec3::norm(c.w)) * dt
        } else {
            0.0
        };
        ins.propagate(c, dt_int, dt, &noise, interval_mean);
        if missed > LOST_BRIDGE_RAD {
            ins.lost(missed);
            // The heading keeps turning as the walker did over the time not integrated.
            ins.turn(self.hole.turn_over(c.t_s, dt - dt_int));
            self.hole.pending = true;
        }
        // Gyroscope bias jumps (the biases are fed back only with `Full`), checked
        // when a stance ends against its stillest window.
        let zaru = correction == Correction::Full;
        let gyro_var = noise.gyro_var_per_s * self.rate_hz;
        if zaru
            && !stance
            && self.stance
            && self.zaru.stance_ended(ins, gyro_var, (self.rate_hz, c.t_s))
        {
            self.bias_jumps = self.bias_jumps.saturating_add(1);
        }
        if stance {
            ins.zupt(zupt_sigma, gate, correction);
            if zaru && !stats.saturated {
                let detector_var = vec3::dot(stats.gyro_std_rads, stats.gyro_std_rads) / 3.0;
                self.zaru
                    .observe(&self.det, self.rate_hz, gyro_var, (detector_var, stats.n));
            }
            if std::mem::take(&mut self.hole.pending) {
                let f = window_mean_f(&self.det, self.window);
                if ins.relevel_if_upside_down(&f, RELEVEL_TILT_RAD * RELEVEL_TILT_RAD) {
                    self.relevels = self.relevels.saturating_add(1);
                }
            }
        }
        let cov_finite = ins.condition();
        if !(cov_finite && ins.state_is_finite())
            || ins.v.norm() > MAX_SPEED_MPS
            || ins.ba.norm() > MAX_ACC_BIAS_MPS2
            || ins.bg.norm() > MAX_GYRO_BIAS_RADS
        {
            // Divergence guard: keep where we were, stop, and admit uncertainty.
            let (q, p, ba, bg, var) = before;
            ins.q = q;
            ins.p = p;
            ins.ba = ba;
            ins.bg = bg;
            ins.v = Vector3::zeros();
            ins.prev_f = Vector3::from(c.f);
            ins.prev_w = Vector3::from(c.w);
            ins.cov = Cov::from_diagonal(&var);
            for i in 0..3 {
                ins.cov[(IV + i, IV + i)] += 1.0;
            }
            self.resets = self.resets.saturating_add(1);
        }
        self.ins_t = c.t_s;

        let mut p = [ins.p.x, ins.p.y, ins.p.z];
        let mut stride = None;
        if stance && !self.stance {
            if c.t_s - self.swing_start_t >= self.config.min_swing_s {
                if let Some((t0, p0)) = self.last_onset {
                    let len = (p[0] - p0[0]).hypot(p[1] - p0[1]);
                    let dur = c.t_s - t0;
                    let mut climb = p[2] - p0[2];
                    let mut levelled = 0.0;
                    if level_stride(self.config.level_stride_max_grade, climb, len) {
                        // The nominal position feeds nothing back into the
                        // mechanisation, so moving its height changes nothing else.
                        ins.p.z -= climb;
                        p[2] = p0[2];
                        levelled = climb;
                        climb = 0.0;
                    }
                    stride = Some(Stride {
                        t_s: c.t_s,
                        length_m: len,
                        duration_s: dur,
                        speed_mps: if dur > 0.0 { len / dur } else { 0.0 },
                        climb_m: climb,
                        levelled_m: levelled,
                    });
                    self.strides = self.strides.saturating_add(1);
                    self.distance_m += len;
                }
                self.last_onset = Some((c.t_s, p));
                self.hole.onset(c.t_s, ins.toe_yaw());
            }
        } else if !stance && self.stance {
            self.swing_start_t = c.t_s;
        }
        self.stance = stance;
        let est = self.make_estimate(c, stance, stride, gap);
        self.latest = Some(est);
        est
    }

    fn make_estimate(
        &self,
        c: &BodySample,
        stance: bool,
        stride: Option<Stride>,
        gap: bool,
    ) -> FootEstimate {
        let Some(ins) = self.ins.as_ref() else {
            return FootEstimate::default();
        };
        let (roll, pitch, yaw) = ins.q.euler_angles();
        let sd = |i: usize| ins.cov[(i, i)].sqrt();
        let heading = (std::f64::consts::FRAC_PI_2 - yaw).rem_euclid(std::f64::consts::TAU);
        let q = ins.q.coords; // x, y, z, w
        FootEstimate {
            t_s: c.t_s,
            position_m: [ins.p.x, ins.p.y, ins.p.z],
            velocity_mps: [ins.v.x, ins.v.y, ins.v.z],
            quaternion: [q.w, q.x, q.y, q.z],
            roll_rad: roll,
            pitch_rad: pitch,
            yaw_rad: yaw,
            heading_rad: heading,
            position_std_m: [sd(IP), sd(IP + 1), sd(IP + 2)],
            velocity_std_mps: [sd(IV), sd(IV + 1), sd(IV + 2)],
            tilt_std_rad: [sd(IA), sd(IA + 1)],
            heading_std_rad: sd(IA + 2),
            accel_bias_mps2: [ins.ba.x, ins.ba.y, ins.ba.z],
            gyro_bias_rads: [ins.bg.x, ins.bg.y, ins.bg.z],
            stance,
            strides: self.strides,
            distance_m: self.distance_m,
            stride,
            saturated: c.saturated,
            gap,
        }
    }

    /// The zero-velocity detector in use.
    pub fn detector(&self) -> &ZeroVelocityDetector {
        &self.config.detector
    }

    /// The detector-window statistics the detector saw for the newest estimate (call
    /// right after a push that returned `Some`): the same code path as the detector,
    /// for training (`stridekit train zupt`) and evaluations. `None` before alignment.
    pub fn detector_stats(&self) -> Option<WindowStats> {
        (self.ins.is_some() && self.window > 0 && self.det.len() >= self.window)
            .then(|| self.still.apply(self.window_stats()))
    }
}

/// Mean specific force (body axes) of the newest `n` filtered samples (the detector's
/// window).
fn window_mean_f(det: &Ring<BodySample, MAX_DETECTOR_WINDOW>, n: usize) -> Vector3<f64> {
    let n = n.clamp(1, det.len().max(1));
    let mut m = Vector3::zeros();
    for k in 0..n {
        m += Vector3::from(det.back(k).unwrap_or_default().f);
    }
    m / n as f64
}

/// Whether a stride that rose `climb_m` over `length_m` horizontally is taken as
/// level ([`FootConfig::level_stride_max_grade`]).
fn level_stride(max_grade: Option<f64>, climb_m: f64, length_m: f64) -> bool {
    max_grade.is_some_and(|g| climb_m.abs() <= g * length_m)
}

#[inline]
fn saturated(v: &[f64; 3], range: Option<f64>) -> bool {
    range.is_some_and(|r| v.iter().any(|x| x.abs() >= AT_RANGE * r))
}

mod snapshot;
