//! A record is where the run says it is, and none is lost or stranded: a claim on the
//! spool left by a killed delivery is taken back, a queue without room keeps records in
//! order instead of splitting a run between the store and the spool, a NUL in an answer
//! is stored (PostgreSQL too) and holds up no other run, another application's SQLite
//! file is left untouched, a directory is no store, control characters never reach the
//! terminal or the CSV raw, "recorded in" only after the store committed, and the SQLite
//! file alone holds every finished run, on SQLite and on a real PostgreSQL server; and
//! the samples CSV holds the curves the HTML report plots.

use crate::support::{
    assert_has, assert_lacks, cli, command, postgres_with_folder, scratch, scratch_file, write_file, Ran,
};
use crate::support_store::{run_recorded, scratch_store};
use drivescript::results::{Locator, RunFilter, StoredRun};
use std::path::{Path, PathBuf};

/// The smallest recipe with a check.
const TINY: &str = "name: Tiny
drive: sd2
steps:
  - expect: { bus_voltage: { above: 100 V } }
";

/// A run of 6 006 steps and a check: more records than the recorder's queue holds.
pub const HEAVY: &str = "name: Heavy
drive: sd2
steps:
  - repeat:
      times: 6000
      steps:
        - print: \"pass\"
  - expect: { bus_voltage: { above: 100 V } }
";

/// Every run in `store`, simulated ones too, in detail.
pub fn stored_runs(store: &str) -> Vec<StoredRun> {
    let mut s = Locator::parse(store).open(false).expect("the store opens");
    let every = RunFilter {
        simulated: true,
        ..RunFilter::default()
    };
    let runs = s.list(&every).expect("list");
    runs.iter().map(|r| s.run(&r.run.id).expect("the run")).collect()
}

/// `drivescript run RECIPE --fast ARGS --results STORE` with `data` as the data
/// directory (where a server's spool is), ending with `code`.
#[track_caller]
fn run_into(recipe: &Path, store: &str, data: &Path, args: &[&str], code: i32) -> Ran {
    let out = command()
        .envs(crate::support::data_home(data))
        .arg("run")
        .arg(recipe)
        .args(["--fast", "--results", store])
        .args(args)
        .output()
        .expect("runs");
    Ran::exited(out, code)
}

/// `drivescript results ARGS --results STORE` with `data` as the data directory.
#[track_caller]
fn results_cmd(args: &[&str], store: &str, data: &Path, code: i32) -> Ran {
    let out = command()
        .envs(crate::support::data_home(data))
        .arg("results")
        .args(args)
        .args(["--results", store])
        .output()
        .expect("runs");
    Ran::exited(out, code)
}

/// The id of a process that has ended.
pub fn dead_pid() -> u32 {
    let mut child = crate::support::command()
        .arg("--version")
        .spawn()
        .expect("the binary runs");
    let pid = child.id();
    child.wait().expect("ends");
    pid
}

/// The spool file and every claim on it in `dir`.
pub fn spool_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            let name = p.file_name().unwrap_or_default().to_string_lossy().into_owned();
            name.ends_with(".spool") || name.contains(".spool.sending-")
        })
        .collect();
    files.sort();
    files
}

/// The spool of the PostgreSQL store `url` in the data directory `data`.
fn server_spool(data: &Path, url: &str) -> PathBuf {
    let dir = data.join("drivescript");
    let spool = Locator::parse(url).spool_path();
    dir.join(spool.file_name().expect("a file name"))
}

