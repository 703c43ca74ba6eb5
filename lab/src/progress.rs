//! Progress on stderr for the commands that take more than a few seconds (indicatif:
//! drawn only when stderr is a terminal, so logs and pipes stay clean).

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar over `len` items, labelled `what`.
pub fn bar(len: usize, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(len as u64);
    if let Ok(style) = ProgressStyle::with_template(
        "{msg:>28} [{bar:30}] {pos}/{len} ({elapsed}, about {eta} left)",
    ) {
        pb.set_style(style.progress_chars("=> "));
    }
    pb.set_message(what.to_string());
    pb
}

/// A spinner for work without a count; set its message at each phase.
pub fn spinner(what: &str) -> ProgressBar {
    let pb = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
        pb.set_style(style);
    }
    pb.set_message(what.to_string());
    pb.enable_steady_tick(Duration::from_millis(120));
    pb
}
