//! Running pace from GNSS fixes and pedometer steps (method 1 of docs/architecture.md).
//!
//! [`PaceTracker`] is the state machine apps feed. It checks every sample at the
//! door (finite numbers, ranges, time order per stream), converts fixes into a local
//! ENU frame anchored at the first fix, keeps the step stream, and runs one of two
//! fusion filters chosen by [`PaceMode`]:
//! - [`PaceMode::AsPublished`]: the paper's complementary filter (`published`);
//! - [`PaceMode::Adaptive`] (default): an adaptive Kalman filter (`adaptive`).
//!
//! A rejected sample returns a [`PaceError`] and leaves the state exactly as it was.

mod accel;
mod adaptive;
mod baseline;
mod cadence;
mod calibration;
mod config;
mod crosscheck;
mod error;
mod held;
mod published;
mod share;
mod steps;
mod types;
mod walking;

/// GNSS-only speed baselines the evaluation compares the fusion filters against.
pub use baseline::{Baseline, BaselineKind};
pub use calibration::{
    AccelStepModel, PaceCalibration, PACE_CALIBRATION_MAGIC, PACE_CALIBRATION_VERSION,
};
pub use config::{AdaptiveParams, PaceConfig, PaceMode, PublishedParams};
pub use error::{PaceError, Stream};
pub use types::{
    GnssFix, PaceEstimate, PaceFlags, PaceSample, PaceSource, StepSample, MIN_PACE_SPEED_MPS,
};

use crate::batch::{self, Batch};
use crate::geo::LocalFrame;
use crate::input::{self, Stream as InputStream, TimeGuard};
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stepdetect::{AccelSample, StepEvent};
use accel::AccelSteps;
use crosscheck::{CrossCheck, Finding};
use held::{unit_known, Held};
use steps::StepStream;

/// Without any sample for longer than this, no distance is added for the gap, seconds
/// (the app was stopped or the device asleep: nothing is known about that time).
pub const MAX_INTEGRATION_GAP_S: f64 = 30.0;

/// Snapshot engine kind byte for the pace tracker.
const SNAPSHOT_KIND: u8 = 1;
/// Snapshot format version written by this build.
/// Version 3: the input layer's time state per stream, the pedometer speed and the
/// session's calibration sums. Version 5: the raw-accelerometer step-length model.
/// Version 6: the calibration's accelerometer model. Version 7: the cross-checks
/// between GNSS and the steps, the step stream's steps per report, the time state of
/// the pushed step samples and the samples held until their unit is known.
const SNAPSHOT_VERSION: u16 = 7;

/// A GNSS fix after validation, in the local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFix {
    pub t_s: f64,
    pub east_m: f64,
    pub north_m: f64,
    /// 68 % horizontal accuracy, metres, if reported.
    pub accuracy_m: Option<f64>,
    /// Receiver speed and its accuracy, m/s, if both reported.
    pub speed: Option<(f64, f64)>,
}

/// Read-only context the filters get with each update.
pub struct Context<'a> {
    pub config: &'a PaceConfig,
    pub steps: &'a StepStream,
    /// Raw accelerometer input's steps, when the app pushes it.
    pub accel: Option<&'a AccelSteps>,
    /// Relative 1-σ added to the pedometer speed while it disagrees with GNSS
    /// (`crosscheck`; 0 while they agree).
    pub pedometer_extra_rel_sigma: f64,
}

/// The fusion filter behind a tracker. Both variants live inline (no heap), so the
/// size difference is accepted: a tracker is created once per activity.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
enum Filter {
    Published(published::PublishedFilter),
    Adaptive(adaptive::AdaptiveFilter),
}

/// Running-pace state machine. Feed it GNSS fixes and step data in time order (each
/// stream on its own); read a [`PaceEstimate`] at every fix or at any time.
#[derive(Clone, Debug, PartialEq)]
pub struct PaceTracker {
    config: PaceConfig,
    frame: Option<LocalFrame>,
    /// Time state of the GNSS stream.
    fix_time: TimeGuard,
    /// Time state of the pushed step samples (units; the step stream keeps the order
    /// of every step, detected ones included).
    step_time: TimeGuard,
    /// Fixes and step samples held until their stream's unit is known (`held`).
    held: Held,
    steps: StepStream,
    filter: Filter,
    /// Step detector and feature step length for raw accelerometer input, created on
    /// the first sample (see `accel`).
    accel: Option<AccelSteps>,
    /// Cross-checks between GNSS and the steps (strides for steps, a pedometer that
    /// disagrees), see `crosscheck`.
    check: CrossCheck,
}