/// A spool whose delivery was killed (`FILE.sending-PID` of a process that is gone) is
/// delivered by the next sync — before, every later sync said "nothing to deliver" and
/// the run never reached the store; a claim of a process still delivering is left to it.
fn a_stale_claim_is_taken_back(store: &str, spool: &Path, data: &Path, offline: &dyn Fn(bool)) {
    let dir = spool.parent().expect("the spool's folder").to_path_buf();
    let recipe = write_file(&dir, "tiny.yaml", TINY);
    offline(true);
    let ran = run_into(&recipe, store, data, &["--quiet", "--unit", "serial=STALE-1"], 0);
    offline(false);
    assert!(spool.is_file(), "{}", ran.stderr);
    let mut claim = spool.as_os_str().to_os_string();
    claim.push(format!(".sending-{}", dead_pid()));
    std::fs::rename(spool, &claim).expect("a claim of a killed delivery");
    // Another delivery's claim, of a process alive (this one): left to it.
    let mut live = spool.as_os_str().to_os_string();
    live.push(format!(".sending-{}", std::process::id()));
    std::fs::write(&live, "").expect("a live claim");
    let listed = results_cmd(&["list", "--simulated"], store, data, 0);
    assert_has(&listed.stdout, &["1 run(s) kept on this bench, not yet in"]);
    let synced = results_cmd(&["sync"], store, data, 0);
    assert_has(&synced.stdout, &["delivered", "of 1 run(s)"]);
    assert!(!Path::new(&claim).exists());
    assert!(Path::new(&live).exists(), "another process's claim is its own");
    std::fs::remove_file(&live).expect("removed");
    let runs = stored_runs(store);
    let run = runs
        .iter()
        .find(|r| r.run.unit.serial.as_deref() == Some("STALE-1"))
        .expect("the spooled run reached the store");
    assert_eq!((run.verdict(), run.checks.len()), ("passed", 1));
    let again = results_cmd(&["sync"], store, data, 0);
    assert_has(&again.stdout, &["nothing to deliver"]);
    // Where the record was, said even with --quiet.
    assert_has(
        &ran.stderr,
        &["kept on this bench, not yet in", "drivescript results sync"],
    );
    assert_lacks(&ran.stderr, &["recorded in"]);
}

#[test]
fn a_stale_spool_claim_is_taken_back_by_the_next_sync_in_sqlite() {
    let (dir, s) = &scratch_store("stale-claim");
    // A first run makes the store; a directory in its place makes the next spool.
    record_tiny_run(dir, s);
    let aside = dir.join("aside");
    std::fs::create_dir_all(&aside).expect("aside");
    let offline = |off: bool| take_offline(Path::new(s), &aside, off);
    a_stale_claim_is_taken_back(s, &dir.join("results.sqlite.spool"), dir, &offline);
}

/// Records a run of `TINY` in `store`, which makes the store.
fn record_tiny_run(dir: &Path, store: &str) {
    let recipe = write_file(dir, "t.yaml", TINY);
    run_recorded(&recipe, store, &[], 0);
}

/// Puts the SQLite store `store` (its file and write-ahead log) aside with a directory in
/// its place (`off`), so that a run cannot record in it, or back.
pub fn take_offline(store: &Path, aside: &Path, off: bool) {
    let name = store.file_name().expect("a file").to_string_lossy().into_owned();
    let parts = ["", "-wal", "-shm"];
    if off {
        for part in parts {
            let from = store.with_file_name(format!("{name}{part}"));
            if from.exists() {
                std::fs::rename(&from, aside.join(format!("{name}{part}"))).expect("aside");
            }
        }
        std::fs::create_dir(store).expect("a directory in its place");
    } else {
        std::fs::remove_dir(store).expect("the directory removed");
        for part in parts {
            let from = aside.join(format!("{name}{part}"));
            if from.exists() {
                std::fs::rename(&from, store.with_file_name(format!("{name}{part}"))).expect("back");
            }
        }
    }
}

/// More records than the queue holds while the store is held by another process: the
/// run waits for the writer at its end (after the safe stop) and the store gets the whole
/// run in order — before, the overflow went to the spool and the store showed a finished
/// PASSED run with part of its steps.
#[test]
fn a_queue_without_room_keeps_every_record_in_order_and_the_store_gets_the_whole_run() {
    let (dir, s) = &scratch_store("overflow");
    let recipe = write_file(dir, "heavy.yaml", HEAVY);
    record_tiny_run(dir, s);
    let lock = rusqlite::Connection::open(s).expect("open");
    lock.execute_batch("BEGIN EXCLUSIVE").expect("lock");
    let child = command()
        .args(["run", recipe.to_str().unwrap(), "--fast", "--results", s])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("runs");
    // Held for less than the store's busy timeout (5 s): the writer waits, then writes.
    std::thread::sleep(std::time::Duration::from_millis(2000));
    lock.execute_batch("ROLLBACK").expect("unlock");
    drop(lock);
    let out = child.wait_with_output().expect("ends");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert_has(&err, &["recorded in"]);
    assert_lacks(&err, &["spool", "lost"]);
    assert!(!dir.join("results.sqlite.spool").exists());
    let runs = stored_runs(s);
    let heavy = runs.iter().find(|r| r.run.recipe == "Heavy").expect("the run");
    assert_eq!(heavy.verdict(), "passed");
    let end = heavy.end.as_ref().expect("ended");
    assert_eq!(heavy.steps.len() as i64 + end.omitted_steps, 6006, "every step");
    assert_eq!(heavy.checks.len(), 1);
}

