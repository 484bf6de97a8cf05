//! The run observer that records a run in the store as it goes: the run at its start, the
//! unit's identity when known, each step and check as decided, and the end (verdict, the
//! safe stop's verified end state, the plot series) — after the safe stop, never on its
//! path. The session only hands records to a bounded queue without waiting: what the
//! queue has no room for waits, in order, in the run's own list until there is room, so a
//! slow, locked or dead store never holds up a step or a stop and no record is dropped or
//! overtaken. The end of the run waits (bounded) for the writer; what the store has not
//! committed by then goes whole to the spool, delivered by the next run or `results sync`,
//! and the run says where its record is.

use super::record::{CheckRow, EndRow, Record, RunRow, SeriesRow, StepRow};
use super::results_writer::{Job, Landed, Writer};
use super::{Locator, Spool};
use crate::session::{CheckResult, RunInfo, RunObserver, RunReport, StepRecord, UnitIdentity, MAX_RECORDS};
use crate::stop_request::StopRequests;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::io::Write;
use std::sync::mpsc::{sync_channel, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime};

/// Records waiting for the writer at most; past that they wait in the run's list.
const QUEUE: usize = 4096;
/// How long the end of a run waits for the writer to catch up (the drive is stopped by
/// then); a store slower than that finds the rest in the spool next time.
const FINISH_WAIT: Duration = Duration::from_secs(30);

/// What the command line knows of every run of the command.
#[derive(Debug, Clone, Default)]
pub struct RecorderSettings {
    /// The run is on the built-in simulated drive.
    pub simulated: bool,
    /// The port, TCP address or CAN bus.
    pub port: Option<String>,
    pub address: Option<String>,
    /// What is known of each file before it runs.
    pub files: Vec<FileFacts>,
    /// Say nothing when all goes well (`--quiet`).
    pub quiet: bool,
}

/// One file of the command, as the command line knows it before the run.
#[derive(Debug, Clone, Default)]
pub struct FileFacts {
    /// The file's path as given (as [`RunInfo::path`] says it).
    pub path: String,
    /// The dictionary it runs with and that dictionary's family.
    pub dictionary: Option<String>,
    pub family: Option<String>,
    /// The report files it writes.
    pub report_files: Vec<String>,
}

/// Where the recorder's notes go (the command line gives standard error).
pub type Notes = Arc<Mutex<dyn Write + Send>>;

/// The observer; see the module.
pub struct ResultsRecorder {
    settings: RecorderSettings,
    store_name: String,
    jobs: SyncSender<Job>,
    spool: Arc<Spool>,
    notes: Notes,
    run: Option<CurrentRun>,
    /// The run's stop requests: a signal after the safe stop ends the wait for the store.
    stop: Option<Arc<StopRequests>>,
}

#[derive(Default)]
struct CurrentRun {
    id: String,
    path: String,
    steps: Kept,
    checks: Kept,
    attempts: HashMap<(String, String), i64>,
    /// Every record of the run (bounded as the report's records are): spooled whole when
    /// the writer has not taken them all by the end, so records still in the queue of a
    /// stuck writer are not lost with the process. Replaying one twice changes nothing.
    sent: Vec<Record>,
    /// How many of `sent` are in the writer's queue; the rest wait for room, in order.
    handed: usize,
}

/// Records of one kind kept for a run, as the run report keeps them: every failure, and
/// passed ones up to [`MAX_RECORDS`].
#[derive(Default)]
struct Kept {
    count: i64,
    omitted: i64,
}

impl Kept {
    /// The sequence number of the next record, or `None` when a passed one is left out.
    fn next(&mut self, passed: bool) -> Option<i64> {
        if passed && self.count >= MAX_RECORDS as i64 {
            self.omitted += 1;
            return None;
        }
        self.count += 1;
        Some(self.count)
    }
}

