//! Output files of the commands: the folders are created, a missing extension is
//! added (`--out traj` writes `traj.csv`), and the command says what it wrote and
//! whether it replaced a file.

use std::path::{Path, PathBuf};

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
        let _ = std::fs::remove_dir_all(&dir);
    }
}
