//! The one CSV writer: a file created with its header (directory too) or continued, and the
//! one quoting rule (the `csv` crate's: a field with a comma, a quote or a line break is
//! quoted, quotes doubled). Rows go through a buffer that is flushed at least every
//! [`FLUSH_EVERY`] of wall time, on [`CsvFile::flush`] and when the writer is dropped, so an
//! aborted run loses at most the last quarter second and a long run makes few `write`
//! calls. Errors name the path. Knows nothing about what the rows mean.

use crate::output_file_error::{create_output_file, OutputFileError};
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The longest rows stay in memory before they reach the file.
pub const FLUSH_EVERY: Duration = Duration::from_millis(250);

/// Bytes held before they go to the file whatever the time.
const BUFFER: usize = 64 * 1024;

pub struct CsvFile {
    file: File,
    buffer: Vec<u8>,
    path: PathBuf,
    /// When the rows last went to the file, on [`flush_clock`].
    flushed: Duration,
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
        Ok(CsvFile {
            file: create_output_file(path, append)?,
            buffer: Vec::with_capacity(BUFFER + 1024),
            path: path.to_path_buf(),
            flushed: flush_clock(),
        })
    }

    /// Writes one row; the file gets it within [`FLUSH_EVERY`].
    pub fn row<T: AsRef<str>>(&mut self, fields: &[T]) -> Result<(), OutputFileError> {
        let start = self.buffer.len();
        for (i, field) in fields.iter().enumerate() {
            if i > 0 {
                self.buffer.push(b',');
            }
            push_field(&mut self.buffer, field.as_ref());
        }
        // As the csv crate writes it: a row of nothing would read as no row at all.
        if self.buffer.len() == start {
            self.buffer.extend_from_slice(b"\"\"");
        }
        self.buffer.push(b'\n');
        self.written()
    }

    /// Writes whole rows made with [`push_field`], each ending in `\n`: a writer that makes
    /// many rows at once (one per value of a sample) formats what they share only once.
    pub fn rows_text(&mut self, rows: &[u8]) -> Result<(), OutputFileError> {
        self.buffer.extend_from_slice(rows);
        self.written()
    }

    /// After rows went into the buffer: hands them to the file when the buffer is full or
    /// the last flush is [`FLUSH_EVERY`] ago.
    fn written(&mut self) -> Result<(), OutputFileError> {
        if self.buffer.len() >= BUFFER {
            self.write_buffer()?;
        }
        if flush_clock().saturating_sub(self.flushed) >= FLUSH_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    fn write_buffer(&mut self) -> Result<(), OutputFileError> {
        let result = self.file.write_all(&self.buffer);
        // What could not be written is not tried again: the error says the file is short.
        self.buffer.clear();
        result.map_err(|e| OutputFileError::file(&self.path, e))
    }

    /// Hands every row written so far to the file.
    pub fn flush(&mut self) -> Result<(), OutputFileError> {
        self.flushed = flush_clock();
        self.write_buffer()?;
        self.file
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
        let _ = self.write_buffer();
    }
}

/// The time the flush rule goes by, read for every row: on Linux the kernel's coarse
/// monotonic clock (to a few milliseconds, and read without the processor's time counter,
/// which cost as much as formatting a row of a long run), elsewhere the standard one.
fn flush_clock() -> Duration {
    #[cfg(target_os = "linux")]
    {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime only writes the timespec it is given. The clock is there
        // on every Linux this runs on; were it not, the time would stand still and rows
        // would go to the file when the buffer fills and at the step's end.
        unsafe {
            libc::clock_gettime(libc::CLOCK_MONOTONIC_COARSE, &mut t);
        }
        Duration::new(
            u64::try_from(t.tv_sec).unwrap_or(0),
            u32::try_from(t.tv_nsec).unwrap_or(0),
        )
    }
    #[cfg(not(target_os = "linux"))]
    {
        static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
        START.get_or_init(std::time::Instant::now).elapsed()
    }
}

/// Appends `field` to `out` as one CSV field: quoted (quotes doubled) when it holds a
/// comma, a quote or a line break, as is otherwise.
pub fn push_field(out: &mut Vec<u8>, field: &str) {
    let bytes = field.as_bytes();
    if bytes.iter().any(|b| matches!(b, b',' | b'"' | b'\n' | b'\r')) {
        out.push(b'"');
        for &b in bytes {
            if b == b'"' {
                out.push(b'"');
            }
            out.push(b);
        }
        out.push(b'"');
    } else {
        out.extend_from_slice(bytes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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

    #[test]
    fn a_full_disk_is_an_error_that_names_the_file() {
        let path = Path::new("/dev/full");
        let mut f = CsvFile::append(path).unwrap();
        f.row(&["1"]).unwrap();
        let err = f.flush().unwrap_err().to_string();
        assert!(err.starts_with("cannot write /dev/full: "), "{err}");
    }

    /// The text the csv crate writes for `rows`, which files written before this writer
    /// was ours were made with.
    fn by_the_csv_crate(rows: &[Vec<String>]) -> String {
        let mut w = csv::WriterBuilder::new().flexible(true).from_writer(Vec::new());
        for r in rows {
            w.write_record(r).unwrap();
        }
        String::from_utf8(w.into_inner().unwrap()).unwrap()
    }

    proptest! {
        #[test]
        fn rows_are_written_byte_for_byte_as_the_csv_crate_writes_them(
            rows in prop::collection::vec(
                prop::collection::vec("[a-z ,\"\r\n#'0-9.-]{0,6}", 0..5),
                0..5,
            )
        ) {
            let dir = std::env::temp_dir()
                .join(format!("drivescript-csvfile-prop-{}", std::process::id()));
            let path = dir.join("p.csv");
            let mut f = CsvFile::append(&path).unwrap();
            std::fs::write(&path, "").unwrap();
            for r in &rows {
                f.row(r).unwrap();
            }
            f.flush().unwrap();
            prop_assert_eq!(std::fs::read_to_string(&path).unwrap(), by_the_csv_crate(&rows));
        }
    }
}
