//! `stridekit eval …`: accuracy of the engines on the shared data sets and the
//! simulators, printed as markdown tables.

use std::path::PathBuf;

use clap::{ArgGroup, Subcommand};
use stridekit_core::PaceConfig;

use super::{data_dir, name_value, orientation_setting, pace_setting, positive};
use crate::outcome::Failure;

#[derive(Debug, Subcommand)]
pub enum Eval {
    /// Pace: speed RMSE on simulated and real runs.
    ///
    /// Speed RMSE of raw GNSS, GNSS EMA, AsPublished and the default on simulated runs
    /// and on the real runs with injected GNSS degradation.
    Pace {
        /// Real runs (default: the shared pace/original folder; skipped when absent).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Simulated runs.
        #[arg(long, value_name = "N", default_value_t = 10)]
        seeds: u64,
        /// Change a parameter of the default filter (AdaptiveParams names), for
        /// sensitivity checks; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = pace_setting)]
        set: Vec<(String, f64)>,
    },
    /// Step counting on the Oxford Step Counter traces.
    ///
    /// Step counting of the AsPublished and default detectors on the Oxford Step
    /// Counter traces: count error and step-event F1 per trace and placement, also at
    /// 100 and 50 Hz, with jitter, drops and dropped bursts.
    Steps {
        /// Oxford traces (default: the shared steps/oxford folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Add parameter sensitivity and a leave-one-user-out check (slow).
        #[arg(long)]
        sensitivity: bool,
    },
    /// Dead reckoning on real indoor walks (or --sim).
    ///
    /// Pedestrian dead reckoning on real indoor walks with surveyed waypoints (ATE,
    /// start-pinned, end and distance error per floor and overall), or with --sim on
    /// the phone simulator.
    #[command(group(ArgGroup::new("real").args(["data", "diagnose", "maps", "map_set"]).multiple(true).conflicts_with("simulated")))]
    #[command(group(ArgGroup::new("simulated").args(["sim", "seeds"]).multiple(true)))]
    Pdr {
        /// Android sensor logs with waypoints (default: the shared phone-indoor walks).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Print where the error comes from instead.
        #[arg(long, conflicts_with = "maps")]
        diagnose: bool,
        /// Score on the floor plans instead (each walk's folder holds its plan): the
        /// map-frame error without a plan, with it (live and smoothed), with fixes
        /// made from waypoints every 30 s, and leave one floor out.
        #[arg(long)]
        maps: bool,
        /// With --maps: change a setting of the map engine (e.g. particles=500,
        /// heading_sigma_deg=20); repeatable.
        #[arg(long = "set", id = "map_set", value_name = "NAME=VALUE", value_parser = name_value, requires = "maps")]
        set: Vec<(String, f64)>,
        /// Evaluate on the phone simulator instead (every placement: GNSS outage and
        /// closed loop).
        #[arg(long)]
        sim: bool,
        /// Simulator seeds per placement (implies --sim).
        #[arg(long, value_name = "N")]
        seeds: Option<u64>,
    },
    /// Step-length models over a GNSS outage.
    ///
    /// Step-length models: distance error over a 5-minute GNSS outage after
    /// calibration, on the phone simulator and on the real runs.
    Steplength {
        /// Real runs (default: the shared pace/original folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
    },
    /// Foot-mounted navigation on the VICON trials.
    ///
    /// Foot-mounted navigation on the pyshoe VICON trials: position RMSE, loop closure
    /// and zero-velocity agreement per trial, gait and session for every detector.
    #[command(group(ArgGroup::new("mode").args(["tune", "tune_adaptive_shoe", "diagnose", "detector_gap"])))]
    Foot {
        /// The trials (default: the shared foot/pyshoe-vicon folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Print the grid searches on the training split that chose the defaults.
        #[arg(long)]
        tune: bool,
        /// Only the gyro-timing and adaptive-SHOE part of --tune.
        #[arg(long)]
        tune_adaptive_shoe: bool,
        /// Stride-length and height-per-stride errors against the truth.
        #[arg(long)]
        diagnose: bool,
        /// Where the default zero-velocity detector departs from the oracle labels,
        /// per trial, and what it costs (also on time-stretched copies).
        #[arg(long)]
        detector_gap: bool,
    },
    /// Phone-placement classifier, leave one user out.
    ///
    /// Phone-placement classifier, leave-one-user-out on the Oxford traces.
    Placement {
        /// Oxford traces (default: the shared steps/oxford folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Neutralise features (ablation; comma-separated names from
        /// core/src/placement/features.rs).
        #[arg(long, value_name = "NAME,NAME", value_parser = feature_names)]
        drop: Option<String>,
        /// Training penalty.
        #[arg(long, value_name = "X", value_parser = positive)]
        l2: Option<f64>,
        /// Add the same protocol for a small MLP (comparison only, not shipped).
        #[arg(long)]
        mlp: bool,
    },
    /// Learned odometry and baselines on simulated walks.
    ///
    /// ATE / RTE per placement of the learned odometry and the naive baselines on
    /// held-out simulated walks.
    Odometry {
        /// A model file (default: the shipped model).
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
        /// Walks per placement.
        #[arg(long, value_name = "N", default_value_t = 5)]
        seeds: u64,
        /// Let the pipeline detect the placement instead of telling it.
        #[arg(long)]
        unknown_placement: bool,
    },
    /// Orientation filters against optical motion capture (BROAD).
    ///
    /// Orientation filters against optical motion capture on the BROAD trials.
    Orientation {
        /// BROAD trials (default: the shared orientation/broad folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Without the magnetometer (inclination only).
        #[arg(long)]
        imu_only: bool,
        /// Change a setting of the default filter (DecoupledSettings names);
        /// repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = orientation_setting)]
        set: Vec<(String, f64)>,
        /// Score only the default filter.
        #[arg(long)]
        quick: bool,
    },
    /// Perturbed copies of the development recordings (the robustness bench).
    ///
    /// Replays every development recording of one engine under controlled, seeded
    /// perturbations (vibration, magnetometer offsets and drifts, gyroscope bias steps
    /// and scale errors, sample rate, jitter, dropped bursts, clipping, other walking
    /// speeds), each swept over a range, and prints per recording the error against the
    /// unperturbed one, a summary per perturbation and the worst 5 % of the cases.
    Perturb {
        /// Which engine to sweep.
        #[arg(long, value_enum)]
        engine: PerturbEngine,
        /// Its recordings (default: the engine's shared data folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// One level per kind of perturbation (the middle one).
        #[arg(long)]
        quick: bool,
    },
}

