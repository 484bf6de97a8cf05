//! Records the store could not take, kept in a local file (one JSON record a line) until
//! the next run or `results sync` delivers them. Each append is one write, so processes
//! sharing a spool do not interleave lines. Delivery claims the file first by renaming it
//! to `FILE.sending-PID`, so two deliveries never send the same lines twice; on any
//! failure what was not delivered goes back to the spool, and a claim whose process is
//! gone (killed while delivering) is taken back by the next delivery — a replayed record
//! changes nothing, so a kill at any moment strands and loses nothing.

use super::claim_owner::gone;
use super::record::Record;
use super::{Store, StoreError};
use std::io::{Read, Seek, SeekFrom, Write};
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
    /// Runs the store refused (not for being unreachable): back in the spool, each
    /// with why, so that one run the store cannot take never holds up the others.
    pub refused: Vec<(String, String)>,
}

/// The mark of a claim in a file name: `results.sqlite.spool.sending-4242`.
const CLAIM: &str = ".sending-";

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

    /// Appends `records` in one write. A line cut short by a kill during an earlier
    /// append is ended first, so it spoils only itself, never the next record.
    pub fn append(&self, records: &[Record]) -> Result<(), StoreError> {
        if records.is_empty() {
            return Ok(());
        }
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
            .read(true)
            .append(true)
            .open(&self.path)
            .map_err(|e| self.error(e))?;
        if ends_unfinished(&mut file) {
            text.insert(0, '\n');
        }
        file.write_all(text.as_bytes()).map_err(|e| self.error(e))
    }

    /// Whether records wait to be delivered: in the spool, or in a claim whose process
    /// is gone.
    pub fn pending(&self) -> bool {
        std::fs::metadata(&self.path).is_ok_and(|m| m.len() > 0) || !self.stale_claims().is_empty()
    }

    /// The ids of the runs with records waiting here (in the spool or in any claim), in
    /// the order they were spooled: runs kept on this bench, not yet in the store.
    pub fn runs(&self) -> Vec<String> {
        let mut files = vec![self.path.clone()];
        files.extend(self.claims().into_iter().map(|(p, _)| p));
        let mut runs: Vec<String> = Vec::new();
        for file in files {
            let Ok(text) = std::fs::read_to_string(&file) else {
                continue;
            };
            for line in text.lines() {
                if let Ok(r) = serde_json::from_str::<Record>(line) {
                    if !runs.iter().any(|x| x == r.run()) {
                        runs.push(r.run().to_string());
                    }
                }
            }
        }
        runs
    }

    /// Every claim beside the spool, with the process that made it.
    fn claims(&self) -> Vec<(PathBuf, u32)> {
        let (Some(dir), Some(name)) = (self.path.parent(), self.path.file_name()) else {
            return Vec::new();
        };
        let dir = if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        };
        let prefix = format!("{}{CLAIM}", name.to_string_lossy());
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        let mut claims: Vec<(PathBuf, u32)> = entries
            .flatten()
            .filter_map(|e| {
                let file = e.file_name().to_string_lossy().into_owned();
                let pid = file.strip_prefix(&prefix)?.split('.').next()?.parse().ok()?;
                Some((e.path(), pid))
            })
            .collect();
        claims.sort();
        claims
    }

    /// The claims of processes that are gone: a delivery killed half-way.
    fn stale_claims(&self) -> Vec<PathBuf> {
        self.claims()
            .into_iter()
            .filter(|(path, pid)| gone(*pid, path))
            .map(|(p, _)| p)
            .collect()
    }

    /// The name of this process's claim number `n`.
    fn claim_path(&self, n: usize) -> PathBuf {
        let mut name = self.path.as_os_str().to_os_string();
        name.push(format!("{CLAIM}{}", std::process::id()));
        if n > 0 {
            name.push(format!(".{n}"));
        }
        PathBuf::from(name)
    }

    /// Takes the spool and every stale claim under claims of this process (a rename
    /// each, so of two deliveries only one takes a file); the claims, oldest first.
    fn claim(&self) -> Result<Vec<PathBuf>, StoreError> {
        let mut taken = Vec::new();
        let mut n = 0;
        // A name no claim has: a rename onto a claim would put its records out of reach.
        let free = |n: &mut usize| {
            while self.claim_path(*n).exists() {
                *n += 1;
            }
            self.claim_path(*n)
        };
        for stale in self.stale_claims() {
            let mine = free(&mut n);
            // Another delivery took it a moment ago: nothing to do.
            if std::fs::rename(&stale, &mine).is_ok() {
                touch(&mine);
                taken.push(mine);
            }
        }
        let mine = free(&mut n);
        // Dated before the rename as well, so the claim is never seen with the spool's
        // older time under this process's number.
        touch(&self.path);
        match std::fs::rename(&self.path, &mine) {
            Ok(()) => {
                touch(&mine);
                taken.push(mine);
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => {
                self.give_back(&taken);
                return Err(self.error(e));
            }
        }
        Ok(taken)
    }

    /// Returns what `claims` hold to the spool and removes them. Killed between the two,
    /// the claims stay as stale ones and their records are delivered twice, which
    /// changes nothing.
    fn give_back(&self, claims: &[PathBuf]) {
        for claim in claims {
            let back = std::fs::read(claim).and_then(|bytes| {
                if bytes.is_empty() {
                    return Ok(());
                }
                let mut file = std::fs::OpenOptions::new()
                    .create(true)
                    .read(true)
                    .append(true)
                    .open(&self.path)?;
                let mut text = Vec::with_capacity(bytes.len() + 2);
                if ends_unfinished(&mut file) {
                    text.push(b'\n');
                }
                text.extend_from_slice(&bytes);
                if !text.ends_with(b"\n") {
                    text.push(b'\n');
                }
                file.write_all(&text)
            });
            // Kept as a claim (taken back later) when it could not be given back.
            if back.is_ok() {
                let _ = std::fs::remove_file(claim);
            }
        }
    }

    /// Delivers every spooled record to `store`, in order, each run in one transaction
    /// (all its records or none). A store that cannot be reached ends the delivery and
    /// everything not delivered goes back to the spool; a run the store refuses goes
    /// back alone and the others are delivered.
    pub fn deliver(&self, store: &mut Store) -> Result<Delivered, StoreError> {
        if !self.pending() {
            return Ok(Delivered::default());
        }
        let claims = self.claim()?;
        let mut text = String::new();
        for claim in &claims {
            let read = std::fs::File::open(claim).and_then(|mut f| f.read_to_string(&mut text));
            if let Err(e) = read {
                self.give_back(&claims);
                return Err(self.error(e));
            }
            if !text.is_empty() && !text.ends_with('\n') {
                text.push('\n');
            }
        }
        let mut done = Delivered::default();
        let mut bad = String::new();
        let mut runs: Vec<(String, Vec<Record>)> = Vec::new();
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            match serde_json::from_str::<Record>(line) {
                Ok(r) => match runs.iter_mut().find(|(id, _)| id == r.run()) {
                    Some((_, records)) => records.push(r),
                    None => runs.push((r.run().to_string(), vec![r])),
                },
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
        let mut back: Vec<Record> = Vec::new();
        let mut failed = None;
        for (id, records) in runs {
            if failed.is_some() {
                back.extend(records);
                continue;
            }
            match store.apply_all(&records) {
                Ok(()) => {
                    done.records += records.len();
                    done.runs += 1;
                }
                Err(e @ StoreError::Query { .. }) => {
                    done.refused.push((id, e.to_string()));
                    back.extend(records);
                }
                Err(e) => {
                    failed = Some(e);
                    back.extend(records);
                }
            }
        }
        if done.runs > 0 {
            store.checkpoint();
        }
        // On failure the claims stay, to be taken back by the next delivery.
        self.append(&back)?;
        for claim in &claims {
            let _ = std::fs::remove_file(claim);
        }
        match failed {
            Some(e) => Err(e),
            None => Ok(done),
        }
    }
}

/// Dates a claim to its making (a rename keeps the spool's time), which is how a claim is
/// told from one of an earlier process by the same number (see `claim_owner`). Where it
/// fails the claim keeps the spool's time: at worst another delivery takes it over, and a
/// replayed record changes nothing.
fn touch(claim: &Path) {
    let _ = std::fs::OpenOptions::new()
        .append(true)
        .open(claim)
        .and_then(|f| f.set_modified(std::time::SystemTime::now()));
}

/// Whether `file` ends in the middle of a line (a write cut short by a kill).
fn ends_unfinished(file: &mut std::fs::File) -> bool {
    let mut last = [0u8; 1];
    file.seek(SeekFrom::End(-1))
        .and_then(|_| file.read_exact(&mut last))
        .is_ok_and(|()| last[0] != b'\n')
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::record::passed_run;
    use crate::results::{Locator, RunFilter};

    /// A line cut short by a kill during an append spoils only itself: the next append
    /// starts on a line of its own, and a delivery keeps the cut line in `FILE.bad`.
    #[test]
    fn a_line_cut_short_by_a_kill_spoils_only_itself() {
        let dir = crate::scratch_dir::scratch_dir("spool-unit");
        let spool = Spool::new(dir.join("r.sqlite.spool"));
        spool.append(&passed_run("a1", "S-1")).expect("appended");
        let mut f = std::fs::OpenOptions::new()
            .append(true)
            .open(spool.path())
            .expect("opens");
        f.write_all(b"{\"record\":\"started\",\"id\":\"cut")
            .expect("a cut line");
        drop(f);
        spool.append(&passed_run("b2", "S-2")).expect("appended");
        assert_eq!(spool.runs(), ["a1", "b2"]);
        let mut store = Locator::Sqlite(dir.join("r.sqlite")).open(true).expect("opens");
        let done = spool.deliver(&mut store).expect("delivered");
        assert_eq!((done.runs, done.records, done.unreadable), (2, 6, 1));
        let every = RunFilter {
            simulated: true,
            ..RunFilter::default()
        };
        assert_eq!(store.list(&every).expect("list").len(), 2);
        assert!(!spool.pending());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
