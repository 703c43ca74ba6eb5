//! Every reader of `stridekit-formats`: no input may panic or hang it. Readers that
//! take a path get the input through a per-process temporary file.

use std::io::Cursor;
use std::path::PathBuf;

use stridekit_formats as f;

fn text(data: &[u8]) -> String {
    String::from_utf8_lossy(data).into_owned()
}

/// Writes `data` to a temporary file named `name` (unique to this process) and returns
/// its path.
fn temp_file(name: &str, data: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stridekit-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let path = dir.join(name);
    std::fs::write(&path, data).expect("temporary file");
    path
}

pub fn fit(data: &[u8]) {
    let _ = f::read_fit(data);
}

pub fn tcx(data: &[u8]) {
    let _ = f::read_tcx(&text(data));
}

pub fn gpx(data: &[u8]) {
    let _ = f::read_gpx(&text(data));
}

pub fn csv(data: &[u8]) {
    let _ = f::read_csv(&text(data));
}

/// pyshoe and x-io foot-IMU CSV (one parser, two layouts).
pub fn foot_csv(data: &[u8]) {
    let _ = f::parse_foot_csv(&text(data), "fuzz".into());
}

pub fn ridi(data: &[u8]) {
    let _ = f::parse_ridi_csv("fuzz", &text(data));
}

pub fn ronin(data: &[u8]) {
    let _ = f::parse_ronin_csv("fuzz", &text(data));
}

pub fn android_log(data: &[u8]) {
    let _ = f::parse_android_log("fuzz", &text(data));
}

/// The gzip path of the Android reader (and of `read_inertial`).
pub fn android_log_gz(data: &[u8]) {
    let _ = f::read_inertial(&temp_file("walk.txt.gz", data));
}

pub fn broad(data: &[u8]) {
    let _ = f::parse_broad(Cursor::new(data));
}

pub fn oxford_accel(data: &[u8]) {
    let _ = f::read_oxford_accel_raw(&temp_file("accelerometer.csv", data));
}

/// Dispatch on the header as `read_inertial` does for a `.csv` (RIDI or RoNIN).
pub fn inertial_csv(data: &[u8]) {
    let _ = f::read_inertial(&temp_file("walk.csv", data));
}
