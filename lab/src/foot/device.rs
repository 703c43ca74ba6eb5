//! What foot recordings say about their device: whether the gyroscope and the
//! accelerometer clipped and where (`stridekit_core::foot::GyroCeilingDetector` and
//! `AccelCeilingDetector` over every sample: a device's range is a constant, so
//! evidence anywhere in a recording holds for all of it, the first strides included),
//! and whether a file is a trial of the UofT VICON
//! set (its factory-calibrated MicroStrain), the one device the replays know by name.

use stridekit_core::foot::{AccelCeilingDetector, GyroCeiling, GyroCeilingDetector};
use stridekit_formats::FootRecording;

/// The stance label columns pyshoe's VICON release adds to each UofT trial (per-trial
/// optimised labels of its five detectors, `zv_` prefix dropped): a file with all of
/// them is a trial of that set, recorded with its MicroStrain 3DM-GX3-25.
pub const UOFT_VICON_LABELS: [&str; 5] =
    ["shoe_opt", "ared_opt", "amvd_opt", "mbgtd_opt", "vicon_opt"];

/// The device evidence of one or more recordings of the same IMU.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Evidence {
    /// The lowest gyroscope ceiling the data show, or `None`: no sign of clipping.
    pub ceiling: Option<GyroCeiling>,
    /// Every axis and sign with a ceiling.
    pub ceilings: Vec<GyroCeiling>,
    /// The largest gyroscope magnitude in the data, rad/s.
    pub peak_rads: f64,
    /// The accelerometer's pre-scan over every sample (the navigator's rule).
    pub accel: AccelCeilingDetector,
    /// Every recording is a trial of the UofT VICON set ([`UOFT_VICON_LABELS`]).
    pub uoft_vicon_set: bool,
}

/// The evidence of recordings of one device (one detector over all of them in turn).
pub fn evidence(recs: &[&FootRecording]) -> Evidence {
    let mut d = GyroCeilingDetector::new();
    let mut accel = AccelCeilingDetector::new();
    for rec in recs {
        for w in &rec.gyro_rads {
            d.push(*w);
        }
        for f in &rec.accel_mps2 {
            accel.push(*f);
        }
    }
    Evidence {
        ceiling: d.ceiling(),
        ceilings: d.ceilings().collect(),
        peak_rads: d.peak_rads(),
        accel,
        uoft_vicon_set: !recs.is_empty() && recs.iter().all(|r| is_uoft_vicon_trial(r)),
    }
}

/// The recording carries every label column of the UofT VICON set.
pub fn is_uoft_vicon_trial(rec: &FootRecording) -> bool {
    UOFT_VICON_LABELS.iter().all(|l| rec.label(l).is_some())
}

/// "y−" for the negative side of sensor axis 1.
pub fn side_name(c: &GyroCeiling) -> String {
    format!(
        "{}{}",
        ["x", "y", "z"][c.axis.min(2)],
        if c.positive { "+" } else { "−" }
    )
}
