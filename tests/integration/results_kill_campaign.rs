//! The results store under SIGKILL: record-heavy runs and `results sync`s killed at
//! random (seeded, replayable) moments while the store comes and goes, then one last
//! sync. Afterwards every run in the store is complete (its every step and its check) or
//! marked incomplete, no step or check is there without its run, every run that ended on
//! its own is there complete, and nothing is left in the spool or in a claim on it. `DRIVESCRIPT_KILL_SEED=N` replays a campaign.

use crate::results_integrity::{spool_files, stored_runs, take_offline, HEAVY};
use crate::support::{command, scratch_file, PostgresServer};
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// Steps of a whole run of [`HEAVY`] (its 6 000 prints, the check, the default finally).
const STEPS: i64 = 6006;

/// [`HEAVY`] with 1 000 prints, for a server (each record a round trip): 1 006 steps.
fn medium() -> String {
    HEAVY
        .replace("name: Heavy", "name: Medium")
        .replace("times: 6000", "times: 1000")
}

/// xorshift64: the campaign's moments, the same for the same seed.
struct Moments(u64);

impl Moments {
    fn new() -> Moments {
        let seed = std::env::var("DRIVESCRIPT_KILL_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(39);
        eprintln!("kill campaign seed {seed} (DRIVESCRIPT_KILL_SEED replays it)");
        Moments(seed.max(1))
    }
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// A duration in `0..below`.
    fn within(&mut self, below: Duration) -> Duration {
        let micros = below.as_micros().max(1) as u64;
        Duration::from_micros(self.next() % micros)
    }
}

/// What a campaign did.
#[derive(Debug, Default)]
struct Tally {
    kills: usize,
    /// Runs that ended on their own (exit code 0).
    runs_ended: usize,
    syncs_ended: usize,
}

/// `kills` SIGKILLs of runs of `recipe` and syncs into `store`, with `data` as the data
/// directory; every 20 actions the store goes off line (`offline(true)`: runs spool) or
/// back. Ends on line with a sync that is not killed.
fn campaign(recipe: &Path, store: &str, data: &Path, kills: usize, offline: &dyn Fn(bool)) -> Tally {
    let mut moments = Moments::new();
    let spawn = |args: &[&str]| {
        command()
            .envs(crate::support::data_home(data))
            .args(args)
            .args(["--results", store])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("starts")
    };
    let run_args = ["run", recipe.to_str().unwrap(), "--fast", "--quiet"];
    // How long a whole run takes here: the kills fall within it (some after it).
    let started = Instant::now();
    let status = spawn(&run_args).wait().expect("ends");
    assert_eq!(status.code(), Some(0));
    let whole = started.elapsed().mul_f64(1.3);
    let mut tally = Tally {
        runs_ended: 1,
        ..Tally::default()
    };
    let mut off = false;
    let mut action = 0;
    while tally.kills < kills {
        assert!(action < kills * 4, "too few kills landed: {tally:?}");
        if action % 20 == 19 {
            off = !off;
            offline(off);
        }
        action += 1;
        let sync = !off && moments.next().is_multiple_of(2);
        let mut child = if sync {
            spawn(&["results", "sync"])
        } else {
            spawn(&run_args)
        };
        std::thread::sleep(moments.within(whole));
        match child.try_wait().expect("waits") {
            None => {
                child.kill().expect("SIGKILL");
                child.wait().expect("ends");
                tally.kills += 1;
            }
            Some(status) => {
                assert_eq!(
                    status.code(),
                    Some(0),
                    "a {} ended badly",
                    if sync { "sync" } else { "run" }
                );
                if sync {
                    tally.syncs_ended += 1;
                } else {
                    tally.runs_ended += 1;
                }
            }
        }
    }
    if off {
        offline(false);
    }
    let sync = || {
        command()
            .envs(crate::support::data_home(data))
            .args(["results", "sync", "--results", store])
            .output()
            .expect("the last sync")
    };
    let mut last = sync();
    // Under Wine a killed process's connection can stay open to the server in the middle
    // of a transaction, its row locks held until the server ends the idle transaction
    // (30 s); a delivery of that run meanwhile stops at the 10 s statement limit and
    // leaves it in the spool, as it says. The sync is tried again until then: what is
    // judged is that nothing is lost or stranded.
    for _ in 0..4 {
        let said = String::from_utf8_lossy(&last.stderr).into_owned();
        // On Linux a killed process's connection closes with it: no retry there, so a
        // real lock held too long still fails the campaign.
        if !cfg!(windows) || last.status.code() == Some(0) || !said.contains("statement timeout") {
            break;
        }
        eprintln!("the last sync is tried again after: {said}");
        std::thread::sleep(Duration::from_secs(5));
        last = sync();
    }
    assert_eq!(
        last.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&last.stderr)
    );
    tally
}

