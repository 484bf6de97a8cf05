//! The one CSV writer: a file created with its header (directory too) or continued. Rows
//! go through a buffer that is flushed at least every [`FLUSH_EVERY`] of wall time, on
//! [`CsvFile::flush`] and when the writer is dropped, so an aborted run loses at most the
//! last quarter second and a long run makes few `write` calls. Errors name the path. Knows
//! nothing about what the rows mean.

use crate::output_file_error::{create_output_file, OutputFileError};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The longest rows stay in memory before they reach the file.
pub const FLUSH_EVERY: Duration = Duration::from_millis(250);

pub struct CsvFile {
    writer: csv::Writer<File>,
    path: PathBuf,
    flushed: Instant,
}

impl CsvFile {
    /// Creates (truncates) `path` and writes `header`.
    pub fn create(path: &Path, header: &[String]) -> Result<Self, OutputFileError> {
        let mut file = Self::open(path, false)?;
        file.row(header)?;
        file.flush()?;
        Ok(file)
    }

    /// Continues a file this run started (no header).
    pub fn append(path: &Path) -> Result<Self, OutputFileError> {
        Self::open(path, true)
    }

    fn open(path: &Path, append: bool) -> Result<Self, OutputFileError> {
        let file = create_output_file(path, append)?;
        Ok(CsvFile {
            writer: csv::WriterBuilder::new()
                .buffer_capacity(64 * 1024)
                .from_writer(file),
            path: path.to_path_buf(),
            flushed: Instant::now(),
        })
    }

    /// Writes one row; the file gets it within [`FLUSH_EVERY`].
    pub fn row<T: AsRef<[u8]>>(&mut self, fields: &[T]) -> Result<(), OutputFileError> {
        self.writer
            .write_record(fields)
            .map_err(|source| OutputFileError::Csv {
                path: self.path.clone(),
                source,
            })?;
        if self.flushed.elapsed() >= FLUSH_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    /// Hands every row written so far to the file.
    pub fn flush(&mut self) -> Result<(), OutputFileError> {
        self.flushed = Instant::now();
        self.writer
            .flush()
            .map_err(|e| OutputFileError::file(&self.path, e))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for CsvFile {
    fn drop(&mut self) {
        // Best effort: a write error here was or will be reported by `flush`.
        let _ = self.writer.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_on_disk_at_once_and_a_file_can_be_continued() {
        let dir = std::env::temp_dir().join(format!("drivescript-csvfile-{}", std::process::id()));
        let path = dir.join("deep/x.csv");
        let mut f = CsvFile::create(&path, &["a".to_string(), "b [rpm]".to_string()]).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "a,b [rpm]\n",
            "the header at once"
        );
        f.row(&["1", "2,5"]).unwrap();
        f.flush().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b [rpm]\n1,\"2,5\"\n");
        drop(f);
        CsvFile::append(&path).unwrap().row(&["3", "4"]).unwrap();
        assert!(std::fs::read_to_string(&path).unwrap().ends_with("3,4\n"));
        let err = CsvFile::create(&dir.join("deep"), &[]).err().unwrap().to_string();
        assert!(err.contains("deep"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
