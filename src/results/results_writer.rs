//! The recorder's writer thread: takes records off the queue and writes each to the store,
//! opening it (and delivering the spool first) at a run's start; a run the store fails
//! during goes on to the spool, so a run's records are never split between a store that
//! came back and the spool.

use super::record::Record;
use super::results_recorder::note;
use super::{Locator, Notes, Spool, Store, StoreError};
use std::collections::HashSet;
use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::Arc;

/// What the recorder puts on the queue.
pub enum Job {
    Record(Box<Record>),
    /// Answered once everything before it is handled.
    Flush(SyncSender<()>),
}

/// The writer thread's side.
pub struct Writer {
    locator: Locator,
    spool: Arc<Spool>,
    notes: Notes,
    store: Option<Store>,
    /// Runs whose records go to the spool (the store failed during them).
    spooled: HashSet<String>,
}

impl Writer {
    pub fn new(locator: Locator, spool: Arc<Spool>, notes: Notes) -> Writer {
        Writer {
            locator,
            spool,
            notes,
            store: None,
            spooled: HashSet::new(),
        }
    }

    pub fn run(mut self, queue: Receiver<Job>) {
        for job in queue {
            match job {
                Job::Flush(ack) => {
                    let _ = ack.send(());
                }
                Job::Record(record) => self.write(*record),
            }
        }
    }

    fn write(&mut self, record: Record) {
        let run = record.run().to_string();
        if !self.spooled.contains(&run) {
            let result = self.deliver(&record);
            let Err(e) = result else { return };
            self.spooled.insert(run.clone());
            if matches!(e, StoreError::Unreachable { .. } | StoreError::Query { .. }) {
                self.store = None;
            }
            note(
                &self.notes,
                &format!(
                    "results: {e}\nresults: run {run} is kept in {} and delivered by the next run or `drivescript results sync`",
                    self.spool.path().display()
                ),
            );
        }
        if let Err(e) = self.spool.append(std::slice::from_ref(&record)) {
            note(
                &self.notes,
                &format!("results: a record of run {run} is lost: {e}"),
            );
        }
    }

    /// Writes `record` to the store, opening it (and delivering the spool) at a run's start.
    fn deliver(&mut self, record: &Record) -> Result<(), StoreError> {
        if self.store.is_none() && matches!(record, Record::Started(_)) {
            let mut store = self.locator.open(true)?;
            if self.spool.pending() {
                match self.spool.deliver(&mut store) {
                    Ok(d) if d.records > 0 => note(
                        &self.notes,
                        &format!("results: delivered {} spooled run(s) to {}", d.runs, store.name()),
                    ),
                    Ok(_) => {}
                    Err(e) => note(&self.notes, &format!("results: the spool stays for later: {e}")),
                }
            }
            self.store = Some(store);
        }
        match self.store.as_mut() {
            Some(store) => store.apply(record),
            None => Err(StoreError::Unreachable {
                store: self.locator.name(),
                why: "it failed earlier in this command".into(),
            }),
        }
    }
}
