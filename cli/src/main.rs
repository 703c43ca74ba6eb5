//! `stridekit`: the command-line tool of the stridekit SDK.

mod activity;
mod calibrate_pdr;
mod demo;
mod eval_foot;
mod eval_foot_diagnose;
mod eval_foot_sessions;
mod eval_foot_tune_shoe;
mod eval_orientation;
mod eval_pace;
mod eval_pace_device;
mod eval_pdr;
mod eval_pdr_odometry;
mod eval_pdr_real;
mod eval_steplength;
mod eval_steps;
mod foot;
mod odometry;
mod orientation;
mod orientation_metric;
mod pdr;
mod pdr_diagnose;
mod pdr_metrics;
mod pdr_walks;
mod placement;
mod placement_mlp;
mod rejected;
mod replay;
mod report;
mod soak;
mod steps;
mod train_zupt;

use std::path::PathBuf;
use std::process::ExitCode;

use stridekit_core::PaceConfig;

const USAGE: &str =
    "stridekit — running pace and pedestrian navigation from phone and watch sensors

USAGE:
  stridekit demo [--out DIR] [--seed N]
      Simulate a 40-minute run with GNSS disturbances, outages and stops; print a
      summary and write a report with SVG plots (default DIR: report).
  stridekit pace FILE.(fit|tcx|gpx|csv) [--mode default|published]
      Replay a real activity file; print per-epoch estimates as CSV on stdout.
      Samples the tracker rejects are skipped and counted by reason (stderr).
  stridekit steps FILE|DIR [--out steps.csv]
      Replay a phone accelerometer recording (an Oxford Step Counter trace folder or
      its accelerometer.csv) through the step detector; write one row per step
      (t_s on the recording's clock, step number, cadence in steps/min, interval).
      Rejected samples are skipped and counted by reason (stderr).
  stridekit eval pace [--data DIR] [--seeds N] [--set NAME=VALUE ...]
      Speed RMSE of raw GNSS, GNSS EMA, AsPublished and default on N simulated runs
      (default 10) and on the real runs in DIR (default: ../shared/data/pace/original)
      with injected GNSS degradation. Prints markdown tables. --set changes a
      parameter of the default filter (see AdaptiveParams) for sensitivity checks.
  stridekit eval steps [--data DIR] [--sensitivity]
      Step counting of the AsPublished and default detectors on the Oxford Step
      Counter traces in DIR (default: ../shared/data/steps/oxford): count error and
      step-event F1 per trace and per placement, also at 100 and 50 Hz, with
      jittered timestamps and 10 % dropped (native and 50 Hz) and with dropped bursts.
      --sensitivity adds parameter sensitivity and a leave-one-user-out check.
  stridekit eval pdr [--data DIR] [--diagnose]
      Pedestrian dead reckoning on real indoor walks with surveyed waypoints (Android
      sensor logs; default DIR: ../shared/data/phone-indoor), no GNSS: ATE, start-pinned
      error, end error and distance error per floor and overall for the defaults (with
      and without magnetometer), calibrated leave-one-floor-out, Android's rotation
      vector as orientation and the learned odometry. --diagnose prints where the
      error comes from instead.
  stridekit eval pdr --sim [--seeds N]
      Pedestrian dead reckoning on the phone simulator, every placement: step count,
      distance and end-point error after a 10-minute GNSS outage and around a closed
      loop (default 3 seeds).
  stridekit pdr FILE [--out traj.csv] [--calibration FILE] [--no-mag]
      Replay a phone recording (Android sensor log .txt/.txt.gz, see
      formats/src/android.rs) through PhoneNavigator without GNSS; write the
      trajectory (one row per step: t_s,east_m,north_m,step_length_m,azimuth_deg,steps;
      default pdr_trajectory.csv) and beside it an SVG of the track over the aligned
      waypoints; rejected samples are skipped and counted.
  stridekit calibrate pdr --data DIR --out FILE [--model weinberg|linear|linear-f|constant]
      Learn the personal PDR calibration (step-length model, how the phone is
      carried) from walks with waypoints and write it (format in
      core/src/pdr/calibration.rs); load it with stridekit pdr --calibration FILE.
  stridekit eval steplength [--data DIR]
      Step-length models (constant, linear robust and as published, frequency-only,
      Weinberg): distance error over a 5-minute GNSS outage after calibration, on the
      phone simulator and on the real runs in DIR (default: ../shared/data/pace/original).
  stridekit foot FILE.csv [--out traj.csv] [--labels NAME] [--axes SPEC]
                 [--imu consumer|calibrated]
      Replay a foot-mounted IMU recording (pyshoe / UofT CSV, or an x-io NGIMU CSV
      export: Time (s), Gyroscope (deg/s), Accelerometer (g)) through the foot
      navigator; write the trajectory CSV (default foot_trajectory.csv) and, next to
      it, traj.svg (top view) and traj_height.svg (height over time). Samples the
      navigator rejects (repeated or reversed timestamps, NaN, out of range) are
      skipped and counted by reason. Prints strides, distance and the end − start
      displacement (loop closure). --axes: where the sensor axes point, in the
      order x, y, z, from f/b l/r u/d (frd = x forward, y right, z down, as in
      pyshoe; flu = x forward, y left, z up), or which signed sensor axis gives
      body forward, left, up (x,-y,-z = frd); default frd for pyshoe files, flu for
      x-io. --imu: calibrated (factory-calibrated IMU, default for pyshoe/UofT files)
      or consumer (gyro bias measured at the start rest; default otherwise). With
      truth columns (gt_*), the truth is aligned to the estimate (rotation about the
      vertical + translation), written beside it in the CSV, drawn in both plots
      and its position RMSE printed. --labels drives the zero-velocity updates with
      a stance label column (e.g. vicon_opt) instead of the detector.
  stridekit eval foot [--data DIR] [--tune | --tune-adaptive-shoe | --diagnose]
      Foot-mounted navigation on the pyshoe VICON trials in DIR (default:
      ../shared/data/foot/pyshoe-vicon): horizontal and 3-D position RMSE, loop
      closure and zero-velocity agreement per trial, per gait and per session for the
      fixed, adaptive, SVM (6-fold and leave-one-session-out), SHOE and adaptive SHOE
      detectors and the oracle labels. --tune prints the grid searches on the
      training split that chose the defaults (--tune-adaptive-shoe: only the gyro
      timing and adaptive SHOE part); --diagnose prints stride-length and
      height-per-stride errors against the truth.
  stridekit train zupt [--data DIR] [--trials A,B,...|--split K/N] [--out FILE]
      Train the SVM zero-velocity detector (six Gaussian-kernel SVMs) on the trials
      in DIR (default: all; --split K/N leaves out fold K of N, by position modulo N)
      and write a model file (format v1, see core/src/foot/svm.rs).
  stridekit train placement [--data DIR] [--out FILE]
      Train the phone-placement classifier (logistic regression, core::placement) on
      every Oxford Step Counter trace in DIR (default: ../shared/data/steps/oxford)
      and write a model file (default placement_lr_v1.txt, format in
      core/src/placement/model.rs).
  stridekit eval placement [--data DIR] [--drop NAME,NAME...] [--l2 X] [--mlp]
      Phone-placement classifier, leave-one-user-out on the Oxford traces: window,
      smoothed and per-trace (majority vote) accuracy, confusion matrices, per-user
      accuracy, model size and cost; and the real-data model on simulated walks.
      --drop neutralises features (ablation; names in core/src/placement/features.rs),
      --l2 changes the training penalty (default 0.01); --mlp adds the same
      protocol for a small MLP (comparison only, not shipped).
  stridekit train odometry [--sim-seeds N | --ridi DIR | --ronin DIR] [--out FILE]
                           [--window SAMPLES] [--lambda L]
      Fit the learned phone odometry (one velocity regressor per placement and a
      general one) on N simulated walks per placement (default 8), or on RIDI
      sequences / RoNIN CSV exports in DIR; write a model file (format v1, see
      core/src/odometry/model.rs; default odometry_v1.txt).
  stridekit eval odometry [--model FILE] [--seeds N] [--unknown-placement]
      ATE / RTE (RoNIN's definitions) per placement of the learned pipeline, without
      bias correction, and naive double integration with fixed and AHRS orientation,
      on N held-out simulated walks per placement (default 5; seeds from 10000).
  stridekit odometry FILE|DIR|sim:SEED:PLACEMENT [--model M] [--out traj.svg]
      Replay a recording (RIDI sequence, RIDI data.csv, RoNIN CSV export or a
      simulator walk) through the learned pipeline and the baselines; print ATE / RTE
      and write an SVG of the trajectories against the truth.
  stridekit orientation FILE [--out q.csv] [--imu-only]
      Replay a recording with IMU and magnetometer samples (the BROAD CSV, .csv or
      .csv.gz) through the default orientation filter; write one row per accepted
      sample, t_s,qw,qx,qy,qz (body -> East-North-Up) and the filter's flags (default
      orientation.csv). Rejected samples are skipped and counted by reason. With
      optical truth in the file, prints the BROAD errors. --imu-only ignores the
      magnetometer.
  stridekit eval orientation [--data DIR] [--imu-only] [--set NAME=VALUE ...] [--quick]
      Orientation filters against optical motion capture on the BROAD trials in DIR
      (default: ../shared/data/orientation/broad): RMSE of the total, heading and
      inclination error during movement per trial and as means, for the default,
      Madgwick and the variants kept; and leave-half-out figures (settings chosen on
      the odd trials scored on the even ones, and the reverse). --imu-only: without
      the magnetometer (inclination). --set changes a setting of the default filter
      (DecoupledSettings field names) for sensitivity checks; --quick scores only it.
  stridekit soak [--hours H] [--seed N]
      Soak test (a command, not CI): H simulated hours (default 24) of 200 Hz phone
      IMU with 1 Hz GNSS and of 200 Hz foot-mounted IMU through every engine, each
      twice: unsplit, and restored from its own snapshot every simulated minute.
      Outputs must match bit for bit and be finite; prints RSS every simulated hour,
      then run time, peak memory (VmHWM), RSS growth after hour 1 and per-engine
      counts. Exits non-zero on any mismatch, non-finite output or memory growth.
  stridekit help
";

fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

/// Refuses anything in `args[from..]` that is not one of the command's flags:
/// `with_value` flags take the next argument, `switches` stand alone.
fn check_flags(
    args: &[String],
    from: usize,
    with_value: &[&str],
    switches: &[&str],
) -> Result<(), String> {
    let mut i = from;
    while i < args.len() {
        let a = args[i].as_str();
        if with_value.contains(&a) {
            if args.get(i + 1).is_none_or(|v| v.starts_with("--")) {
                return Err(format!("{a} needs a value"));
            }
            i += 2;
        } else if switches.contains(&a) {
            i += 1;
        } else {
            let mut known: Vec<&str> = with_value.to_vec();
            known.extend(switches);
            let command = args[..from.min(args.len())].join(" ");
            let context = if command.is_empty() {
                String::new()
            } else {
                format!(" for `{command}`")
            };
            return Err(format!(
                "unknown argument {a}{context} (accepted: {})",
                known.join(", ")
            ));
        }
    }
    Ok(())
}

/// [`check_flags`] over all of `args`, as an optional message.
fn unknown_flags(args: &[String], valued: &[&str], bare: &[&str]) -> Option<String> {
    check_flags(args, 0, valued, bare).err()
}

/// `eval pdr` on the simulator or on real walks.
enum EvalPdr {
    Sim { seeds: u64 },
    Real { data: PathBuf, diagnose: bool },
}

/// Flags of `eval pdr`: `--sim [--seeds N]` or `[--data DIR] [--diagnose]`.
fn eval_pdr_args(args: &[String]) -> Result<EvalPdr, String> {
    let (mut sim, mut seeds, mut data, mut diagnose) = (false, 3, None, false);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--sim" => sim = true,
            "--seeds" => {
                sim = true;
                seeds = it
                    .next()
                    .and_then(|s| s.parse().ok())
                    .ok_or("--seeds needs a number")?;
            }
            "--data" => data = Some(PathBuf::from(it.next().ok_or("--data needs a DIR")?)),
            "--diagnose" => diagnose = true,
            other => {
                return Err(format!(
                    "unknown option {other} for eval pdr (--sim [--seeds N] | [--data DIR] [--diagnose])"
                ))
            }
        }
    }
    if sim {
        if data.is_some() || diagnose {
            return Err("eval pdr: --sim/--seeds and --data/--diagnose exclude each other".into());
        }
        return Ok(EvalPdr::Sim { seeds });
    }
    let data = match data {
        Some(d) => d,
        None => stridekit_formats::data_dir()
            .map(|d| d.join("phone-indoor"))
            .ok_or(
                "real indoor walks not found: pass --data DIR or set STRIDEKIT_DATA (or use --sim)",
            )?,
    };
    Ok(EvalPdr::Real { data, diagnose })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        None | Some("demo") => {
            let out = flag(&args, "--out").unwrap_or_else(|| "report".into());
            let seed = flag(&args, "--seed")
                .and_then(|s| s.parse().ok())
                .unwrap_or(1);
            demo::run(&PathBuf::from(out), seed)
        }
        Some("pace") => match args.get(1) {
            Some(file) => match unknown_flags(&args[2..], &["--mode"], &[]) {
                Some(e) => Err(e),
                None => {
                    let config = match flag(&args, "--mode").as_deref() {
                        None | Some("default") => Ok(PaceConfig::default()),
                        Some("published") => Ok(PaceConfig::as_published()),
                        Some(m) => Err(format!("unknown mode {m} (default|published)")),
                    };
                    config.and_then(|c| replay::run(&PathBuf::from(file), c))
                }
            },
            None => Err("pace needs a FILE".into()),
        },
        Some("steps") => match args.get(1) {
            Some(file) if !file.starts_with("--") => {
                match unknown_flags(&args[2..], &["--out"], &[]) {
                    Some(e) => Err(e),
                    None => steps::run(&steps::StepsArgs {
                        file: PathBuf::from(file),
                        out: flag(&args, "--out").map(PathBuf::from),
                    }),
                }
            }
            _ => Err("steps needs a FILE (an Oxford trace folder or accelerometer.csv)".into()),
        },
        Some("eval") if args.get(1).map(String::as_str) == Some("pace") => {
            let seeds = flag(&args, "--seeds")
                .and_then(|s| s.parse().ok())
                .unwrap_or(10);
            let mut default = PaceConfig::default();
            for kv in args.windows(2).filter(|w| w[0] == "--set").map(|w| &w[1]) {
                let parsed = kv
                    .split_once('=')
                    .and_then(|(k, v)| v.parse::<f64>().ok().map(|v| (k, v)));
                let Some((k, v)) = parsed else {
                    eprintln!("error: --set takes NAME=NUMBER, got {kv}");
                    return ExitCode::FAILURE;
                };
                if let Err(e) = default.adaptive.set(k, v).and_then(|_| default.validate()) {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            }
            let (table, _) = eval_pace::simulator_table(seeds, default);
            println!("{table}");
            let dir = flag(&args, "--data")
                .map(PathBuf::from)
                .or_else(|| stridekit_formats::data_dir().map(|d| d.join("pace/original")));
            match dir {
                Some(d) if d.is_dir() => {
                    eval_pace::real_table(&d, default).map(|t| println!("{t}"))
                }
                _ => {
                    println!("Real runs: skipped (../shared/data/pace/original not found; pass --data DIR or set STRIDEKIT_DATA)");
                    Ok(())
                }
            }
        }
        Some("foot") => match args.get(1) {
            Some(file) if !file.starts_with("--") => {
                check_flags(&args, 2, &["--out", "--labels", "--axes", "--imu"], &[])
                    .and_then(|()| {
                        let imu = flag(&args, "--imu")
                            .map(|s| foot::ImuProfile::parse(&s))
                            .transpose()?;
                        foot::run(&foot::FootArgs {
                            file: PathBuf::from(file),
                            out: PathBuf::from(
                                flag(&args, "--out")
                                    .unwrap_or_else(|| "foot_trajectory.csv".into()),
                            ),
                            labels: flag(&args, "--labels"),
                            axes: flag(&args, "--axes"),
                            imu,
                        })
                    })
            }
            _ => Err("foot needs a FILE first: stridekit foot FILE.csv [--out traj.csv] [--labels NAME] [--axes SPEC] [--imu consumer|calibrated]".into()),
        },
        Some("eval") if args.get(1).map(String::as_str) == Some("foot") => {
            if let Err(e) = check_flags(
                &args,
                2,
                &["--data"],
                &["--tune", "--tune-adaptive-shoe", "--diagnose"],
            ) {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
            let dir = flag(&args, "--data")
                .map(PathBuf::from)
                .or_else(|| stridekit_formats::data_dir().map(|d| d.join("foot/pyshoe-vicon")));
            match dir {
                Some(d) if d.is_dir() => if args.iter().any(|a| a == "--diagnose") {
                    eval_foot_diagnose::run(&d)
                } else if args.iter().any(|a| a == "--tune-adaptive-shoe") {
                    eval_foot_tune_shoe::run(&d)
                } else if args.iter().any(|a| a == "--tune") {
                    eval_foot::tune(&d, &[0.025, 0.05, 0.1])
                } else {
                    eval_foot::run(&d)
                }
                .map(|t| println!("{t}")),
                _ => Err("foot trials not found: pass --data DIR or set STRIDEKIT_DATA".into()),
            }
        }
        Some("train") if args.get(1).map(String::as_str) == Some("zupt") => {
            if let Err(e) = check_flags(&args, 2, &["--data", "--trials", "--split", "--out"], &[]) {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
            let dir = flag(&args, "--data")
                .map(PathBuf::from)
                .or_else(|| stridekit_formats::data_dir().map(|d| d.join("foot/pyshoe-vicon")));
            let out = flag(&args, "--out").unwrap_or_else(|| "zupt_svm_v1.txt".into());
            let line = format!("stridekit {}", args.join(" "));
            match dir {
                Some(d) if d.is_dir() => train_zupt::run(
                    &d,
                    flag(&args, "--trials").as_deref(),
                    flag(&args, "--split").as_deref(),
                    &PathBuf::from(out),
                    &line,
                )
                .map(|t| println!("{t}")),
                _ => Err("foot trials not found: pass --data DIR or set STRIDEKIT_DATA".into()),
            }
        }
        Some("train" | "eval") if args.get(1).map(String::as_str) == Some("placement") => {
            let dir = flag(&args, "--data")
                .map(PathBuf::from)
                .or_else(|| stridekit_formats::data_dir().map(|d| d.join("steps/oxford")));
            match dir {
                Some(d) if d.is_dir() => if args[0] == "train" {
                    let out = flag(&args, "--out").unwrap_or_else(|| "placement_lr_v1.txt".into());
                    let line = format!("stridekit {}", args.join(" "));
                    placement::train_cmd(&d, &PathBuf::from(out), &line)
                } else {
                    placement::eval_cmd(
                        &d,
                        flag(&args, "--drop").as_deref(),
                        flag(&args, "--l2").and_then(|v| v.parse().ok()),
                        args.iter().any(|a| a == "--mlp"),
                    )
                }
                .map(|t| println!("{t}")),
                _ => Err("Oxford traces not found: pass --data DIR or set STRIDEKIT_DATA".into()),
            }
        }
        Some("eval") if args.get(1).map(String::as_str) == Some("pdr") => eval_pdr_args(&args[2..])
            .and_then(|a| match a {
                EvalPdr::Sim { seeds } => eval_pdr::report(seeds).map(|t| println!("{t}")),
                EvalPdr::Real { data, diagnose } => {
                    eval_pdr_real::run(&data, diagnose).map(|t| println!("{t}"))
                }
            }),
        Some("eval") if args.get(1).map(String::as_str) == Some("steplength") => {
            let dir = flag(&args, "--data").map(PathBuf::from);
            eval_steplength::report(dir.as_deref()).map(|t| println!("{t}"))
        }
        Some("eval") if args.get(1).map(String::as_str) == Some("steps") => {
            let dir = flag(&args, "--data")
                .map(PathBuf::from)
                .or_else(|| stridekit_formats::data_dir().map(|d| d.join("steps/oxford")));
            match dir {
                Some(d) if d.is_dir() => eval_steps::run(&d).and_then(|t| {
                    println!("{t}");
                    if args.iter().any(|a| a == "--sensitivity") {
                        println!("{}", eval_steps::robustness(&d)?);
                    }
                    Ok(())
                }),
                _ => Err("Oxford traces not found: pass --data DIR or set STRIDEKIT_DATA".into()),
            }
        }
        Some("train") if args.get(1).map(String::as_str) == Some("odometry") => {
            let out = flag(&args, "--out").unwrap_or_else(|| "odometry_v1.txt".into());
            let line = format!("stridekit {}", args.join(" "));
            let ridi = flag(&args, "--ridi").map(PathBuf::from);
            let ronin = flag(&args, "--ronin").map(PathBuf::from);
            let src = match (&ridi, &ronin) {
                (Some(d), _) => odometry::TrainSource::Ridi(d),
                (_, Some(d)) => odometry::TrainSource::Ronin(d),
                _ => odometry::TrainSource::Sim {
                    seeds: flag(&args, "--sim-seeds")
                        .and_then(|s| s.parse().ok())
                        .unwrap_or(8),
                },
            };
            let mut params = stridekit_core::odometry::PipelineParams::default();
            if let Some(w) = flag(&args, "--window").and_then(|s| s.parse().ok()) {
                params.window = w;
            }
            if let Some(l) = flag(&args, "--lambda").and_then(|s| s.parse().ok()) {
                params.lambda = l;
            }
            odometry::train(src, params, &PathBuf::from(out), &line).map(|t| println!("{t}"))
        }
        Some("eval") if args.get(1).map(String::as_str) == Some("odometry") => {
            let seeds = flag(&args, "--seeds")
                .and_then(|s| s.parse().ok())
                .unwrap_or(5);
            let model = flag(&args, "--model").map(PathBuf::from);
            let known = !args.iter().any(|a| a == "--unknown-placement");
            odometry::eval(model.as_deref(), seeds, known).map(|t| println!("{t}"))
        }
        Some("odometry") => match args.get(1) {
            Some(file) => {
                let model = flag(&args, "--model").map(PathBuf::from);
                let out = flag(&args, "--out").unwrap_or_else(|| "odometry.svg".into());
                odometry::replay(file, model.as_deref(), &PathBuf::from(out))
                    .map(|t| println!("{t}"))
            }
            None => Err("odometry needs a FILE".into()),
        },
        Some("pdr") => pdr::PdrArgs::parse(&args[1..])
            .and_then(|a| pdr::run(&a))
            .map(|t| print!("{t}")),
        Some("calibrate") if args.get(1).map(String::as_str) == Some("pdr") => {
            let line = format!("stridekit {}", args.join(" "));
            calibrate_pdr::CalibrateArgs::parse(&args[2..])
                .and_then(|a| calibrate_pdr::run(&a, &line))
                .map(|t| print!("{t}"))
        }
        Some("orientation") => match args.get(1) {
            Some(file) if !file.starts_with("--") => {
                check_flags(&args, 2, &["--out"], &["--imu-only"]).and_then(|_| {
                    orientation::run(&orientation::OrientationArgs {
                        file: PathBuf::from(file),
                        out: PathBuf::from(
                            flag(&args, "--out").unwrap_or_else(|| "orientation.csv".into()),
                        ),
                        imu_only: args.iter().any(|a| a == "--imu-only"),
                    })
                })
            }
            _ => Err("orientation needs a FILE".into()),
        },
        Some("eval") if args.get(1).map(String::as_str) == Some("orientation") => {
            check_flags(&args, 2, &["--data", "--set"], &["--imu-only", "--quick"]).and_then(|_| {
                let mut set = Vec::new();
                for kv in args.windows(2).filter(|w| w[0] == "--set").map(|w| &w[1]) {
                    match kv
                        .split_once('=')
                        .and_then(|(k, v)| v.parse::<f64>().ok().map(|v| (k.to_string(), v)))
                    {
                        Some(p) => set.push(p),
                        None => return Err(format!("--set takes NAME=NUMBER, got {kv}")),
                    }
                }
                let dir = flag(&args, "--data")
                    .map(PathBuf::from)
                    .or_else(|| stridekit_formats::data_dir().map(|d| d.join("orientation/broad")));
                match dir {
                    Some(d) if d.is_dir() => {
                        eval_orientation::run(&eval_orientation::EvalOrientationArgs {
                            data: d,
                            imu_only: args.iter().any(|a| a == "--imu-only"),
                            set,
                            quick: args.iter().any(|a| a == "--quick"),
                        })
                        .map(|t| println!("{t}"))
                    }
                    _ => {
                        Err("BROAD trials not found: pass --data DIR or set STRIDEKIT_DATA".into())
                    }
                }
            })
        }
        Some("soak") => soak::cmd(&args[1..]),
        Some("help" | "--help" | "-h") => {
            print!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(format!("unknown command {other}\n\n{USAGE}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