impl ResultsRecorder {
    /// A recorder writing to `locator` from a thread of its own.
    pub fn start(locator: Locator, settings: RecorderSettings, notes: Notes) -> ResultsRecorder {
        let (jobs, queue) = sync_channel(QUEUE);
        let spool = Arc::new(Spool::new(locator.spool_path()));
        let store_name = locator.name();
        let writer = Writer::new(locator, spool.clone(), notes.clone());
        let spawned = std::thread::Builder::new()
            .name("results".into())
            .spawn(move || writer.run(queue));
        if let Err(e) = spawned {
            note(
                &notes,
                &format!(
                    "results: cannot start the writer ({e}); runs go to {}",
                    spool.path().display()
                ),
            );
        }
        ResultsRecorder {
            settings,
            store_name,
            jobs,
            spool,
            notes,
            run: None,
            stop: None,
        }
    }

    /// The recorder whose wait at the end of a run a stop signal cuts short.
    pub fn with_stop(mut self, stop: Arc<StopRequests>) -> Self {
        self.stop = Some(stop);
        self
    }

    /// Hands `record` and those waiting before it to the writer, as many as the queue has
    /// room for; never waits.
    fn send(&mut self, record: Record) {
        let Some(run) = self.run.as_mut() else { return };
        run.sent.push(record);
        while run.handed < run.sent.len() {
            let job = Job::Record(Box::new(run.sent[run.handed].clone()));
            match self.jobs.try_send(job) {
                Ok(()) => run.handed += 1,
                // The writer catches up later; the run's end waits for it.
                Err(TrySendError::Full(_)) => return,
                // No writer (it could not start): the run's end spools the whole run.
                Err(TrySendError::Disconnected(_)) => return,
            }
        }
    }

    /// Whether a stop signal came since `before` signals: the end of the run stops
    /// waiting for the store then.
    fn signals(&self) -> usize {
        self.stop.as_ref().map_or(0, |s| s.count_at(Duration::ZERO))
    }

    /// Hands the rest of `run` to the writer and waits (at most [`FINISH_WAIT`], and only
    /// until a stop signal comes) until the writer has handled all of it: where the run's
    /// records went, `None` when the writer did not answer in time.
    fn flushed(&self, run: &mut CurrentRun) -> Option<Landed> {
        let before = self.signals();
        let started = Instant::now();
        let waited_enough = || started.elapsed() >= FINISH_WAIT || self.signals() > before;
        let (ack, done) = sync_channel(1);
        let mut flush = Some(Job::Flush(run.id.clone(), ack));
        loop {
            let job = match run.sent.get(run.handed) {
                Some(r) => Job::Record(Box::new(r.clone())),
                None => match flush.take() {
                    Some(f) => f,
                    None => break,
                },
            };
            match self.jobs.try_send(job) {
                Ok(()) => {
                    if run.handed < run.sent.len() {
                        run.handed += 1;
                    }
                }
                Err(TrySendError::Full(job)) => {
                    if let Job::Flush(..) = job {
                        flush = Some(job);
                    }
                    if waited_enough() {
                        return None;
                    }
                    std::thread::sleep(Duration::from_millis(2));
                }
                Err(TrySendError::Disconnected(_)) => return None,
            }
        }
        loop {
            match done.recv_timeout(Duration::from_millis(50)) {
                Ok(stored) => return Some(stored),
                Err(RecvTimeoutError::Disconnected) => return None,
                Err(RecvTimeoutError::Timeout) => {}
            }
            if waited_enough() {
                return None;
            }
        }
    }
}

pub(super) fn note(notes: &Notes, text: &str) {
    if let Ok(mut w) = notes.lock() {
        let _ = writeln!(w, "{text}");
    }
}

/// UTC, RFC 3339 with milliseconds: sorts as text.
pub fn utc_text(at: SystemTime) -> String {
    humantime::format_rfc3339_millis(at).to_string()
}

