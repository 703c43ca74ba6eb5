//! The error type shared by all readers.

/// Why an activity file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// The file could not be read from disk.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// [`crate::read_activity`] does not know the file extension.
    #[error("unknown activity file extension {0:?} (expected fit, tcx, gpx or csv)")]
    UnknownExtension(String),
    /// The content is malformed for its format.
    #[error("invalid {format} file: {message}")]
    Parse {
        /// `"FIT"`, `"TCX"`, `"GPX"` or `"CSV"`.
        format: &'static str,
        /// What is wrong, with a position when one is known.
        message: String,
    },
    /// A CSV header lacks a required column.
    #[error("CSV header has no {0} column")]
    MissingColumn(&'static str),
    /// The file is well formed but holds no timed records.
    #[error("the file holds no timed records")]
    Empty,
}

impl FormatError {
    pub(crate) fn parse(format: &'static str, message: impl Into<String>) -> Self {
        FormatError::Parse {
            format,
            message: message.into(),
        }
    }
}
