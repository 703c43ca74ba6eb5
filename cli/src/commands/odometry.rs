//! `stridekit odometry INPUT`: its arguments and its run (the replay and its
//! report: `stridekit_lab::odometry::commands::replay`). Writes an SVG of the
//! trajectories; `--out -` is refused (exit 2).

use std::path::{Path, PathBuf};

use clap::Args;

use super::EXIT_CODES;
use crate::outcome::{usage, Failure};
use crate::output::OutFile;

/// Replay a recording through the learned phone odometry.
///
/// Replay a recording (RIDI sequence, RIDI data.csv, RoNIN CSV export, or a simulator
/// walk `sim:SEED:PLACEMENT`) through the learned odometry and the baselines; print
/// ATE / RTE and write an SVG of the trajectories against the truth.
#[derive(Debug, Args)]
#[command(after_help = EXIT_CODES)]
pub struct OdometryArgs {
    /// FILE, DIR or sim:SEED:PLACEMENT.
    #[arg(value_parser = odometry_input)]
    pub input: String,
    /// A model file (default: the shipped model).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// The SVG to write.
    #[arg(long, value_name = "FILE", default_value = "odometry.svg")]
    pub out: PathBuf,
}

/// `sim:SEED:PLACEMENT` is checked by clap (exit 2); a path is read later.
fn odometry_input(s: &str) -> Result<String, String> {
    if let Some(spec) = s.strip_prefix("sim:") {
        stridekit_lab::odometry::commands::parse_sim_spec(spec)?;
    }
    Ok(s.to_string())
}

pub fn run(a: OdometryArgs) -> Result<(), Failure> {
    if a.out == Path::new("-") {
        return Err(usage("--out", "odometry writes an SVG: give a file name"));
    }
    let out = OutFile::prepare(&a.out, "svg")?;
    if !a.input.starts_with("sim:") {
        stridekit_formats::check_file(Path::new(&a.input))
            .or_else(|e| match e {
                stridekit_formats::FormatError::Folder => Ok(()),
                other => Err(other),
            })
            .map_err(|e| {
                stridekit_lab::replay::input::read_error(Path::new(&a.input), e, "a recording")
            })?;
    }
    let text = stridekit_lab::odometry::commands::replay(&a.input, a.model.as_deref(), &out.path)?;
    println!("{text}");
    Ok(())
}
