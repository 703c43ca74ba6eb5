//! The phone navigator's step lengths cross-checked against fixes (issue 36), on a
//! real indoor walk (`../shared/data/phone-indoor`, or `$STRIDEKIT_DATA`; skipped with
//! a message when absent): its surveyed waypoints pushed as fixes of 1.5 m accuracy,
//! with a personal calibration whose step lengths are 1.5× the walker's.

use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pdr::{NavEstimate, NavigatorConfig, PdrCalibration, PhoneNavigator};
use stridekit_core::steplength::{StepLengthModel, PRIOR_PENDULUM_K};
use stridekit_core::GnssFix;

/// A 100 m walk with 17 waypoints (floor F1).
const WALK: &str = "phone-indoor/site1/F1/5dd9ef829191710006b5707a.txt.gz";

/// Replays the walk with its waypoints as fixes; returns the last estimate, whether
/// the disagreement was ever flagged, and the waypoints' path length.
fn replay(calibration: Option<PdrCalibration>) -> Option<(NavEstimate, bool, f64)> {
    let Some(path) = stridekit_formats::data_dir().map(|d| d.join(WALK)) else {
        eprintln!("SKIPPED: {WALK} not found (../shared/data; set STRIDEKIT_DATA)");
        return None;
    };
    let rec = stridekit_lab::pdr::walks::load_walk(&path).unwrap().rec;
    let frame = LocalFrame::new(47.0, 8.0, 0.0);
    let fixes: Vec<GnssFix> = rec
        .truth
        .iter()
        .map(|&(t, x, y)| {
            let (lat, lon) = frame.to_geodetic(x, y);
            GnssFix::new(t, lat, lon).with_accuracy(1.5)
        })
        .collect();
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    if let Some(c) = &calibration {
        nav.set_calibration(c).unwrap();
    }
    let (mut k, mut flagged) = (0, false);
    for s in &rec.samples {
        while k < fixes.len() && fixes[k].t_s <= s.t_s {
            flagged |= nav.push_fix(&fixes[k]).unwrap().step_scale_disagrees;
            k += 1;
        }
        nav.push_imu(&ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: s.mag_ut,
        })
        .unwrap();
    }
    let truth: f64 = rec
        .truth
        .windows(2)
        .map(|w| (w[1].1 - w[0].1).hypot(w[1].2 - w[0].2))
        .sum();
    Some((nav.estimate().unwrap(), flagged, truth))
}

#[test]
fn a_calibration_with_steps_half_again_too_long_is_corrected_by_the_fixes() {
    let wrong = PdrCalibration {
        step_length_model: StepLengthModel::Pendulum,
        step_length_theta: [1.5 * PRIOR_PENDULUM_K, 0.0, 0.0],
        step_length_sigma: [0.02, 1.0, 1.0],
        carrying_body: None,
    };
    let Some((e, flagged, truth)) = replay(Some(wrong)) else {
        return;
    };
    assert!(flagged, "the disagreement with the fixes was never flagged");
    assert!(
        (0.55..0.8).contains(&e.step_scale),
        "step scale {}",
        e.step_scale
    );
    // Before: 145 m walked for 99.5 m of waypoints (+46 %), the calibration held.
    let err = e.distance_m / truth - 1.0;
    assert!(
        err.abs() < 0.25,
        "{:.1} m against {truth:.1} m ({:+.1} %)",
        e.distance_m,
        100.0 * err
    );
    // The same walk without the wrong calibration: nothing to correct.
    let (e, flagged, _) = replay(None).unwrap();
    assert!(!flagged && e.step_scale == 1.0, "{e:?}");
}
