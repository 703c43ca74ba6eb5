//! Step length while walking, apart from the running line.
//!
//! Walking and running are different gaits: a runner who walks a recovery, a hill or
//! a cool-down at 100–120 steps/min takes steps of ≈ 0.7–0.8 m, not what the running
//! line `a + b·(c − c̄)` learned at 150–190 steps/min says when read that far below its
//! data (its slope, ≈ 0.5 m per step/s, gives ≈ 0.45 m there: on the real runs, walks
//! inside GNSS outages came out at 0.8 m/s against the watch's 1.45 m/s). Below
//! [`WALK_MAX_CADENCE`] the step length is a population walking line instead: ≈ 0.72 m
//! at 112 steps/min (an adult's comfortable walk, ≈ 1.35 m/s), growing in proportion to
//! cadence (L ≈ (L₀ / c₀)·c), blended into the running line over ±6 steps/min around
//! the boundary. It is not learned: learning it from the GNSS windows of
//! the real runs' short walks made it worse (docs/lab/2026-12-06-pace-history.md), and while GNSS is good it
//! carries the speed anyway. A walk teaches the running line nothing either.

/// Cadences below this are a walk, steps/s (132 steps/min: a brisk walk reaches
/// ≈ 125–130, a slow jog ≈ 140–150).
pub(crate) const WALK_MAX_CADENCE: f64 = 2.2;
/// Cadence at which the walking step length is stated, steps/s (112 steps/min).
const WALK_REF_CADENCE: f64 = 1.87;
/// Walking step length at that cadence, m, and its 1-σ between people (adults'
/// comfortable walking speed ≈ 1.35 m/s at ≈ 112 steps/min).
const WALK_STEP_M: f64 = 0.72;
pub(crate) const WALK_STEP_SIGMA_M: f64 = 0.12;

/// Half-width of the band around [`WALK_MAX_CADENCE`] over which the step length
/// blends from the walking line into the running line, steps/s (±6 steps/min): a
/// cadence that hovers at the boundary (a brisk walk, a slow jog) gives no jumps.
const BLEND_HALF_WIDTH: f64 = 0.1;

/// Whether `cadence` (steps/s) is a walk.
pub(crate) fn is_walk(cadence: f64) -> bool {
    cadence > 0.0 && cadence < WALK_MAX_CADENCE
}

/// Weight of the walking line at `cadence` (steps/s): 1 below the blend band, 0
/// above it, a smooth step in between (0.5 at [`WALK_MAX_CADENCE`]).
pub(crate) fn walk_weight(cadence: f64) -> f64 {
    if cadence.is_nan() || cadence <= 0.0 {
        return 0.0;
    }
    let x = ((WALK_MAX_CADENCE + BLEND_HALF_WIDTH - cadence) / (2.0 * BLEND_HALF_WIDTH))
        .clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Step length at a walking cadence (steps/s), m.
pub(crate) fn walking_step_m(cadence: f64) -> f64 {
    (WALK_STEP_M * cadence / WALK_REF_CADENCE).clamp(0.2, 1.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_walk_is_about_one_point_three_metres_per_second() {
        let c = 110.0 / 60.0;
        assert!(is_walk(c));
        assert!(!is_walk(170.0 / 60.0));
        assert!(!is_walk(0.0));
        assert!(
            (c * walking_step_m(c) - 1.29).abs() < 0.03,
            "{}",
            c * walking_step_m(c)
        );
        // Slower cadence, shorter steps.
        assert!(walking_step_m(1.5) < walking_step_m(2.0));
        // The blend: all walk below the band, all run above, half at the boundary.
        assert_eq!(walk_weight(2.0), 1.0);
        assert_eq!(walk_weight(2.4), 0.0);
        assert!((walk_weight(WALK_MAX_CADENCE) - 0.5).abs() < 1e-12);
        assert!(walk_weight(2.15) > walk_weight(2.25));
        assert_eq!(walk_weight(0.0), 0.0);
    }
}