/// A sample a batch push rejected, with its index in the batch.
pub type Rejection = crate::batch::Rejected<PaceError>;

impl PaceTracker {
    /// A tracker with a validated configuration.
    pub fn new(config: PaceConfig) -> Result<Self, PaceError> {
        config.validate()?;
        Ok(Self {
            filter: Self::make_filter(&config),
            config,
            frame: None,
            fix_time: TimeGuard::new(InputStream::Gnss),
            step_time: TimeGuard::new(InputStream::Steps),
            held: Held::default(),
            steps: StepStream::new(),
            accel: None,
            check: CrossCheck::new(),
        })
    }

    fn make_filter(config: &PaceConfig) -> Filter {
        match config.mode {
            PaceMode::AsPublished => Filter::Published(published::PublishedFilter::new(config)),
            PaceMode::Adaptive => Filter::Adaptive(adaptive::AdaptiveFilter::new(config)),
        }
    }

    pub fn config(&self) -> &PaceConfig {
        &self.config
    }

    /// The local ENU frame (anchored at the first fix), once a fix was seen.
    pub fn frame(&self) -> Option<&LocalFrame> {
        self.frame.as_ref()
    }

    /// Steps detected from raw accelerometer input so far.
    pub fn detected_steps(&self) -> u64 {
        self.accel.as_ref().map_or(0, |a| a.detector().step_count())
    }

    /// Calibration of the feature step-length model of raw accelerometer input
    /// (`None` without such input).
    pub fn accel_step_length_calibration(&self) -> Option<crate::steplength::Calibration> {
        self.accel.as_ref().map(|a| a.calibration())
    }

    /// The step-length line learned so far, to carry to the next session (see
    /// [`PaceCalibration`]); `None` until the step length is learned from good GNSS
    /// (or given), and always `None` in [`PaceMode::AsPublished`].
    ///
    /// With raw accelerometer input, the export also holds the feature step-length
    /// model ([`PaceCalibration::accel_model`]) once GNSS has calibrated it (or it was
    /// imported); otherwise the imported one, if any, is carried on unchanged. When
    /// only that model was learned (a walk with good GNSS teaches the running line
    /// nothing), the export holds it with the running line as it stands, unlearned:
    /// its `step_length_std_m` stays wide (the prior's, ≈ 0.4 m), and such a line is
    /// not imported (see [`PaceConfig::calibration`]).
    pub fn calibration(&self) -> Option<PaceCalibration> {
        let Filter::Adaptive(f) = &self.filter else {
            return None;
        };
        let imported = self.config.calibration.and_then(|c| c.accel_model);
        let accel_model = self
            .accel
            .as_ref()
            .and_then(AccelSteps::export)
            .or(imported);
        let line = f
            .calibration(self.config.calibration)
            .or_else(|| accel_model.and_then(|_| f.current_line()));
        line.map(|c| PaceCalibration { accel_model, ..c })
    }

    /// The fused position, metres east and north of the first fix (the origin of
    /// [`Self::frame`]): GNSS-corrected, carried on by speed and the track's direction in
    /// outages. `None` before the first fix and in [`PaceMode::AsPublished`] (the
    /// published method estimates speed only).
    pub fn position_enu_m(&self) -> Option<[f64; 2]> {
        match &self.filter {
            Filter::Published(_) => None,
            Filter::Adaptive(f) => f.position_enu_m(),
        }
    }

    /// Counter resets seen in the step stream.
    pub fn step_counter_resets(&self) -> u64 {
        self.steps.resets()
    }

    fn validate_fix(&self, fix: &GnssFix) -> Result<(), PaceError> {
        self.fix_time.check(fix.t_s)?;
        input::gnss_fix(fix)?;
        Ok(())
    }

    /// Push one GNSS fix; returns the estimate for this epoch. Until the GNSS stream's
    /// time unit is known (it showed an interval within its limits,
    /// [`TimeGuard::established`], or the fix is close in time to the step stream's
    /// known-good samples) the fix is held, not used, and the estimate is the one
    /// before it (see `held`).
    pub fn push_fix(&mut self, fix: &GnssFix) -> Result<PaceEstimate, PaceError> {
        self.validate_fix(fix)?;
        self.fix_time.accept(fix.t_s);
        let known = unit_known(&self.fix_time, &self.step_time, fix.t_s);
        if !known && self.held.hold_fix(*fix) {
            return Ok(self.current());
        }
        self.release_held();
        Ok(self.apply_fix(fix))
    }

