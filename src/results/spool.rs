//! Records the store could not take, kept in a local file (one JSON record a line) until
//! the next run or `results sync` delivers them. Each append is one write, so processes
//! sharing a spool do not interleave lines; delivery takes the file away first, so two
//! deliveries never send the same lines twice (and a replay would change nothing anyway).

use super::record::Record;
use super::{Store, StoreError};
use std::io::Write;
use std::path::{Path, PathBuf};

pub struct Spool {
    path: PathBuf,
}

/// What a delivery did.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Delivered {
    pub records: usize,
    pub runs: usize,
    /// Lines that were no record (a damaged spool): kept in `FILE.bad`.
    pub unreadable: usize,
}

impl Spool {
    pub fn new(path: PathBuf) -> Spool {
        Spool { path }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    fn error(&self, why: impl std::fmt::Display) -> StoreError {
        StoreError::Spool {
            path: self.path.display().to_string(),
            why: why.to_string(),
        }
    }

    /// Appends `records` in one write.
    pub fn append(&self, records: &[Record]) -> Result<(), StoreError> {
        let mut text = String::new();
        for r in records {
            text.push_str(&serde_json::to_string(r).map_err(|e| self.error(e))?);
            text.push('\n');
        }
        if let Some(dir) = self.path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| self.error(e))?;
        }
        let mut file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&self.path)
            .map_err(|e| self.error(e))?;
        file.write_all(text.as_bytes()).map_err(|e| self.error(e))
    }

    /// Whether records wait to be delivered.
    pub fn pending(&self) -> bool {
        std::fs::metadata(&self.path).is_ok_and(|m| m.len() > 0)
    }

    /// Delivers every spooled record to `store`, in order and in one transaction; when the
    /// store fails, all of them go back to the spool.
    pub fn deliver(&self, store: &mut Store) -> Result<Delivered, StoreError> {
        if !self.pending() {
            return Ok(Delivered::default());
        }
        let mut taking = self.path.as_os_str().to_os_string();
        taking.push(format!(".sending-{}", std::process::id()));
        let taking = PathBuf::from(taking);
        if let Err(e) = std::fs::rename(&self.path, &taking) {
            // Another process took it a moment ago.
            if e.kind() == std::io::ErrorKind::NotFound {
                return Ok(Delivered::default());
            }
            return Err(self.error(e));
        }
        let text = std::fs::read_to_string(&taking).map_err(|e| self.error(e))?;
        let mut done = Delivered::default();
        let mut bad = String::new();
        let mut records = Vec::new();
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            match serde_json::from_str::<Record>(line) {
                Ok(r) => records.push(r),
                Err(_) => {
                    done.unreadable += 1;
                    bad.push_str(line);
                    bad.push('\n');
                }
            }
        }
        if !bad.is_empty() {
            let mut path = self.path.as_os_str().to_os_string();
            path.push(".bad");
            let _ = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(PathBuf::from(path))
                .and_then(|mut f| f.write_all(bad.as_bytes()));
        }
        if let Err(e) = store.apply_all(&records) {
            self.append(&records)?;
            let _ = std::fs::remove_file(&taking);
            return Err(e);
        }
        done.records = records.len();
        let mut runs: Vec<&str> = records.iter().map(Record::run).collect();
        runs.sort_unstable();
        runs.dedup();
        done.runs = runs.len();
        let _ = std::fs::remove_file(&taking);
        Ok(done)
    }
}
