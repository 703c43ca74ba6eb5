//! `stridekit demo`: its arguments and its run (the simulation and the report:
//! `stridekit_lab::demo`).

use std::path::PathBuf;

use clap::Args;
use stridekit_lab::demo::Demo;

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

/// Simulate, print the summary, write the report into `--out` (created).
pub fn run(a: DemoArgs) -> Result<(), String> {
    let d = Demo::simulate(a.seed);
    let summary = d.summary();
    print!("{}", summary.text);
    std::fs::create_dir_all(&a.out)
        .map_err(|e| format!("cannot create {}: {e}", a.out.display()))?;
    let shown = d.write_report(&a.out, &summary)?;
    println!(
        "\nReport written to {}/ (index.html, summary.md, {})",
        a.out.display(),
        shown.join(", ")
    );
    Ok(())
}
