//! The pedometer side of the adaptive filter: cadence × step length as a measurement
//! of speed (and zero velocity while standing), the pedometer-only output before GNSS
//! gives a velocity, and trust in the step stream.

use nalgebra::SMatrix;

use super::line::GaitStep;
use super::settings::*;
use super::state::{Direction, Learn, LA, LB, VE, VN};
use super::AdaptiveFilter;
use crate::pace::walking::{is_walk, WALK_STEP_SIGMA_M};
use crate::pace::Context;

/// The step length a pedometer update uses: the gait's, or the accelerometer
/// model's (`from_features`: then the running line neither enters nor learns).
struct PedStep {
    length_m: f64,
    c_read: f64,
    walk_w: f64,
    from_features: bool,
}

impl AdaptiveFilter {
    /// New steps after the step stream was distrusted: trust it again.
    pub(super) fn retrust_steps(&mut self, t_s: f64, ctx: &Context) {
        if self.steps_distrusted
            && ctx.steps.total() > 0.0
            && ctx
                .steps
                .cadence_at(t_s, CADENCE_WINDOW_S, ctx.config.stationary_after_s)
                > Some(0.0)
        {
            self.steps_distrusted = false;
            self.contradictions = 0;
        }
    }

    /// The pedometer constrains speed after every GNSS update, when its data is fresh
    /// (or says standing).
    pub(super) fn pedometer_fresh_at(&self, t_s: f64, ctx: &Context) -> bool {
        ctx.steps
            .last_t_s()
            .is_some_and(|ts| t_s - ts <= STEP_DATA_FRESH_S)
            || ctx.steps.stationary_at(t_s, ctx.config.stationary_after_s)
    }

    /// Cadence × step length of the pedometer, m/s (`None` before any step data).
    pub fn pedometer_speed_mps(&self) -> Option<f64> {
        self.ped_speed.is_finite().then_some(self.ped_speed)
    }

    /// Whether the output comes from the pedometer alone: step data flows and GNSS has
    /// not given a velocity yet (no fix, or a single one).
    pub(super) fn pedometer_only_output(&self, ctx: &Context) -> bool {
        ctx.steps.has_data()
            && !self.steps_distrusted
            && self.ped_speed.is_finite()
            && !self.last_dir.east.is_finite()
            && self.speed() < MIN_DIRECTED_SPEED_MPS
    }

    /// The slow cadence at `t` (the line's regressor), `c` when there is none.
    fn slow_cadence(&self, t: f64, ctx: &Context, c: f64) -> f64 {
        ctx.steps
            .cadence_at(t, SLOW_CADENCE_WINDOW_S, ctx.config.stationary_after_s)
            .filter(|&v| v > 0.0)
            .unwrap_or(c)
    }

    /// Before any GNSS fix: speed is cadence × step length (the calibrated, configured
    /// or prior line read at the cadence, or with raw acceleration and an imported
    /// model the mean modelled length of the last steps), at most once a second;
    /// distance grows.
    pub(super) fn pedometer_only(&mut self, t: f64, ctx: &Context) {
        if t - self.last_ped_t_s < PED_UPDATE_INTERVAL_S || t <= self.out.t_s {
            return;
        }
        let Some((c, _)) = ctx.steps.smoothed_cadence(t, ctx.config.stationary_after_s) else {
            return;
        };
        let dt = t - self.last_ped_t_s;
        self.last_ped_t_s = t;
        self.stationary = c <= 0.0;
        if self.stationary {
            self.ped_speed = 0.0;
        } else {
            let c_slow = self.slow_cadence(t, ctx, c);
            self.track_cadence_ref(c_slow, dt.min(CADENCE_REF_MAX_DT_S));
            // An imported accelerometer model paces these steps by their own
            // features, as in an outage (see `pedometer_update`).
            let l = ctx
                .accel
                .and_then(|a| a.step_length_m(t))
                .unwrap_or_else(|| self.gait_step_length(c, c_slow).length_m);
            self.ped_speed = c * l;
        }
        self.publish(ctx, t);
    }