/// The store's `.sqlite` file alone holds every finished run: a CI job that keeps only it
/// (not the write-ahead log beside it) lists the run.
#[test]
fn the_sqlite_file_alone_holds_every_finished_run() {
    let (dir, s) = &scratch_store("checkpoint");
    let recipe = write_file(dir, "heavy.yaml", HEAVY);
    run_recorded(&recipe, s, &["--unit", "serial=KEPT-1"], 0);
    let copy = dir.join("artifact");
    std::fs::create_dir_all(&copy).expect("dir");
    std::fs::copy(s, copy.join("results.sqlite")).expect("only the file copied");
    let c = copy.join("results.sqlite");
    let listed = cli(
        &["results", "list", "--simulated", "--results", c.to_str().unwrap()],
        0,
    );
    assert_has(&listed.stdout, &["PASSED", "Heavy", "KEPT-1"]);
    let runs = stored_runs(c.to_str().unwrap());
    assert_eq!(
        runs[0].steps.len() as i64 + runs[0].end.as_ref().unwrap().omitted_steps,
        6006
    );
}

/// Another application's SQLite file — in the default rollback journal or in WAL mode —
/// is refused with a clear error and left exactly as it was (before, a run switched it to
/// WAL first); the run goes on and keeps its record on this bench.
#[test]
fn a_foreign_sqlite_file_is_left_untouched_with_a_clear_error() {
    let (dir, recipe) = scratch_file("foreign-untouched", "tiny.yaml", TINY);
    for mode in ["DELETE", "WAL"] {
        let other = dir.join(format!("other-{mode}.sqlite"));
        {
            let c = rusqlite::Connection::open(&other).expect("another application's database");
            c.query_row(&format!("PRAGMA journal_mode = {mode}"), [], |_| Ok(()))
                .expect("journal mode");
            c.execute_batch("CREATE TABLE invoices (id INTEGER); INSERT INTO invoices VALUES (7);")
                .expect("its table");
        }
        let before = std::fs::read(&other).expect("its bytes");
        let o = other.to_str().unwrap();
        let ran = run_into(&recipe, o, &dir, &[], 0);
        assert_has(
            &ran.stderr,
            &[
                "is not a drivescript results store",
                "other tables (invoices)",
                "kept on this bench",
            ],
        );
        let refused = cli(&["results", "list", "--results", o], 2);
        assert_has(
            &refused.stderr,
            &["is not a drivescript results store", "other tables (invoices)"],
        );
        let synced = cli(&["results", "sync", "--results", o], 2);
        assert_has(&synced.stderr, &["is not a drivescript results store"]);
        assert!(
            std::fs::read(&other).expect("its bytes") == before,
            "{mode}: the file changed"
        );
        let c = rusqlite::Connection::open(&other).expect("opens");
        let journal: String = c
            .query_row("PRAGMA journal_mode", [], |r| r.get(0))
            .expect("journal mode");
        assert_eq!(journal.to_uppercase(), mode);
        let tables: i64 = c
            .query_row("SELECT count(*) FROM sqlite_master", [], |r| r.get(0))
            .expect("tables");
        assert_eq!(tables, 1, "{mode}: nothing of drivescript's added");
    }
}

/// A run the store refuses and the spool cannot take either is said to be lost, never
/// "kept on this bench" (before, the writer said its records were lost and the run's end
/// line then said they waited in the spool).
#[test]
fn a_run_neither_store_nor_spool_takes_is_said_lost_not_kept() {
    let (dir, recipe) = scratch_file("spool-unwritable", "tiny.yaml", TINY);
    let other = dir.join("other.sqlite");
    {
        let c = rusqlite::Connection::open(&other).expect("another application's database");
        c.execute_batch("CREATE TABLE invoices (id INTEGER);")
            .expect("its table");
    }
    // The spool's path taken by a folder: nothing can be appended to it.
    std::fs::create_dir_all(dir.join("other.sqlite.spool")).expect("a folder");
    let ran = run_into(&recipe, other.to_str().unwrap(), &dir, &[], 0);
    assert_has(
        &ran.stderr,
        &[
            "is not a drivescript results store",
            "are lost",
            "nor kept on this bench",
        ],
    );
    assert_lacks(&ran.stderr, &["kept on this bench, not yet in", "recorded in"]);
}

