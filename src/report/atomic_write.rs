//! Writes a report file whole or not at all: the text goes to `PATH.tmp` first and is then
//! renamed over `PATH`, so a crash or a full disk never leaves a half-written report that CI
//! would misread. Creates the directory. Knows nothing about what the text is.
//! On Windows a file another program holds open for a moment (a viewer reading it, a virus
//! scanner) cannot be replaced; the rename is tried again for [`HELD_OPEN_LIMIT`].

use std::io::Write;
use std::path::{Path, PathBuf};

/// Why a report file was not written (its directory or the file); the text names the path.
pub type ReportWriteError = crate::output_file_error::OutputFileError;

/// Writes `text` to `path` atomically.
pub fn write_atomically(path: &Path, text: &str) -> Result<(), ReportWriteError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| ReportWriteError::Directory {
            dir: dir.to_path_buf(),
            source,
        })?;
    }
    let failed = |source| ReportWriteError::File {
        path: path.to_path_buf(),
        source,
    };
    let tmp = tmp_path(path);
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(text.as_bytes())?;
        f.sync_all()
    });
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(failed(e));
    }
    replace(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        failed(e)
    })
}

/// How long a report held open by another program is waited for on Windows.
pub const HELD_OPEN_LIMIT: std::time::Duration = std::time::Duration::from_secs(2);

/// Renames `from` over `to`. Windows refuses to replace a file another program has open
/// without leave to delete it (access denied) or has locked (a sharing or lock violation:
/// a virus scanner, an indexer), and most hold it only for a moment: tried again until
/// [`HELD_OPEN_LIMIT`]; the last refusal is the error.
pub fn replace(from: &Path, to: &Path) -> std::io::Result<()> {
    /// ERROR_ACCESS_DENIED, ERROR_SHARING_VIOLATION, ERROR_LOCK_VIOLATION.
    const HELD_BY_ANOTHER: [i32; 3] = [5, 32, 33];
    let started = std::time::Instant::now();
    loop {
        match std::fs::rename(from, to) {
            Err(e)
                if cfg!(windows)
                    && e.raw_os_error()
                        .is_some_and(|code| HELD_BY_ANOTHER.contains(&code))
                    && started.elapsed() < HELD_OPEN_LIMIT =>
            {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            done => return done,
        }
    }
}

/// `report.xml` → `report.xml.tmp`.
pub fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_os_string();
    name.push(".tmp");
    PathBuf::from(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("drivescript-atomic-{}", std::process::id()));
        let path = dir.join("deep/report.xml");
        write_atomically(&path, "first").unwrap();
        write_atomically(&path, "second").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "second");
        assert!(!tmp_path(&path).exists());
        assert_eq!(tmp_path(&path).file_name().unwrap(), "report.xml.tmp");

        // A directory in the way: an error naming the path, the old file untouched.
        let blocked = dir.join("deep");
        let err = write_atomically(&blocked, "x").unwrap_err().to_string();
        assert!(err.contains("deep"), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "second");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The report open in another program as Windows' own programs open files: for reading,
    /// without leave to delete or rename it (on Linux nothing holds a rename up).
    fn held_open(path: &Path) -> std::fs::File {
        let mut options = std::fs::OpenOptions::new();
        options.read(true);
        #[cfg(windows)]
        {
            use std::os::windows::fs::OpenOptionsExt;
            const FILE_SHARE_READ: u32 = 1;
            options.share_mode(FILE_SHARE_READ);
        }
        options.open(path).unwrap()
    }

    /// `report.html` holding "old" in a fresh folder `name`, and a reader holding it open.
    fn old_report_held_open(name: &str) -> (PathBuf, PathBuf, std::fs::File) {
        let dir = crate::scratch_dir::scratch_dir(name);
        let path = dir.join("report.html");
        write_atomically(&path, "old").unwrap();
        let reader = held_open(&path);
        (dir, path, reader)
    }

    /// A reader that has the report open while it is replaced (as a test polling it, or a
    /// viewer, does) holds the run up for a moment at most, never fails it.
    #[test]
    fn a_report_held_open_by_a_reader_is_replaced_once_it_lets_go() {
        let (dir, path, reader) = old_report_held_open("held");
        let held_for = std::time::Duration::from_millis(300);
        let let_go = std::thread::spawn(move || {
            std::thread::sleep(held_for);
            drop(reader);
        });
        let started = std::time::Instant::now();
        write_atomically(&path, "new").unwrap();
        if cfg!(windows) {
            // Replaced only after the reader let go: the write waited for it.
            assert!(started.elapsed() >= held_for / 2, "{:?}", started.elapsed());
        }
        let_go.join().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert!(!tmp_path(&path).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A report held beyond [`HELD_OPEN_LIMIT`] is an error that names it, the old report
    /// stays whole and no temporary is left behind.
    #[cfg(windows)]
    #[test]
    fn a_report_held_beyond_the_limit_is_an_error_and_the_old_one_stays() {
        let (dir, path, reader) = old_report_held_open("held-long");
        let err = write_atomically(&path, "new").unwrap_err().to_string();
        drop(reader);
        assert!(err.contains("report.html"), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert!(!tmp_path(&path).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
