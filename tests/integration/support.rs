//! Helpers shared by the integration tests: running the built binary (to its end, or as a
//! simulator; in the background see `live_run`), in-process runs, scratch folders,
//! assertions on output text, and loading vectors.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The data directory a command is given, where its default store and a server's spool
/// live: `XDG_DATA_HOME` on Linux, `%LOCALAPPDATA%` on Windows (`.envs(data_home(dir))`).
pub fn data_home(dir: &std::path::Path) -> [(&'static str, &std::path::Path); 2] {
    [("XDG_DATA_HOME", dir), ("LOCALAPPDATA", dir)]
}

/// The `drivescript` binary as every test runs it: its results go to a store of this
/// test process's own (never the user's data directory); a test that checks the store
/// names its own with `--results` or `DRIVESCRIPT_RESULTS`.
pub fn command() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_drivescript"));
    c.env("DRIVESCRIPT_RESULTS", tests_results_store());
    c
}

/// The results store [`command`] gives every run: one per test process.
pub fn tests_results_store() -> PathBuf {
    crate::stale_scratch::sweep_once();
    std::env::temp_dir()
        .join(format!("drivescript-tests-{}", std::process::id()))
        .join("results.sqlite")
}

/// Runs `drivescript ARGS | head -1` in the repository: reads the first line of the
/// output, closes the pipe and waits for the end. The line and how the command ended.
pub fn first_line_then_closed_pipe(args: &[&str]) -> (String, std::process::ExitStatus) {
    use std::io::{BufRead, BufReader};
    let mut child = started(
        command()
            .args(args)
            .current_dir(repo_root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped()),
    );
    let mut out = BufReader::new(child.stdout.take().expect("stdout"));
    let mut first = String::new();
    out.read_line(&mut first).expect("first line");
    drop(out);
    (first, child.wait().expect("the command ends"))
}

/// Starts the drivescript binary as `command` says. Under Wine on a busy machine, creating
/// a process now and then fails with Windows error 1359 ("internal error") before the exe
/// runs a single instruction; that is Wine's, not the product's, and a second try starts it.
/// Any other error, and a third 1359, fail the test.
pub fn started(command: &mut Command) -> std::process::Child {
    const WINE_INTERNAL_ERROR: i32 = 1359;
    let mut tries = 0;
    loop {
        tries += 1;
        match command.spawn() {
            Ok(child) => return child,
            Err(e) if cfg!(windows) && e.raw_os_error() == Some(WINE_INTERNAL_ERROR) && tries < 3 => {
                eprintln!("starting drivescript failed under Wine ({e}); trying again");
                std::thread::sleep(std::time::Duration::from_millis(500));
            }
            Err(e) => panic!("the drivescript binary starts: {e:?}"),
        }
    }
}

/// Runs `drivescript ARGS` with `stdin`, returning its output.
pub fn drivescript(args: &[&str], stdin: &str) -> Output {
    let mut child = started(
        command()
            .args(args)
            .current_dir(repo_root())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped()),
    );
    let written = child
        .stdin
        .take()
        .expect("stdin is piped")
        .write_all(stdin.as_bytes());
    // A run refused before it reads its input may end before the input is written.
    if let Err(e) = written {
        assert_eq!(
            e.kind(),
            std::io::ErrorKind::BrokenPipe,
            "stdin accepts input: {e}"
        );
    }
    child.wait_with_output().expect("drivescript finishes")
}

/// A test's outside tool (yaml-language-server, python-can, jsonschema, xmllint) is
/// missing. Locally the test says so and skips that check; under CI (`CI` set, as
/// `.ci/run` is run) it fails, so CI cannot pass without checking anything.
#[track_caller]
pub fn tool_missing(what: &str) {
    if skip_is_fatal(std::env::var("CI").ok().as_deref()) {
        panic!("{what}, and under CI (CI is set) that check must run: `.ci/run` installs it");
    }
    eprintln!("skipped: {what} (`.ci/run` installs it)");
}

/// Whether python3 can import `modules` (`"pymodbus, serial"`); where it cannot,
/// [`tool_missing`] says `missing` (and fails under CI).
pub fn python_imports(modules: &str, missing: &str) -> bool {
    let here = Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !here {
        tool_missing(missing);
    }
    here
}

/// Headless Chromium, with the flags that keep it off the network and out of a profile
/// shared with other tests, ready for `--print-to-pdf=` or `--screenshot=` and a file;
/// `None` (after [`tool_missing`]) where it is not installed.
pub fn headless_chromium(profile: &Path) -> Option<Command> {
    let mut command = chromium(profile)?;
    command.arg("--no-pdf-header-footer");
    Some(command)
}

/// [`headless_chromium`] for a page that lives on (driven over the DevTools protocol):
/// without the printing flag, under which Chromium 14x's renderer dies as soon as the
/// page's size is set.
pub fn chromium(profile: &Path) -> Option<Command> {
    let Some(program) = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|c| {
            Command::new(c)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })
    else {
        tool_missing("no chromium installed: the HTML is not rendered");
        return None;
    };
    let mut command = Command::new(program);
    command
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
        ])
        .arg(format!("--user-data-dir={}", profile.display()));
    Some(command)
}