    /// Apply the held samples whose stream's unit is now known, in time order (step
    /// samples first at equal times, as replays push them).
    fn release_held(&mut self) {
        let fixes_known = |t: &TimeGuard, o: &TimeGuard, f: &GnssFix| unit_known(t, o, f.t_s);
        let steps_known = |t: &TimeGuard, o: &TimeGuard, s: &StepSample| unit_known(t, o, s.t_s());
        let mut fixes = [None; held::HELD];
        if self
            .held
            .peek_fixes()
            .iter()
            .flatten()
            .all(|f| fixes_known(&self.fix_time, &self.step_time, f))
        {
            fixes = self.held.take_fixes();
        }
        let mut steps = [None; held::HELD];
        if self
            .held
            .peek_steps()
            .iter()
            .flatten()
            .all(|s| steps_known(&self.step_time, &self.fix_time, s))
        {
            steps = self.held.take_steps();
        }
        let (mut i, mut j) = (0, 0);
        loop {
            let f = fixes.get(i).copied().flatten();
            let s = steps.get(j).copied().flatten();
            match (f, s) {
                (Some(f), Some(s)) if s.t_s() <= f.t_s => {
                    self.apply_held_steps(&s);
                    j += 1;
                }
                (Some(f), _) => {
                    self.apply_fix(&f);
                    i += 1;
                }
                (None, Some(s)) => {
                    self.apply_held_steps(&s);
                    j += 1;
                }
                (None, None) => break,
            }
        }
    }

    /// A held step sample, still after the stream's last step (a detected step from
    /// raw acceleration in between would put it behind: skipped; one step source per
    /// tracker).
    fn apply_held_steps(&mut self, s: &StepSample) {
        if self.steps.check(s).is_ok() {
            self.apply_steps(s);
        }
    }

    /// Run an accepted fix through the filter and the cross-checks.
    fn apply_fix(&mut self, fix: &GnssFix) -> PaceEstimate {
        let frame = *self
            .frame
            .get_or_insert_with(|| LocalFrame::new(fix.lat_deg, fix.lon_deg, 0.0));
        let enu = frame.to_enu(fix.lat_deg, fix.lon_deg, 0.0);
        let local = LocalFix {
            t_s: fix.t_s,
            east_m: enu[0],
            north_m: enu[1],
            accuracy_m: fix.horizontal_accuracy_m,
            speed: fix.speed_mps.zip(fix.speed_accuracy_mps),
        };
        if let Some(a) = &mut self.accel {
            a.on_fix(local.t_s, local.east_m, local.north_m, local.accuracy_m);
        }
        let ctx = Context {
            config: &self.config,
            steps: &self.steps,
            accel: self.accel.as_ref(),
            pedometer_extra_rel_sigma: self.check.pedometer_extra_rel_sigma(),
        };
        let mut e = match &mut self.filter {
            Filter::Published(f) => f.on_fix(&local, &ctx),
            Filter::Adaptive(f) => f.on_fix(&local, &ctx),
        };
        self.cross_check(&local);
        e.flags = self.check.flags();
        e
    }

    /// The cross-checks after a fix, and what the tracker does about their findings.
    fn cross_check(&mut self, fix: &LocalFix) {
        let pedometer_mps = match &self.filter {
            Filter::Published(f) => f.pedometer_speed_mps(),
            Filter::Adaptive(f) => f.pedometer_speed_mps(),
        };
        let stationary_after_s = self.config.stationary_after_s;
        match self
            .check
            .on_fix(fix, &self.steps, pedometer_mps, stationary_after_s)
        {
            Finding::Nothing => {}
            Finding::Rescale(k) => {
                self.steps.rescale(k);
                match &mut self.filter {
                    Filter::Published(f) => f.rescale_steps(k),
                    Filter::Adaptive(f) => f.rescale_steps(k),
                }
            }
            Finding::Disagrees { cadence_hz } => {
                if let Filter::Adaptive(f) = &mut self.filter {
                    f.on_pedometer_disagrees(cadence_hz);
                }
            }
        }
    }

    /// Push one step sample. Until the step stream's time unit is known (as for
    /// [`Self::push_fix`]) the sample is held, not used (see `held`).
    pub fn push_steps(&mut self, sample: &StepSample) -> Result<(), PaceError> {
        self.step_time.check(sample.t_s())?;
        self.steps.check(sample)?;
        self.step_time.accept(sample.t_s());
        let known = unit_known(&self.step_time, &self.fix_time, sample.t_s());
        if !known && self.held.hold_steps(*sample) {
            return Ok(());
        }
        self.release_held();
        self.apply_held_steps(sample);
        Ok(())
    }

