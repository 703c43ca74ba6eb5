//! Gait initiation: the first steps of a walk from standing are short.
//!
//! Starting to walk from a standstill, the body is accelerated from rest over the
//! first step or two: the first step is well short of the walker's steady step and
//! the second is closer to it; from the third on the gait is steady. A step-length
//! model fitted on steady walking (or the first step's accelerometer features, which
//! span the standing before it) reads those steps at full length, so every start of
//! a walk — and every restart after a stop — adds the better part of a step that was
//! not walked, always in the direction of the first leg.
//!
//! [`GAIT_INITIATION`] holds the shares of the steady step length used for the first
//! and second step of a walk. They are physiological values, not fitted here: on the
//! 287 indoor walks (`stridekit eval pdr --diagnose`, docs/lab/2026-12-06-phone-history.md) the model read
//! the first waypoint leg (from standing) 0.9 step-equivalents longer than the other
//! legs, and `0.6 + 0.85` takes 0.55 steps off; the sensitivity to other shares is in
//! docs/lab/2026-12-06-phone-history.md.
//!
//! A walk starts at the first step, and again at a step that comes [`STOP_S`] or more
//! after the previous one: a stop long enough to be standing. Shorter gaps in the
//! steps are mostly not stops: the detector loses a few steps in a turn or when the
//! steps weaken, and restarts its bout while the walker walks on (measured on the
//! indoor walks, docs/lab/2026-12-06-phone-history.md); those steps are not shortened.

/// Share of the steady step length of the first and the second step of a walk.
pub const GAIT_INITIATION: [f64; 2] = [0.6, 0.85];

/// A gap between steps at least this long is a stop: the next step starts a walk, s.
pub const STOP_S: f64 = 5.0;

/// Where a step is in its walk, as the index of [`GAIT_INITIATION`] it takes
/// (saturating past it: steady).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoutPosition {
    index: u8,
}

impl BoutPosition {
    /// Past the initiation steps (also the state before any step: the first step
    /// starts a walk).
    pub const STEADY: Self = Self {
        index: GAIT_INITIATION.len() as u8,
    };

    /// Advance by a step at `t_s` whose previous step was at `previous_t_s` (`None`:
    /// there was none) and return its share of the steady step length.
    pub fn next_step(&mut self, t_s: f64, previous_t_s: Option<f64>) -> f64 {
        self.step(Self::starts_walk(t_s, previous_t_s))
    }

    /// Whether a step at `t_s` starts a walk: there was no step before it
    /// (`previous_t_s` `None`) or the previous one was [`STOP_S`] or more before it.
    fn starts_walk(t_s: f64, previous_t_s: Option<f64>) -> bool {
        previous_t_s.is_none_or(|t| t_s - t >= STOP_S)
    }

    /// Advance by one step (`restart`: it starts a walk) and return its share of the
    /// steady step length.
    fn step(&mut self, restart: bool) -> f64 {
        if restart {
            self.index = 0;
        } else if (self.index as usize) < GAIT_INITIATION.len() {
            self.index += 1;
        }
        self.factor()
    }

    /// The share of the steady step length at this position.
    fn factor(&self) -> f64 {
        GAIT_INITIATION
            .get(self.index as usize)
            .copied()
            .unwrap_or(1.0)
    }

    /// Whether the position is past the initiation steps.
    pub fn is_steady(&self) -> bool {
        self.index as usize >= GAIT_INITIATION.len()
    }

    pub(crate) fn code(&self) -> u8 {
        self.index
    }

    /// From [`code`](Self::code); `None` if out of range.
    pub(crate) fn from_code(code: u8) -> Option<Self> {
        ((code as usize) <= GAIT_INITIATION.len()).then_some(Self { index: code })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_two_steps_of_a_walk_are_short_and_the_rest_steady() {
        let mut b = BoutPosition::STEADY;
        let mut prev = None;
        let mut shares = Vec::new();
        // A walk, a 3 s gap (steps lost in a turn: no restart), a 6 s stop, a walk.
        for t in [1.0, 1.5, 2.0, 2.5, 5.5, 6.0, 12.0, 12.5, 13.0] {
            shares.push(b.next_step(t, prev));
            prev = Some(t);
        }
        assert_eq!(shares, vec![0.6, 0.85, 1.0, 1.0, 1.0, 1.0, 0.6, 0.85, 1.0]);
        assert!(b.is_steady());
    }

    #[test]
    fn a_stop_is_a_gap_of_at_least_stop_s() {
        assert!(BoutPosition::starts_walk(10.0, None));
        assert!(BoutPosition::starts_walk(10.0, Some(10.0 - STOP_S)));
        assert!(!BoutPosition::starts_walk(10.0, Some(10.0 - 0.99 * STOP_S)));
    }

    #[test]
    fn codes_round_trip_and_out_of_range_is_refused() {
        let mut b = BoutPosition::STEADY;
        for restart in [true, false, false, false] {
            b.step(restart);
            assert_eq!(BoutPosition::from_code(b.code()), Some(b));
        }
        assert_eq!(
            BoutPosition::from_code(GAIT_INITIATION.len() as u8 + 1),
            None
        );
    }
}
