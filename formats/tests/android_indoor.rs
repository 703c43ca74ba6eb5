//! Reads the real Android sensor logs of `phone-indoor/` (Microsoft Indoor Location
//! Competition 2.0 sample, site 1): every file parses, has 50 Hz IMU samples with a
//! magnetometer, the rotation vector, waypoints inside the walk and the floor name.
//!
//! The data is not part of the repository: without `../shared/data` (or
//! `STRIDEKIT_DATA`) the test prints a skip message and passes.

use stridekit_formats::{data_dir, list_android_logs, read_inertial};

#[test]
fn every_indoor_walk_reads() {
    let Some(dir) = data_dir().map(|d| d.join("phone-indoor")) else {
        eprintln!("skipping: ../shared/data not found (set STRIDEKIT_DATA)");
        return;
    };
    if !dir.is_dir() {
        eprintln!("skipping: {} not found", dir.display());
        return;
    }
    let logs = list_android_logs(&dir).unwrap();
    assert_eq!(logs.len(), 287, "the README says 287 traces");
    let mut waypoints = 0;
    for path in &logs {
        let r = read_inertial(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let floor = path.parent().and_then(|p| p.file_name()).unwrap();
        assert_eq!(r.meta_value("FloorName"), floor.to_str(), "{}", r.name);
        assert!(r.samples.len() > 100, "{}", r.name);
        assert!(r.samples.iter().all(|s| s.mag_ut.is_some()), "{}", r.name);
        assert!(r.orientation.len() + 10 >= r.samples.len(), "{}", r.name);
        assert!(r.truth.len() >= 2, "{}", r.name);
        assert!(!r.truncated, "{}: whole logs end with endTime", r.name);
        let span = r.samples.last().unwrap().t_s - r.samples[0].t_s;
        let rate = (r.samples.len() - 1) as f64 / span;
        assert!((40.0..60.0).contains(&rate), "{}: {rate} Hz", r.name);
        // Every quaternion is a unit one.
        for (_, q) in &r.orientation {
            let n: f64 = q.iter().map(|v| v * v).sum();
            assert!((n - 1.0).abs() < 1e-3, "{}: |q|² = {n}", r.name);
        }
        waypoints += r.truth.len();
    }
    eprintln!("{} logs, {waypoints} waypoints", logs.len());
}