    /// Run an accepted step sample through the step stream, the filter and the
    /// cross-checks.
    fn apply_steps(&mut self, sample: &StepSample) {
        self.steps.push(sample);
        let ctx = Context {
            config: &self.config,
            steps: &self.steps,
            accel: self.accel.as_ref(),
            pedometer_extra_rel_sigma: self.check.pedometer_extra_rel_sigma(),
        };
        let t = sample.t_s();
        match &mut self.filter {
            Filter::Published(f) => f.on_steps(t, &ctx),
            Filter::Adaptive(f) => f.on_steps(t, &ctx),
        }
        self.check
            .on_steps(t, &self.steps, self.config.stationary_after_s);
    }

    /// Push one raw accelerometer sample (m/s², gravity included, any axes): the
    /// tracker detects steps itself (the default
    /// [`StepDetector`](crate::stepdetect::StepDetector)) and feeds them to the step
    /// stream. An alternative to platform step counts: use one step source
    /// per tracker (a detected step earlier than a pushed count is ignored).
    pub fn push_accel(&mut self, t_s: f64, accel_mps2: [f64; 3]) -> Result<(), PaceError> {
        let first = match &mut self.accel {
            Some(a) => a.detector_mut().push_accel(t_s, accel_mps2)?,
            None => {
                let mut a =
                    AccelSteps::new(self.config.calibration.and_then(|c| c.accel_model).as_ref());
                let first = a.detector_mut().push_accel(t_s, accel_mps2)?;
                self.accel = Some(a);
                first
            }
        };
        if let Some(e) = first {
            self.on_detected_step(&e);
        }
        while let Some(e) = self
            .accel
            .as_mut()
            .and_then(|a| a.detector_mut().pop_step())
        {
            self.on_detected_step(&e);
        }
        Ok(())
    }

    /// Push many accelerometer samples; rejected ones are skipped and reported.
    pub fn push_accel_batch(&mut self, samples: &[AccelSample]) -> Vec<Rejection> {
        let mut rejected = Vec::new();
        batch::each(
            samples,
            |()| {},
            |r| rejected.push(r),
            |s| self.push_accel(s.t_s, s.accel_mps2).map(|()| None),
        );
        rejected
    }

    fn on_detected_step(&mut self, e: &StepEvent) {
        if let Some(a) = &mut self.accel {
            a.on_step(e);
        }
        let sample = StepSample::Event { t_s: e.t_s };
        if self.steps.check(&sample).is_err() {
            log::debug!(
                "detected step at {} s is not after the step stream: ignored",
                e.t_s
            );
            return;
        }
        self.apply_steps(&sample);
    }

    /// Push a sample of either stream; a fix returns its estimate.
    pub fn push(&mut self, sample: &PaceSample) -> Result<Option<PaceEstimate>, PaceError> {
        match sample {
            PaceSample::Fix(f) => self.push_fix(f).map(Some),
            PaceSample::Steps(s) => self.push_steps(s).map(|_| None),
        }
    }

    /// Push many samples in order. Invalid samples are skipped and reported; the
    /// others are processed as if pushed one by one. One estimate per accepted GNSS
    /// fix.
    pub fn push_batch(&mut self, samples: &[PaceSample]) -> Batch<PaceEstimate, PaceError> {
        batch::run(samples, |s| self.push(s))
    }

    /// The current estimate, at the time of the newest sample of either stream;
    /// `None` until a sample (fix, step sample or accelerometer sample) was accepted.
    pub fn estimate(&self) -> Option<PaceEstimate> {
        let started = self.fix_time.last_t_s().is_some()
            || self.step_time.last_t_s().is_some()
            || self.steps.has_data()
            || self
                .accel
                .as_ref()
                .is_some_and(|a| a.detector().last_t_s().is_some());
        started.then(|| self.current())
    }

    fn current(&self) -> PaceEstimate {
        let ctx = Context {
            config: &self.config,
            steps: &self.steps,
            accel: self.accel.as_ref(),
            pedometer_extra_rel_sigma: self.check.pedometer_extra_rel_sigma(),
        };
        let e = match &self.filter {
            Filter::Published(f) => f.estimate(&ctx),
            Filter::Adaptive(f) => f.estimate(&ctx),
        };
        PaceEstimate {
            // A held sample is the newest seen: the estimate is at its time, the state
            // without it.
            t_s: e.t_s.max(self.held.newest_t_s()),
            flags: self.check.flags(),
            ..e
        }
    }
}

mod snapshot;