/// Every run in `store` complete (`steps` steps and its check) or marked incomplete, at
/// least as many complete as ended on their own, nothing left in the spool's folder
/// `spools`.
fn nothing_lost_or_stranded(store: &str, spools: &Path, tally: &Tally, steps: i64) {
    let left = spool_files(spools);
    assert!(left.is_empty(), "stranded after the last sync: {left:?}");
    let orphans = "SELECT (SELECT count(*) FROM steps WHERE run_id NOT IN (SELECT id FROM runs)) \
         + (SELECT count(*) FROM checks WHERE run_id NOT IN (SELECT id FROM runs))";
    let orphans: i64 = if store.starts_with("postgres://") {
        let mut db = postgres::Client::connect(store, postgres::NoTls).expect("connects");
        db.query_one(orphans, &[]).expect("counted").get(0)
    } else {
        let db = rusqlite::Connection::open(store).expect("opens");
        db.query_row(orphans, [], |r| r.get(0)).expect("counted")
    };
    assert_eq!(orphans, 0, "steps or checks without their run");
    let runs = stored_runs(store);
    let mut complete = 0;
    for r in &runs {
        let Some(end) = &r.end else { continue };
        assert_eq!(
            (
                end.verdict.as_str(),
                r.steps.len() as i64 + end.omitted_steps,
                r.checks.len()
            ),
            ("passed", steps, 1),
            "run {} is marked finished but is not whole",
            r.run.id
        );
        complete += 1;
    }
    assert!(
        complete >= tally.runs_ended,
        "{complete} complete runs in the store, {} runs ended on their own: {tally:?}",
        tally.runs_ended
    );
    let bad = std::fs::read_dir(spools)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".bad"))
        .map(|e| {
            std::fs::read_to_string(e.path())
                .unwrap_or_default()
                .lines()
                .count()
        })
        .sum::<usize>();
    eprintln!(
        "{tally:?}: {} runs in the store, {complete} complete, {} incomplete; {bad} spool line(s) cut short by a kill",
        runs.len(),
        runs.len() - complete
    );
}

/// How many kills a campaign has on this system: under Wine each Windows process takes a
/// second or more to start, so there it has fewer (still enough that the store goes off
/// line and comes back while runs and syncs are killed).
fn kills(linux: usize, wine: usize) -> usize {
    if cfg!(windows) {
        wine
    } else {
        linux
    }
}

/// 200 SIGKILLs on SQLite, the store put aside (a directory in its place) every 20
/// actions so that runs spool and syncs deliver.
#[test]
fn sigkill_at_random_moments_of_runs_and_syncs_loses_or_strands_nothing_in_sqlite() {
    let started = Instant::now();
    let (dir, recipe) = scratch_file("kill-sqlite", "heavy.yaml", HEAVY);
    let store = dir.join("results.sqlite");
    let aside = dir.join("aside");
    std::fs::create_dir_all(&aside).expect("aside");
    let offline = |off: bool| take_offline(&store, &aside, off);
    let s = store.to_str().unwrap();
    let tally = campaign(&recipe, s, &dir, kills(200, 40), &offline);
    nothing_lost_or_stranded(s, &dir, &tally, STEPS);
    eprintln!(
        "{} kills on SQLite in {:.1} s",
        kills(200, 40),
        started.elapsed().as_secs_f64()
    );
}

/// 50 SIGKILLs on a real PostgreSQL server, stopped and started every 20 actions, of
/// runs of 1 006 steps (a queue's overflow on a server has its own test).
#[test]
fn sigkill_at_random_moments_of_runs_and_syncs_loses_or_strands_nothing_in_postgresql() {
    let Some(server) = PostgresServer::start("kill-postgres") else {
        return;
    };
    let started = Instant::now();
    let (dir, recipe) = scratch_file("kill-postgres-files", "medium.yaml", &medium());
    let url = server.url();
    let offline = |off: bool| if off { server.down() } else { server.up() };
    let tally = campaign(&recipe, &url, &dir, kills(50, 25), &offline);
    nothing_lost_or_stranded(&url, &dir.join("drivescript"), &tally, 1006);
    eprintln!(
        "{} kills on PostgreSQL in {:.1} s",
        kills(50, 25),
        started.elapsed().as_secs_f64()
    );
}