/// A run id nobody else makes: 16 hex digits from the time, the process and a counter.
fn new_run_id() -> String {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let nanos = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let mut h = Sha256::new();
    h.update(nanos.to_le_bytes());
    h.update(std::process::id().to_le_bytes());
    h.update(n.to_le_bytes());
    h.update(format!("{:?}", std::thread::current().id()).as_bytes());
    h.finalize().iter().take(8).map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 of the file's exact text, in hex.
fn file_sha256(path: &str) -> Option<String> {
    let bytes = std::fs::read(path).ok()?;
    Some(
        Sha256::digest(&bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect(),
    )
}

impl ResultsRecorder {
    /// The run's row as it starts, under a new id.
    fn started_row(&self, run: &RunInfo, drive: &str) -> RunRow {
        let id = new_run_id();
        let facts = self
            .settings
            .files
            .iter()
            .find(|f| f.path == run.path)
            .cloned()
            .unwrap_or_default();
        let row = RunRow {
            id: id.clone(),
            kind: run.kind.to_string(),
            recipe: run.name.clone(),
            recipe_path: run.path.clone(),
            recipe_sha256: run.text_sha256.clone().or_else(|| file_sha256(&run.path)),
            tool_version: env!("CARGO_PKG_VERSION").to_string(),
            started_at: utc_text(SystemTime::now()),
            simulated: self.settings.simulated,
            drive: drive.to_string(),
            dictionary: facts.dictionary,
            family: facts.family,
            port: self.settings.port.clone(),
            address: self.settings.address.clone(),
            host: std::env::var("HOSTNAME").ok().or_else(|| {
                std::fs::read_to_string("/etc/hostname")
                    .ok()
                    .map(|h| h.trim().to_string())
            }),
            unit: run.unit.clone(),
            params: run.params.clone(),
        };
        row
    }

    /// Hands the run's end to the writer and waits (bounded) until the store has the
    /// whole run, else spools all of it; says where the run's record is — "recorded"
    /// only once the store committed it, and a run kept on this bench even with `--quiet`.
    fn finish(&mut self, mut run: CurrentRun, end: EndRow) {
        run.sent.push(Record::Finished(end));
        let flushed = self.flushed(&mut run);
        if flushed == Some(Landed::Stored) {
            if !self.settings.quiet {
                note(
                    &self.notes,
                    &format!("results: run {} recorded in {}", run.id, self.store_name),
                );
            }
            return;
        }
        let lost = match flushed {
            // The writer spooled what the store did not commit.
            Some(Landed::Spooled | Landed::Stored) => None,
            // The writer could not spool some of it (and said why): they are not kept.
            Some(Landed::Lost) => {
                note(
                    &self.notes,
                    &format!(
                        "results: run {} is neither wholly in {} nor kept on this bench",
                        run.id, self.store_name
                    ),
                );
                return;
            }
            None => self.spool.append(&run.sent).err(),
        };
        if flushed.is_none() {
            note(
                &self.notes,
                &format!(
                    "results: {} had not taken the whole run when it ended (it did not answer within {} s, or a stop signal came)",
                    self.store_name,
                    FINISH_WAIT.as_secs(),
                ),
            );
        }
        let said = match lost {
            None => format!(
                "results: run {} is kept on this bench, not yet in {} — `drivescript results sync` delivers it (kept in {})",
                run.id,
                self.store_name,
                self.spool.path().display()
            ),
            Some(e) => format!(
                "results: what of run {} {} has not taken is lost: {e}",
                run.id, self.store_name
            ),
        };
        note(&self.notes, &said);
    }
}

impl RunObserver for ResultsRecorder {
    fn run_started(&mut self, run: &RunInfo, drive: &str) {
        let row = self.started_row(run, drive);
        self.run = Some(CurrentRun {
            id: row.id.clone(),
            path: run.path.clone(),
            ..CurrentRun::default()
        });
        self.send(Record::Started(row));
    }

    /// A run refused before it started is kept for its unit (verdict `refused`, or
    /// `error` when the drive could not be reached), with the reason and no checks; one
    /// without a serial number is a file being written, not a unit's history.
    fn run_refused(&mut self, run: &RunInfo, exit_code: i32, why: &str) {
        if run.unit.serial.is_none() {
            return;
        }
        let row = self.started_row(run, super::record::NOT_STARTED);
        let id = row.id.clone();
        self.run = Some(CurrentRun {
            id: id.clone(),
            path: run.path.clone(),
            ..CurrentRun::default()
        });
        self.send(Record::Started(row));
        let Some(current) = self.run.take() else { return };
        let verdict = if exit_code == crate::session::ERROR_EXIT {
            "error"
        } else {
            "refused"
        };
        let end = EndRow {
            run: id,
            ended_at: utc_text(SystemTime::now()),
            verdict: verdict.into(),
            exit_code: i64::from(exit_code),
            reason: Some(why.trim().to_string()),
            ..EndRow::default()
        };
        self.finish(current, end);
    }

    fn unit_identified(&mut self, unit: &UnitIdentity) {
        if let Some(run) = &self.run {
            let record = Record::Unit {
                run: run.id.clone(),
                unit: unit.clone(),
            };
            self.send(record);
        }
    }

    fn step_finished(&mut self, step: &StepRecord) {
        let Some(run) = self.run.as_mut() else { return };
        let Some(seq) = run.steps.next(step.ok) else {
            return;
        };
        let record = Record::Step(StepRow {
            run: run.id.clone(),
            seq,
            step: step.id.clone(),
            label: step.label.clone(),
            ok: step.ok,
            detail: step.detail.clone(),
            phase: step.phase.to_string(),
            started_s: step.started.as_secs_f64(),
            duration_s: step.duration.as_secs_f64(),
        });
        self.send(record);
    }

    fn check(&mut self, c: &CheckResult) {
        let Some(run) = self.run.as_mut() else { return };
        let attempt = run.attempts.entry((c.name.clone(), c.step.clone())).or_insert(0);
        *attempt += 1;
        let attempt = *attempt;
        let Some(seq) = run.checks.next(c.passed) else {
            return;
        };
        let record = Record::Check(CheckRow {
            run: run.id.clone(),
            seq,
            name: c.name.clone(),
            key: Some(c.key.clone()),
            inclusive: Some(c.inclusive),
            measured: c.measured,
            measured_text: c.measured_text.clone(),
            unit: c.unit.clone(),
            limits: c.limits,
            passed: c.passed,
            marginal: c.marginal,
            step: c.step.clone(),
            stage: c.stage.clone(),
            attempt,
            message: c.message.clone(),
            reference_run: c.reference.as_ref().map(|r| r.run.clone()),
            reference_at: c.reference.as_ref().map(|r| r.started_at.clone()),
            reference_value: c.reference.as_ref().map(|r| r.value),
            decimals: c.decimals.and_then(|d| i64::try_from(d).ok()),
        });
        self.send(record);
    }

    fn run_finished(&mut self, r: &RunReport) {
        let Some(run) = self.run.take() else { return };
        let mut files = self
            .settings
            .files
            .iter()
            .find(|f| f.path == run.path)
            .map(|f| f.report_files.clone())
            .unwrap_or_default();
        files.extend(r.csv_files.iter().cloned());
        let end = EndRow {
            run: run.id.clone(),
            ended_at: utc_text(SystemTime::now()),
            verdict: r.verdict.word().to_lowercase(),
            exit_code: i64::from(r.exit_code()),
            reason: r.verdict.reason(),
            drive_identity: r.identity.clone(),
            final_state: r.end.final_state.map(|s| s.to_string()),
            final_speed: r.end.final_speed,
            speed_unit: r.end.speed_unit.clone(),
            coasting: r.end.coasting,
            stop_confirmed: r.end.stop_confirmed,
            safe_stop: r.safe_stop.clone(),
            report_files: files,
            series: r
                .series
                .iter()
                .map(|s| SeriesRow {
                    object: s.object.clone(),
                    unit: s.unit.clone(),
                    step: s.step.clone(),
                    points: s.points.clone(),
                })
                .collect(),
            omitted_steps: run.steps.omitted,
            omitted_checks: run.checks.omitted,
        };
        self.finish(run, end);
    }
}