/// A store path that is a directory is named as such, with what to give instead — before,
/// `results list` said no run had been recorded there yet.
#[test]
fn a_store_path_that_is_a_directory_gets_a_clear_error() {
    let dir = scratch("directory-store");
    let folder = dir.join("results");
    std::fs::create_dir_all(&folder).expect("a folder");
    let f = folder.to_str().unwrap();
    let listed = cli(&["results", "list", "--results", f], 2);
    assert_has(&listed.stderr, &[f, "is a directory", "results.sqlite"]);
    assert_lacks(&listed.stderr, &["no run has been recorded"]);
    let recipe = write_file(&dir, "tiny.yaml", TINY);
    let ran = run_into(&recipe, f, &dir, &["--quiet"], 0);
    assert_has(
        &ran.stderr,
        &["is a directory", "kept on this bench, not yet in", "results sync"],
    );
    // The directory gone, the store is not there yet, but the run waits on this bench.
    std::fs::remove_dir(&folder).expect("removed");
    let listed = cli(&["results", "list", "--results", f], 1);
    assert_has(
        &listed.stderr,
        &[
            "there is no results store at",
            "1 run(s) kept on this bench wait in",
            "results sync",
        ],
    );
}

/// ESC sequences in a serial number or an answer are shown escaped in the run's output,
/// `results list`, `results show` and the CSV export; the store keeps them exactly.
#[test]
fn control_characters_are_shown_escaped_on_terminals_and_in_the_csv() {
    let (dir, s) = &scratch_store("control-characters");
    let recipe = write_file(dir, "tiny.yaml", TINY);
    let serial = "SP-\u{1b}[2J\u{1b}]0;owned\u{7}-9";
    let ran = run_into(&recipe, s, dir, &["--unit", &format!("serial={serial}")], 0);
    let shown = "SP-\\x1b[2J\\x1b]0;owned\\x07-9";
    assert_has(&ran.stdout, &[shown]);
    let runs = stored_runs(s);
    assert_eq!(runs[0].run.unit.serial.as_deref(), Some(serial), "stored exactly");
    let listed = cli(&["results", "list", "--simulated", "--results", s], 0);
    let show = cli(&["results", "show", &runs[0].run.id, "--results", s], 0);
    let csv = cli(
        &[
            "results",
            "export",
            "--simulated",
            "--format",
            "csv",
            "--results",
            s,
        ],
        0,
    );
    for (what, text) in [
        ("run", &ran.stdout),
        ("list", &listed.stdout),
        ("show", &show.stdout),
        ("csv", &csv.stdout),
    ] {
        assert_has(text, &[shown]);
        assert!(
            !text.contains('\u{1b}') && !text.contains('\u{7}'),
            "{what}: {text:?}"
        );
    }
}

