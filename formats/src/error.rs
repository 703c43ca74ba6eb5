//! The error type shared by all readers.

/// Why an activity file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// The file could not be read from disk.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// [`crate::read_activity`] can tell the format neither from the content nor from
    /// the file extension (given here, lower case).
    #[error(
        "not an activity file: neither its content nor its extension {0:?} is FIT, TCX, GPX \
         or an activity CSV (t_s, lat_deg, lon_deg)"
    )]
    UnknownExtension(String),
    /// The path does not exist.
    #[error("no such file or folder")]
    Missing,
    /// The path is a folder where a file is expected.
    #[error("this is a folder, not a file")]
    Folder,
    /// The path is a folder, but not one of the recording folders a reader takes.
    #[error("this is a folder without {0}")]
    FolderWithout(&'static str),
    /// The file holds another kind of recording than the reader reads (told from its
    /// content, see [`crate::sniff`]).
    #[error("its content is of another kind ({found}), not a {expected}")]
    OtherContent {
        /// What the file holds ([`crate::Content::name`]).
        found: &'static str,
        /// What the reader reads.
        expected: &'static str,
    },
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

/// Rows of a text file that a reader could not read (a header, garbage, a truncated
/// last line) and skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Unreadable {
    /// How many.
    pub rows: u64,
    /// 1-based line of the first.
    pub first_line: Option<usize>,
}

impl Unreadable {
    pub(crate) fn add(&mut self, line: usize) {
        self.rows += 1;
        self.first_line.get_or_insert(line);
    }

    /// `("unreadable row (first at line L)", rows)`, when there were any.
    pub fn reason(&self) -> Option<(String, u64)> {
        self.first_line
            .map(|line| (format!("unreadable row (first at line {line})"), self.rows))
    }
}
