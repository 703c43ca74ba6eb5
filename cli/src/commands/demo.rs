//! `stridekit demo`.

use std::path::PathBuf;

use clap::Args;

/// Simulate a run and write a report with plots (start here).
///
/// Simulate a 40-minute run with GNSS disturbances, outages and stops; print a summary
/// and write a report (index.html with SVG plots) into DIR.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Folder of the report (created when missing).
    #[arg(long, value_name = "DIR", default_value = "report")]
    pub out: PathBuf,
    /// Seed of the simulated run.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
}

pub fn run(a: DemoArgs) -> Result<(), String> {
    crate::demo::run(&a.out, a.seed)
}
