//! The heading across dropped samples: a turn inside a gap is lost to the AHRS, so μ
//! takes the AHRS's yaw error over the gap from both sides of it: the gyroscope's rates
//! about the vertical (a trapezoid) and the magnetic field's direction in the AHRS frame.

/// Time constant of the field direction's mean before a gap, and the span averaged
/// after one before the bridge is decided, s.
const FIELD_WINDOW_S: f64 = 0.5;
/// Time constant of a slower mean of the field's direction, s: how far the fast one
/// moved from it is how much the field turned against the gyroscope over the last
/// seconds (a disturbed field, walked through), and may turn across the gap.
const FIELD_SLOW_S: f64 = 2.0;
/// How fast a walker may turn unseen by the rates on either side of a gap, rad/s
/// (a 90° corner takes about 3 s): the trapezoid's uncertainty per second of gap.
const UNSEEN_RATE_RADS: f64 = 0.5;
/// How far the field's direction may turn over the metre walked in a gap indoors,
/// rad (5°; on the development walks 0–10° over 2 s, docs/lab/2026-12-06-pdr-gaps.md).
const FIELD_TURN_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// The largest variance of the trapezoid's error, rad²: an angle uniform on the circle
/// (π²/3), a heading the rates say nothing about (a long gap, a fast turn).
const LOST_VAR_RAD2: f64 = std::f64::consts::PI * std::f64::consts::PI / 3.0;
/// A field mean whose resultant is shorter than this (unit vectors averaged) has no
/// direction to compare.
const MIN_FIELD_RESULTANT: f64 = 0.5;

/// The bridge's state: the typical interval, the previous vertical rate, the field
/// direction before the next gap, and a gap waiting for the field after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct GapBridge {
    /// Typical interval between samples, s (0 before the second sample).
    pub(super) dt_typ_s: f64,
    /// The previous sample's rate about the vertical (ENU, counter-clockwise), rad/s.
    pub(super) rate_up_rads: f64,
    /// Exponential mean of the field's horizontal unit vector in the AHRS frame
    /// (east, north) over `FIELD_WINDOW_S`, and its weight (0 before any field) ...
    pub(super) field: [f64; 3],
    /// ... and over `FIELD_SLOW_S`.
    pub(super) field_slow: [f64; 2],
    /// The pending gap: the time it ended (NaN when none), the field mean before it
    /// turned by the trapezoid's error (east, north) and the square of the angle the
    /// field had turned by against the gyroscope (rad²), the sums of the field's unit
    /// vectors after it (east, north, count), the trapezoid's yaw error and its
    /// variance (rad, rad²).
    pub(super) pending_t_s: f64,
    pub(super) before: [f64; 3],
    pub(super) after: [f64; 3],
    pub(super) gyro_err_rad: f64,
    pub(super) gyro_var_rad2: f64,
}

impl Default for GapBridge {
    fn default() -> Self {
        Self {
            dt_typ_s: 0.0,
            rate_up_rads: 0.0,
            field: [0.0; 3],
            field_slow: [0.0; 2],
            pending_t_s: f64::NAN,
            before: [0.0; 3],
            after: [0.0; 3],
            gyro_err_rad: 0.0,
            gyro_var_rad2: 0.0,
        }
    }
}

/// A correction of μ to apply from `t_s` on (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Bridged {
    pub(super) t_s: f64,
    pub(super) mu_step_rad: f64,
}

impl GapBridge {
    /// Whether `dt` (s, > 0) is a gap; learns the typical interval from the others.
    pub(super) fn is_gap(&mut self, dt: f64) -> bool {
        !(dt.is_nan() || dt <= 0.0) && crate::signal::is_gap(&mut self.dt_typ_s, dt)
    }

    /// A gap of `dt` s ended at `t_s`: `rate_up` is this sample's rate about the
    /// vertical, `ahrs_turn_rad` the AHRS's change of azimuth over the gap (clockwise).
    /// Returns the correction of μ by an earlier gap still pending (decided with what
    /// was seen after it), and the trapezoid's correction, both to apply now; the
    /// field's part follows from [`Self::push_field`] once the field after the gap is
    /// seen.
    pub(super) fn on_gap(
        &mut self,
        t_s: f64,
        dt: f64,
        rate_up: f64,
        ahrs_turn_rad: f64,
    ) -> (Option<Bridged>, f64) {
        let earlier = self.decide();
        // Azimuth is clockwise: a counter-clockwise rate turns it back.
        let trapezoid = -0.5 * (self.rate_up_rads + rate_up) * dt;
        let err = crate::angle::wrap(ahrs_turn_rad - trapezoid);
        let hidden = 0.5 * self.rate_up_rads.abs().max(rate_up.abs()) * dt;
        self.gyro_err_rad = err;
        self.gyro_var_rad2 = (hidden * hidden + (UNSEEN_RATE_RADS * dt).powi(2)).min(LOST_VAR_RAD2);
        self.rate_up_rads = rate_up;
        if self.field[2] > 0.0 {
            // The AHRS frame moved by its error over the gap: where the field should
            // be seen after it, as far as the trapezoid tells.
            let [e, n] = rotate([self.field[0], self.field[1]], err);
            let [se, sn] = rotate(self.field_slow, err);
            self.field = [e, n, self.field[2]];
            self.field_slow = [se, sn];
            let turned = (e * sn - n * se).atan2(e * se + n * sn);
            self.pending_t_s = t_s;
            self.before = [e, n, turned * turned];
            self.after = [0.0; 3];
        }
        (earlier, err)
    }

    /// One sample that is not a gap: its rate about the vertical.
    pub(super) fn push_rate(&mut self, rate_up: f64) {
        self.rate_up_rads = rate_up;
    }