    /// Cadence × step length as a measurement of the speed at `t` (zero velocity when
    /// the steps say standing); `learn`: GNSS may teach the line now.
    pub(super) fn pedometer_update(&mut self, t: f64, ctx: &Context, learn: bool) {
        if !ctx.steps.has_data() || self.steps_distrusted {
            return;
        }
        let dt = t - self.last_ped_t_s;
        let Some((c, c_sigma)) = ctx.steps.smoothed_cadence(t, ctx.config.stationary_after_s)
        else {
            return;
        };
        self.last_ped_t_s = t;
        let was_stationary = self.stationary;
        self.stationary = c <= 0.0;
        self.walking_gait = is_walk(c);
        if self.stationary {
            self.ped_speed = 0.0;
            self.zupt();
            return;
        }
        // The step-length line is read at a slow cadence: cadence noise in its
        // regressor would otherwise teach b ≈ −a/c (the slope that hides the noise).
        let c_slow = self.slow_cadence(t, ctx, c);
        self.track_cadence_ref(c_slow, dt.min(CADENCE_REF_MAX_DT_S));
        let walking = self.walking_gait;
        let step = self.pedometer_step(t, ctx, c, c_slow, learn);
        self.ped_speed = c * step.length_m;
        let Some(s) = self.directed_speed(c * step.length_m, was_stationary) else {
            return;
        };
        let teach = if walking {
            Learn::Nothing
        } else {
            Learn::level_if(learn)
        };
        self.speed_measurement(ctx, s, c, c_sigma, &step, teach);
    }

    /// The step length of this update. GNSS cannot teach the step length now (an
    /// outage, a disturbed stretch): with raw acceleration, the calibrated model of
    /// these steps' features follows a pace change at the same cadence that the line
    /// cannot (see `super::super::accel`).
    fn pedometer_step(&self, t: f64, ctx: &Context, c: f64, c_slow: f64, learn: bool) -> PedStep {
        let GaitStep {
            length_m,
            c_read,
            walk_w,
        } = self.gait_step_length(c, c_slow);
        let from_features = if learn {
            None
        } else {
            ctx.accel.and_then(|a| a.step_length_m(t))
        };
        match from_features {
            // Not a state: the line neither enters nor learns.
            Some(lf) => PedStep {
                length_m: lf,
                c_read,
                walk_w: 1.0,
                from_features: true,
            },
            None => PedStep {
                length_m,
                c_read,
                walk_w,
                from_features: false,
            },
        }
    }

    /// The speed along which the pedometer measures: the filter's, or after a stop
    /// `v` along the last direction of motion (uncertain enough for GNSS to correct
    /// quickly). `None` without a direction (a start, a U-turn through zero: GNSS
    /// will give one).
    fn directed_speed(&mut self, v: f64, was_stationary: bool) -> Option<f64> {
        let s = self.speed();
        if s < MIN_DIRECTED_SPEED_MPS {
            if !(was_stationary && self.last_dir.east.is_finite()) {
                return None;
            }
            self.restart_along_last_direction(v);
            return Some(v);
        }
        Some(s)
    }

    /// Moving again after a stop: velocity `v` along the last direction of motion.
    fn restart_along_last_direction(&mut self, v: f64) {
        let Direction { east, north } = self.last_dir;
        self.x[VE] = v * east;
        self.x[VN] = v * north;
        for i in [VE, VN] {
            self.decorrelate(i);
            self.p[(i, i)] = (RESTART_SPEED_SHARE * v).powi(2) + RESTART_SPEED_VAR;
        }
    }

    /// |v| = c · L(c) along the direction of motion, with noise from the gait, the
    /// cadence, a disagreement with GNSS and the walking line.
    fn speed_measurement(
        &mut self,
        ctx: &Context,
        s: f64,
        c: f64,
        c_sigma: f64,
        step: &PedStep,
        teach: Learn,
    ) {
        let PedStep {
            length_m: l,
            c_read,
            walk_w: w,
            from_features,
        } = *step;
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[(0, VE)] = self.x[VE] / s;
        h[(0, VN)] = self.x[VN] / s;
        let v_ped = c * l;
        let rel = self.params.pedometer_rel_sigma;
        let c_sigma = c_sigma.max(MIN_CADENCE_SIGMA);
        let mut r = (rel * v_ped).powi(2)
            + (c_sigma * l).powi(2)
            + (ctx.pedometer_extra_rel_sigma * v_ped).powi(2);
        // The walking line is not a state: its uncertainty is measurement noise here;
        // the running line enters with its weight and learns nothing from a walk.
        if !from_features {
            r += (c * w * WALK_STEP_SIGMA_M).powi(2);
        }
        h[(0, LA)] = -c * (1.0 - w);
        h[(0, LB)] = -c * (1.0 - w) * (c_read - self.cadence_ref);
        self.info_ped += self.scalar_update(&h, v_ped - s, r, teach);
    }
}
