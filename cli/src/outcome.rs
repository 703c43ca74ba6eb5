//! How a command ends, and its exit status: 0 a usable result (warnings may have been
//! printed), 1 a failure (the input could not be read, or the replay produced nothing
//! usable), 2 a bad flag or value; a closed output pipe ends quietly with 0.
//!
//! "Nothing usable" (exit 1) is: every sample refused, a stream refused for its units
//! (its samples refused as milliseconds, nanoseconds or g outnumber those accepted),
//! no step, no stride, no estimate. The message names each cause once.

use stridekit_lab::rejected::Rejected;
use stridekit_lab::replay::{ReplayError, Usable};

/// Exit status of a command that failed or produced nothing usable (a bad flag or
/// value exits with clap's 2).
pub const EXIT_FAILED: u8 = 1;

/// Why a command did not end with a usable result.
#[derive(Debug, PartialEq, Eq)]
pub enum Failure {
    /// The command failed: unreadable input, nothing usable, an output not written.
    Failed(String),
    /// A flag value the command cannot use (exit 2, as clap's own checks).
    Usage(String),
    /// The reader of stdout went away (`| head -1`): end quietly.
    ClosedPipe,
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Failure::Failed(message)
    }
}

impl From<&str> for Failure {
    fn from(message: &str) -> Self {
        Failure::Failed(message.to_string())
    }
}

/// A replay that did not run: a failure (exit 1), or a flag's value it cannot use
/// (exit 2).
impl From<ReplayError> for Failure {
    fn from(e: ReplayError) -> Self {
        match e {
            ReplayError::Failed(message) => Failure::Failed(message),
            ReplayError::Usage { flag, why } => usage(flag, why),
        }
    }
}

/// An I/O error of writing `what`: a closed pipe ends quietly, anything else fails.
pub fn write_error(what: &str) -> impl Fn(std::io::Error) -> Failure + '_ {
    move |e| {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            Failure::ClosedPipe
        } else {
            Failure::Failed(format!("cannot write {what}: {e}"))
        }
    }
}

/// A bad value of `flag` (exit 2).
pub fn usage(flag: &str, why: impl std::fmt::Display) -> Failure {
    Failure::Usage(format!("invalid value for {flag}: {why}"))
}

/// A replay's streams as pushed: (stream name as [`Rejected`] names it, samples).
pub type StreamCounts<'a> = &'a [(&'a str, u64)];

/// Fails when the replay produced nothing usable: `produced` is false (no step, no
/// stride, no estimate: `what` says which), or a stream was refused for its units.
/// `Ok` carries nothing; the summary has been printed before.
pub fn check_usable(
    produced: bool,
    what: &str,
    rejected: &Rejected,
    streams: StreamCounts,
) -> Result<(), Failure> {
    let refused = refused_for_units(rejected, streams);
    if produced && refused.is_empty() {
        return Ok(());
    }
    let mut causes = refused;
    if !produced {
        let total: u64 = streams.iter().map(|(_, n)| n).sum();
        causes.insert(
            0,
            if total > 0 && rejected.total() >= total {
                format!("{what}: every sample was refused")
            } else {
                what.to_string()
            },
        );
    }
    Err(Failure::Failed(causes.join("; ")))
}

/// [`check_usable`] of what a replay produced.
pub fn check(u: Usable) -> Result<(), Failure> {
    check_usable(u.produced, u.what, u.rejected, &u.streams)
}

/// One message per stream refused for its units: its unit refusals outnumber the
/// samples of it that were accepted.
pub fn refused_for_units(rejected: &Rejected, streams: StreamCounts) -> Vec<String> {
    rejected
        .unit_refusals()
        .iter()
        .filter(|(stream, r)| {
            let pushed = streams
                .iter()
                .find(|(s, _)| s == stream)
                .map_or(r.samples, |(_, n)| *n);
            2 * r.samples > pushed
        })
        .map(|(stream, r)| {
            format!(
                "the {stream} stream was refused for its units ({} of its samples): {}",
                r.samples, r.message
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use stridekit_core::input::{InputError, LikelyTimeUnit, Stream};

    fn time_unit(stream: Stream, likely: LikelyTimeUnit) -> InputError {
        InputError::TimeUnit {
            stream,
            t_s: 1.0,
            interval_s: 2.0,
            likely,
        }
    }

    #[test]
    fn a_stream_refused_for_its_units_fails_once_naming_the_first_unit() {
        let mut r = Rejected::default();
        for _ in 0..9 {
            r.input(&time_unit(Stream::Gnss, LikelyTimeUnit::Milliseconds));
        }
        for _ in 0..9 {
            r.input(&time_unit(Stream::Gnss, LikelyTimeUnit::Microseconds));
        }
        let streams = [("GNSS", 21), ("step", 600)];
        let e = check_usable(true, "no distance", &r, &streams).unwrap_err();
        let Failure::Failed(m) = e else {
            panic!("{e:?}")
        };
        assert!(m.contains("GNSS stream was refused") && m.contains("milliseconds"));
        assert!(!m.contains("microseconds"), "{m}");
        // A few refusals in a long good stream: a usable result.
        assert!(check_usable(true, "x", &r, &[("GNSS", 1000)]).is_ok());
        // Nothing produced, every sample refused.
        let e = check_usable(false, "no step detected", &r, &[("GNSS", 18)]).unwrap_err();
        assert_eq!(
            e,
            Failure::Failed(
                "no step detected: every sample was refused; the GNSS stream was refused for \
                 its units (18 of its samples): GNSS timestamps are not seconds: they look like \
                 milliseconds (divide by 1000)"
                    .into()
            )
        );
    }

    #[test]
    fn a_closed_pipe_is_not_a_failure() {
        let e = std::io::Error::from(std::io::ErrorKind::BrokenPipe);
        assert_eq!(write_error("stdout")(e), Failure::ClosedPipe);
        let e = std::io::Error::from(std::io::ErrorKind::PermissionDenied);
        assert!(matches!(write_error("x.csv")(e), Failure::Failed(m) if m.contains("x.csv")));
    }
}
