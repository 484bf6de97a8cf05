//! The fault campaign: for every family's simulated drive (SD2 object access and cyclic,
//! CT ANSI, Lenze 931, Lenze 9400, CANopen CiA 402, Modbus RTU and TCP) recipes generated
//! from the step grammar, each run with one fault injected at a random moment — a trip, a
//! lost or silent line, late, garbled or corrupt replies, an EMCY, a heartbeat loss, a stop
//! signal, a second signal, a panic, a drive that disobeys, a results store that goes
//! away — half of them inside the safe stop (placed by a dry run of the same recipe), and
//! the invariants of `judge` held on what each run left. In process, in virtual time.
//!
//! Seeded and reproducible: seed N picks the family (N mod 8), the recipe and the fault.
//! `DRIVESCRIPT_CAMPAIGN_SEED=N[,M…]` replays those seeds, `DRIVESCRIPT_CAMPAIGN_SCENARIOS`
//! (and `DRIVESCRIPT_CAMPAIGN_FIRST`) runs any count; a failure prints the seed and the
//! command that replays it; `DRIVESCRIPT_CAMPAIGN_VERBOSE=1` lists every scenario's fault
//! and exit code. `DRIVESCRIPT_CAMPAIGN_KEEP=1` writes each failed scenario as a case under
//! `tests/cases/` (see `kept`), `=all` every scenario run (the seeds a fix made pass, with
//! the ending they have now); the seeds of kept cases run in every campaign.

mod fault;
mod judge;
mod kept;
#[cfg(unix)]
mod live;
mod recipe_gen;
mod target;

use crate::support::{repo_root, scratch, write_file, InProcessRun};
use drivescript::clock::SharedClock;
use drivescript::results::{Locator, RecorderSettings, ResultsRecorder, RunFilter, Spool};
use drivescript::run::{SafeStopArgs, SharedObserver};
use drivescript::session::{RunObserver, RunReport, StepRecord};
use drivescript::sim::SimulatedDrive;
use fault::{Fault, Kind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};
use std::time::{Duration, Instant};

/// Scenarios a plain `cargo test` runs (40 per family).
const SCENARIOS: u64 = 320;
const STOP_TIMEOUT: Duration = Duration::from_secs(20);
const RECONNECT_TIMEOUT: Duration = Duration::from_secs(3);
/// The stop's timeout (twice: braking, then a coasting drive), the reconnect, an own
/// `finally`'s wait and a margin for the link's retries.
const STOP_BOUND: Duration = Duration::from_secs(2 * 20 + 3 + 20 + 15);
/// A scenario that has not ended after this much real time hangs.
const HANG: Duration = Duration::from_secs(120);

/// What one scenario came to.
pub struct Outcome {
    pub seed: u64,
    pub target: &'static str,
    pub exit: i32,
    pub fault: Option<Fault>,
    pub problems: Vec<String>,
    pub console: String,
    pub recipe: String,
    /// The stop began at (this run).
    pub stop_start: Duration,
}

/// The seeds to run: the ones named, else the kept cases' and a range.
fn seeds() -> Vec<u64> {
    let number = |name: &str| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.trim().parse::<u64>().ok())
    };
    if let Ok(named) = std::env::var("DRIVESCRIPT_CAMPAIGN_SEED") {
        return named.split(',').filter_map(|s| s.trim().parse().ok()).collect();
    }
    let first = number("DRIVESCRIPT_CAMPAIGN_FIRST").unwrap_or(0);
    let count = number("DRIVESCRIPT_CAMPAIGN_SCENARIOS").unwrap_or(SCENARIOS);
    let mut seeds: Vec<u64> = (first..first + count).collect();
    for kept in kept::seeds() {
        if !seeds.contains(&kept) {
            seeds.push(kept);
        }
    }
    seeds
}

/// The line that replays `seed`.
pub fn replay_command(seed: u64) -> String {
    format!("DRIVESCRIPT_CAMPAIGN_SEED={seed} cargo test --test integration fault_campaign -- --nocapture")
}

