//! stridekit's default pace filter: an adaptive extended Kalman filter fusing GNSS
//! positions with cadence × a learned step-length line (the model, its measurements
//! and what it learns when: docs/pace.md, "`PaceMode::Adaptive`").

mod gnss;
mod kalman;
mod line;
mod path;
mod pedometer;
mod publish;
mod settings;
mod snapshot;
mod state;

use super::config::AdaptiveParams;
use super::share::GnssChord;
use super::{Context, LocalFix, PaceConfig, PaceEstimate, PaceSource};
use crate::signal::Ring;

pub(crate) use settings::{DEFAULT_STEP_LENGTH_M, PRIOR_CADENCE, SLOPE_PRIOR};

use settings::*;
use state::{Direction, FixPoint, PathWindow, SessionLine, M8, V8};
use state::{LA, PE, PN, VE, VN};

/// State of the adaptive filter.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveFilter {
    params: AdaptiveParams,
    x: V8,
    p: M8,
    initialized: bool,
    /// Filter time, seconds.
    t_s: f64,
    last_fix_t_s: f64,
    last_ped_t_s: f64,
    last_trusted_t_s: f64,
    reset_t_s: f64,
    nis_avg: f64,
    /// Reference cadence c̄ of the step-length line, steps/s (NaN until moving).
    cadence_ref: f64,
    distance_m: f64,
    stationary: bool,
    contradictions: u32,
    steps_distrusted: bool,
    /// Path window observing step length.
    window: PathWindow,
    /// Recent fixes for GNSS-only stationarity.
    recent_fixes: Ring<FixPoint, RECENT_FIXES>,
    /// GNSS-only stationarity verdict at the last fix.
    gnss_still: bool,
    /// Previous fix, for GNSS displacement checks.
    prev_fix: FixPoint,
    /// Consecutive fixes beyond the NIS gate, and since when.
    gated_run: u32,
    gated_since_t_s: f64,
    /// The last direction of motion; NaN until moving.
    last_dir: Direction,
    /// The cadence is far enough from c̄ for the slope b to be observable.
    slope_observable: bool,
    /// Speed-information gained from GNSS and from the pedometer at the last epoch.
    info_gnss: f64,
    info_ped: f64,
    /// The chord of the fixes within the gate behind the reported GNSS weight (`super::share`).
    chord: GnssChord,
    /// The last epoch's share of the variance reduction (its fallback when an epoch
    /// had none).
    epoch_gnss_weight: f64,
    /// Cadence × step length from the pedometer alone, m/s (NaN before any step data):
    /// the output until GNSS gives a velocity (no GNSS at all, or before the second fix).
    ped_speed: f64,
    /// The accepted path windows of this session (the calibration's level and cadence).
    session: SessionLine,
    /// The latest cadence was a walk (`super::walking`): the pedometer uses the
    /// walking step length, and GNSS teaches the running line nothing.
    walking_gait: bool,
    out: PaceEstimate,
}

impl AdaptiveFilter {
    pub fn new(config: &PaceConfig) -> Self {
        let mut f = Self {
            params: config.adaptive,
            x: V8::zeros(),
            p: M8::zeros(),
            initialized: false,
            t_s: f64::NAN,
            last_fix_t_s: f64::NAN,
            last_ped_t_s: f64::NEG_INFINITY,
            last_trusted_t_s: f64::NEG_INFINITY,
            reset_t_s: f64::NEG_INFINITY,
            nis_avg: EXPECTED_NIS_2DOF,
            cadence_ref: f64::NAN,
            distance_m: 0.0,
            stationary: false,
            contradictions: 0,
            steps_distrusted: false,
            slope_observable: false,
            last_dir: Direction::NONE,
            window: PathWindow::IDLE,
            recent_fixes: Ring::new(),
            gnss_still: false,
            prev_fix: FixPoint::NONE,
            gated_run: 0,
            gated_since_t_s: f64::NAN,
            info_gnss: 0.0,
            info_ped: 0.0,
            chord: GnssChord::NONE,
            epoch_gnss_weight: 1.0,
            ped_speed: f64::NAN,
            session: SessionLine::default(),
            walking_gait: false,
            out: PaceEstimate::initial(
                config
                    .calibration
                    .map(|c| c.step_length_m)
                    .or(config.initial_step_length_m),
            ),
        };
        f.start_line(config);
        f
    }

