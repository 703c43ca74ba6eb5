//! `stridekit`: the command-line tool of the stridekit SDK.

mod activity;
mod demo;
mod eval_foot;
mod eval_orientation;
mod eval_pace;
mod eval_pdr;
mod eval_steplength;
mod eval_steps;
mod foot;
mod odometry;
mod orientation;
mod orientation_metric;
mod placement;
mod placement_mlp;
mod replay;
mod report;
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
  stridekit eval pace [--data DIR] [--seeds N] [--set NAME=VALUE ...]
      Speed RMSE of raw GNSS, GNSS EMA, AsPublished and default on N simulated runs
      (default 10) and on the real runs in DIR (default: ../shared/data/pace/original)
      with injected GNSS degradation. Prints markdown tables. --set changes a
      parameter of the default filter (see AdaptiveParams) for sensitivity checks.
  stridekit eval steps [--data DIR] [--sensitivity]
      Step counting of the AsPublished and default detectors on the Oxford Step
      Counter traces in DIR (default: ../shared/data/steps/oxford): count error and
      step-event F1 per trace and per placement, also at 50 Hz and with jitter.
      --sensitivity adds parameter sensitivity and a leave-one-user-out check.
  stridekit eval pdr [--seeds N]
      Pedestrian dead reckoning on the phone simulator, every placement: step count,
      distance and end-point error after a 10-minute GNSS outage (default 3 seeds).
  stridekit eval steplength [--data DIR]
      Step-length models (constant, linear robust and as published, frequency-only,
      Weinberg): distance error over a 5-minute GNSS outage after calibration, on the
      phone simulator and on the real runs in DIR (default: ../shared/data/pace/original).
  stridekit foot FILE.csv [--out traj.csv] [--labels NAME]
      Replay a foot-mounted IMU recording (pyshoe CSV: x fwd, y right, z down)
      through the foot navigator; write the trajectory CSV (default
      foot_trajectory.csv) and, next to it, traj.svg (top view) and traj_height.svg
      (height over time). With truth columns (gt_*), the truth is aligned to the
      estimate (rotation about the vertical + translation), written beside it in the
      CSV, drawn in both plots and its position RMSE printed. --labels drives the
      zero-velocity updates with a stance label column (e.g. vicon_opt) instead of
      the detector.
  stridekit eval foot [--data DIR] [--tune]
      Foot-mounted navigation on the pyshoe VICON trials in DIR (default:
      ../shared/data/foot/pyshoe-vicon): position RMSE, loop closure and zero-velocity
      agreement per trial and per gait for the fixed, adaptive, SVM (cross-validated
      over trials) and SHOE detectors and the oracle labels. --tune prints the grid
      searches on the training split that chose the detector defaults.
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
  stridekit help
";

fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

/// Refuses flags a command does not know (`takes_value`: flags followed by a value).
fn check_flags(
    args: &[String],
    from: usize,
    takes_value: &[&str],
    switches: &[&str],
) -> Result<(), String> {
    let mut i = from;
    while i < args.len() {
        let a = args[i].as_str();
        if takes_value.contains(&a) {
            if i + 1 >= args.len() {
                return Err(format!("{a} needs a value"));
            }
            i += 2;
        } else if switches.contains(&a) {
            i += 1;
        } else {
            return Err(format!(
                "unknown argument {a} (expected {})",
                takes_value
                    .iter()
                    .chain(switches)
                    .copied()
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    Ok(())
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
            Some(file) => {
                let config = match flag(&args, "--mode").as_deref() {
                    None | Some("default") => Ok(PaceConfig::default()),
                    Some("published") => Ok(PaceConfig::as_published()),
                    Some(m) => Err(format!("unknown mode {m} (default|published)")),
                };
                config.and_then(|c| replay::run(&PathBuf::from(file), c))
            }
            None => Err("pace needs a FILE".into()),
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
            Some(file) => {
                let out = flag(&args, "--out").unwrap_or_else(|| "foot_trajectory.csv".into());
                foot::run(
                    &PathBuf::from(file),
                    &PathBuf::from(out),
                    eval_foot::base_config(),
                    flag(&args, "--labels"),
                )
            }
            None => Err("foot needs a FILE".into()),
        },
        Some("eval") if args.get(1).map(String::as_str) == Some("foot") => {
            let dir = flag(&args, "--data")
                .map(PathBuf::from)
                .or_else(|| stridekit_formats::data_dir().map(|d| d.join("foot/pyshoe-vicon")));
            match dir {
                Some(d) if d.is_dir() => if args.iter().any(|a| a == "--tune") {
                    eval_foot::tune(&d, &[0.025, 0.05, 0.1])
                } else {
                    eval_foot::run(&d)
                }
                .map(|t| println!("{t}")),
                _ => Err("foot trials not found: pass --data DIR or set STRIDEKIT_DATA".into()),
            }
        }
        Some("train") if args.get(1).map(String::as_str) == Some("zupt") => {
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
        Some("eval") if args.get(1).map(String::as_str) == Some("pdr") => {
            let seeds = flag(&args, "--seeds")
                .and_then(|s| s.parse().ok())
                .unwrap_or(3);
            eval_pdr::report(seeds).map(|t| println!("{t}"))
        }
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