#[test]
fn fault_campaign() {
    let seeds = seeds();
    let dir = scratch("runs");
    let started = Instant::now();
    let next = AtomicUsize::new(0);
    let outcomes = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(&seed) = seeds.get(i) else { break };
                let outcome = watched(seed, &dir);
                outcomes
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .push(outcome);
            });
        }
    });
    let mut outcomes = outcomes.into_inner().unwrap_or_else(PoisonError::into_inner);
    outcomes.sort_by_key(|o| o.seed);
    let failed: Vec<&Outcome> = outcomes.iter().filter(|o| !o.problems.is_empty()).collect();
    eprintln!(
        "fault campaign: {} scenario(s) in {:.1} s of real time",
        outcomes.len(),
        started.elapsed().as_secs_f64()
    );
    let mut exits: Vec<(i32, usize)> = Vec::new();
    for o in &outcomes {
        match exits.iter_mut().find(|(e, _)| *e == o.exit) {
            Some((_, n)) => *n += 1,
            None => exits.push((o.exit, 1)),
        }
    }
    exits.sort_unstable();
    eprintln!("  exit codes (code×count): {exits:?}");
    for t in target::TARGETS {
        let of: Vec<&Outcome> = outcomes.iter().filter(|o| o.target == t.name).collect();
        let bad: Vec<String> = of
            .iter()
            .filter(|o| !o.problems.is_empty())
            .map(|o| o.seed.to_string())
            .collect();
        eprintln!(
            "  {:<11} {:>4} ran, {:>3} failed{}",
            t.name,
            of.len(),
            bad.len(),
            if bad.is_empty() {
                String::new()
            } else {
                format!(": seeds {}", bad.join(","))
            }
        );
    }
    if std::env::var("DRIVESCRIPT_CAMPAIGN_VERBOSE").is_ok_and(|v| v == "1") {
        for o in &outcomes {
            let fault = o.fault.map_or("refused before a fault".into(), |f| f.describe());
            eprintln!(
                "  seed {:>5} {:<11} exit {:>3}  {fault}",
                o.seed, o.target, o.exit
            );
        }
    }
    let keep = std::env::var("DRIVESCRIPT_CAMPAIGN_KEEP").unwrap_or_default();
    if keep == "all" {
        outcomes.iter().for_each(kept::write);
    }
    let keep = keep == "1";
    let mut text = String::new();
    for o in &failed {
        text.push_str(&format!(
            "\n== seed {} ({}), {}, exit {}, stop began at {:?}\n  replay: {}\n  {}\n--- recipe ---\n{}--- console ---\n{}",
            o.seed,
            o.target,
            o.fault.map_or("no fault placed".into(), |f| f.describe()),
            o.exit,
            o.stop_start,
            replay_command(o.seed),
            o.problems.join("\n  "),
            o.recipe,
            o.console
        ));
        if keep {
            kept::write(o);
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {} scenario(s) broke an invariant (seeds {}):{text}",
        failed.len(),
        outcomes.len(),
        failed
            .iter()
            .map(|o| o.seed.to_string())
            .collect::<Vec<_>>()
            .join(",")
    );
}

/// Runs `seed` on a thread of its own; a scenario that does not end in time is a failure
/// (the thread is left behind).
fn watched(seed: u64, dir: &Path) -> Outcome {
    let (done, result) = std::sync::mpsc::channel();
    let dir = dir.to_path_buf();
    std::thread::spawn(move || {
        let _ = done.send(scenario(seed, &dir));
    });
    result.recv_timeout(HANG).unwrap_or_else(|e| Outcome {
        seed,
        target: target::target_of(seed).name,
        exit: -1,
        fault: None,
        problems: vec![format!(
            "the scenario did not end within {HANG:?} of real time ({e})"
        )],
        console: String::new(),
        recipe: String::new(),
        stop_start: Duration::ZERO,
    })
}

/// A run of `recipe` with the campaign's safe-stop settings.
fn base_run<'a>(recipe: &Path) -> InProcessRun<'a> {
    let mut run = InProcessRun::new(recipe);
    run.safe_stop = SafeStopArgs {
        stop_timeout: Some(STOP_TIMEOUT),
        reconnect_timeout: Some(RECONNECT_TIMEOUT),
        ..SafeStopArgs::default()
    };
    run
}

/// When the steps ended (and the safe stop began): the end of the last step record of the
/// steps themselves.
fn steps_end(report: &RunReport) -> Duration {
    report
        .steps
        .iter()
        .filter(|s| s.phase == "steps")
        .map(|s| s.started + s.duration)
        .max()
        .unwrap_or(Duration::ZERO)
}

/// Locks the results store from the `after`-th finished step on (0: at once), as a
/// store that goes away: another connection holds it exclusively.
struct StoreGone {
    path: PathBuf,
    after: usize,
    seen: usize,
    lock: Option<rusqlite::Connection>,
}

impl StoreGone {
    fn take(&mut self) {
        if self.lock.is_none() {
            let conn = rusqlite::Connection::open(&self.path).expect("the store opens");
            conn.execute_batch("BEGIN EXCLUSIVE").expect("the store locks");
            self.lock = Some(conn);
        }
    }
}

impl RunObserver for StoreGone {
    fn step_finished(&mut self, _record: &StepRecord) {
        self.seen += 1;
        if self.seen >= self.after {
            self.take();
        }
    }
}

/// The verdict the store holds for the run named `name`, after delivering its spool.
fn stored_verdict(store: &Path, name: &str) -> Result<String, String> {
    let locator = Locator::parse(&store.display().to_string());
    let mut s = locator.open(true).map_err(|e| e.to_string())?;
    let spool = Spool::new(locator.spool_path());
    if locator.spool_path().exists() {
        spool.deliver(&mut s).map_err(|e| format!("the spool: {e}"))?;
    }
    let runs = s
        .list(&RunFilter {
            simulated: true,
            ..RunFilter::default()
        })
        .map_err(|e| e.to_string())?;
    let run = runs
        .iter()
        .find(|r| r.run.recipe == name)
        .ok_or_else(|| format!("no run {name} among {} stored", runs.len()))?;
    Ok(s.run(&run.run.id)
        .map_err(|e| e.to_string())?
        .verdict()
        .to_string())
}

