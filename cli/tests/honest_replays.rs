//! Replays that tell the truth (issue 36), on real recordings of `../shared/data`:
//! time units refused with one message per cause, a non-zero exit when nothing usable
//! came out, summaries that say what the result rests on, cut-off files reported in
//! every format, formats told by content, messages for folders and missing paths, CSV
//! on stdout only when asked (`--out -`), a closed pipe that ends quietly, one column
//! vocabulary and exit 2 for bad values. The copies the tests need (cut, renamed,
//! converted to g or milliseconds) are made in a temporary folder. Each test skips,
//! saying why, when the data are absent.

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use stridekit_formats::data_dir;

fn stridekit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stridekit"))
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stridekit-honest-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `rel` under the shared data folder, or `None` (the test skips, saying why).
fn shared(rel: &str) -> Option<PathBuf> {
    match data_dir().map(|d| d.join(rel)) {
        Some(p) if p.exists() => Some(p),
        Some(p) => {
            eprintln!("skipping: {} not found", p.display());
            None
        }
        None => {
            eprintln!("skipping: ../shared/data not found (set STRIDEKIT_DATA)");
            None
        }
    }
}

fn run(cmd: &mut Command) -> (Option<i32>, String, String) {
    let Output {
        status,
        stdout,
        stderr,
    } = cmd.output().unwrap();
    (
        status.code(),
        String::from_utf8_lossy(&stdout).into_owned(),
        String::from_utf8_lossy(&stderr).into_owned(),
    )
}

/// The first `bytes` of `from`, written to `to`.
fn cut(from: &Path, to: &Path, bytes: usize) {
    let all = std::fs::read(from).unwrap();
    std::fs::write(to, &all[..bytes.min(all.len() - 1)]).unwrap();
}

/// An Oxford `accelerometer.csv` with every acceleration divided by `divide` and
/// every timestamp by `time_divide` (integer ns column).
fn convert_oxford(from: &Path, to: &Path, divide: f64, time_divide: i64) {
    let text = std::fs::read_to_string(from).unwrap();
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let f: Vec<&str> = line.split(',').collect();
        let t: i64 = f[0].parse().unwrap();
        let a: Vec<String> = f[2..5]
            .iter()
            .map(|v| format!("{:.6}", v.parse::<f64>().unwrap() / divide))
            .collect();
        out += &format!("{},{},{}\n", t / time_divide, f[1], a.join(","));
    }
    std::fs::write(to, out).unwrap();
}

const OXFORD_TRACE: &str = "steps/oxford/Nexus_Jamie_Hard_InHand_1";
const FOOT_TRIAL: &str = "foot/pyshoe-vicon/2017-11-22-11-22-03.csv";
const FOOT_POD_FIT: &str = "pace/original/fitparse-compressed-speed-distance.fit";
const RUN_FIT: &str = "pace/original/runpandas-run.fit";
const RUN_CSV: &str = "pace/csv/runpandas_2020-12-02T06_08_29-300_Running.csv";
const INDOOR_WALK: &str = "phone-indoor/site1/B1/5de8c70c376b9d0006fdaa39.txt.gz";
const BROAD_TRIAL: &str = "orientation/broad/01_undisturbed_slow_rotation_A.csv.gz";