/// Renders the HTML file `page` in headless Chromium in a window of `size` (`1200,1400`)
/// and keeps the picture as `target/NAME.png` for a look; nothing (after [`tool_missing`])
/// where Chromium is not installed.
#[track_caller]
pub fn screenshot(page: &Path, size: &str, name: &str) {
    let dir = page.parent().expect("the page's folder");
    let Some(mut chromium) = headless_chromium(&dir.join(format!("profile-{name}"))) else {
        return;
    };
    let png = dir.join(format!("{name}.png"));
    let out = chromium
        .arg(format!("--window-size={size}"))
        .arg(format!("--screenshot={}", png.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium runs");
    assert!(png.is_file(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::metadata(&png).map(|m| m.len()).unwrap_or(0) > 10_000);
    let _ = std::fs::copy(&png, repo_root().join(format!("target/{name}.png")));
}

/// The first line of `text` that holds `part`; fails the test, showing `text`, when none does.
#[track_caller]
pub fn line_with<'a>(text: &'a str, part: &str) -> &'a str {
    let found = text.lines().find(|l| l.contains(part));
    found.unwrap_or_else(|| panic!("no line with {part:?} in:\n{text}"))
}

/// Whether a `CI` variable of this value makes a skipped check fail: set to anything but
/// empty, `0` or `false`.
fn skip_is_fatal(ci: Option<&str>) -> bool {
    ci.is_some_and(|v| !matches!(v.trim(), "" | "0" | "false"))
}

#[test]
fn a_missing_tool_fails_under_ci_and_is_skipped_locally() {
    assert!(skip_is_fatal(Some("true")) && skip_is_fatal(Some("1")));
    assert!(!skip_is_fatal(None) && !skip_is_fatal(Some("")) && !skip_is_fatal(Some("false")));
    let ran_under = |ci: Option<&str>| {
        std::panic::catch_unwind(|| {
            if skip_is_fatal(ci) {
                panic!("fatal");
            }
        })
        .is_ok()
    };
    assert!(!ran_under(Some("true")) && ran_under(None));
}

/// A fresh, empty folder for a test's files, `drivescript-FILE-NAME-PID` in the system's
/// temporary folder, FILE the calling test file, so tests of different files never share
/// one. Those that ended test processes left are removed first (see `stale_scratch`).
#[track_caller]
pub fn scratch(name: &str) -> PathBuf {
    crate::stale_scratch::sweep_once();
    let file = Path::new(std::panic::Location::caller().file())
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let dir = std::env::temp_dir().join(format!("drivescript-{file}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// A [`scratch`] folder `name` holding one file `file` with `text`: the folder and the
/// file's path.
#[track_caller]
pub fn scratch_file(name: &str, file: &str, text: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(name);
    let path = write_file(&dir, file, text);
    (dir, path)
}

/// Runs `check(dir, store)` with a SQLite results store in the fresh [`scratch`] folder
/// `NAME-sqlite`: the SQLite half of a test run against both kinds of store.
#[track_caller]
pub fn with_sqlite_store(name: &str, check: impl FnOnce(&Path, &str)) {
    let dir = scratch(&format!("{name}-sqlite"));
    check(&dir, &sqlite_store(&dir));
}

/// Runs `check(dir, store)` with a PostgreSQL server of its own (`NAME-postgres`) as the
/// store and the fresh [`scratch`] folder `NAME-postgres-files`; where no server can be
/// started it does what [`PostgresServer::start`] says (skips, or fails under CI).
#[track_caller]
pub fn with_postgres_store(name: &str, check: impl FnOnce(&Path, &str)) {
    let Some((server, dir)) = postgres_with_folder(&format!("{name}-postgres")) else {
        return;
    };
    check(&dir, &server.url());
}

/// A PostgreSQL server of its own (`NAME`, as [`PostgresServer::start`] starts it, `None`
/// where it says) and the fresh [`scratch`] folder `NAME-files` for the test's other files.
#[track_caller]
pub fn postgres_with_folder(name: &str) -> Option<(PostgresServer, PathBuf)> {
    let server = PostgresServer::start(name)?;
    Some((server, scratch(&format!("{name}-files"))))
}

/// The path of a SQLite results store in `dir`, as `--results` takes it.
pub fn sqlite_store(dir: &Path) -> String {
    dir.join("results.sqlite").to_string_lossy().into_owned()
}

/// A copy of the file `original` as `dir/name` with `from` replaced by `to` (a recipe or
/// script changed in one place); the copy's path.
pub fn write_changed(dir: &Path, name: &str, original: &Path, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(original).expect("the file to change");
    assert!(text.contains(from), "{} has no `{from}`", original.display());
    write_file(dir, name, &text.replace(from, to))
}

/// Writes `text` to `dir/name`; the file's path.
pub fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("file written");
    path
}

/// Writes `text` as `name` in `dir` and runs `drivescript check` on it, which must exit
/// with `code`.
#[track_caller]
pub fn check_file(dir: &Path, name: &str, text: &str, code: i32) -> Ran {
    let file = write_file(dir, name, text);
    cli(&["check", file.to_str().expect("a UTF-8 path")], code)
}

/// Runs `drivescript ARGS --drive DRIVE --dictionary FILE`, FILE a path in the repository,
/// as [`cli`] does: it must exit with `code`.
#[track_caller]
pub fn cli_with_dictionary(args: &[&str], drive: &str, file: &str, code: i32) -> Ran {
    let file = repo_root().join(file);
    let file = file.to_string_lossy();
    cli(&[args, &["--drive", drive, "--dictionary", &file]].concat(), code)
}

/// The words of a command line with no quoted arguments (`run r.yaml --fast`), for [`cli`].
pub fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// What a finished `drivescript` run wrote, as text.
pub struct Ran {
    pub stdout: String,
    pub stderr: String,
}

/// Runs `drivescript ARGS` with no input and fails the test, showing both outputs, unless
/// it exits with `code`.
#[track_caller]
pub fn cli(args: &[&str], code: i32) -> Ran {
    Ran::exited(drivescript(args, ""), code)
}

impl Ran {
    /// What a finished command wrote; fails the test, showing both outputs, unless it
    /// exited with `code`.
    #[track_caller]
    pub fn exited(out: Output, code: i32) -> Ran {
        let ran = Ran {
            stdout: stdout(&out),
            stderr: stderr(&out),
        };
        assert_eq!(out.status.code(), Some(code), "{}{}", ran.stdout, ran.stderr);
        ran
    }
}

/// Runs `command` (`what` names it) and fails the test, showing what it wrote, unless it
/// succeeds; what it wrote.
#[track_caller]
pub fn succeeded(command: &mut Command, what: &str) -> Output {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("{what} does not run: {e}"));
    assert!(out.status.success(), "{what}: {}{}", stdout(&out), stderr(&out));
    out
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// One entry of `sd2-dnc.yaml`.
#[derive(Debug, serde::Deserialize)]
pub struct Vector {
    pub name: String,
    pub hex: String,
    pub frame: serde_json::Value,
}

pub fn load_vectors(path: &Path) -> Vec<Vector> {
    load_yaml(path)
}

impl Vector {
    /// `got` (with whether the decoder called the telegram valid) is this vector's `frame`,
    /// or, where the frame is `reject`, a rejection that gives its reason.
    #[track_caller]
    pub fn assert_decoded(&self, got: &serde_json::Value, valid: bool) {
        if self.frame == serde_json::Value::String("reject".into()) {
            assert!(
                !valid && got["reject"].as_str().is_some_and(|r| !r.is_empty()),
                "{}: decoded to {got} but must be rejected",
                self.name
            );
        } else {
            assert!(valid, "{}: {got}", self.name);
            assert_eq!(got, &self.frame, "{}", self.name);
        }
    }
}

/// Every one of `count` vectors, decoded by `decode` (the JSON and whether it is valid),
/// is its `frame` or the rejection it must be.
#[track_caller]
pub fn assert_every_vector_decodes(
    vectors: &[Vector],
    count: usize,
    mut decode: impl FnMut(&[u8]) -> (serde_json::Value, bool),
) {
    assert_eq!(vectors.len(), count);
    for v in vectors {
        let bytes = drivescript::hex::parse_hex(&v.hex).unwrap();
        let (got, valid) = decode(&bytes);
        v.assert_decoded(&got, valid);
    }
}

/// The repository's copy of a vector file holds exactly the vectors of the shared original
/// `../shared/vectors/NAME`, where that is there to compare with.
#[track_caller]
pub fn assert_matches_shared(copy: &[Vector], name: &str) {
    let shared = repo_root().join("../shared/vectors").join(name);
    if shared.exists() {
        let original = load_vectors(&shared);
        assert_eq!(copy.len(), original.len());
        for (c, o) in copy.iter().zip(&original) {
            assert_eq!((&c.name, &c.hex, &c.frame), (&o.name, &o.hex, &o.frame));
        }
    }
}

/// A YAML file of test vectors read into `T`; a file that is missing or does not fit fails
/// the test naming it.
fn load_yaml<T: serde::de::DeserializeOwned>(path: &Path) -> T {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_saphyr::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// One entry of `lenze-9400-sdo.yaml`: a CAN frame and what it decodes to.
#[derive(Debug, serde::Deserialize)]
pub struct FrameVector {
    pub name: String,
    pub id: String,
    pub data: String,
    pub frame: serde_json::Value,
}

pub fn load_frame_vectors(path: &Path) -> Vec<FrameVector> {
    load_yaml(path)
}

pub fn sd2_vectors() -> Vec<Vector> {
    load_vectors(&repo_root().join("tests/vectors/sd2-dnc.yaml"))
}

/// A recipe run in this process, with the command line's defaults: the built-in families,
/// the built-in SD2 dictionary, the built-in simulated drive, virtual time. Tests change
/// the fields they need and call [`InProcessRun::run`].
pub struct InProcessRun<'a> {
    pub registry: drivescript::family::Registry,
    pub recipe: PathBuf,
    pub set: Vec<(String, String)>,
    pub fast: bool,
    pub output_dir: PathBuf,
    pub dictionary: drivescript::run::DictionaryArgs,
    pub connection: drivescript::run::ConnectionArgs,
    pub outputs: drivescript::run::OutputArgs,
    pub prepare: Option<&'a drivescript::run::PrepareSimulator>,
    pub stop: std::sync::Arc<drivescript::stop_request::StopRequests>,
    pub safe_stop: drivescript::run::SafeStopArgs,
    pub observers: Vec<drivescript::run::SharedObserver>,
    /// `--unit`, `--answers`, `--answer`.
    pub operator: drivescript::run::OperatorArgs,
    /// The lines an operator types at a terminal; `None`: no terminal.
    pub input: Option<std::sync::Arc<drivescript::run::TerminalInput>>,
    /// Where past runs are read for checks that compare with the last pass.
    pub history: Option<std::sync::Arc<dyn drivescript::session::History>>,
}

impl<'a> InProcessRun<'a> {
    pub fn new(recipe: impl Into<PathBuf>) -> Self {
        InProcessRun {
            registry: drivescript::family::Registry::builtin(),
            recipe: recipe.into(),
            set: Vec::new(),
            fast: true,
            output_dir: std::env::temp_dir(),
            dictionary: drivescript::run::DictionaryArgs::builtin_default(),
            connection: drivescript::run::ConnectionArgs::simulated(),
            outputs: drivescript::run::OutputArgs::default(),
            prepare: None,
            stop: std::sync::Arc::new(drivescript::stop_request::StopRequests::new()),
            safe_stop: drivescript::run::SafeStopArgs::default(),
            observers: Vec::new(),
            operator: drivescript::run::OperatorArgs::default(),
            input: None,
            history: None,
        }
    }

    /// Asks for a JUnit file and an HTML report in `dir` (`junit.xml`, `report.html`):
    /// their paths.
    pub fn reports_in(&mut self, dir: &Path) -> (PathBuf, PathBuf) {
        let (junit, html) = (dir.join("junit.xml"), dir.join("report.html"));
        self.outputs.junit = Some(junit.clone());
        self.outputs.report = Some(html.clone());
        (junit, html)
    }

    /// Runs it with a terminal nobody types at (a question waits until its timeout);
    /// what it produced and its console output.
    pub fn run_at_a_silent_terminal(mut self) -> (drivescript::run::RunResult, String) {
        let (reader, typing) = std::io::pipe().expect("pipe");
        self.input = Some(drivescript::run::TerminalInput::of(reader));
        let ran = self.run();
        drop(typing);
        ran
    }

    /// Runs it; what it produced and its console output (standard output, then errors).
    pub fn run(&self) -> (drivescript::run::RunResult, String) {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let result = drivescript::run::run(&self.request(), &mut out, &mut err);
        (result, console(&out, &err))
    }

    /// Runs it as [`run`](Self::run) and fails the test, showing the output, unless it
    /// exits with `code` and its output holds every one of `parts`.
    #[track_caller]
    pub fn run_expecting(&self, code: i32, parts: &[&str]) -> (drivescript::run::RunResult, String) {
        let (result, output) = self.run();
        assert_eq!(result.exit_code, code, "{output}");
        assert_has(&output, parts);
        (result, output)
    }

    /// [`run_expecting`](Self::run_expecting) with a trace written to `trace`: the result,
    /// the console output and the trace's text.
    #[track_caller]
    pub fn run_traced(
        &mut self,
        trace: &Path,
        code: i32,
        parts: &[&str],
    ) -> (drivescript::run::RunResult, String, String) {
        self.outputs.trace = Some(trace.to_path_buf());
        let (result, output) = self.run_expecting(code, parts);
        let text = std::fs::read_to_string(trace).unwrap_or_else(|e| panic!("{}: {e}", trace.display()));
        (result, output, text)
    }

    /// Runs `files` as one command of several, with this run's settings; the exit code and
    /// the console output.
    pub fn run_many(&self, files: &[PathBuf]) -> (i32, String) {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let code = drivescript::run::run_many(files, &self.request(), &mut out, &mut err);
        (code, console(&out, &err))
    }

    fn request(&self) -> drivescript::run::RunRequest<'_> {
        drivescript::run::RunRequest {
            registry: &self.registry,
            file: &self.recipe,
            set: &self.set,
            fast: self.fast,
            output_dir: self.output_dir.clone(),
            dictionary: &self.dictionary,
            connection: &self.connection,
            outputs: &self.outputs,
            prepare_simulator: self.prepare,
            stop: self.stop.clone(),
            safe_stop: self.safe_stop.clone(),
            terminal: false,
            operator: &self.operator,
            input: self.input.clone(),
            observers: self.observers.clone(),
            history: self.history.clone(),
        }
    }
}

/// Standard output, then errors.
pub fn console(out: &[u8], err: &[u8]) -> String {
    format!("{}{}", String::from_utf8_lossy(out), String::from_utf8_lossy(err))
}

/// A `prepare` for an [`InProcessRun`] that sets faults on the run's simulated drive before
/// it starts: `inject` is given the drive's fault injection (`|f| f.panic_at(…)`).
pub fn faults_before_the_run(
    inject: impl Fn(&mut drivescript::sim::FaultInjection) -> &mut drivescript::sim::FaultInjection,
) -> impl Fn(
    &std::sync::Arc<std::sync::Mutex<dyn drivescript::sim::SimulatedDrive>>,
    &drivescript::clock::SharedClock,
) {
    move |sim, _| {
        inject(
            sim.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .faults(),
        );
    }
}

/// The control words the run's simulated drive received, in order; none when the run
/// opened no simulated drive.
pub fn control_words(result: &drivescript::run::RunResult) -> Vec<u16> {
    result
        .simulator
        .as_ref()
        .map(|s| {
            s.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .control_words_written()
        })
        .unwrap_or_default()
}

/// A `drivescript simulate ARGS` in the background, stopped when dropped.
/// Under Wine, one on a pseudo-terminal runs on the Linux side (see `wine_host`), its
/// endpoint the COM port linked to the pty: the tests go through Windows' serial API.
pub struct Simulator {
    child: Option<std::process::Child>,
    /// The first line it printed: the pty path or the TCP address (`COM10` under Wine).
    pub endpoint: String,
    #[cfg(windows)]
    _on_linux: Option<crate::wine_host::HostLine>,
}

impl Simulator {
    pub fn start(args: &[&str]) -> Simulator {
        #[cfg(windows)]
        if args.iter().any(|a| matches!(*a, "--pty" | "--slcan-pty")) {
            let (line, port) = crate::wine_host::HostLine::ask(&[&["simulate"], args].concat())
                .expect("a simulated drive on a COM port needs the Linux side under Wine");
            return Simulator {
                child: None,
                endpoint: port,
                _on_linux: Some(line),
            };
        }
        Simulator::spawn(args, Stdio::null())
    }

    /// [`Simulator::start`], and the command its `try:` line offers (without `try: `);
    /// the rest of its standard error is drained so it never blocks.
    pub fn start_with_hint(args: &[&str]) -> (Simulator, String) {
        use std::io::BufRead;
        let mut sim = Simulator::spawn(args, Stdio::piped());
        let child = sim.child.as_mut().expect("a simulator of this process");
        let mut err = std::io::BufReader::new(child.stderr.take().expect("stderr is piped"));
        let mut hint = String::new();
        let mut seen = String::new();
        while err.read_line(&mut seen).unwrap_or(0) > 0 {
            if let Some(h) = seen.trim().strip_prefix("try: ") {
                hint = h.to_string();
                break;
            }
            seen.clear();
        }
        assert!(!hint.is_empty(), "simulate offers a `try:` line: {seen}");
        std::thread::spawn(move || std::io::copy(&mut err, &mut std::io::sink()));
        (sim, hint)
    }

    fn spawn(args: &[&str], stderr: Stdio) -> Simulator {
        use std::io::BufRead;
        let mut child = command()
            .arg("simulate")
            .args(args)
            .stdout(Stdio::piped())
            .stderr(stderr)
            .spawn()
            .expect("simulate starts");
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().expect("stdout is piped"))
            .read_line(&mut line)
            .expect("simulate prints its endpoint");
        Simulator {
            child: Some(child),
            endpoint: line.trim().to_string(),
            #[cfg(windows)]
            _on_linux: None,
        }
    }

    /// `drivescript simulate --pty ARGS` (e.g. `--address dnc:2,dnc:3`).
    pub fn pty(args: &[&str]) -> Simulator {
        Simulator::start(&[&["--pty"], args].concat())
    }

    /// `drivescript ARGS --port ENDPOINT`, a command on this simulator's line, which must
    /// exit with `code` as [`cli`] checks.
    #[track_caller]
    pub fn cli(&self, args: &[&str], code: i32) -> Ran {
        cli(&[args, &["--port", &self.endpoint]].concat(), code)
    }
}

impl Drop for Simulator {
    fn drop(&mut self) {
        if let Some(child) = &mut self.child {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// The rows of a wide sample CSV of speed_actual and current_actual, its header checked.
pub fn wide_speed_and_current_rows(path: &Path) -> Vec<csv::StringRecord> {
    let mut reader = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(
        reader.headers().expect("a header"),
        &csv::StringRecord::from(vec![
            "time [s]",
            "utc",
            "step",
            "speed_actual [rpm]",
            "current_actual [A]"
        ]),
        "{}",
        path.display()
    );
    reader.records().map(Result::unwrap).collect()
}

/// Fails the test, showing all of `text`, unless it says the drive was left in `state` at
/// standstill. In real time a spindle may still turn a few rpm when the stop reads it back;
/// the stop's own verdict is standstill within its window (10 rpm), not 0 rpm exactly.
#[track_caller]
pub fn assert_left_at_standstill(text: &str, state: &str) {
    let lead = format!("drive left in {state} at ");
    let speed = text
        .split(lead.as_str())
        .nth(1)
        .and_then(|rest| rest.split(" rpm").next())
        .and_then(|n| n.trim().parse::<f64>().ok());
    assert!(
        speed.is_some_and(|s| s.abs() <= 10.0),
        "expected `{lead}` within 10 rpm of standstill in:\n{text}"
    );
}

/// Fails the test, showing all of `text`, unless `text` holds every one of `parts`.
#[track_caller]
pub fn assert_has(text: &str, parts: &[&str]) {
    for part in parts {
        assert!(text.contains(part), "expected {part:?} in:\n{text}");
    }
}

/// Fails the test, showing the output, unless a finished run's `(exit code, output)` has
/// exit code `code` and output holding every one of `parts`; the output.
#[track_caller]
pub fn assert_exit((got, text): (i32, String), code: i32, parts: &[&str]) -> String {
    assert_eq!(got, code, "{text}");
    assert_has(&text, parts);
    text
}

/// Fails the test, showing all of `text`, unless `text` holds `parts` in this order.
#[track_caller]
pub fn assert_in_order(text: &str, parts: &[&str]) {
    let mut rest = text;
    for part in parts {
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => panic!("expected {part:?} after {parts:?}'s earlier parts in:\n{text}"),
        }
    }
}

/// Fails the test, showing all of `text`, if `text` holds any of `parts`.
#[track_caller]
pub fn assert_lacks(text: &str, parts: &[&str]) {
    for part in parts {
        assert!(!text.contains(part), "did not expect {part:?} in:\n{text}");
    }
}

/// `drivescript ARGS` (from the repository root) on a pseudo-terminal, as a person at a
/// keyboard runs it: the pty is its standard input, output and error and its controlling
/// terminal, so a typed Ctrl-C (`\x03`) is a SIGINT and Ctrl-D (`\x04`) an end of input.
#[cfg(unix)]
pub struct Terminal {
    child: std::process::Child,
    master: std::fs::File,
    seen: std::sync::Arc<std::sync::Mutex<String>>,
}

#[cfg(unix)]
impl Terminal {
    /// Starts it with `env` added to the environment.
    pub fn start(args: &[&str], env: &[(&str, &str)]) -> Terminal {
        use std::os::fd::{FromRawFd, OwnedFd};
        use std::os::unix::process::CommandExt;
        let (mut master, mut slave) = (0, 0);
        let size = libc::winsize {
            ws_row: 40,
            ws_col: 120,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        // SAFETY: openpty writes two descriptors it opened; the null pointers ask for no
        // name and default settings.
        let ok = unsafe {
            libc::openpty(
                &mut master,
                &mut slave,
                std::ptr::null_mut(),
                std::ptr::null(),
                &size,
            )
        };
        assert_eq!(ok, 0, "openpty: {}", std::io::Error::last_os_error());
        // SAFETY: both descriptors were just opened and are owned here alone.
        let (master, slave) = unsafe { (std::fs::File::from_raw_fd(master), OwnedFd::from_raw_fd(slave)) };
        let io = |fd: &OwnedFd| Stdio::from(fd.try_clone().expect("dup the pty"));
        let mut command = command();
        command
            .args(args)
            .current_dir(repo_root())
            .envs(env.iter().copied())
            .stdin(io(&slave))
            .stdout(io(&slave))
            .stderr(io(&slave));
        // SAFETY: only async-signal-safe calls between fork and exec: a new session whose
        // controlling terminal is the pty (standard input).
        unsafe {
            command.pre_exec(|| {
                libc::setsid();
                libc::ioctl(0, libc::TIOCSCTTY as _, 0);
                Ok(())
            });
        }
        let child = command.spawn().expect("the run starts");
        drop(slave);
        let seen = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
        let (mut reader, into) = (master.try_clone().expect("dup the pty"), seen.clone());
        std::thread::spawn(move || {
            use std::io::Read;
            let mut buf = [0u8; 1024];
            // Ends with EIO once the run and its children have closed the terminal.
            while let Ok(n @ 1..) = reader.read(&mut buf) {
                into.lock()
                    .expect("output lock")
                    .push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        });
        Terminal { child, master, seen }
    }

    /// What the terminal has shown so far.
    pub fn screen(&self) -> String {
        self.seen.lock().expect("output lock").clone()
    }

    /// Waits until the terminal shows `text` `times` times (at most 30 s); fails the test
    /// otherwise.
    pub fn wait_for(&self, text: &str, times: usize) {
        let started = std::time::Instant::now();
        while self.screen().matches(text).count() < times {
            assert!(
                started.elapsed() < std::time::Duration::from_secs(30),
                "never showed {text:?} {times} time(s):\n{}",
                self.screen()
            );
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
    }

    /// Types `keys` (`"yes\r"`: a line and Enter).
    pub fn type_keys(&mut self, keys: &str) {
        use std::io::Write;
        self.master.write_all(keys.as_bytes()).expect("type into the pty");
    }

    /// Sends signal `name` (`TERM`, …) to the run.
    pub fn signal(&self, name: &str) {
        send_signal(&self.child, name);
    }

    /// Waits for the run to end (at most 60 s); its exit code and everything it showed.
    pub fn finish(mut self) -> (Option<i32>, String) {
        let started = std::time::Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait().expect("wait for the run") {
                break s;
            }
            if started.elapsed() > std::time::Duration::from_secs(60) {
                let _ = self.child.kill();
                panic!("the run did not end:\n{}", self.screen());
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        };
        // What it wrote last is read before the terminal is closed.
        std::thread::sleep(std::time::Duration::from_millis(100));
        (status.code(), self.screen())
    }
}

/// Sends signal `name` (`INT`, `TERM`, …) to `child`.
#[cfg(unix)]
pub fn send_signal(child: &std::process::Child, name: &str) {
    let status = Command::new("kill")
        .arg(format!("-{name}"))
        .arg(child.id().to_string())
        .status()
        .expect("kill runs");
    assert!(status.success());
}

/// A PostgreSQL server of a test's own in a scratch folder, on a free TCP port of
/// 127.0.0.1, trusting local connections; stopped when dropped. The server refuses to run
/// as root, so under root (as CI runs) it runs as the user `nobody`. Under Wine it runs on
/// the Linux side (see `wine_host`).
#[cfg(unix)]
pub struct PostgresServer {
    bin: PathBuf,
    data: PathBuf,
    log: PathBuf,
    port: u16,
    as_nobody: bool,
    /// Server options for TLS, when it takes only TLS connections.
    tls: String,
}

#[cfg(unix)]
impl PostgresServer {
    /// Starts one in the scratch folder `name`; `None` (after [`tool_missing`]) where
    /// PostgreSQL is not installed.
    #[track_caller]
    pub fn start(name: &str) -> Option<PostgresServer> {
        let bin = std::fs::read_dir("/usr/lib/postgresql")
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.path().join("bin"))
            .filter(|b| b.join("initdb").is_file())
            .max_by_key(|b| {
                b.parent()
                    .and_then(|v| v.file_name())
                    .and_then(|v| v.to_str())
                    .and_then(|v| v.parse::<u32>().ok())
            });
        let Some(bin) = bin else {
            tool_missing("no PostgreSQL server installed (/usr/lib/postgresql/*/bin/initdb)");
            return None;
        };
        let dir = scratch(name);
        // SAFETY: geteuid has no preconditions and only reads the process's user id.
        let as_nobody = unsafe { libc::geteuid() } == 0;
        let server = PostgresServer {
            bin,
            data: dir.join("data"),
            log: dir.join("server.log"),
            port: free_port(),
            as_nobody,
            tls: String::new(),
        };
        if as_nobody {
            let status = Command::new("chown")
                .args(["-R", "nobody"])
                .arg(&dir)
                .status()
                .expect("chown runs");
            assert!(status.success(), "chown the scratch folder to nobody");
        }
        let out = server
            .tool("initdb")
            .arg("-D")
            .arg(&server.data)
            .args([
                "-A",
                "trust",
                "-U",
                "drivescript",
                "-E",
                "UTF8",
                "--no-locale",
                "-N",
            ])
            .output()
            .expect("initdb runs");
        assert!(out.status.success(), "initdb: {}{}", stdout(&out), stderr(&out));
        server.up();
        Some(server)
    }

    /// [`PostgresServer::start`], taking only TLS connections, with a certificate for
    /// 127.0.0.1 signed by a CA of its own: the server and the CA's certificate (PEM).
    /// `None` (after [`tool_missing`]) without PostgreSQL or the openssl command.
    #[track_caller]
    pub fn start_tls(name: &str) -> Option<(PostgresServer, PathBuf)> {
        if Command::new("openssl").arg("version").output().is_err() {
            tool_missing("no openssl command: the TLS certificates are not made");
            return None;
        }
        let mut server = PostgresServer::start(name)?;
        server.down();
        let dir = server.data.parent().expect("the scratch folder").to_path_buf();
        let openssl = |args: &[&str]| {
            let out = Command::new("openssl")
                .args(args)
                .current_dir(&dir)
                .output()
                .expect("openssl runs");
            assert!(out.status.success(), "openssl {args:?}: {}", stderr(&out));
        };
        write_file(
            &dir,
            "ext.cnf",
            "subjectAltName=IP:127.0.0.1\nbasicConstraints=CA:FALSE\n",
        );
        openssl(&[
            "req",
            "-x509",
            "-newkey",
            "rsa:2048",
            "-nodes",
            "-keyout",
            "ca.key",
            "-out",
            "ca.crt",
            "-days",
            "2",
            "-subj",
            "/CN=drivescript test CA",
        ]);
        openssl(&[
            "req",
            "-newkey",
            "rsa:2048",
            "-nodes",
            "-keyout",
            "server.key",
            "-out",
            "server.csr",
            "-subj",
            "/CN=127.0.0.1",
        ]);
        openssl(&[
            "x509",
            "-req",
            "-in",
            "server.csr",
            "-CA",
            "ca.crt",
            "-CAkey",
            "ca.key",
            "-CAcreateserial",
            "-out",
            "server.crt",
            "-days",
            "2",
            "-extfile",
            "ext.cnf",
        ]);
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(dir.join("server.key"), std::fs::Permissions::from_mode(0o600))
            .expect("key mode");
        if server.as_nobody {
            let status = Command::new("chown")
                .args(["-R", "nobody"])
                .arg(&dir)
                .status()
                .expect("chown runs");
            assert!(status.success());
        }
        // Only TLS connections from 127.0.0.1.
        std::fs::write(
            server.data.join("pg_hba.conf"),
            "hostssl all all 127.0.0.1/32 trust\n",
        )
        .expect("pg_hba.conf");
        server.tls = format!(
            " -c ssl=on -c ssl_cert_file={} -c ssl_key_file={}",
            dir.join("server.crt").display(),
            dir.join("server.key").display()
        );
        server.up();
        Some((server, dir.join("ca.crt")))
    }

    /// `postgres://…` of the server, with a password (which it does not ask for) so that
    /// tests can see it is never shown.
    pub fn url(&self) -> String {
        format!(
            "postgres://drivescript:pw-s3cret@127.0.0.1:{}/postgres",
            self.port
        )
    }

    fn tool(&self, name: &str) -> Command {
        let program = self.bin.join(name);
        if self.as_nobody {
            let mut c = Command::new("runuser");
            c.args(["-u", "nobody", "--"]).arg(program);
            c
        } else {
            Command::new(program)
        }
    }

    /// Starts the server (again) and waits until it takes connections.
    pub fn up(&self) {
        let options = format!(
            "-p {} -c listen_addresses=127.0.0.1 -c unix_socket_directories='' -c fsync=off -c max_connections=100{}",
            self.port, self.tls
        );
        let out = self
            .tool("pg_ctl")
            .arg("-D")
            .arg(&self.data)
            .arg("-l")
            .arg(&self.log)
            .args(["-o", &options, "-w", "-t", "60", "start"])
            .output()
            .expect("pg_ctl runs");
        let log = std::fs::read_to_string(&self.log).unwrap_or_default();
        assert!(
            out.status.success(),
            "pg_ctl start: {}{}{log}",
            stdout(&out),
            stderr(&out)
        );
    }

    /// Stops the server at once.
    pub fn down(&self) {
        let _ = self
            .tool("pg_ctl")
            .arg("-D")
            .arg(&self.data)
            .args(["-m", "immediate", "-w", "stop"])
            .output();
    }
}

#[cfg(unix)]
impl Drop for PostgresServer {
    fn drop(&mut self) {
        self.down();
    }
}

#[cfg(windows)]
pub struct PostgresServer {
    line: std::sync::Mutex<crate::wine_host::HostLine>,
    url: String,
}

#[cfg(windows)]
impl PostgresServer {
    #[track_caller]
    pub fn start(name: &str) -> Option<PostgresServer> {
        Some(PostgresServer::ask("plain", name)?.0)
    }

    #[track_caller]
    pub fn start_tls(name: &str) -> Option<(PostgresServer, PathBuf)> {
        let (server, ca) = PostgresServer::ask("tls", name)?;
        Some((server, PathBuf::from(ca)))
    }

    #[track_caller]
    fn ask(kind: &str, name: &str) -> Option<(PostgresServer, String)> {
        let (line, answer) = crate::wine_host::HostLine::ask(&["postgres", kind, name])?;
        let (url, ca) = answer.split_once('\t').unwrap_or((&answer, ""));
        let server = PostgresServer {
            url: url.to_string(),
            line: std::sync::Mutex::new(line),
        };
        Some((server, ca.to_string()))
    }

    pub fn url(&self) -> String {
        self.url.clone()
    }

    pub fn up(&self) {
        self.line.lock().expect("the line to the Linux side").say("up");
    }

    pub fn down(&self) {
        self.line.lock().expect("the line to the Linux side").say("down");
    }
}

/// A TCP port of 127.0.0.1 nothing listens on at the moment.
#[cfg(unix)]
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

/// A port on loopback that takes every connection and never says a word.
pub fn silent_server() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("listener");
    let port = listener.local_addr().expect("address").port();
    std::thread::spawn(move || {
        let mut kept = Vec::new();
        for conn in listener.incoming() {
            kept.push(conn);
        }
    });
    port
}

/// `drivescript run RECIPE --results STORE ARGS`: its exit code and everything it wrote
/// (standard output, then errors).
pub fn run_recording(recipe: &Path, store: &str, args: &[&str]) -> (i32, String) {
    let out = command()
        .arg("run")
        .arg(recipe)
        .args(["--results", store])
        .args(args)
        .output()
        .expect("runs");
    (out.status.code().unwrap_or(-1), console(&out.stdout, &out.stderr))
}

/// `drivescript results report --unit SERIAL` of every run in `store` (simulated ones too)
/// into `page`; the page.
pub fn unit_certificate(store: &str, serial: &str, page: &Path) -> String {
    cli(
        &[
            "results",
            "report",
            "--unit",
            serial,
            "--simulated",
            "--results",
            store,
            "-o",
            page.to_str().expect("utf-8 path"),
        ],
        0,
    );
    std::fs::read_to_string(page).expect("the page")
}

/// A short recipe with one check and a sampled series, in virtual time.
pub const SHORT_RECIPE: &str = "name: Short acceptance
drive: sd2
params:
  speed: 3000 rpm
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: \"{{speed}}\" }
  - wait_until: { speed_actual: { near: \"{{speed}}\", within: 1 % }, timeout: 10 s }
  - sample: { objects: [speed_actual], every: 100 ms, for: 5 s }
  - expect:
      speed_actual: { mean: { near: \"{{speed}}\", within: 1 % } }
";

/// `--unit serial=SP-1 --unit station=…` for `run`, from `(field, value)` pairs.
pub fn unit_args(fields: &[(&str, &str)]) -> Vec<String> {
    fields
        .iter()
        .flat_map(|(k, v)| ["--unit".to_string(), format!("{k}={v}")])
        .collect()
}
