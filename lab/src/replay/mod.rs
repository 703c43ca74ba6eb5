//! The replays behind `stridekit pace|steps|foot|pdr|orientation` and `calibrate foot`:
//! each module reads its recording (`read`), replays it into a result struct
//! (`replay`), and renders apart (`write_csv`, `chart`, `summary`). The CLI opens the
//! outputs, prints, and turns [`ReplayError`] and [`Usable`] into exit codes.

pub mod basis;
pub mod foot;
pub mod foot_calibrate;
pub mod foot_config;
pub mod input;
pub mod map;
pub mod orientation;
pub mod pace;
pub mod pdr;
pub mod steps;

use crate::rejected::Rejected;

/// Why a replay did not run.
#[derive(Debug, PartialEq, Eq)]
pub enum ReplayError {
    /// Unreadable input or a failed replay (the CLI exits 1).
    Failed(String),
    /// A flag's value the replay cannot use, e.g. an unreadable `--calibration` file
    /// (the CLI exits 2, as for clap's own checks).
    Usage { flag: &'static str, why: String },
}

impl From<String> for ReplayError {
    fn from(message: String) -> Self {
        ReplayError::Failed(message)
    }
}

impl From<&str> for ReplayError {
    fn from(message: &str) -> Self {
        ReplayError::Failed(message.to_string())
    }
}

/// What a replay produced, for the exit status: whether it gave a result (`what`
/// says what is missing when not), and the samples refused per stream.
pub struct Usable<'a> {
    pub produced: bool,
    pub what: &'a str,
    pub rejected: &'a Rejected,
    /// (stream name as [`Rejected`] names it, samples pushed).
    pub streams: Vec<(&'a str, u64)>,
}

/// The file name of `path`, for titles and summaries.
pub fn display_name(path: &std::path::Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