    /// A field sample at `t_s` whose strength is undisturbed, `dt` after the previous
    /// sample: its horizontal unit vector in the AHRS frame (east, north). Returns the
    /// field's correction of a pending gap once `FIELD_WINDOW_S` after it was seen.
    pub(super) fn push_field(&mut self, t_s: f64, dt: f64, unit_en: [f64; 2]) -> Option<Bridged> {
        if self.pending_t_s.is_nan() {
            let (k, k_slow) = if self.field[2] > 0.0 {
                ((dt / FIELD_WINDOW_S).min(1.0), (dt / FIELD_SLOW_S).min(1.0))
            } else {
                (1.0, 1.0)
            };
            for (i, u) in unit_en.into_iter().enumerate() {
                self.field[i] += k * (u - self.field[i]);
                self.field_slow[i] += k_slow * (u - self.field_slow[i]);
            }
            self.field[2] = 1.0;
            return None;
        }
        self.after[0] += unit_en[0];
        self.after[1] += unit_en[1];
        self.after[2] += 1.0;
        (t_s - self.pending_t_s >= FIELD_WINDOW_S)
            .then(|| self.decide())
            .flatten()
    }

    /// The pending gap's field correction (the field's view of the AHRS's error
    /// beyond the trapezoid's, weighted by the two uncertainties), if any; the field's
    /// mean then restarts from what was seen after the gap.
    fn decide(&mut self) -> Option<Bridged> {
        let t_s = self.pending_t_s;
        self.pending_t_s = f64::NAN;
        if t_s.is_nan() || self.after[2] < 1.0 {
            return None;
        }
        let [be, bn, turned2] = self.before;
        let (ae, an) = (self.after[0] / self.after[2], self.after[1] / self.after[2]);
        self.field = [ae, an, 1.0];
        let (rb, ra) = (be.hypot(bn), ae.hypot(an));
        if rb < MIN_FIELD_RESULTANT || ra < MIN_FIELD_RESULTANT {
            return None;
        }
        // The field's azimuth in the AHRS frame moves by the AHRS's error: what the
        // trapezoid did not take.
        let residual = crate::angle::wrap(ae.atan2(an) - be.atan2(bn));
        // The field's own turn, as much as it turned against the gyroscope before the
        // gap, and the spread of each mean (circular variance ≈ σ²/2).
        let field_var =
            FIELD_TURN_RAD * FIELD_TURN_RAD + turned2 + 2.0 * (1.0 - rb) + 2.0 * (1.0 - ra);
        let w = self.gyro_var_rad2 / (self.gyro_var_rad2 + field_var);
        let step = w * residual;
        self.field_slow = rotate(self.field_slow, step);
        Some(Bridged {
            t_s,
            mu_step_rad: step,
        })
    }
}

/// The horizontal vector (east, north) turned clockwise by `rad`.
fn rotate(v: [f64; 2], rad: f64) -> [f64; 2] {
    let (s, c) = rad.sin_cos();
    [v[0] * c + v[1] * s, v[1] * c - v[0] * s]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_lost_in_a_gap_is_taken_from_the_field() {
        let mut b = GapBridge::default();
        let north = [0.0, 1.0];
        for _ in 0..100 {
            assert!(!b.is_gap(0.01));
            b.push_rate(0.0);
            assert!(b.push_field(0.0, 0.01, north).is_none());
        }
        // A 0.8 s gap at a walker's rates: the AHRS turned 0.1 rad (clockwise) less
        // than the phone did, so the field seems 0.3 rad further clockwise … as the
        // AHRS kept 0.2 of a 0.5 rad turn.
        assert!(b.is_gap(0.8));
        let (earlier, g) = b.on_gap(10.0, 0.8, -0.25, 0.2);
        assert!(earlier.is_none());
        // Trapezoid: −0.5·(0 − 0.25)·0.8 = 0.1 rad: the AHRS is 0.1 ahead of it.
        assert!((g - 0.1).abs() < 1e-12, "{g}");
        assert!((b.before[0] - 0.1f64.sin()).abs() < 1e-12 && b.before[2] < 1e-20);
        let (s, c) = (-0.3f64).sin_cos();
        let mut out = None;
        for i in 1..=60 {
            out = out.or(b.push_field(10.0 + 0.01 * i as f64, 0.01, [s, c]));
        }
        let out = out.expect("decided after the window");
        assert_eq!(out.t_s, 10.0);
        // The field says −0.3 (the AHRS 0.3 behind), the gyroscope 0.1 ahead: the
        // field wins most (its 5° against the 0.4 rad a walker may turn in 0.8 s).
        let total = g + out.mu_step_rad;
        assert!(total < -0.2 && total > -0.3, "{total}");
    }

    #[test]
    fn without_a_field_only_the_trapezoid_bridges() {
        let mut b = GapBridge::default();
        for _ in 0..10 {
            b.is_gap(0.01);
        }
        assert!(b.is_gap(1.5));
        let (_, g) = b.on_gap(5.0, 1.5, 0.0, 2.0);
        assert!((g - 2.0).abs() < 1e-12);
        assert!(b.pending_t_s.is_nan());
    }

    #[test]
    fn a_long_gap_leaves_a_bounded_variance() {
        // A gap of days at the largest rate: the heading is lost, not infinitely so
        // (the snapshot's range check refused the engine's own state before).
        let mut b = GapBridge::default();
        for _ in 0..10 {
            b.is_gap(0.01);
        }
        assert!(b.is_gap(1e6));
        b.on_gap(1e6, 1e6, 30.0, 1.0);
        assert!(b.gyro_var_rad2 <= LOST_VAR_RAD2 && b.gyro_var_rad2 > 3.0);
    }
}
