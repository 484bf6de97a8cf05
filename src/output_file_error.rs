//! Creating a file the run writes (a trace, its notes, a samples CSV, an anonymised copy),
//! its directory too, and the one error for it and for writing it: what failed and the
//! path. Knows nothing about what the files hold.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

/// Why an output file could not be created or written; the text names the path.
#[derive(Debug, thiserror::Error)]
pub enum OutputFileError {
    #[error("cannot create the directory {}: {source}", dir.display())]
    Directory { dir: PathBuf, source: std::io::Error },
    #[error("cannot write {}: {source}", path.display())]
    File { path: PathBuf, source: std::io::Error },
}

impl OutputFileError {
    /// A failed write of `path`.
    pub fn file(path: &Path, source: std::io::Error) -> Self {
        OutputFileError::File {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Creates (truncates) `path`, or (`append`) continues it, with its directory.
pub fn create_output_file(path: &Path, append: bool) -> Result<File, OutputFileError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| OutputFileError::Directory {
            dir: dir.to_path_buf(),
            source,
        })?;
    }
    OpenOptions::new()
        .create(true)
        .append(append)
        .write(true)
        .truncate(!append)
        .open(path)
        .map_err(|e| OutputFileError::file(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_that_cannot_be_made_names_its_directory_or_itself() {
        let err = create_output_file(Path::new("/proc/drivescript/x.csv"), false).unwrap_err();
        assert!(matches!(err, OutputFileError::Directory { .. }), "{err:?}");
        assert!(
            err.to_string()
                .starts_with("cannot create the directory /proc/drivescript: "),
            "{err}"
        );
        let dir = std::env::temp_dir();
        let err = create_output_file(&dir, false).unwrap_err();
        assert!(matches!(err, OutputFileError::File { .. }), "{err:?}");
        assert!(err.to_string().starts_with("cannot write "), "{err}");
    }
}
