//! Step length observed from GNSS: path length over a window of fixes divided by the
//! steps in it (trusted fixes only), one measurement of the step-length line per
//! window at the window's mean cadence.

use nalgebra::SMatrix;

use super::settings::*;
use super::state::{FixPoint, Learn, PathWindow, LA, LB};
use super::AdaptiveFilter;
use crate::pace::walking::is_walk;
use crate::pace::{Context, LocalFix};
use crate::stats::CHI2_99_1DOF;

/// A closed path window: its GNSS path, steps, duration and start.
struct ClosedWindow {
    path_m: f64,
    steps: f64,
    span_s: f64,
    start_t_s: f64,
}

impl AdaptiveFilter {
    /// Observe step length from GNSS path length over steps (trusted fixes only).
    ///
    /// Chords between fixes at least `CHORD_MIN_S` apart are summed over a window of
    /// `PATH_WINDOW_S`; path / steps measures the step-length line at the window's
    /// mean cadence. Summing chords keeps turns from being read as shorter steps (a
    /// position residual would be), and long chords keep position noise from
    /// inflating the path: along-track errors telescope to the two window ends.
    pub(super) fn learn_from_path(&mut self, fix: &LocalFix, ctx: &Context, trusted: bool) {
        let Some(closed) = self.extend_window(fix, ctx, trusted) else {
            return;
        };
        if closed.steps < PATH_MIN_STEPS {
            return;
        }
        let c_mean = closed.steps / closed.span_s;
        if is_walk(c_mean) {
            // A walk teaches the running line nothing (and the walking step length is
            // not learned: see `super::super::walking`).
            return;
        }
        self.measure_window(fix, ctx, &closed, c_mean);
    }

    /// Add the chord to `fix` to the window; when the window is long enough, close it
    /// (a new one starts at `fix`) and return it.
    fn extend_window(
        &mut self,
        fix: &LocalFix,
        ctx: &Context,
        trusted: bool,
    ) -> Option<ClosedWindow> {
        let steps_now = ctx.steps.total_at(fix.t_s);
        let usable = trusted && !self.stationary && !self.steps_distrusted;
        let (Some(steps_now), true) = (steps_now, usable) else {
            self.window = PathWindow::IDLE;
            return None;
        };
        if !self.window.active {
            self.window = PathWindow::start(fix, steps_now);
            return None;
        }
        let FixPoint {
            east_m: ae,
            north_m: an,
            t_s: at,
        } = self.window.anchor;
        if fix.t_s - at < CHORD_MIN_S {
            return None;
        }
        self.window.path_m += (fix.east_m - ae).hypot(fix.north_m - an);
        self.window.anchor = FixPoint::of(fix);
        let span = fix.t_s - self.window.start_t_s;
        let steps = steps_now - self.window.start_steps;
        if span < PATH_WINDOW_S {
            return None;
        }
        let closed = ClosedWindow {
            path_m: self.window.path_m,
            steps,
            span_s: span,
            start_t_s: self.window.start_t_s,
        };
        self.window = PathWindow::start(fix, steps_now);
        Some(closed)
    }

    /// The window's path / steps as a measurement of the line at `c_mean` (gated);
    /// an accepted window also enters the session's line.
    fn measure_window(&mut self, fix: &LocalFix, ctx: &Context, w: &ClosedWindow, c_mean: f64) {
        let ClosedWindow {
            path_m: path,
            steps,
            span_s: _,
            start_t_s: start_t,
        } = *w;
        let cref = if self.cadence_ref.is_finite() {
            self.cadence_ref
        } else {
            c_mean
        };
        // Windows right after a start (acceleration from standing) say nothing about
        // how step length grows with cadence.
        let settled = start_t - ctx.steps.bout_start_t_s() >= SLOPE_SETTLE_S;
        self.slope_observable = settled && (c_mean - cref).abs() > SLOPE_MIN_CADENCE_DEV;
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, LA)] = 1.0;
        h[(0, LB)] = c_mean - cref;
        let y = path / steps - (self.x[LA] + self.x[LB] * (c_mean - cref));
        let sigma_path = std::f64::consts::SQRT_2 * PATH_SIGMA_SHARE * self.fix_sigma(fix);
        let r = (sigma_path / steps).powi(2);
        let sv = (h * self.p * h.transpose())[(0, 0)] + r;
        if y * y / sv > CHI2_99_1DOF {
            return;
        }
        self.scalar_update(&h, y, r, Learn::LevelAndSlope);
        // The session's mean line for the calibration record: every accepted window,
        // weighted by its steps.
        let l_obs = path / steps;
        let s = &mut self.session;
        s.steps += steps;
        s.steps_x_cadence += steps * c_mean;
        s.steps_x_length += steps * l_obs;
    }
}
