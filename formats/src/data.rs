//! Where the shared real recordings live.

use std::path::PathBuf;

/// Environment variable that overrides the location of the shared data folder.
pub const DATA_ENV_VAR: &str = "STRIDEKIT_DATA";

/// The shared real-data folder (the one holding `pace/`, `steps/`, `foot/`): the
/// `STRIDEKIT_DATA` environment variable if set, else `../shared/data` relative to the
/// workspace root. Returns `None` when that folder does not exist, e.g. in a fresh clone;
/// tests and benchmarks then skip with a message.
pub fn data_dir() -> Option<PathBuf> {
    let dir = match std::env::var_os(DATA_ENV_VAR) {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"),
    };
    if !dir.is_dir() {
        return None;
    }
    Some(dir.canonicalize().unwrap_or(dir))
}
