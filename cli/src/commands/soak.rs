//! `stridekit soak`.

use clap::Args;

/// Hours of simulated sensor data through every engine with snapshot/restore.
///
/// Soak test (a command, not CI): H simulated hours of 200 Hz phone IMU with 1 Hz GNSS
/// and of 200 Hz foot-mounted IMU through every engine, each twice: unsplit, and
/// restored from its own snapshot every simulated minute. Outputs must match bit for
/// bit and be finite; prints RSS every simulated hour, then run time, peak memory,
/// RSS growth after hour 1 and per-engine counts. Exits 1 on any mismatch,
/// non-finite output or memory growth.
#[derive(Debug, Args)]
pub struct SoakArgs {
    /// Simulated hours, in (0, 1000].
    #[arg(long, value_name = "H", default_value_t = 24.0, value_parser = hours)]
    pub hours: f64,
    /// Seed of the simulated sessions.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
}

fn hours(s: &str) -> Result<f64, String> {
    let h: f64 = s.parse().map_err(|_| format!("{s} is not a number"))?;
    if h.is_finite() && h > 0.0 && h <= 1000.0 {
        Ok(h)
    } else {
        Err(format!("{s} is not in (0, 1000] hours"))
    }
}

pub fn run(a: SoakArgs) -> Result<(), String> {
    stridekit_lab::soak::cmd(&stridekit_lab::soak::SoakArgs {
        hours: a.hours,
        seed: a.seed,
    })
}