/// The same on PostgreSQL, with one server: a NUL in an answer is stored and read back
/// exactly (before, the server refused that record for ever and every run spooled after it
/// stayed behind it); a stale claim is taken back; a run while the server is down says it
/// is kept on this bench, even with `--quiet`, and never "recorded in"; the overflow of
/// the queue reaches the server whole.
#[test]
fn postgresql_holds_every_record_and_says_where_it_is() {
    let Some((server, dir)) = postgres_with_folder("postgres-integrity") else {
        return;
    };
    let url = server.url();
    let recipe = write_file(&dir, "tiny.yaml", TINY);
    // A NUL in the serial number: while the server is down (spooled, then a second run
    // spooled behind it), and with the server up.
    server.down();
    let nul = "NUL\u{0}-1";
    // The command line cannot carry a NUL: the answer comes from a file.
    let (asking, answers) = asking_for_the_serial(&dir, "\"NUL\\0-1\"");
    let ran = run_into(
        &asking,
        &url,
        &dir,
        &["--quiet", "--answers", answers.to_str().unwrap()],
        0,
    );
    run_into(&recipe, &url, &dir, &["--quiet", "--unit", "serial=BEHIND-1"], 0);
    server.up();
    let synced = results_cmd(&["sync"], &url, &dir, 0);
    assert_has(&synced.stdout, &["of 2 run(s)"]);
    run_into(&asking, &url, &dir, &["--answers", answers.to_str().unwrap()], 0);
    let runs = stored_runs(&url);
    let with_nul: Vec<&StoredRun> = runs
        .iter()
        .filter(|r| r.run.unit.serial.as_deref() == Some(nul))
        .collect();
    assert_eq!(
        with_nul.len(),
        2,
        "{:?}",
        runs.iter().map(|r| &r.run.unit).collect::<Vec<_>>()
    );
    assert!(with_nul.iter().all(|r| r.verdict() == "passed"));
    assert!(runs
        .iter()
        .any(|r| r.run.unit.serial.as_deref() == Some("BEHIND-1")));
    // Found by it too.
    let mut s = Locator::parse(&url).open(false).expect("opens");
    assert_eq!(s.unit_runs(nul, true).expect("the unit's runs").len(), 2);
    drop(s);
    // The run while the server was down said where its record was, even with --quiet.
    assert_has(
        &ran.stderr,
        &["kept on this bench, not yet in postgres://drivescript@127.0.0.1"],
    );
    assert_lacks(&ran.stderr, &["recorded in", "pw-s3cret"]);
    // A stale claim.
    let data = dir.join("stale");
    std::fs::create_dir_all(data.join("drivescript")).expect("data dir");
    let spool = server_spool(&data, &url);
    let offline = |off: bool| if off { server.down() } else { server.up() };
    a_stale_claim_is_taken_back(&url, &spool, &data, &offline);
    // The queue's overflow, whole.
    let heavy = write_file(&dir, "heavy.yaml", HEAVY);
    let ran = run_into(&heavy, &url, &dir, &[], 0);
    assert_has(&ran.stderr, &["recorded in postgres://"]);
    let runs = stored_runs(&url);
    let h = runs.iter().find(|r| r.run.recipe == "Heavy").expect("the run");
    assert_eq!(h.steps.len() as i64 + h.end.as_ref().unwrap().omitted_steps, 6006);
}

/// A recipe in `dir` whose operator step asks for the unit's serial, and an answers file
/// giving it `serial` (as YAML writes it).
fn asking_for_the_serial(dir: &Path, serial: &str) -> (PathBuf, PathBuf) {
    let answers = write_file(dir, "answers.yaml", &format!("serial: {serial}\n"));
    let asking = write_file(
        dir,
        "asking.yaml",
        "name: Asking\ndrive: sd2\nsteps:\n  - enter_text: { prompt: Serial, sets: serial }\n    name: serial\n  - expect: { bus_voltage: { above: 100 V } }\n",
    );
    (asking, answers)
}

/// A NUL in SQLite is stored and read back exactly.
#[test]
fn a_nul_in_an_answer_is_stored_exactly_in_sqlite() {
    let (dir, s) = &scratch_store("nul-sqlite");
    let (asking, answers) = asking_for_the_serial(dir, "\"NUL\\0-1\"");
    run_into(&asking, s, dir, &["--answers", answers.to_str().unwrap()], 0);
    let runs = stored_runs(s);
    assert_eq!(runs[0].run.unit.serial.as_deref(), Some("NUL\u{0}-1"));
    let listed = cli(&["results", "list", "--simulated", "--results", s], 0);
    assert_has(&listed.stdout, &["NUL\\x00-1"]);
}

