//! Output files of the commands: the folders are created, a missing extension is
//! added (`--out traj` writes `traj.csv`), and the command says what it wrote and
//! whether it replaced a file. `--out -` sends a replay's CSV to stdout; its summary
//! then goes to stderr ([`say!`]), else to stdout.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::outcome::{write_error, Failure};

/// The summary goes to stderr (stdout carries the CSV).
static SUMMARY_TO_STDERR: AtomicBool = AtomicBool::new(false);

/// Print one line of a command's summary: to stdout, or to stderr when stdout
/// carries the CSV (`--out -`).
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::output::say_line(format_args!($($arg)*))
    };
}
pub(crate) use say;

/// See [`say!`].
pub fn say_line(line: std::fmt::Arguments) {
    if SUMMARY_TO_STDERR.load(Ordering::Relaxed) {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
}

/// Where a replay's CSV goes: a file (`--out FILE`) or stdout (`--out -`).
#[derive(Clone, Debug)]
pub enum Sink {
    File(OutFile),
    Stdout,
}

/// Stdout: where a CSV goes when no file is named (only for options built in code;
/// the commands' `--out` has a file name as its default).
impl Default for Sink {
    fn default() -> Self {
        Sink::Stdout
    }
}

impl Sink {
    /// `-`: stdout (the summary then goes to stderr); else [`OutFile::prepare`].
    pub fn from_arg(path: &Path, ext: &str) -> Result<Self, String> {
        if path == Path::new("-") {
            SUMMARY_TO_STDERR.store(true, Ordering::Relaxed);
            Ok(Sink::Stdout)
        } else {
            OutFile::prepare(path, ext).map(Sink::File)
        }
    }

    /// The file, `None` for stdout.
    pub fn path(&self) -> Option<&Path> {
        match self {
            Sink::File(f) => Some(&f.path),
            Sink::Stdout => None,
        }
    }

    /// A file beside the CSV, the CSV's name with `ext` (`traj.csv` → `traj.svg`);
    /// `None` when the CSV goes to stdout (charts are not written then).
    pub fn beside(&self, ext: &str) -> Option<PathBuf> {
        self.path().map(|p| p.with_extension(ext))
    }

    /// A buffered writer to the file or stdout.
    pub fn open(&self) -> Result<Box<dyn Write>, Failure> {
        Ok(match self {
            Sink::File(f) => Box::new(std::io::BufWriter::new(
                std::fs::File::create(&f.path).map_err(write_error(&f.path.to_string_lossy()))?,
            )),
            Sink::Stdout => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
        })
    }

    /// What the CSV is written to, for messages.
    pub fn name(&self) -> String {
        match self {
            Sink::File(f) => f.path.display().to_string(),
            Sink::Stdout => "stdout".into(),
        }
    }

    /// "wrote PATH" (and "(replaced)"), `None` for stdout.
    pub fn wrote(&self) -> Option<String> {
        match self {
            Sink::File(f) => Some(f.wrote()),
            Sink::Stdout => None,
        }
    }
}

/// Writes a CSV to `sink` with `write`, then flushes; an I/O error names the sink (a
/// closed pipe ends quietly).
pub fn write_to(
    sink: &Sink,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), Failure> {
    let name = sink.name();
    let mut w = sink.open()?;
    write(&mut *w)
        .and_then(|()| w.flush())
        .map_err(write_error(&name))
}

/// A file a command is about to write.
#[derive(Clone, Debug)]
pub struct OutFile {
    pub path: PathBuf,
    /// A file was already there (it is replaced).
    pub existed: bool,
}

impl OutFile {
    /// `path` with `ext` added when it has no extension, its folder created.
    pub fn prepare(path: &Path, ext: &str) -> Result<Self, String> {
        let path = if path.extension().is_none() && !ext.is_empty() {
            path.with_extension(ext)
        } else {
            path.to_path_buf()
        };
        if path.is_dir() {
            return Err(format!("{} is a folder, not a file", path.display()));
        }
        create_parent(&path)?;
        Ok(Self {
            existed: path.exists(),
            path,
        })
    }

    /// "wrote PATH" (and "(replaced)" when a file was there).
    pub fn wrote(&self) -> String {
        format!(
            "wrote {}{}",
            self.path.display(),
            if self.existed { " (replaced)" } else { "" }
        )
    }
}

/// Create the folder a file goes into.
pub fn create_parent(path: &Path) -> Result<(), String> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create the folder {}: {e}", dir.display())),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_extension_is_added_and_folders_are_created() {
        let dir = std::env::temp_dir().join(format!("stridekit-out-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let o = OutFile::prepare(&dir.join("sub/dir/traj"), "csv").unwrap();
        assert_eq!(o.path, dir.join("sub/dir/traj.csv"));
        assert!(dir.join("sub/dir").is_dir());
        assert!(!o.existed);
        std::fs::write(&o.path, "x").unwrap();
        let again = OutFile::prepare(&o.path, "csv").unwrap();
        assert!(again.existed);
        assert!(again.wrote().ends_with("(replaced)"));
        std::fs::create_dir_all(dir.join("folder.csv")).unwrap();
        assert!(OutFile::prepare(&dir.join("folder.csv"), "csv").is_err());
        let file = Sink::from_arg(&dir.join("traj"), "csv").unwrap();
        assert_eq!(file.beside("svg"), Some(dir.join("traj.svg")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
