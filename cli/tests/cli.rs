//! The command-line tool as a user runs it: the README's main command (`demo`) and
//! the replay of a user CSV.

use std::path::{Path, PathBuf};
use std::process::Command;

fn stridekit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stridekit"))
}

/// Run `cmd`; its output, after checking it succeeded (its stderr otherwise).
fn succeed(cmd: &mut Command) -> std::process::Output {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stridekit-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn demo_prints_a_summary_and_writes_the_report() {
    let out_dir = temp_dir("demo");
    let out = succeed(stridekit().args(["demo", "--out"]).arg(&out_dir));
    let stdout = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "| stridekit (default) |",
        "| AsPublished |",
        "Next session without GNSS",
        "Report written to",
    ] {
        assert!(stdout.contains(needle), "missing {needle:?} in:\n{stdout}");
    }
    for file in [
        "index.html",
        "summary.md",
        "pace.svg",
        "speed.svg",
        "gnss_weight.svg",
        "step_length.svg",
        "track.svg",
        "treadmill.svg",
    ] {
        let p = out_dir.join(file);
        let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(text.len() > 100, "{} is too small", p.display());
        if file.ends_with(".svg") {
            assert!(text.contains("<svg"), "{} is not SVG", p.display());
        }
    }
    let html = std::fs::read_to_string(out_dir.join("index.html")).unwrap();
    // A rendered page: an HTML table, the methods explained, every figure captioned.
    for needle in [
        "<table>",
        "<dt>AsPublished</dt>",
        "<figcaption>",
        "pace.svg",
        "/km",
    ] {
        assert!(html.contains(needle), "index.html lacks {needle:?}");
    }
    assert!(!html.contains("<pre>"));
    let track = std::fs::read_to_string(out_dir.join("track.svg")).unwrap();
    assert!(track.contains("stridekit"), "the fused track is missing");
    report_says_what_it_shows(&out_dir, &stdout);
    let _ = std::fs::remove_dir_all(&out_dir);
}

/// Issue 36 item 8: the demo report claims no more than its charts show, in the
/// names an app developer uses, with one label per method and pace errors in s/km.
fn report_says_what_it_shows(dir: &Path, stdout: &str) {
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let md = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    // Kotlin/Swift names, marked up as code; no Rust path, no literal backtick.
    assert!(
        !html.contains('`') && !html.contains("::"),
        "Rust paths or backticks in index.html"
    );
    assert!(html.contains("<code>PaceTracker.calibration()</code>"));
    assert!(!stdout.contains("::"), "Rust paths in the summary");
    // The speed caption measures the outages instead of "stays on the truth".
    assert!(
        !md.contains("stays on the truth through"),
        "the old overclaim"
    );
    assert!(
        md.contains("at the outage's top speed, 4.7 m/s, stridekit (default) reads 4.1 m/s"),
        "the first outage as the chart shows it:\n{md}"
    );
    // One label per method: the table's names are the legends'.
    for (svg, name) in [
        ("pace.svg", "raw GNSS diff"),
        ("speed.svg", "GNSS EMA"),
        ("speed.svg", "stridekit (default)"),
        ("gnss_weight.svg", "AsPublished"),
    ] {
        let text = std::fs::read_to_string(dir.join(svg)).unwrap();
        assert!(text.contains(name), "{svg} lacks the legend {name:?}");
        assert!(
            html.contains(&format!("<td>{name}</td>")),
            "the table lacks {name:?}"
        );
    }
    // The GNSS weight is a share: its axis ends at 1.
    let weight = std::fs::read_to_string(dir.join("gnss_weight.svg")).unwrap();
    let ticks: Vec<f64> = weight
        .split("text-anchor=\"end\"")
        .skip(1)
        .filter_map(|t| t.split('>').nth(1)?.split('<').next()?.trim().parse().ok())
        .collect();
    assert_eq!(
        ticks.iter().copied().fold(f64::NAN, f64::max),
        1.0,
        "{ticks:?}"
    );
    // Pace errors in s/km beside the m/s.
    assert!(
        stdout.contains("| stridekit (default) | 0.347 · 10 s/km |"),
        "{stdout}"
    );
    assert!(html.contains("s/km</small>"));
}

