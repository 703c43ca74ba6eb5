//! The adaptive filter's output at an epoch: speed and its σ, stationarity, distance
//! (trapezoidal integral of the output speed), the GNSS weight and the step length
//! reported.

use super::settings::*;
use super::state::{Direction, LA, VE, VN};
use super::AdaptiveFilter;
use crate::pace::share::pedometer_information;
use crate::pace::walking::{walk_weight, walking_step_m, WALK_STEP_SIGMA_M};
use crate::pace::{Context, PaceEstimate, PaceFlags, PaceSource, MAX_INTEGRATION_GAP_S};

/// What the step stream says at the output time.
struct StepReading {
    /// No step data, or the step stream is distrusted.
    no_steps: bool,
    /// The output is the pedometer's alone (`pedometer_only_output`).
    ped_only: bool,
    /// Smoothed cadence, steps/s.
    cadence: Option<f64>,
    /// Slow cadence (the line's regressor), steps/s.
    slow: Option<f64>,
    /// The walking line's share of the step length now (0 when not moving).
    walk_w: f64,
    /// The accelerometer model's step length, when it sets the pedometer's.
    from_features: Option<f64>,
}

impl AdaptiveFilter {
    /// Integrate distance up to the filter time and refresh the output.
    pub(super) fn publish(&mut self, ctx: &Context, t_out: f64) {
        let rd = self.step_reading(ctx, t_out);
        let s_len = self.step_rel_sigma(ctx, &rd);
        let (raw, sd) = if rd.ped_only {
            // σ of cadence × step length: the step length's and the gait's.
            let rel = s_len.hypot(self.params.pedometer_rel_sigma);
            (self.ped_speed, rel * self.ped_speed)
        } else {
            (self.speed(), self.speed_var().sqrt())
        };
        let still = if rd.no_steps {
            self.gnss_still
        } else {
            self.stationary
        };
        let speed = if still { 0.0 } else { raw };
        if raw > DIRECTION_MIN_SPEED_MPS && !rd.ped_only {
            self.last_dir = Direction {
                east: self.x[VE] / raw,
                north: self.x[VN] / raw,
            };
        }
        self.integrate_distance(t_out, speed);
        let w_epoch = self.epoch_weight(&rd, t_out);
        self.epoch_gnss_weight = w_epoch;
        let w = if rd.ped_only {
            0.0
        } else {
            // At a stop no steps come: what is known of the pace is GNSS's.
            let stepping = !rd.no_steps && rd.cadence.is_some_and(|c| c > 0.0);
            self.reported_gnss_weight(ctx, t_out, raw, s_len, !stepping)
        };
        let step_length = self.reported_step_length(ctx, &rd, w_epoch);
        self.out = PaceEstimate {
            t_s: t_out,
            speed_mps: speed,
            pace_s_per_km: PaceEstimate::pace_for(speed),
            speed_std_mps: Some(sd),
            cadence_spm: rd.cadence.map(|c| c * S_PER_MIN),
            step_length_m: step_length,
            gnss_weight: w,
            distance_m: self.distance_m,
            source: if still {
                PaceSource::Stationary
            } else {
                PaceSource::from_gnss_weight(w)
            },
            flags: PaceFlags::default(),
        };
        self.info_gnss = 0.0;
        self.info_ped = 0.0;
    }

    fn step_reading(&self, ctx: &Context, t_out: f64) -> StepReading {
        let no_steps = !ctx.steps.has_data() || self.steps_distrusted;
        let ped_only = self.pedometer_only_output(ctx);
        let cadence = ctx
            .steps
            .smoothed_cadence(t_out, ctx.config.stationary_after_s)
            .map(|(c, _)| c);
        let slow =
            ctx.steps
                .cadence_at(t_out, SLOW_CADENCE_WINDOW_S, ctx.config.stationary_after_s);
        let walk_w = cadence.map_or(0.0, walk_weight);
        // The step length the pedometer speed uses when GNSS cannot teach it and raw
        // acceleration gives one (see `pedometer_update`).
        let from_features = match cadence {
            Some(c) if c > 0.0 && !self.gnss_trusted_at(t_out) => {
                ctx.accel.and_then(|a| a.step_length_m(t_out))
            }
            _ => None,
        };
        StepReading {
            no_steps,
            ped_only,
            cadence,
            slow,
            walk_w,
            from_features,
        }
    }