/// One scenario, start to end.
pub fn scenario(seed: u64, dir: &Path) -> Outcome {
    let target = target::target_of(seed);
    let mut rng = recipe_gen::Rng::new(seed);
    let generated = recipe_gen::recipe(seed, &target, &mut rng);
    let work = dir.join(format!("seed-{seed}"));
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).expect("scratch folder");
    let recipe = write_file(&work, "recipe.yaml", &generated.yaml);
    let mut outcome = Outcome {
        seed,
        target: target.name,
        exit: 0,
        fault: None,
        problems: Vec::new(),
        console: String::new(),
        recipe: generated.yaml.clone(),
        stop_start: Duration::ZERO,
    };
    // The dry run: where the safe stop begins without a fault.
    let dry_clock: Arc<OnceLock<SharedClock>> = Arc::new(OnceLock::new());
    let dry_slot = dry_clock.clone();
    let keep_clock = move |_: &Arc<Mutex<dyn SimulatedDrive>>, c: &SharedClock| {
        let _ = dry_slot.set(c.clone());
    };
    let mut dry = base_run(&recipe);
    dry.output_dir = work.clone();
    dry.prepare = Some(&keep_clock);
    let (ran, console) = dry.run();
    drop(dry);
    let Some(report) = ran.report else {
        outcome.exit = ran.exit_code;
        outcome.console = console;
        if ran.exit_code != 2 {
            outcome
                .problems
                .push(format!("the dry run did not start (exit {})", ran.exit_code));
        }
        return outcome;
    };
    let dry_start = steps_end(&report);
    let dry_end = dry_clock.get().map_or(dry_start, |c| c.now());
    let fault = fault::choose(&target, &mut rng, dry_start, dry_end);
    outcome.fault = Some(fault);
    let (junit, html, store) = (
        work.join("junit.xml"),
        work.join("report.html"),
        work.join("results.sqlite"),
    );
    let clock: Arc<OnceLock<SharedClock>> = Arc::new(OnceLock::new());
    let slot = clock.clone();
    let prepare = move |sim: &Arc<Mutex<dyn SimulatedDrive>>, c: &SharedClock| {
        let _ = slot.set(c.clone());
        fault.inject(&mut *sim.lock().unwrap_or_else(PoisonError::into_inner));
    };
    let recorder = ResultsRecorder::start(
        Locator::parse(&store.display().to_string()),
        RecorderSettings {
            simulated: true,
            quiet: true,
            ..RecorderSettings::default()
        },
        Arc::new(Mutex::new(std::io::sink())),
    );
    let gone = Arc::new(Mutex::new(StoreGone {
        path: store.clone(),
        after: match fault.kind {
            Kind::StoreGone(after) => after,
            _ => usize::MAX,
        },
        seen: 0,
        lock: None,
    }));
    if matches!(fault.kind, Kind::StoreGone(0)) {
        gone.lock().unwrap_or_else(PoisonError::into_inner).take();
    }
    let mut run = base_run(&recipe);
    run.output_dir = work.clone();
    run.outputs.junit = Some(junit.clone());
    run.outputs.report = Some(html.clone());
    run.prepare = Some(&prepare);
    fault.schedule(&run.stop);
    run.observers.push(gone.clone() as SharedObserver);
    run.observers
        .push(Arc::new(Mutex::new(recorder)) as SharedObserver);
    let (result, console) = run.run();
    drop(run);
    gone.lock().unwrap_or_else(PoisonError::into_inner).lock = None;
    outcome.exit = result.exit_code;
    outcome.console = console;
    let now = clock.get().map_or(Duration::ZERO, |c| c.now());
    let (state, speed_rpm, changes) = match &result.simulator {
        Some(sim) => {
            let sim = sim.lock().unwrap_or_else(PoisonError::into_inner);
            (
                target.controlled.then(|| sim.state()),
                sim.speed_rpm(now),
                sim.commanded_changes(),
            )
        }
        None => (None, 0.0, Vec::new()),
    };
    let this_end = result.report.as_ref().map_or(Duration::ZERO, steps_end);
    outcome.stop_start = fault.signal_at().map_or(this_end, |s| s.min(this_end));
    let ended = judge::Ended {
        exit: result.exit_code,
        report: result.report.as_ref(),
        console: &outcome.console,
        junit: std::fs::read_to_string(&junit).ok(),
        html: std::fs::read_to_string(&html).ok(),
        stored: stored_verdict(&store, &generated.name),
        state,
        speed_rpm,
        changes,
        stop_start: outcome.stop_start,
        end: now,
        stop_bound: STOP_BOUND,
    };
    outcome.problems = judge::problems(&ended);
    if outcome.problems.is_empty() {
        let _ = std::fs::remove_dir_all(&work);
    }
    outcome
}

/// Where kept cases live.
fn cases_root() -> PathBuf {
    repo_root().join("tests/cases")
}