/// Item 2: fix times in milliseconds. Before: exit 0, "distance 0 m", and two
/// contradictory messages (some fixes "look like microseconds", some "milliseconds").
/// Now: exit 1, one message for the GNSS stream naming milliseconds.
#[test]
fn a_gnss_stream_in_milliseconds_is_refused_with_one_message() {
    let Some(run_csv) = shared(RUN_CSV) else {
        return;
    };
    let dir = temp_dir("ms");
    let text = std::fs::read_to_string(run_csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (t, lat, lon, spm) = (
        col("t_unix_s"),
        col("lat_deg"),
        col("lon_deg"),
        col("steps_per_min"),
    );
    let mut ms = String::from("t_s,lat_deg,lon_deg,steps_per_min\n");
    let mut t0 = None;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let t_s: f64 = f[t].parse().unwrap();
        let t0 = *t0.get_or_insert(t_s);
        ms += &format!(
            "{:.0},{},{},{}\n",
            (t_s - t0) * 1000.0,
            f[lat],
            f[lon],
            f[spm]
        );
    }
    let file = dir.join("run_ms.csv");
    std::fs::write(&file, ms).unwrap();
    let (code, stdout, stderr) = run(stridekit()
        .arg("pace")
        .arg(&file)
        .arg("--out")
        .arg(dir.join("out.csv")));
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains("GNSS stream was refused for its units")
            && stderr.contains("milliseconds (divide by 1000)"),
        "{stderr}"
    );
    assert!(!stdout.contains("microseconds"), "one message: {stdout}");
    assert_eq!(
        stdout.matches("GNSS timestamps").count(),
        1,
        "one line per cause: {stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 3: nothing usable exits 1 and says why. Before: `steps` in g, "30304
/// rejected; 0 steps", exit 0; `foot` in g, "0 strides", exit 0; milliseconds in the
/// nanosecond column, 30,152 "duplicate timestamp" rejections, exit 0.
#[test]
fn a_replay_that_produced_nothing_usable_exits_1() {
    let (Some(trace), Some(trial)) = (shared(OXFORD_TRACE), shared(FOOT_TRIAL)) else {
        return;
    };
    let dir = temp_dir("nothing");
    std::fs::create_dir_all(dir.join("g")).unwrap();
    convert_oxford(
        &trace.join("accelerometer.csv"),
        &dir.join("g/accelerometer.csv"),
        9.80665,
        1,
    );
    let (code, _, stderr) = run(stridekit()
        .arg("steps")
        .arg(dir.join("g"))
        .arg("--out")
        .arg(dir.join("g.csv")));
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("no step detected") && stderr.contains("look like g"),
        "{stderr}"
    );
    // Milliseconds written into the nanosecond column.
    let ms = dir.join("ms.csv");
    convert_oxford(&trace.join("accelerometer.csv"), &ms, 1.0, 1_000_000);
    let (code, _, stderr) = run(stridekit()
        .arg("steps")
        .arg(&ms)
        .arg("--out")
        .arg(dir.join("ms_steps.csv")));
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("no step detected"), "{stderr}");
    // The foot trial in g.
    let text = std::fs::read_to_string(trial).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let acc: Vec<usize> = header
        .split(',')
        .enumerate()
        .filter(|(_, h)| h.starts_with("acc_"))
        .map(|(i, _)| i)
        .collect();
    let mut g = format!("{header}\n");
    for line in lines {
        let f: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(i, v)| {
                if acc.contains(&i) {
                    format!("{:.6}", v.parse::<f64>().unwrap() / 9.80665)
                } else {
                    v.to_string()
                }
            })
            .collect();
        g += &f.join(",");
        g.push('\n');
    }
    let foot_g = dir.join("foot_g.csv");
    std::fs::write(&foot_g, g).unwrap();
    let (code, _, stderr) = run(stridekit()
        .arg("foot")
        .arg(&foot_g)
        .arg("--out")
        .arg(dir.join("foot.csv")));
    // Exit 1 naming the units. (Strides may be counted: the detector's stillness floor
    // follows the constant |f| − g of samples in g as it follows a vibration.)
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("look like g"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 4: the summary says what the result rests on. Before: a foot-pod-only FIT
/// replayed to 12,374 m (the pod: 10,249 m) with no word of the step-length prior.
#[test]
fn summaries_say_what_the_result_rests_on() {
    let (Some(pod), Some(run_fit), Some(walk), Some(broad), Some(trial)) = (
        shared(FOOT_POD_FIT),
        shared(RUN_FIT),
        shared(INDOOR_WALK),
        shared(BROAD_TRIAL),
        shared(FOOT_TRIAL),
    ) else {
        return;
    };
    let dir = temp_dir("rests-on");
    let out = |name: &str| dir.join(name);
    let (code, stdout, stderr) = run(stridekit()
        .arg("pace")
        .arg(&pod)
        .arg("--out")
        .arg(out("pod")));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stdout.contains("no GNSS")
            && stdout.contains("population step-length prior")
            && stdout.contains("`stridekit eval pace`"),
        "{stdout}"
    );
    assert!(
        stdout.contains("the file's own distance") && stdout.contains("10249 m"),
        "{stdout}"
    );
    let (_, stdout, _) = run(stridekit()
        .arg("pace")
        .arg(&run_fit)
        .arg("--out")
        .arg(out("run")));
    assert!(
        stdout.contains("rests on: GNSS (1157 fixes")
            && stdout.contains("learned from this file's GNSS"),
        "{stdout}"
    );
    let (code, stdout, stderr) = run(stridekit()
        .arg("pdr")
        .arg(&walk)
        .arg("--out")
        .arg(out("pdr")));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stdout.contains("pendulum step-length model with population parameters")
            && stdout.contains("heading: the magnetometer"),
        "{stdout}"
    );
    let (_, stdout, _) = run(stridekit()
        .arg("pdr")
        .arg(&walk)
        .arg("--no-mag")
        .arg("--out")
        .arg(out("pdr_nomag")));
    assert!(stdout.contains("north is not known"), "{stdout}");
    let (_, stdout, _) = run(stridekit()
        .arg("orientation")
        .arg(&broad)
        .arg("--imu-only")
        .arg("--out")
        .arg(out("q")));
    assert!(
        stdout.contains("heading: relative to the start"),
        "{stdout}"
    );
    let (_, stdout, _) = run(stridekit()
        .arg("foot")
        .arg(&trial)
        .arg("--out")
        .arg(out("foot")));
    assert!(
        stdout.contains("rests on: the IMU alone")
            && stdout.contains("accelerometer alignment: none given"),
        "{stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 5: a file cut off mid-write is read up to the cut and reported, in every
/// format. Before: a FIT cut at 20 kB read as a 1,529 m run of 5,476 m, silently; a
/// cut .csv.gz failed the whole file.
#[test]
fn cut_off_files_are_reported_in_every_format() {
    let Some(data) = shared("") else {
        return;
    };
    let dir = temp_dir("cut");
    let files = [
        ("pace", RUN_FIT, "run.fit", 20_000),
        (
            "pace",
            "pace/original/runpandas-run_garmin.tcx",
            "run.tcx",
            40_000,
        ),
        (
            "pace",
            "pace/original/runpandas-strava_export.gpx",
            "run.gpx",
            40_000,
        ),
        ("pace", RUN_CSV, "run.csv", 30_001),
        ("steps", INDOOR_WALK, "walk.txt.gz", 30_000),
        (
            "steps",
            "steps/oxford/Nexus_Jamie_Hard_InHand_1/accelerometer.csv",
            "accel.csv",
            300_001,
        ),
        ("foot", FOOT_TRIAL, "foot.csv", 400_001),
        ("orientation", BROAD_TRIAL, "broad.csv.gz", 500_000),
    ];
    for (command, rel, name, bytes) in files {
        let from = data.join(rel);
        if !from.is_file() {
            eprintln!("skipping {rel}: not found");
            continue;
        }
        let whole = run(stridekit()
            .arg(command)
            .arg(&from)
            .arg("--out")
            .arg(dir.join(format!("{name}.whole"))));
        assert!(!whole.2.contains("cut off"), "{rel}: {}", whole.2);
        let file = dir.join(name);
        cut(&from, &file, bytes);
        let (code, stdout, stderr) = run(stridekit()
            .arg(command)
            .arg(&file)
            .arg("--out")
            .arg(dir.join(format!("{name}.out"))));
        assert!(
            stderr.contains("was cut off mid-write"),
            "{rel} cut at {bytes} bytes: exit {code:?}\n{stdout}\n{stderr}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 5: the format comes from the content; folders and missing paths are named as
/// such. Before: an Oxford CSV renamed `my_walk.csv` was "not a supported
/// accelerometer recording"; a folder gave `unknown activity file extension ""` or
/// "No such file or directory".
#[test]
fn formats_come_from_the_content_and_paths_are_named() {
    let (Some(trace), Some(pod)) = (shared(OXFORD_TRACE), shared(FOOT_POD_FIT)) else {
        return;
    };
    let dir = temp_dir("content");
    let renamed = dir.join("my_walk.csv");
    std::fs::copy(trace.join("accelerometer.csv"), &renamed).unwrap();
    let (code, stdout, stderr) = run(stridekit()
        .arg("steps")
        .arg(&renamed)
        .arg("--out")
        .arg(dir.join("steps.csv")));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("305 steps"), "{stdout}");
    // A FIT without its extension is still a FIT.
    let no_ext = dir.join("activity");
    std::fs::copy(&pod, &no_ext).unwrap();
    let (code, _, stderr) = run(stridekit()
        .arg("pace")
        .arg(&no_ext)
        .arg("--out")
        .arg(dir.join("pace.csv")));
    assert_eq!(code, Some(0), "{stderr}");
    // A recording of another kind names the command that replays it.
    let (code, _, stderr) = run(stridekit()
        .arg("pace")
        .arg(&renamed)
        .arg("--out")
        .arg(dir.join("x.csv")));
    assert_eq!(code, Some(1));
    assert!(
        stderr.contains("Oxford") && stderr.contains("`stridekit steps` replays it"),
        "{stderr}"
    );
    let empty = dir.join("empty_folder");
    std::fs::create_dir_all(&empty).unwrap();
    for command in ["pace", "steps", "foot", "pdr", "orientation"] {
        let (code, _, stderr) = run(stridekit()
            .arg(command)
            .arg(&empty)
            .arg("--out")
            .arg(dir.join("x.csv")));
        assert_eq!(code, Some(1), "{command}");
        assert!(stderr.contains("is a folder"), "{command}: {stderr}");
        let (code, _, stderr) = run(stridekit()
            .arg(command)
            .arg(dir.join("missing.csv"))
            .arg("--out")
            .arg(dir.join("x.csv")));
        assert_eq!(code, Some(1), "{command}");
        assert!(
            stderr.contains("no such file or folder"),
            "{command}: {stderr}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 7: the CSV goes to a file (the terminal gets the summary) or to stdout only
/// with `--out -`; a closed pipe ends quietly with 0; the foot CSV speaks the pdr
/// CSV's vocabulary at the data's precision; bad values exit 2. Before: `pace FILE`
/// printed ~1,800 CSV rows; `| head -1` gave "error: Broken pipe (os error 32)", exit
/// 1; the foot CSV had `x_m,y_m` and 20-digit floats; `foot --axes xyz` exited 1.
#[test]
fn csv_goes_where_asked_and_pipes_close_quietly() {
    let (Some(run_fit), Some(trial)) = (shared(RUN_FIT), shared(FOOT_TRIAL)) else {
        return;
    };
    let dir = temp_dir("output");
    let (code, stdout, stderr) = run(stridekit().current_dir(&dir).arg("pace").arg(&run_fit));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stdout.lines().count() < 10 && stdout.contains("distance"),
        "a summary, no rows: {stdout}"
    );
    assert!(dir.join("pace.csv").is_file());
    // `--out -` into a pipe closed after one line.
    let mut child = stridekit()
        .arg("pace")
        .arg(&run_fit)
        .args(["--out", "-"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 64];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap();
    // (stdout dropped: the pipe is closed)
    let out = child.wait_with_output().unwrap();
    assert!(first.starts_with(b"t_s,"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(
        !stderr.contains("Broken pipe") && !stderr.contains("error"),
        "{stderr}"
    );
    // The foot CSV.
    let (code, stdout, stderr) = run(stridekit().arg("foot").arg(&trial).args(["--out", "-"]));
    assert_eq!(code, Some(0), "{stderr}");
    let mut lines = stdout.lines();
    assert_eq!(
        lines.next(),
        Some("t_s,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,yaw_rad,stance,strides,distance_m,gt_east_m,gt_north_m,gt_up_m")
    );
    let longest = lines
        .take(500)
        .flat_map(|l| l.split(','))
        .map(|v| v.split('.').nth(1).map_or(0, str::len))
        .max()
        .unwrap();
    assert!(longest <= 6, "{longest} decimals");
    assert!(
        stderr.contains("rests on"),
        "the summary on stderr: {stderr}"
    );
    let (code, _, stderr) = run(stridekit().arg("foot").arg(&trial).args(["--axes", "xyz"]));
    assert_eq!(code, Some(2), "{stderr}");
    let (code, _, stderr) = run(stridekit()
        .arg("foot")
        .arg(&trial)
        .args(["--labels", "no_such_column", "--out"])
        .arg(dir.join("f.csv")));
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("zv_no_such_column"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
