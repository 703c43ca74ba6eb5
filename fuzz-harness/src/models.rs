//! Every model / calibration text parser: no panic, cost linear in the input (the
//! parsers cap sizes; libFuzzer's timeout catches the rest), and an accepted model's
//! text is a fixed point: parse(to_text(m)) succeeds and prints the same text.

use stridekit_core::foot::SvmModel;
use stridekit_core::odometry::OdometryModel;
use stridekit_core::pace::PaceCalibration;
use stridekit_core::pdr::PdrCalibration;
use stridekit_core::placement::PlacementModel;

fn text(data: &[u8]) -> String {
    String::from_utf8_lossy(data).into_owned()
}

macro_rules! fixed_point {
    ($parse:expr, $print:expr, $data:expr) => {
        if let Ok(m) = $parse(&text($data)) {
            let once = $print(&m);
            let again = $parse(&once).unwrap_or_else(|e| panic!("own text refused: {e}"));
            assert!($print(&again) == once, "to_text is not a fixed point");
        }
    };
}

pub fn svm(data: &[u8]) {
    fixed_point!(SvmModel::parse, SvmModel::to_text, data);
}

pub fn placement(data: &[u8]) {
    fixed_point!(PlacementModel::parse, PlacementModel::to_text, data);
}

pub fn odometry(data: &[u8]) {
    fixed_point!(OdometryModel::parse, OdometryModel::to_text, data);
}

pub fn pdr_calibration(data: &[u8]) {
    fixed_point!(
        PdrCalibration::parse,
        |c: &PdrCalibration| c.to_text(&[]),
        data
    );
}

pub fn pace_calibration(data: &[u8]) {
    fixed_point!(
        PaceCalibration::parse,
        |c: &PaceCalibration| c.to_text(&[]),
        data
    );
}