/// The samples CSV holds the curves the HTML report plots: each poll of a coast-down and
/// of a wait for a stable slope, in their steps (before, only `sample` steps).
#[test]
fn the_samples_csv_holds_the_coast_down_and_the_polls_of_a_stable_wait() {
    let (dir, recipe) = scratch_file(
        "csv-curves",
        "curves.yaml",
        "name: Curves
drive: sd2
steps:
  - set: { speed_setpoint: 6000 rpm }
  - go_to: operation_enabled
  - wait_until:
      motor_temperature: { slope: { below: 5 K/min, over: 1 min } }
      timeout: 1 h
      every: 10 s
  - wait_until: { speed_actual: { near: 6000 rpm, within: 1 % } }
  - coast_down: { from: 5900 rpm, below: 100 rpm, expect: { below: 60 s } }
",
    );
    let csv = dir.join("samples.csv");
    cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--no-results",
            "--csv",
            csv.to_str().unwrap(),
        ],
        0,
    );
    let text = std::fs::read_to_string(&csv).expect("the CSV");
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let of = |step: &str, object: &str| {
        rows.iter()
            .filter(|r| r[2] == step && r[3] == object)
            .filter_map(|r| r[4].parse::<f64>().ok())
            .collect::<Vec<f64>>()
    };
    let stable = of("3", "motor_temperature");
    assert!(stable.len() >= 6, "the stable wait's polls: {stable:?}\n{text}");
    let coast = of("5", "speed_actual");
    assert!(coast.len() >= 3, "the coast-down's curve: {coast:?}\n{text}");
    assert!(coast[0] > 5000.0 && coast[coast.len() - 1] < 100.0, "{coast:?}");
    assert!(coast.windows(2).all(|w| w[1] <= w[0]), "it falls: {coast:?}");
}

/// `{serial}` in an output name is filled from an answer given beforehand (`--answers`)
/// to the operator step that sets it — known before the first step — and the store names
/// the file as written (before, the name was refused).
#[test]
fn serial_in_an_output_name_comes_from_an_answer_given_beforehand() {
    let (dir, s) = &scratch_store("serial-from-answers");
    let (asking, answers) = asking_for_the_serial(dir, "SP-104233");
    let report = dir.join("{serial}-report.html");
    run_into(
        &asking,
        s,
        dir,
        &[
            "--answers",
            answers.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ],
        0,
    );
    let written = dir.join("SP-104233-report.html");
    assert!(written.is_file(), "{}", written.display());
    let runs = stored_runs(s);
    let files = &runs[0].end.as_ref().expect("ended").report_files;
    assert!(files.contains(&written.display().to_string()), "{files:?}");
    // Without the answer the name still needs the serial beforehand.
    let refused = run_into(
        &asking,
        s,
        dir,
        &["--answer", "other=1", "--report", report.to_str().unwrap()],
        2,
    );
    assert_has(
        &refused.stderr,
        &["`{serial}` needs the unit's serial", "--answers FILE"],
    );
}

/// A run with records still in this bench's spool is marked unsynced in `results list`
/// (the table and `--json`), until a sync delivers them.
#[test]
fn results_list_marks_runs_with_records_still_in_the_spool() {
    let (dir, s) = &scratch_store("unsynced");
    let recipe = write_file(dir, "tiny.yaml", TINY);
    run_into(&recipe, s, dir, &[], 0);
    run_into(&recipe, s, dir, &[], 0);
    let runs = stored_runs(s);
    let id = runs[0].run.id.clone();
    // The unit of one run learnt late, still waiting in the spool.
    write_file(
        dir,
        "results.sqlite.spool",
        &format!(
            "{{\"record\":\"unit\",\"run\":\"{id}\",\"unit\":{{\"serial\":\"LATE-1\",\"part\":null,\"operator\":null,\"station\":null}}}}\n"
        ),
    );
    let listed = cli(&["results", "list", "--simulated", "--results", s], 0);
    let line = crate::support::line_with(&listed.stdout, &id);
    assert_has(line, &["PASSED (simulated) (unsynced)"]);
    let other = crate::support::line_with(&listed.stdout, &runs[1].run.id);
    assert_lacks(other, &["unsynced"]);
    assert_has(
        &listed.stdout,
        &["1 run(s) kept on this bench, not yet in", "results sync"],
    );
    let json = cli(&["results", "list", "--simulated", "--json", "--results", s], 0);
    let list: serde_json::Value = serde_json::from_str(&json.stdout).expect("JSON");
    let marks: Vec<(String, bool)> = list
        .as_array()
        .expect("a list")
        .iter()
        .map(|r| {
            (
                r["id"].as_str().unwrap_or_default().to_string(),
                r["unsynced"] == true,
            )
        })
        .collect();
    assert!(
        marks.contains(&(id.clone(), true)) && marks.contains(&(runs[1].run.id.clone(), false)),
        "{marks:?}"
    );
    cli(&["results", "sync", "--results", s], 0);
    let listed = cli(&["results", "list", "--simulated", "--results", s], 0);
    assert_lacks(&listed.stdout, &["unsynced", "kept on this bench"]);
    assert_has(&listed.stdout, &["LATE-1"]);
}
