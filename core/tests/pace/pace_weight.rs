//! The GNSS weight and source the default filter reports on a real run (issue 36):
//! GNSS's share of what is known about the last minute's pace, not of one epoch's
//! variance reduction (which the once-a-second pedometer update took whole: a clean
//! run read `Pedometer`, weight 0). Skips with a message when the data are absent.

use stridekit_core::{PaceConfig, PaceEstimate, PaceSample, PaceSource, PaceTracker};
use stridekit_lab::activity::prepare;

/// A 42-minute run of one runner, 912 fixes 2 s apart, cadence ≈ 170–185 steps/min.
const RUN: &str = "2020-12-02T06_08_29-300_Running.tcx";
/// The outage cut into it, s from its start.
const OUTAGE_S: (f64, f64) = (1200.0, 1500.0);

fn run_samples() -> Option<Vec<PaceSample>> {
    let Some(dir) = stridekit_formats::data_dir().map(|d| d.join("pace/original")) else {
        eprintln!(
            "SKIPPED: real runs not found (../shared/data/pace/original; set STRIDEKIT_DATA)"
        );
        return None;
    };
    let activity = stridekit_formats::read_activity(&dir.join(RUN)).expect("readable run");
    Some(prepare(&activity).samples)
}

/// The estimates after every sample.
fn replay(samples: &[PaceSample]) -> Vec<PaceEstimate> {
    let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
    samples
        .iter()
        .map(|s| {
            tr.push(s).unwrap();
            tr.estimate().unwrap()
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[test]
fn gnss_weighs_on_a_clean_run_and_not_in_an_outage() {
    let Some(samples) = run_samples() else {
        return;
    };
    let t0 = samples[0].t_s();
    let in_outage = |t: f64| (OUTAGE_S.0..OUTAGE_S.1).contains(&(t - t0));
    // Clean: every estimate from the second minute on (before: weight 0 between fixes,
    // about 0.003 at them; source `Pedometer` for the whole run).
    let clean = replay(&samples);
    let moving: Vec<&PaceEstimate> = clean
        .iter()
        .filter(|e| e.t_s - t0 > 60.0 && e.source != PaceSource::Stationary)
        .collect();
    let w = median(moving.iter().map(|e| e.gnss_weight).collect());
    assert!(w > 0.25, "median GNSS weight {w:.3} on a clean run");
    let ped = moving
        .iter()
        .filter(|e| e.source == PaceSource::Pedometer)
        .count() as f64
        / moving.len() as f64;
    assert!(
        ped < 0.2,
        "{:.0} % of a clean run read Pedometer",
        100.0 * ped
    );
    // An outage of 5 minutes: after its first minute the pace rests on the steps.
    let cut: Vec<PaceSample> = samples
        .iter()
        .filter(|s| !(matches!(s, PaceSample::Fix(_)) && in_outage(s.t_s())))
        .copied()
        .collect();
    let estimates = replay(&cut);
    let outage: Vec<&PaceEstimate> = estimates
        .iter()
        .filter(|e| in_outage(e.t_s) && e.t_s - t0 > OUTAGE_S.0 + 60.0)
        .filter(|e| e.source != PaceSource::Stationary)
        .collect();
    assert!(!outage.is_empty());
    for e in &outage {
        assert!(
            e.gnss_weight < 0.01,
            "weight {} at {}",
            e.gnss_weight,
            e.t_s
        );
        assert_eq!(e.source, PaceSource::Pedometer, "at {}", e.t_s);
    }
}
