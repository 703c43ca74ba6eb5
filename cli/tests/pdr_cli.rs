//! `stridekit pdr` and `stridekit calibrate pdr` as a user runs them, on a small
//! hand-written Android sensor log (a phone bouncing at a walking cadence, turning
//! slowly), with a repeated timestamp and a malformed line that must be skipped and
//! counted, not fatal.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

fn stridekit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stridekit"))
}

/// The command exited 0 (its stderr is the failure message otherwise).
fn succeeded(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stridekit-pdr-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// 40 s at 50 Hz: vertical bounce at 1.8 steps/s with a forward surge, a slow turn,
/// waypoints every 10 s along a straight line (their geometry is not the point).
fn write_log(path: &Path) {
    let mut s = String::from("#\tstartTime:1000\n#\tFloorName:F9\n");
    let t0 = 1_000_000i64;
    for k in 0..5 {
        let _ = writeln!(s, "{}\tTYPE_WAYPOINT\t{}\t0", t0 + 10_000 * k, 10 * k);
    }
    for i in 0..2000 {
        let ms = t0 + 20 * i;
        let t = i as f64 * 0.02;
        let ph = 2.0 * std::f64::consts::PI * 1.8 * t;
        // Heel strikes: a short impact once per step (the detector wants one), and a
        // little deterministic jitter.
        let impact = if (ph / (2.0 * std::f64::consts::PI)).fract() < 0.04 {
            4.0
        } else {
            0.0
        };
        let jitter = 0.2 * ((i * 7919) % 13) as f64 / 13.0;
        let (az, ay) = (9.81 + 3.0 * ph.sin() + impact + jitter, 1.5 * ph.cos());
        let _ = writeln!(s, "{ms}\tTYPE_ACCELEROMETER\t0.1\t{ay:.5}\t{az:.5}\t3");
        let _ = writeln!(s, "{ms}\tTYPE_GYROSCOPE\t0\t0\t0.02\t3");
        let _ = writeln!(s, "{ms}\tTYPE_MAGNETIC_FIELD\t0\t20\t-40\t3");
        // Android's own fusion: flat, top edge north (what the magnetometer says).
        let _ = writeln!(s, "{ms}\tTYPE_ROTATION_VECTOR\t0\t0\t0\t1\t3");
        if i == 700 {
            // Repeated timestamp: rejected by the navigator, counted.
            let _ = writeln!(s, "{ms}\tTYPE_ACCELEROMETER\t0.1\t{ay:.5}\t{az:.5}\t3");
            let _ = writeln!(s, "{ms}\tTYPE_ACCELEROMETER\tgarbage");
            let _ = writeln!(s, "{ms}\tTYPE_WIFI\tx\ty");
        }
    }
    // A whole log ends with its endTime (one without it reads as cut off).
    let _ = writeln!(s, "#\tendTime:{}", t0 + 40_000);
    std::fs::write(path, s).unwrap();
}

#[test]
fn pdr_replays_a_log_skipping_bad_samples_and_calibrate_writes_a_file() {
    let dir = temp_dir("replay");
    let log = dir.join("walks").join("walk.txt");
    std::fs::create_dir_all(log.parent().unwrap()).unwrap();
    write_log(&log);
    let csv = dir.join("traj.csv");
    let out = stridekit()
        .arg("pdr")
        .arg(&log)
        .arg("--out")
        .arg(&csv)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    succeeded(&out);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("cut off"));
    assert!(
        stdout.contains("rejected samples: none\n")
            && stdout
                .contains("skipped by the reader 1: accelerometer stream: duplicate timestamp"),
        "{stdout}"
    );
    assert!(
        stdout.contains("skipped by the reader 1: malformed TYPE_ACCELEROMETER"),
        "{stdout}"
    );
    assert!(
        stdout.contains("skipped by the reader 1: TYPE_WIFI"),
        "{stdout}"
    );
    assert!(stdout.contains("against 5 waypoints"), "{stdout}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t_s,east_m,north_m,step_length_m,azimuth_deg,steps")
    );
    let rows: Vec<&str> = lines.collect();
    assert!(rows.len() > 40, "{} steps", rows.len());
    // t_s on the file's clock: ms / 1000.
    let t: f64 = rows[0].split(',').next().unwrap().parse().unwrap();
    assert!((1000.0..1040.0).contains(&t), "{t}");
    assert!(dir.join("traj.svg").is_file());

    // The log's gyroscope turns 0.02 rad/s while the field and Android's rotation
    // vector say the phone points north throughout: a gyroscope bias. Said to be raw,
    // the fast magnetic loop holds the heading; taken as platform-calibrated (the
    // default), the slow loop lets most of the 46° drift through.
    let last_azimuth = |extra: &[&str], name: &str| -> f64 {
        let csv = dir.join(name);
        let out = stridekit()
            .arg("pdr")
            .arg(&log)
            .arg("--out")
            .arg(&csv)
            .args(extra)
            .output()
            .unwrap();
        succeeded(&out);
        let text = std::fs::read_to_string(&csv).unwrap();
        let last = text.lines().last().unwrap().split(',').nth(4).unwrap();
        last.parse::<f64>().unwrap()
    };
    let (raw, calibrated) = (
        last_azimuth(&["--raw-gyro"], "raw.csv"),
        last_azimuth(&[], "calibrated.csv"),
    );
    let off_north = |az: f64| (az + 180.0).rem_euclid(360.0) - 180.0;
    assert!(
        off_north(raw).abs() + 10.0 < off_north(calibrated).abs(),
        "raw {raw}°, calibrated {calibrated}°"
    );

    // Calibrate from the folder, then replay with it.
    let cal = dir.join("me.pdrcal");
    let out = stridekit()
        .args(["calibrate", "pdr", "--data"])
        .arg(dir.join("walks"))
        .arg("--out")
        .arg(&cal)
        .output()
        .unwrap();
    succeeded(&out);
    let text = std::fs::read_to_string(&cal).unwrap();
    assert!(text.starts_with("stridekit-pdr-calibration 1\n"), "{text}");
    let out = stridekit()
        .arg("pdr")
        .arg(&log)
        .arg("--out")
        .arg(dir.join("cal.csv"))
        .arg("--calibration")
        .arg(&cal)
        .arg("--no-mag")
        .output()
        .unwrap();
    succeeded(&out);

    // The same log through the step detector: one row per step on the file's clock.
    let steps_csv = dir.join("out/steps");
    let out = stridekit()
        .arg("steps")
        .arg(&log)
        .arg("--out")
        .arg(&steps_csv)
        .output()
        .unwrap();
    succeeded(&out);
    let text = std::fs::read_to_string(dir.join("out/steps.csv")).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    // 40 s at 1.8 steps/s.
    assert!((60..=80).contains(&rows.len()), "{} steps", rows.len());
    let t0: f64 = rows[0].split(',').next().unwrap().parse().unwrap();
    assert!(
        (1000.0..1040.0).contains(&t0),
        "t_s {t0} is not on the file's clock"
    );

    // The same log through the orientation filter and the learned odometry: the
    // repeated sample skipped and counted the same way, Android's rotation vector as
    // the orientation's second opinion.
    let replay = |command: &str, out: &Path| -> String {
        let o = stridekit()
            .arg(command)
            .arg(&log)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{command}: {stdout}");
        assert!(
            stdout.contains("skipped by the reader 1: accelerometer stream: duplicate timestamp"),
            "{command}: {stdout}"
        );
        stdout
    };
    let stdout = replay("orientation", &dir.join("q.csv"));
    let inclination: f64 = stdout
        .split("inclination ")
        .nth(1)
        .and_then(|r| r.split('°').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no comparison with the rotation vector: {stdout}"));
    assert!(
        stdout.contains("against Android's rotation vector"),
        "{stdout}"
    );
    assert!(inclination < 10.0, "{stdout}");
    let svg = std::fs::read_to_string(dir.join("q.svg")).unwrap();
    assert!(
        svg.contains("Difference to Android"),
        "the chart beside the CSV"
    );
    let rows = std::fs::read_to_string(dir.join("q.csv")).unwrap();
    assert_eq!(
        rows.lines().count(),
        2001,
        "header + one row per accepted sample"
    );
    replay("odometry", &dir.join("odo.svg"));

    // Typed refusals: unknown flag, bad calibration file.
    let out = stridekit()
        .args(["pdr", "x.txt", "--fast"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unexpected argument '--fast'"));
    std::fs::write(dir.join("bad.pdrcal"), "stridekit-pdr-calibration 7\n").unwrap();
    let out = stridekit()
        .arg("pdr")
        .arg(&log)
        .arg("--calibration")
        .arg(dir.join("bad.pdrcal"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "a bad value of --calibration");
    assert!(String::from_utf8_lossy(&out.stderr).contains("version 7"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A folder of one floor (a building of its own, a user's few walks) is evaluated:
/// leave-one-floor-out has nothing to learn from there, so those rows score no walk
/// and say why instead of stopping the command; a folder without waypoints is an
/// error that says what is missing.
#[test]
fn eval_pdr_takes_a_folder_of_one_floor_and_refuses_one_without_waypoints() {
    let dir = temp_dir("onefloor");
    std::fs::create_dir_all(dir.join("walks")).unwrap();
    write_log(&dir.join("walks").join("walk.txt"));
    let out = stridekit()
        .args(["eval", "pdr", "--data"])
        .arg(dir.join("walks"))
        .output()
        .unwrap();
    succeeded(&out);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("| defaults, magnetometer | 1 | "),
        "{stdout}"
    );
    assert!(
        stdout.contains("| calibrated leave-one-floor-out, magnetometer | 0 | – |"),
        "{stdout}"
    );
    assert!(stdout.contains("- without F9: none ("), "{stdout}");

    let bare = dir.join("bare");
    std::fs::create_dir_all(&bare).unwrap();
    let text = std::fs::read_to_string(dir.join("walks").join("walk.txt")).unwrap();
    let no_waypoints: String = text
        .lines()
        .filter(|l| !l.contains("TYPE_WAYPOINT"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(bare.join("walk.txt"), no_waypoints).unwrap();
    let out = stridekit()
        .args(["eval", "pdr", "--data"])
        .arg(&bare)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("no walk with surveyed waypoints"),
        "{stderr}"
    );
}