    /// Relative σ of the step length: the accelerometer model's when it sets it,
    /// else the lines'.
    fn step_rel_sigma(&self, ctx: &Context, rd: &StepReading) -> f64 {
        let l_run = self.x[LA].max(MIN_STEP_LENGTH_M);
        let s_run = self.p[(LA, LA)].max(0.0).sqrt() / l_run;
        let s_walk = rd
            .cadence
            .map_or(0.0, |c| WALK_STEP_SIGMA_M / walking_step_m(c));
        rd.from_features
            .and(ctx.accel.and_then(|a| a.rel_sigma()))
            .unwrap_or(rd.walk_w * s_walk + (1.0 - rd.walk_w) * s_run)
    }

    /// Distance grows by the trapezoid of the previous and this output speed (not
    /// before the first output, not across a gap).
    fn integrate_distance(&mut self, t_out: f64, speed: f64) {
        let prev_t = self.out.t_s;
        let dt = t_out - prev_t;
        if self.out.source != PaceSource::Initializing && dt > 0.0 && dt <= MAX_INTEGRATION_GAP_S {
            self.distance_m += 0.5 * (self.out.speed_mps + speed) * dt;
        }
    }

    /// This epoch's share of the variance reduction: what the step length reported
    /// has always used (the reported weight is `reported_gnss_weight`).
    fn epoch_weight(&self, rd: &StepReading, t_out: f64) -> f64 {
        let total = self.info_gnss + self.info_ped;
        if rd.ped_only {
            0.0
        } else if total > 0.0 {
            self.info_gnss / total
        } else if t_out - self.last_fix_t_s > GNSS_SILENT_S && !rd.no_steps {
            // GNSS silent, steps arriving: the pedometer carries the speed.
            0.0
        } else {
            self.epoch_gnss_weight
        }
    }

    /// The step length reported: the accelerometer model's, the gait blend while
    /// walking, the learned line at the slow cadence, else the configured or prior
    /// one while it carries the speed.
    fn reported_step_length(&self, ctx: &Context, rd: &StepReading, w_epoch: f64) -> Option<f64> {
        let learned = self.step_length_learned();
        match (rd.slow, rd.cadence) {
            _ if rd.from_features.is_some() => rd.from_features,
            // Walking or near it (the walking line has a population value from the
            // start): the same blend the pedometer speed uses.
            (_, Some(c)) if rd.walk_w > 0.0 && (learned || rd.walk_w >= 1.0) => Some(
                self.gait_step_length(c, rd.slow.filter(|&v| v > 0.0).unwrap_or(c))
                    .length_m,
            ),
            (Some(c), _) if c > 0.0 && learned => Some(self.step_length_at(c)),
            // The same physical range as every other reading of the line.
            _ if learned => Some(self.level_in_range()),
            // Not learned yet: the configured one, else the prior the pedometer speed
            // is using whenever steps carry it (a `Pedometer` or `Fused` source).
            _ => ctx.config.initial_step_length_m.or_else(|| {
                (!rd.no_steps && w_epoch < PRIOR_IN_USE_MAX_GNSS_WEIGHT && rd.cadence.is_some())
                    .then(|| self.level_in_range())
            }),
        }
    }

    /// The GNSS weight reported at `t_s` (`super::super::share`): GNSS's share of the
    /// information about the last minute's mean speed, against the pedometer's at
    /// `speed_mps` with a step length of relative σ `step_rel` (none when `no_steps`).
    /// Without either, the epoch's share.
    fn reported_gnss_weight(
        &self,
        ctx: &Context,
        t_s: f64,
        speed_mps: f64,
        step_rel: f64,
        no_steps: bool,
    ) -> f64 {
        let gnss = self.chord.information(t_s);
        let ped = if no_steps {
            0.0
        } else {
            pedometer_information(
                speed_mps,
                step_rel.hypot(ctx.pedometer_extra_rel_sigma),
                self.params.pedometer_rel_sigma,
                PED_UPDATE_INTERVAL_S,
            )
        };
        if gnss + ped > 0.0 {
            gnss / (gnss + ped)
        } else {
            self.epoch_gnss_weight
        }
    }
}
