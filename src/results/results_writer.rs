//! The recorder's writer thread: takes records off the queue in batches and writes each
//! batch to the store in one transaction (records come in order, so a run's row is always
//! in before its steps: a kill leaves whole batches, never a step without its run),
//! opening the store (and delivering the spool first) at a run's start. A run the store
//! fails during goes on to the spool, so a run's records are never split between a store
//! that came back and the spool; it answers, when asked, where a run's records are.

use super::record::Record;
use super::results_recorder::note;
use super::{Locator, Notes, Spool, Store, StoreError};
use std::collections::HashSet;
use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::Arc;

/// Records written in one transaction at most.
const BATCH: usize = 512;

/// What the recorder puts on the queue.
pub enum Job {
    Record(Box<Record>),
    /// Answered once everything before it is handled: where the records of the run named
    /// are.
    Flush(String, SyncSender<Landed>),
}

/// Where a run's records went, as the writer knows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Landed {
    /// The store committed every one.
    Stored,
    /// Some are in the spool, the rest in the store.
    Spooled,
    /// Some could be written neither to the store nor to the spool.
    Lost,
}

/// The writer thread's side.
pub struct Writer {
    locator: Locator,
    spool: Arc<Spool>,
    notes: Notes,
    store: Option<Store>,
    /// Runs whose start the store committed.
    stored: HashSet<String>,
    /// Runs whose records go to the spool (the store failed during them).
    spooled: HashSet<String>,
    /// Runs of which some records the spool could not take either.
    lost: HashSet<String>,
}

impl Writer {
    pub fn new(locator: Locator, spool: Arc<Spool>, notes: Notes) -> Writer {
        Writer {
            locator,
            spool,
            notes,
            store: None,
            stored: HashSet::new(),
            spooled: HashSet::new(),
            lost: HashSet::new(),
        }
    }

    pub fn run(mut self, queue: Receiver<Job>) {
        while let Ok(first) = queue.recv() {
            let mut batch = Vec::new();
            let mut flush = None;
            match first {
                Job::Record(r) => batch.push(*r),
                Job::Flush(run, ack) => flush = Some((run, ack)),
            }
            while flush.is_none() && batch.len() < BATCH {
                match queue.try_recv() {
                    Ok(Job::Record(r)) => batch.push(*r),
                    Ok(Job::Flush(run, ack)) => flush = Some((run, ack)),
                    Err(_) => break,
                }
            }
            if !batch.is_empty() {
                self.write(batch);
            }
            if let Some((run, ack)) = flush {
                let _ = ack.send(self.landed(&run));
            }
        }
    }

    fn write(&mut self, batch: Vec<Record>) {
        let mut to_store = Vec::new();
        let mut to_spool = Vec::new();
        for record in batch {
            let run = record.run().to_string();
            if !self.spooled.contains(&run) && matches!(record, Record::Started(_)) {
                if let Err(e) = self.open() {
                    self.spool_run(&run, &e);
                }
            }
            if self.spooled.contains(&run) {
                to_spool.push(record);
            } else if self.store.is_none() {
                let e = StoreError::Unreachable {
                    store: self.locator.name(),
                    why: "it failed earlier in this command".into(),
                };
                self.spool_run(&run, &e);
                to_spool.push(record);
            } else {
                to_store.push(record);
            }
        }
        if let Some(store) = self.store.as_mut() {
            if !to_store.is_empty() {
                match store.apply_all(&to_store) {
                    Ok(()) => {
                        for r in &to_store {
                            if let Record::Started(row) = r {
                                self.stored.insert(row.id.clone());
                            }
                        }
                        // The file alone holds every finished run.
                        if to_store.iter().any(|r| matches!(r, Record::Finished(_))) {
                            store.checkpoint();
                        }
                    }
                    Err(e) => {
                        if matches!(e, StoreError::Unreachable { .. } | StoreError::Query { .. }) {
                            self.store = None;
                        }
                        let mut runs: Vec<String> = to_store.iter().map(|r| r.run().to_string()).collect();
                        runs.dedup();
                        for run in runs {
                            self.spool_run(&run, &e);
                        }
                        // The runs' earlier records came first: the spool keeps their order.
                        to_store.append(&mut to_spool);
                        to_spool = to_store;
                    }
                }
            }
        }
        if let Err(e) = self.spool.append(&to_spool) {
            let mut runs: Vec<&str> = to_spool.iter().map(Record::run).collect();
            runs.dedup();
            // Said once a run: its later batches fail the same way.
            runs.retain(|r| self.lost.insert(r.to_string()));
            if !runs.is_empty() {
                note(
                    &self.notes,
                    &format!("results: records of run {} are lost: {e}", runs.join(", ")),
                );
            }
        }
    }

    fn landed(&self, run: &str) -> Landed {
        if self.lost.contains(run) {
            Landed::Lost
        } else if self.stored.contains(run) && !self.spooled.contains(run) {
            Landed::Stored
        } else {
            Landed::Spooled
        }
    }

    /// Sends what is left of `run` to the spool from now on, saying why once.
    fn spool_run(&mut self, run: &str, why: &StoreError) {
        if self.spooled.insert(run.to_string()) {
            note(
                &self.notes,
                &format!(
                    "results: {why}\nresults: run {run} goes to this bench's spool, {}",
                    self.spool.path().display()
                ),
            );
        }
    }

    /// Opens the store when it is not open, delivering the spool first.
    fn open(&mut self) -> Result<(), StoreError> {
        if self.store.is_some() {
            return Ok(());
        }
        let mut store = self.locator.open(true)?;
        if self.spool.pending() {
            match self.spool.deliver(&mut store) {
                Ok(d) => {
                    if d.runs > 0 {
                        note(
                            &self.notes,
                            &format!("results: delivered {} spooled run(s) to {}", d.runs, store.name()),
                        );
                    }
                    for (run, why) in &d.refused {
                        note(
                            &self.notes,
                            &format!("results: spooled run {run} stays in the spool: {why}"),
                        );
                    }
                }
                Err(e) => note(&self.notes, &format!("results: the spool stays for later: {e}")),
            }
        }
        self.store = Some(store);
        Ok(())
    }
}
