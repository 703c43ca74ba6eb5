//! What a replay's result rests on, for its summary: GNSS, a learned or imported
//! calibration, or a population prior with its typical error as measured on real
//! recordings by a project command (the figures are quoted from those commands'
//! output, 2026-12-06; docs/robustness.md, "What a summary rests on").

/// Steps-only pace with the population step-length prior (1.0 m at 168 steps/min),
/// every fix removed, on the 5 real runs of one runner: distance mean |error| 10.5 %
/// (6.3 to 13.0 %), speed RMSE 0.371 m/s against the watch (`stridekit eval pace`,
/// pedometer-only table, "prior only").
pub const PACE_PRIOR: &str = "the population step-length prior (1.0 m at 168 steps/min): \
     a steps-only distance with it is typically off by about 10 % (mean |error| 10.5 %, \
     up to 13 %, on 5 real runs; `stridekit eval pace`)";

/// The same runs with a calibration learned on the runner's other runs (leave one
/// run out): distance mean |error| 3.0 % (`stridekit eval pace`, "calibrated").
pub const PACE_CALIBRATED: &str = "a steps-only distance with a runner's own calibration \
     is typically within about 3 % (mean |error| 3.0 % on 5 real runs, leave one run out; \
     `stridekit eval pace`)";

/// The phone navigator's step length with its default pendulum model and population
/// parameters on 287 real indoor walks: median distance error −1.8 %, median |error|
/// 5.9 % (`stridekit eval pdr`, "defaults, magnetometer").
pub const PDR_PRIOR: &str = "the pendulum step-length model with population parameters \
     (distance median |error| 5.9 % on 287 real indoor walks; `stridekit eval pdr`)";

/// The same walks, calibrated leave one floor out: median |error| 5.8 %, median error
/// +0.6 % (`stridekit eval pdr`).
pub const PDR_CALIBRATED: &str = "a personal calibration (distance median |error| 5.8 %, \
     median error +0.6 %, on 287 real indoor walks calibrated leave one floor out; \
     `stridekit eval pdr`)";

/// The step detector's default configuration on the 48 Oxford traces: median |count
/// error| 0.39 %, worst 2.24 % against the alternation-checked reference (`stridekit
/// eval steps`).
pub const STEPS_DETECTOR: &str = "the step detector's defaults, from the accelerometer \
     alone (median |count error| 0.39 %, worst 2.24 %, on 48 real phone traces; \
     `stridekit eval steps`)";

/// `part` as a percentage of `whole` (0 when `whole` is 0).
pub fn share_pct(part: f64, whole: f64) -> f64 {
    if whole > 0.0 {
        100.0 * part / whole
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn shares() {
        assert_eq!(super::share_pct(1.0, 4.0), 25.0);
        assert_eq!(super::share_pct(1.0, 0.0), 0.0);
    }
}
