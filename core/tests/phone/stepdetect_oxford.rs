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

/// Heel strikes (s) of a trace's `stepcounter.csv`: each 0→1 contact transition.
fn strikes_of(trace: &std::path::Path) -> Vec<f64> {
    let mut strikes = Vec::new();
    let steps = rows(&trace.join("stepcounter.csv"));
    for w in steps.windows(2) {
        for c in [1, 2] {
            if w[0][c] == 0.0 && w[1][c] == 1.0 {
                strikes.push(w[1][0] * 1e-9);
            }
        }
    }
    strikes
}

/// Dropped samples do not lock the cadence at three steps (issue 39): a walk in hand
/// with 10 % of its samples dropped in 24 bursts of 0.1–1 s (the perturbation bench's
/// bursts for this trace, times from its first sample) stays within 3 % of the
/// reference. Bridged gaps are straight lines on the grid; three of them, 0.6 and
/// 1.6 s apart at 55–58 s, correlated with each other and the autocorrelation's
/// stride came out at three steps (1.65 s), read as one slow step: the bout's period
/// was reset to it and every other step taken for a double peak (−4.5 %, 7 steps
/// lost at 62–68 s).
#[test]
fn dropped_bursts_do_not_lock_the_cadence_of_a_real_walk() {
    const NAME: &str = "Samsung_Jamie_Hard_InHand_2";
    const GAPS: [(f64, f64); 24] = [
        (2.27, 2.96),
        (16.38, 16.99),
        (18.09, 19.07),
        (23.03, 23.35),
        (27.04, 27.95),
        (32.09, 33.03),
        (42.29, 42.74),
        (55.43, 55.60),
        (56.07, 56.68),
        (57.64, 58.30),
        (62.54, 63.03),
        (65.43, 66.05),
        (69.56, 70.19),
        (70.75, 71.75),
        (75.86, 76.32),
        (105.40, 106.10),
        (112.03, 112.12),
        (116.09, 117.03),
        (117.96, 118.82),
        (131.06, 131.75),
        (137.00, 137.59),
        (140.94, 141.04),
        (149.26, 150.16),
        (151.43, 152.04),
    ];
    let Some(trace) = oxford_dir().map(|d| d.join(NAME)).filter(|t| t.is_dir()) else {
        eprintln!("SKIPPED: {NAME} not found (../shared/data/steps/oxford; set STRIDEKIT_DATA)");
        return;
    };
    let strikes = strikes_of(&trace);
    let mut d = StepDetector::new(StepDetectorConfig::default()).unwrap();
    let (mut n, mut t0, mut last) = (0usize, f64::NAN, f64::NEG_INFINITY);
    for r in rows(&trace.join("accelerometer.csv")) {
        let t = r[0] * 1e-9;
        if t0.is_nan() {
            t0 = t;
        }
        let dropped = GAPS.iter().any(|&(a, b)| t - t0 >= a && t - t0 < b);
        if t <= last || dropped {
            continue;
        }
        last = t;
        n += usize::from(d.push_accel(t, [r[2], r[3], r[4]]).unwrap().is_some());
        while d.pop_step().is_some() {
            n += 1;
        }
    }
    let err = 100.0 * (n as f64 - strikes.len() as f64) / strikes.len() as f64;
    eprintln!(
        "{NAME} with dropped bursts: {n} steps, reference {}, error {err:+.2} %",
        strikes.len()
    );
    assert!(
        err.abs() <= 3.0,
        "{NAME} with dropped bursts: count error {err:+.2} %"
    );
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
        let strikes = strikes_of(&trace);
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