    pub fn on_fix(&mut self, fix: &LocalFix, ctx: &Context) -> PaceEstimate {
        if !self.initialized {
            return self.first_fix(fix, ctx);
        }
        let gap = fix.t_s - self.last_fix_t_s;
        self.last_fix_t_s = fix.t_s;
        self.predict(fix.t_s);
        if gap > self.params.outage_reset_s {
            self.reanchor(fix);
        } else {
            self.update_on_fix(fix, ctx);
        }
        self.prev_fix = FixPoint::of(fix);
        self.track_gnss_still(fix, ctx);
        let learn = self.gnss_trusted_at(fix.t_s);
        if self.pedometer_fresh_at(fix.t_s, ctx) {
            self.pedometer_update(fix.t_s, ctx, learn);
        }
        let t_out = self.t_s.max(self.out.t_s);
        self.publish(ctx, t_out);
        self.out
    }

    pub fn on_steps(&mut self, t_s: f64, ctx: &Context) {
        self.retrust_steps(t_s, ctx);
        if !self.initialized {
            self.pedometer_only(t_s, ctx);
            return;
        }
        if t_s <= self.t_s {
            return;
        }
        // Between fixes the pedometer carries the state (at most once a second); at a
        // fix it runs right after the GNSS update (see on_fix).
        if t_s - self.last_ped_t_s < PED_UPDATE_INTERVAL_S
            || t_s - self.last_fix_t_s < PED_UPDATE_INTERVAL_S
        {
            return;
        }
        self.predict(t_s);
        let learn = self.gnss_trusted_at(t_s);
        self.pedometer_update(t_s, ctx, learn);
        self.publish(ctx, t_s);
    }

    pub fn estimate(&self, _ctx: &Context) -> PaceEstimate {
        self.out
    }

    /// The runner's position in the local ENU frame (east, north of the first fix),
    /// metres: the filter's own position state, GNSS-corrected and dead-reckoned in
    /// outages. `None` before the first fix.
    pub fn position_enu_m(&self) -> Option<[f64; 2]> {
        self.initialized.then(|| [self.x[PE], self.x[PN]])
    }

    /// The first fix: the filter starts from it; the output stays the pedometer's
    /// when steps carry it, else it is `Initializing`.
    fn first_fix(&mut self, fix: &LocalFix, ctx: &Context) -> PaceEstimate {
        self.init(fix);
        self.last_fix_t_s = fix.t_s;
        self.prev_fix = FixPoint::of(fix);
        let t_out = fix.t_s.max(self.out.t_s);
        self.publish(ctx, t_out);
        if !self.pedometer_only_output(ctx) {
            self.out.source = PaceSource::Initializing;
        }
        self.out
    }

    fn speed(&self) -> f64 {
        self.x[VE].hypot(self.x[VN])
    }

    /// Variance of the speed along the direction of motion.
    fn speed_var(&self) -> f64 {
        let s = self.speed();
        if s > SPEED_VAR_MIN_SPEED_MPS {
            state::along(&self.p, self.x[VE] / s, self.x[VN] / s)
        } else {
            0.5 * (self.p[(VE, VE)] + self.p[(VN, VN)])
        }
    }

    /// Zero the covariances of state `i` with every other state.
    fn decorrelate(&mut self, i: usize) {
        for j in 0..8 {
            if j != i {
                self.p[(i, j)] = 0.0;
                self.p[(j, i)] = 0.0;
            }
        }
    }

    fn step_length_learned(&self) -> bool {
        self.p[(LA, LA)].sqrt() < LEARNED_SIGMA_M
    }
}