/// The engines `eval perturb` sweeps.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum PerturbEngine {
    /// The default AHRS on the BROAD trials.
    Orientation,
    /// The foot navigator on the VICON trials.
    Foot,
    /// The step detector on the Oxford traces.
    Steps,
    /// The phone navigator on the indoor walks.
    Pdr,
    /// The pace tracker on the real runs.
    Pace,
}

impl From<PerturbEngine> for stridekit_lab::perturb::Engine {
    fn from(e: PerturbEngine) -> Self {
        use stridekit_lab::perturb::Engine as E;
        match e {
            PerturbEngine::Orientation => E::Orientation,
            PerturbEngine::Foot => E::Foot,
            PerturbEngine::Steps => E::Steps,
            PerturbEngine::Pdr => E::Pdr,
            PerturbEngine::Pace => E::Pace,
        }
    }
}

/// `--drop`: comma-separated placement feature names (checked by clap: exit 2).
fn feature_names(s: &str) -> Result<String, String> {
    use stridekit_core::placement::FEATURE_NAMES;
    for n in s.split(',') {
        if !FEATURE_NAMES.contains(&n.trim()) {
            return Err(format!(
                "unknown feature {n:?}; features: {}",
                FEATURE_NAMES.join(" ")
            ));
        }
    }
    Ok(s.to_string())
}