#[test]
fn pace_replays_a_user_csv() {
    let dir = temp_dir("csv");
    let csv = dir.join("run.csv");
    // 10 minutes east along the equator at 3 m/s, 1 Hz fixes, 170 steps/min.
    let mut text = String::from("t_s,lat_deg,lon_deg,steps_per_min\n");
    let m_per_deg = 111_319.49;
    for i in 0..600 {
        let lon = 3.0 * i as f64 / m_per_deg;
        text.push_str(&format!("{i},0.0,{lon:.9},170\n"));
        // What real files hold: a repeated row, rows out of order, a bad position.
        match i {
            100 => text.push_str(&format!("{i},0.0,{lon:.9},170\n")),
            200 => text.push_str(&format!("{},0.0,{lon:.9},170\n", i - 50)),
            300 => text.push_str(&format!("{}.5,95.0,{lon:.9},170\n", i)),
            _ => {}
        }
    }
    std::fs::write(&csv, text).unwrap();
    // `--out -`: the CSV on stdout, the summary on stderr.
    let out = succeed(stridekit().arg("pace").arg(&csv).args(["--out", "-"]));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].starts_with("t_s,t_unix_s,speed_mps"));
    assert!(lines.len() > 500, "{} lines", lines.len());
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let last: Vec<&str> = lines.last().unwrap().split(',').collect();
    let speed: f64 = last[col("speed_mps")].parse().unwrap();
    let distance: f64 = last[col("distance_m")].parse().unwrap();
    assert!((speed - 3.0).abs() < 0.2, "speed {speed}");
    assert!((distance - 1797.0).abs() < 40.0, "distance {distance}");
    // 3 m/s is 5:33 per km; the runner's column says so.
    assert_eq!(
        last[col("pace_min_per_km")],
        "5:33",
        "{}",
        lines.last().unwrap()
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("average pace"), "{stderr}");
    // The reader's clean-up is reported, not silent.
    assert!(
        stderr.contains("reader 2: record with the same timestamp as another, merged"),
        "{stderr}"
    );
    assert!(
        stderr.contains("reader 1: record out of time order, sorted"),
        "{stderr}"
    );
    assert!(
        stderr.contains("reader 1: position missing half, not finite or out of range"),
        "{stderr}"
    );
    // --out: the same CSV in a file, the speed chart beside it, the summary on the
    // terminal.
    let out = stridekit()
        .arg("pace")
        .arg(&csv)
        .arg("--out")
        .arg(dir.join("out/run"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(
        !summary.contains("t_s,") && summary.contains("average pace"),
        "the CSV goes to the file, the summary to stdout: {summary}"
    );
    let written = std::fs::read_to_string(dir.join("out/run.csv")).unwrap();
    assert_eq!(written, stdout, "same rows as on stdout");
    let svg = std::fs::read_to_string(dir.join("out/run.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("stridekit"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The last row's value of `name` in a `stridekit pace` CSV.
fn last_value(csv: &str, name: &str) -> String {
    let lines: Vec<&str> = csv.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = header.iter().position(|h| *h == name).expect(name);
    lines
        .last()
        .unwrap()
        .split(',')
        .nth(col)
        .unwrap()
        .to_string()
}

#[test]
fn pace_saves_a_calibration_and_replays_steps_only_with_it() {
    let dir = temp_dir("calibration");
    let csv = dir.join("run.csv");
    // 10 minutes east at 3 m/s, 1 Hz fixes, 170 steps/min: steps of 1.06 m, longer
    // than the population prior's 1.0 m at 168 steps/min.
    let mut text = String::from("t_s,lat_deg,lon_deg,steps_per_min\n");
    for i in 0..600 {
        let lon = 3.0 * i as f64 / 111_319.49;
        text.push_str(&format!("{i},0.0,{lon:.9},170\n"));
    }
    std::fs::write(&csv, text).unwrap();
    let cal = dir.join("me.txt");
    succeed(
        stridekit()
            .arg("pace")
            .arg(&csv)
            .arg("--out")
            .arg(dir.join("with-gnss.csv"))
            .arg("--save-calibration")
            .arg(&cal),
    );
    let saved = std::fs::read_to_string(&cal).unwrap();
    let c = stridekit_core::PaceCalibration::parse(&saved).unwrap();
    assert!(
        (c.step_length_at(170.0) - 3.0 / (170.0 / 60.0)).abs() < 0.03,
        "{c:?}"
    );
    // The same run as a treadmill would give it: steps only, with and without it.
    let replay = |with: bool| {
        let mut cmd = stridekit();
        cmd.arg("pace")
            .arg(&csv)
            .arg("--no-gnss")
            .args(["--out", "-"]);
        if with {
            cmd.arg("--calibration").arg(&cal);
        }
        String::from_utf8(succeed(&mut cmd).stdout).unwrap()
    };
    let calibrated = replay(true);
    assert_eq!(last_value(&calibrated, "source"), "Pedometer");
    assert_eq!(last_value(&calibrated, "gnss_weight"), "0.000");
    let speed: f64 = last_value(&calibrated, "speed_mps").parse().unwrap();
    assert!((speed - 3.0).abs() < 0.06, "calibrated: {speed} m/s");
    let prior: f64 = last_value(&replay(false), "speed_mps").parse().unwrap();
    assert!(
        (prior - 3.0).abs() > (speed - 3.0).abs() + 0.05,
        "prior {prior} vs calibrated {speed} m/s"
    );
    // Nothing to learn without GNSS: a clear failure, not an empty file.
    let out = stridekit()
        .arg("pace")
        .arg(&csv)
        .arg("--no-gnss")
        .arg("--out")
        .arg(dir.join("no-gnss.csv"))
        .arg("--save-calibration")
        .arg(dir.join("none.txt"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no calibration to save"));
    assert!(!dir.join("none.txt").exists());
    // A file that is not a calibration is refused before the replay: a bad value of
    // the flag, exit 2.
    let out = stridekit()
        .arg("pace")
        .arg(&csv)
        .arg("--out")
        .arg(dir.join("refused.csv"))
        .arg("--calibration")
        .arg(&csv)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("not a stridekit-pace-calibration file"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn errors_exit_non_zero_with_a_message() {
    let out = stridekit()
        .args(["pace", "/nonexistent/run.fit"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("error"));
    let out = stridekit().arg("frobnicate").output().unwrap();
    assert!(!out.status.success());
    let out = stridekit().arg("help").output().unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("Usage: stridekit <COMMAND>"));
}

#[test]
fn the_command_line_behaves() {
    // Alone: help, nothing written, exit 2 (a usage error).
    let dir = temp_dir("cli-behaves");
    let out = stridekit().current_dir(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("Usage: stridekit <COMMAND>"));
    assert!(
        std::fs::read_dir(&dir).unwrap().next().is_none(),
        "wrote something"
    );
    // Unknown flags, bad values and extra arguments: exit 2 with clap's message.
    for bad in [
        &["demo", "--oot", "x"][..],
        &["demo", "--seed", "abc"],
        &["demo", "extra"],
        &["pace", "run.fit", "--mode"],
        &["foot", "f.csv", "--lables", "vicon_opt"],
    ] {
        let out = stridekit().current_dir(&dir).args(bad).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", bad.join(" "));
        assert!(String::from_utf8_lossy(&out.stderr).contains("error:"));
    }
    let out = stridekit().args(["pace", "--help"]).output().unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("--mode"));
    let out = stridekit().arg("--version").output().unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("stridekit "));
    // A closed pipe (`stridekit demo | head -1`) ends the command quietly.
    let mut child = stridekit()
        .args(["demo", "--out"])
        .arg(dir.join("report"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    std::io::BufRead::read_line(
        &mut std::io::BufReader::new(child.stdout.take().unwrap()),
        &mut first,
    )
    .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(first.starts_with("# stridekit demo"), "{first}");
    assert!(out.status.success(), "{:?}", out.status);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    let _ = std::fs::remove_dir_all(&dir);
}
