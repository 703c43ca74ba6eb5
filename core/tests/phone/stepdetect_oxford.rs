//! Regression guard on real phone traces: the default detector's step count on four
//! Oxford Step Counter traces (Salvi et al. 2018, CC BY 4.0; four placements, three
//! users, three phones) stays within the project target (|count error| ≤ 3 % per trace)
//! and its step events match the shoe-worn reference (F1 ≥ 0.95, ±0.25 s).
//!
//! The data live outside the repository (`../shared/data/steps/oxford`, or
//! `$STRIDEKIT_DATA/steps/oxford`); without them the test skips with a message.
//! The core crate does not depend on the format readers, so the two CSV files are
//! parsed here directly (no header; accelerometer: ns, flag, ax, ay, az in m/s²;
//! stepcounter: ns, foot-1, foot-2 contact; each 0→1 transition is a heel strike).

use std::path::PathBuf;

use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig};

const TRACES: [&str; 4] = [
    "Pixel_Jamie_Hard_InHand_3",
    "Samsung_Carmelo_Hard_BackPocket_1",
    "Samsung_Dario_Hard_Purse_2",
    "Samsung_Dario_Hard_NeckPouch_1",
];

fn oxford_dir() -> Option<PathBuf> {
    let root = match std::env::var_os("STRIDEKIT_DATA") {
        Some(d) if !d.is_empty() => PathBuf::from(d),
        _ => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
    };
    let dir = root.join("steps/oxford");
    dir.is_dir().then_some(dir)
}

fn rows(path: &PathBuf) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect()
}

fn f1(detected: &[f64], reference: &[f64]) -> f64 {
    let (mut i, mut j, mut m) = (0, 0, 0);
    while i < detected.len() && j < reference.len() {
        let d = detected[i] - reference[j];
        if d.abs() <= 0.25 {
            m += 1;
            i += 1;
            j += 1;
        } else if d < 0.0 {
            i += 1;
        } else {
            j += 1;
        }
    }
    2.0 * m as f64 / (detected.len() + reference.len()) as f64
}

#[test]
fn default_detector_counts_real_traces_within_target() {
    let Some(dir) = oxford_dir() else {
        eprintln!(
            "SKIPPED: Oxford step data not found (../shared/data/steps/oxford; set STRIDEKIT_DATA)"
        );
        return;
    };
    for name in TRACES {
        let trace = dir.join(name);
        if !trace.is_dir() {
            eprintln!("SKIPPED {name}: not in {}", dir.display());
            continue;
        }
        let mut strikes = Vec::new();
        let steps = rows(&trace.join("stepcounter.csv"));
        for w in steps.windows(2) {
            for c in [1, 2] {
                if w[0][c] == 0.0 && w[1][c] == 1.0 {
                    strikes.push(w[1][0] * 1e-9);
                }
            }
        }
        let mut d = StepDetector::new(StepDetectorConfig::default()).unwrap();
        let mut detected = Vec::new();
        let mut last = f64::NEG_INFINITY;
        for r in rows(&trace.join("accelerometer.csv")) {
            let t = r[0] * 1e-9;
            if t <= last {
                continue;
            }
            last = t;
            if let Some(e) = d.push_accel(t, [r[2], r[3], r[4]]).unwrap() {
                detected.push(e.t_s);
            }
            while let Some(e) = d.pop_step() {
                detected.push(e.t_s);
            }
        }
        let err = 100.0 * (detected.len() as f64 - strikes.len() as f64) / strikes.len() as f64;
        let f = f1(&detected, &strikes);
        eprintln!(
            "{name}: {} steps, reference {}, error {err:+.2} %, F1 {f:.3}",
            detected.len(),
            strikes.len()
        );
        assert!(err.abs() <= 3.0, "{name}: count error {err:+.2} %");
        assert!(f >= 0.95, "{name}: F1 {f:.3}");
    }
}
