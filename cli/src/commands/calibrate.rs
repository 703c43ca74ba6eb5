//! `stridekit calibrate …`.

use std::path::{Path, PathBuf};

use clap::{Subcommand, ValueEnum};
use stridekit_core::steplength::StepLengthModel;
use stridekit_lab::replay::foot_calibrate;
use stridekit_lab::replay::foot_config::{FootImu, FootOptions};

use crate::outcome::Failure;
use crate::output::OutFile;

#[derive(Debug, Subcommand)]
pub enum Calibrate {
    /// Learn a personal PDR calibration from walks with waypoints.
    ///
    /// Learn the personal PDR calibration (step-length model, how the phone is
    /// carried) from walks with waypoints and write it (versioned text, format in
    /// core/src/pdr/calibration.rs); load it with `stridekit pdr --calibration FILE`.
    Pdr {
        /// Folder of Android sensor logs with waypoints (default: the shared
        /// phone-indoor walks).
        #[arg(long, value_name = "DIR")]
        data: Option<PathBuf>,
        /// The calibration file to write.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
        /// Step-length model to learn (the navigator's default: pendulum).
        #[arg(long, value_enum, default_value_t = Model::Pendulum)]
        model: Model,
    },
    /// Learn a foot IMU's accelerometer alignment from level walks.
    ///
    /// Learn the rotation of a foot IMU's accelerometer axes against its gyroscope's
    /// (a device calibration: a degree of it makes the height climb at every stride)
    /// from one or more walks on level ground, each starting at rest, and write it
    /// (versioned text); load it with `stridekit foot FILE --calibration FILE` or set
    /// `FootConfig::accel_alignment_rad`. The walks must be level: the fit makes every
    /// stance as high as the one before.
    Foot {
        /// Level walks with the IMU (pyshoe / UofT CSV or x-io NGIMU CSV).
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// The calibration file to write.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
        /// Sensor axes spec, as for `stridekit foot`.
        #[arg(long, value_name = "SPEC", value_parser = super::foot::axes_spec)]
        axes: Option<String>,
        /// The IMU profile, as for `stridekit foot`.
        #[arg(long, value_enum)]
        imu: Option<super::foot::Imu>,
    },
}

/// Step-length models on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Model {
    Pendulum,
    Weinberg,
    Linear,
    LinearF,
    Constant,
}

impl From<Model> for StepLengthModel {
    fn from(m: Model) -> Self {
        let name = match m {
            Model::Pendulum => "pendulum",
            Model::Weinberg => "weinberg",
            Model::Linear => "linear",
            Model::LinearF => "linear-f",
            Model::Constant => "constant",
        };
        stridekit_lab::pdr::calibrate::model_from_arg(name)
            .expect("every ValueEnum name is a model")
    }
}

pub fn run(c: Calibrate) -> Result<(), Failure> {
    match c {
        Calibrate::Foot {
            files,
            out,
            axes,
            imu,
        } => {
            let options = FootOptions {
                axes,
                imu: imu.map(FootImu::from),
                ..Default::default()
            };
            calibrate_foot(&files, &out, &options)
        }
        Calibrate::Pdr { data, out, model } => {
            let data = super::data_dir(data, "phone-indoor", "walks with waypoints")?;
            let out = OutFile::prepare(&out, "")?;
            let text = stridekit_lab::pdr::calibrate::run(
                &stridekit_lab::pdr::calibrate::CalibrateArgs {
                    data,
                    out: out.path.clone(),
                    model: model.into(),
                },
                &super::command_line(),
            )?;
            print!("{text}");
            if out.existed {
                eprintln!("(replaced the previous {})", out.path.display());
            }
            Ok(())
        }
    }
}

/// `calibrate foot`: learn the alignment, write the calibration file and the stance
/// plot beside it, print the report.
fn calibrate_foot(files: &[PathBuf], out: &Path, options: &FootOptions) -> Result<(), Failure> {
    let out = OutFile::prepare(out, "")?;
    let cal = foot_calibrate::learn(files, options)?;
    std::fs::write(&out.path, cal.text()).map_err(|e| format!("{}: {e}", out.path.display()))?;
    let svg = out.path.with_extension("svg");
    cal.plot(&svg)?;
    print!("{}", cal.report(&svg));
    eprintln!("{}", out.wrote());
    Ok(())
}
