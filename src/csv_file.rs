//! The one CSV writer: a file created with its header (directory too) or continued, each
//! row written and flushed at once, so an aborted run keeps every row written. Errors name
//! the path. Knows nothing about what the rows mean.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

pub struct CsvFile {
    writer: csv::Writer<File>,
    path: PathBuf,
}

impl CsvFile {
    /// Creates (truncates) `path` and writes `header`.
    pub fn create(path: &Path, header: &[String]) -> Result<Self, String> {
        let mut file = Self::open(path, false)?;
        file.row(header)?;
        Ok(file)
    }

    /// Continues a file this run started (no header).
    pub fn append(path: &Path) -> Result<Self, String> {
        Self::open(path, true)
    }

    fn open(path: &Path, append: bool) -> Result<Self, String> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create the directory {}: {e}", dir.display()))?;
        }
        let file = OpenOptions::new()
            .create(true)
            .append(append)
            .write(true)
            .truncate(!append)
            .open(path)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        Ok(CsvFile {
            writer: csv::Writer::from_writer(file),
            path: path.to_path_buf(),
        })
    }

    /// Writes one row and flushes it to the file.
    pub fn row<T: AsRef<[u8]>>(&mut self, fields: &[T]) -> Result<(), String> {
        self.writer
            .write_record(fields)
            .and_then(|()| self.writer.flush().map_err(csv::Error::from))
            .map_err(|e| format!("cannot write {}: {e}", self.path.display()))
    }

    pub fn path(&self) -> &Path {
        &self.path
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
        f.row(&["1", "2,5"]).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b [rpm]\n1,\"2,5\"\n");
        drop(f);
        CsvFile::append(&path).unwrap().row(&["3", "4"]).unwrap();
        assert!(std::fs::read_to_string(&path).unwrap().ends_with("3,4\n"));
        let err = CsvFile::create(&dir.join("deep"), &[]).err().unwrap();
        assert!(err.contains("deep"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
