//! `stridekit train …`: the trainers of the shipped models.

use std::path::PathBuf;

use clap::{ArgGroup, Subcommand};

use super::{at_least_one, command_line, data_dir, non_negative};
use crate::outcome::{usage, Failure};
use crate::output::OutFile;

#[derive(Debug, Subcommand)]
pub enum Train {
    /// Train the SVM zero-velocity detector of the foot navigator.
    ///
    /// Train the SVM zero-velocity detector (six Gaussian-kernel SVMs) on the foot
    /// trials and write a model file (format v1, see core/src/foot/svm.rs).
    #[command(group(ArgGroup::new("subset").args(["trials", "split"])))]
    Zupt {
        /// The trials (default: the shared foot/pyshoe-vicon folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// Train on these trials only (comma-separated names).
        #[arg(long, value_name = "A,B,...")]
        trials: Option<String>,
        /// Leave out fold K of N (by position modulo N).
        #[arg(long, value_name = "K/N", value_parser = split_spec)]
        split: Option<String>,
        /// The model file to write.
        #[arg(long, value_name = "FILE", default_value = "zupt_svm_v1.txt")]
        out: PathBuf,
    },
    /// Train the phone-placement classifier.
    ///
    /// Train the phone-placement classifier (logistic regression) on every Oxford Step
    /// Counter trace and write a model file (format in core/src/placement/model.rs).
    Placement {
        /// Oxford traces (default: the shared steps/oxford folder).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// The model file to write.
        #[arg(long, value_name = "FILE", default_value = "placement_lr_v1.txt")]
        out: PathBuf,
    },
    /// Train the learned phone odometry.
    ///
    /// Fit the learned phone odometry (a velocity regressor per placement and a general
    /// one) on simulated walks, RIDI sequences, RoNIN CSV exports or real indoor walks
    /// with surveyed waypoints (Android sensor logs); write a model file (format v2, see
    /// core/src/odometry/model.rs). The shipped model: `--android
    /// ../shared/data/phone-indoor --out core/models/odometry_v1.txt`.
    #[command(group(ArgGroup::new("source").args(["sim_seeds", "ridi", "ronin", "android"])))]
    Odometry {
        /// Simulated walks per placement (the default source, 8 walks).
        #[arg(long, value_name = "N")]
        sim_seeds: Option<u64>,
        /// RIDI sequences in DIR.
        #[arg(long, value_name = "DIR")]
        ridi: Option<PathBuf>,
        /// RoNIN CSV exports in DIR.
        #[arg(long, value_name = "DIR")]
        ronin: Option<PathBuf>,
        /// Android sensor logs with surveyed waypoints in DIR (e.g.
        /// ../shared/data/phone-indoor, which trained the shipped model): trains the
        /// general and in_hand regressors on every walk, and measures the model on them
        /// (fitted) and leave one floor out; both figures go into the model's comments.
        #[arg(long, value_name = "DIR")]
        android: Option<PathBuf>,
        /// The model file to write.
        #[arg(long, value_name = "FILE", default_value = "odometry_v1.txt")]
        out: PathBuf,
        /// Feature window, samples.
        #[arg(long, value_name = "SAMPLES", value_parser = at_least_one)]
        window: Option<usize>,
        /// Ridge penalty.
        #[arg(long, value_name = "L", value_parser = non_negative)]
        lambda: Option<f64>,
    },
}

/// `--split K/N` (checked by clap: exit 2).
fn split_spec(s: &str) -> Result<String, String> {
    stridekit_lab::foot::train_zupt::parse_split(s)?;
    Ok(s.to_string())
}

/// `--trials`: every name is a trial of `dir` (a bad name exits 2).
fn check_trials(dir: &std::path::Path, list: &str) -> Result<(), Failure> {
    let have: Vec<String> = stridekit_formats::list_foot_trials(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .iter()
        .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    let missing: Vec<&str> = list
        .split(',')
        .map(str::trim)
        .filter(|n| !have.iter().any(|h| h == n))
        .collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(usage(
            "--trials",
            format!("no trial {} in {}", missing.join(", "), dir.display()),
        ))
    }
}

pub fn run(t: Train) -> Result<(), Failure> {
    let text = match t {
        Train::Zupt {
            data,
            trials,
            split,
            out,
        } => {
            let d = data_dir(data, "foot/pyshoe-vicon", "foot trials")?;
            if let Some(list) = &trials {
                check_trials(&d, list)?;
            }
            let out = OutFile::prepare(&out, "txt")?;
            stridekit_lab::foot::train_zupt::run(
                &d,
                trials.as_deref(),
                split.as_deref(),
                &out.path,
                &command_line(),
            )?
        }
        Train::Placement { data, out } => {
            let d = data_dir(data, "steps/oxford", "Oxford traces")?;
            let out = OutFile::prepare(&out, "txt")?;
            stridekit_lab::placement_eval::train_cmd(&d, &out.path, &command_line())?
        }
        Train::Odometry {
            sim_seeds,
            ridi,
            ronin,
            android,
            out,
            window,
            lambda,
        } => {
            let src = match (&ridi, &ronin) {
                (Some(d), _) => stridekit_lab::odometry::commands::TrainSource::Ridi(d),
                (_, Some(d)) => stridekit_lab::odometry::commands::TrainSource::Ronin(d),
                _ => stridekit_lab::odometry::commands::TrainSource::Sim {
                    seeds: sim_seeds.unwrap_or(8),
                },
            };
            let mut params = stridekit_core::odometry::PipelineParams::default();
            if let Some(w) = window {
                params.window = w;
            }
            if let Some(l) = lambda {
                params.lambda = l;
            }
            let out = OutFile::prepare(&out, "txt")?;
            match android {
                Some(dir) => stridekit_lab::pdr::odometry::train_command(
                    &dir,
                    params,
                    &out.path,
                    &command_line(),
                )?,
                None => stridekit_lab::odometry::commands::train(
                    src,
                    params,
                    &out.path,
                    &command_line(),
                )?,
            }
        }
    };
    println!("{text}");
    Ok(())
}
