//! Real phone accelerometer traces pushed into the pace tracker: it counts steps
//! from raw acceleration like the platform pedometer would.

use stridekit_core::{PaceConfig, PaceTracker};
use stridekit_formats::{data_dir, list_oxford_traces, read_oxford_trace};

#[test]
fn oxford_traces_give_the_step_count_through_the_tracker() {
    let Some(root) = data_dir().map(|d| d.join("steps/oxford")) else {
        eprintln!("skipping: ../shared/data not found (set STRIDEKIT_DATA)");
        return;
    };
    let traces = list_oxford_traces(&root).expect("list traces");
    // One trace per placement family, fixed choice (not tuned).
    let picks = [
        "Nexus_Jamie_Hard_InHand_1",
        "Samsung_Carmelo_Hard_BackPocket_1",
        "Samsung_Dario_Hard_Purse_1",
    ];
    let mut checked = 0;
    for dir in traces
        .iter()
        .filter(|p| picks.iter().any(|n| p.ends_with(n)))
    {
        let trace = read_oxford_trace(dir).expect("read trace");
        let mut tr = PaceTracker::new(PaceConfig::default()).unwrap();
        let rejected = tr.push_accel_batch(
            &trace
                .accel
                .iter()
                .map(|a| stridekit_core::stepdetect::AccelSample {
                    t_s: a.t_s,
                    accel_mps2: a.accel_mps2,
                })
                .collect::<Vec<_>>(),
        );
        assert!(rejected.is_empty(), "{}: {rejected:?}", trace.name);
        let snapshot = tr.snapshot();
        let restored = PaceTracker::restore(&snapshot).unwrap();
        assert_eq!(restored.snapshot(), snapshot);
        let reference = trace.heel_strikes_t_s.len() as f64;
        let detected = tr.detected_steps() as f64;
        let err = (detected - reference) / reference;
        assert!(
            err.abs() < 0.03,
            "{}: {detected} vs {reference}",
            trace.name
        );
        checked += 1;
    }
    assert_eq!(checked, picks.len());
}
