//! Accuracy of the pace filters on the simulator: the default must beat the
//! as-published filter and halve the GNSS EMA error (issue targets), with margins
//! that hold over several seeds. Numbers in the docs come from `stridekit eval pace`.

use stridekit_core::eval::{replay, score, sim_reference, Scores};
use stridekit_core::sim::{simulate_run, RunScenario};
use stridekit_core::PaceConfig;

fn scores(seed: u64) -> (Scores, f64) {
    let run = simulate_run(&RunScenario::demo(seed));
    let r = replay(
        &run.samples(),
        PaceConfig::as_published(),
        PaceConfig::default(),
    );
    let truth = sim_reference(&run, &r);
    let truth_dist = run.truth.last().unwrap().distance_m;
    (score(&r, &truth, &run.zones), truth_dist)
}

#[test]
fn default_beats_published_and_halves_gnss_ema() {
    for seed in 1..=4 {
        let (s, truth_dist) = scores(seed);
        eprintln!(
            "seed {seed}: all {:?}\n  disturbed {:?}\n  outage {:?}\n  distance {:?} truth {truth_dist:.0}",
            s.all, s.disturbed, s.outage, s.distance_m
        );
        assert!(
            s.all[3] <= 0.5 * s.all[1],
            "seed {seed}: default {} vs EMA {}",
            s.all[3],
            s.all[1]
        );
        assert!(
            s.all[3] < s.all[2],
            "seed {seed}: default {} vs published {}",
            s.all[3],
            s.all[2]
        );
        assert!(
            s.disturbed[3] < s.disturbed[2],
            "seed {seed}: disturbed default {} vs published {}",
            s.disturbed[3],
            s.disturbed[2]
        );
        assert!(s.outage[3] < s.outage[2], "seed {seed}: outage");
        let err = (s.distance_m[1] - truth_dist).abs() / truth_dist;
        assert!(
            err < 0.02,
            "seed {seed}: distance error {:.2} %",
            100.0 * err
        );
    }
}
