//! Regression guard for the target: distance error during a simulated
//! 5-minute GNSS outage after calibration ≤ 3 %. Runs the same protocol as
//! `stridekit eval steplength` on fewer seeds.

use stridekit_core::steplength::{StepLengthConfig, StepLengthModel};
use stridekit_lab::steplength::run_cases;

#[test]
fn five_minute_outage_distance_within_target() {
    let models = [
        StepLengthModel::Linear,
        StepLengthModel::LinearFrequencyOnly,
        StepLengthModel::Constant,
    ];
    let cases = run_cases(3, &models, StepLengthConfig::default());
    assert_eq!(cases.len(), 15);
    for (k, m) in models.iter().enumerate() {
        if *m == StepLengthModel::Constant {
            let max_abs = cases
                .iter()
                .fold(0.0f64, |a, c| a.max(c.results[k].error_pct.abs()));
            // The constant model cannot follow a change of pace: the brisk-walk mix
            // must show it (this is what the linear model is for).
            assert!(max_abs > 8.0, "constant: {max_abs}");
            continue;
        }
        // Target 3 % wherever calibration saw the gait of the outage (walking
        // mixes, running at 2.8–3.4 m/s): measured ~0.7 % mean, ~2 % worst.
        let (covered, beyond): (Vec<_>, Vec<_>) =
            cases.iter().partition(|c| !c.mix.starts_with("walk + run"));
        let errs: Vec<f64> = covered.iter().map(|c| c.results[k].error_pct).collect();
        let mean_abs = errs.iter().map(|e| e.abs()).sum::<f64>() / errs.len() as f64;
        let max_abs = errs.iter().fold(0.0f64, |a, e| a.max(e.abs()));
        assert!(mean_abs < 1.5, "{m:?}: mean |error| {mean_abs} %");
        assert!(max_abs < 3.0, "{m:?}: worst |error| {max_abs} % ({errs:?})");
        // Known limitation: calibrated running at 3.0 m/s, the outage runs at 3.3 m/s
        // with longer steps at almost the same cadence; neither F nor (linearly) SV
        // carries that. Measured −4 … −5 %: guard against it getting worse.
        for c in beyond {
            let e = c.results[k].error_pct;
            assert!(e.abs() < 7.0, "{m:?} {}: {e} %", c.mix);
        }
    }
}