pub fn run(e: Eval) -> Result<(), Failure> {
    let text = match e {
        Eval::Pace { data, seeds, set } => {
            let mut default = PaceConfig::default();
            for (k, v) in &set {
                default
                    .adaptive
                    .set(k, *v)
                    .and_then(|_| default.validate())
                    .map_err(|e| crate::outcome::usage("--set", e))?;
            }
            let (table, _) = stridekit_lab::pace_eval::simulator_table(seeds, default);
            println!("{table}");
            match data_dir(data, "pace/original", "real runs") {
                Ok(d) => stridekit_lab::pace_eval::real_runs(&d, default)?.render(),
                Err(why) => format!("Real runs: skipped ({why})"),
            }
        }
        Eval::Steps { data, sensitivity } => {
            let d = data_dir(data, "steps/oxford", "Oxford traces")?;
            let mut t = stridekit_lab::steps_eval::run(&d)?.render();
            if sensitivity {
                t.push('\n');
                t += &stridekit_lab::steps_eval::robustness(&d)?.render();
            }
            t
        }
        Eval::Pdr {
            data,
            diagnose,
            maps,
            set,
            sim,
            seeds,
        } => {
            if sim || seeds.is_some() {
                stridekit_lab::pdr::sim::report(seeds.unwrap_or(3))?
            } else {
                let d = data_dir(data, "phone-indoor", "real indoor walks (or use --sim)")?;
                if maps {
                    stridekit_lab::pdr::maps::run(&d, &set)?
                } else {
                    stridekit_lab::pdr::real::run(&d, diagnose)?
                }
            }
        }
        Eval::Steplength { data } => stridekit_lab::steplength_eval::report(data.as_deref())?,
        Eval::Foot {
            data,
            tune,
            tune_adaptive_shoe,
            diagnose,
            detector_gap,
        } => {
            let d = data_dir(data, "foot/pyshoe-vicon", "foot trials")?;
            if detector_gap {
                stridekit_lab::foot::detector_gap::run(&d)?
            } else if diagnose {
                stridekit_lab::foot::diagnose::run(&d)?
            } else if tune_adaptive_shoe {
                stridekit_lab::foot::tune_shoe::run(&d)?
            } else if tune {
                stridekit_lab::foot::eval::tune(&d, &[0.025, 0.05, 0.1])?.render()
            } else {
                stridekit_lab::foot::eval::eval(&d)?.render()
            }
        }
        Eval::Placement {
            data,
            drop,
            l2,
            mlp,
        } => {
            let d = data_dir(data, "steps/oxford", "Oxford traces")?;
            stridekit_lab::placement_eval::eval_cmd(&d, drop.as_deref(), l2, mlp)?
        }
        Eval::Odometry {
            model,
            seeds,
            unknown_placement,
        } => stridekit_lab::odometry::commands::eval(model.as_deref(), seeds, !unknown_placement)?
            .render(),
        Eval::Orientation {
            data,
            imu_only,
            set,
            quick,
        } => {
            let d = data_dir(data, "orientation/broad", "BROAD trials")?;
            stridekit_lab::orientation::eval::run(
                &stridekit_lab::orientation::eval::EvalOrientationArgs {
                    data: d,
                    imu_only,
                    set,
                    quick,
                },
            )?
        }
        Eval::Perturb {
            engine,
            data,
            quick,
        } => {
            let engine: stridekit_lab::perturb::Engine = engine.into();
            let d = data_dir(data, engine.data_folder(), "the engine's recordings")?;
            let report = stridekit_lab::perturb::run(&stridekit_lab::perturb::PerturbArgs {
                engine,
                data: d,
                quick,
            })?;
            stridekit_lab::perturb::render(&report)
        }
    };
    println!("{text}");
    Ok(())
}
