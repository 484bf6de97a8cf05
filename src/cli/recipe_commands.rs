//! `drivescript check` and `drivescript run`: validate recipes without a port, and run one
//! with the safe stop at every ending.

use super::connection_args::{parse_duration, ConnectionArgs};
use super::drive_args::{open_drive, DictionaryArgs};
use super::drive_set::{drive_dictionaries, several_checked, several_opened};
use super::not_run::{not_run, silent_drive};
use super::run_setup::{
    finish_reports, observed, open_csv, telegram_outputs, trace_header, write_placeholders, Look,
};
use super::several_runs::{outputs_for, print_outputs, worse};
use super::COMMUNICATION;
use super::{panic_notice, stop_signals, INVALID, PASSED};
use crate::clock::SharedClock;
use crate::dictionary::Quantity;
use crate::family::Registry;
use crate::recipe::{
    declared_drives, load_recipe_for, planned_checks, sampled_objects, Recipe, RecipeInvalid, RunReport,
    Runner, SafeStopChoice, SafeStopSettings,
};
use crate::sim::SimulatedDrive;
use crate::stop_request::StopRequests;
use clap::Args;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

#[derive(Debug, Args)]
/// Validate recipes against the dictionary without opening any port: object names, units,
/// limits, durations, parameters, states, included files, unknown keys. Reports every
/// problem at once; exit code 2 if there is any. With --port or --tcp it also reads the
/// minimum and maximum of every object the recipe writes from the drive (families whose
/// drives report them, e.g. lenze-931) and refuses values outside; only reads are sent.
/// A `.rhai` file is a Rhai script: its syntax and the drive calls written with literals
/// (with --port, its literal values against the drive's limits too).
pub struct CheckArgs {
    #[arg(required = true, value_name = "RECIPE")]
    recipes: Vec<PathBuf>,
    /// Parameter override, NAME=VALUE (e.g. speed=8000rpm); may be repeated.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
    set: Vec<(String, String)>,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

#[derive(Debug, Args)]
/// Run recipes. Without --port or --tcp they run against the built-in simulated drive and
/// say so. Each recipe is checked first; nothing is sent if it has a problem. Whatever
/// happens, the safe stop runs: a drive still enabled and turning gets the speed setpoint
/// 0 and is waited for until it stands still (--stop-timeout, --standstill) before
/// anything disables it, then `finally` runs (default: disable operation, then shutdown),
/// then the state and speed are read back and the stop escalated if the drive did not
/// obey. Only a recipe's `safe_stop: { brake_to_standstill: false }` skips the braking
/// (check says so); a second stop signal switches the power stage off at once. Several recipes
/// run one after the other, each with its own safe stop and reports; the exit code is the
/// worst of them. Before anything moves, every value the recipe writes (a script's
/// literal values too) is compared with the limits the drive itself reports, where its
/// family's drives report them (lenze-931); a value outside refuses the run (exit code 2).
/// A `.rhai` file runs as a Rhai script, with the same reports and safe stop.
pub struct RunArgs {
    #[arg(value_name = "RECIPE", required = true)]
    recipes: Vec<PathBuf>,
    /// Parameter override, NAME=VALUE (e.g. speed=8000rpm); may be repeated.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
    set: Vec<(String, String)>,
    /// Simulated drive only: run in virtual time, so hours take seconds with identical
    /// results.
    #[arg(long, conflicts_with = "realtime")]
    fast: bool,
    /// Run in real time (the default; with a real drive always).
    #[arg(long)]
    realtime: bool,
    /// Directory for every output given as a relative path: --junit, --report, --csv,
    /// --trace and the `csv:` files of sample steps (and of a script's `sample`) (default:
    /// the current directory).
    #[arg(long, value_name = "DIR", default_value = ".")]
    output_dir: PathBuf,
    #[command(flatten)]
    outputs: OutputArgs,
    #[command(flatten)]
    safe_stop: SafeStopArgs,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

/// How the safe stop at the end of every run behaves.
#[derive(Debug, Clone, Default, Args)]
#[command(next_help_heading = "Safe stop")]
pub struct SafeStopArgs {
    /// How long the safe stop waits, setpoint at 0, for standstill before it disables
    /// the drive (also before a recipe's own finally) [default: 60s].
    #[arg(long, value_name = "DURATION", value_parser = parse_stop_duration)]
    pub stop_timeout: Option<std::time::Duration>,
    /// Speeds within ± this count as standstill [default: 10rpm].
    #[arg(long, value_name = "SPEED", value_parser = parse_speed)]
    pub standstill: Option<Quantity>,
    /// How long to keep trying to reopen a lost port to deliver the safe stop [default: 10s].
    #[arg(long, value_name = "DURATION", value_parser = parse_stop_duration)]
    pub reconnect_timeout: Option<std::time::Duration>,
    /// Read the status word for fault watching at most this often [default: 250ms].
    #[arg(long, value_name = "DURATION", value_parser = parse_stop_duration)]
    pub fault_poll: Option<std::time::Duration>,
}

impl SafeStopArgs {
    /// The command line's choices on top of the recipe's, on top of the defaults.
    pub fn settings(&self, recipe: &SafeStopChoice) -> SafeStopSettings {
        let d = SafeStopSettings::default();
        SafeStopSettings {
            standstill_timeout: self
                .stop_timeout
                .or(recipe.timeout)
                .unwrap_or(d.standstill_timeout),
            standstill: self.standstill.or(recipe.standstill).unwrap_or(d.standstill),
            brake_to_standstill: recipe.no_brake_at.is_none(),
            reconnect_timeout: self.reconnect_timeout.unwrap_or(d.reconnect_timeout),
            fault_poll: self.fault_poll.unwrap_or(d.fault_poll),
        }
    }
}

/// A safe-stop wait from the command line: at least a millisecond, at most a day.
fn parse_stop_duration(text: &str) -> Result<std::time::Duration, String> {
    let d = parse_duration(text)?;
    if d.is_zero() || d > std::time::Duration::from_secs(24 * 3600) {
        return Err(format!("`{text}`: give a duration between 1ms and 24h"));
    }
    Ok(d)
}

fn parse_speed(text: &str) -> Result<Quantity, String> {
    let q = Quantity::parse(text).map_err(|e| e.to_string())?;
    match q.unit {
        Some(u) if u.dimension() == crate::dictionary::Dimension::Speed && q.value >= 0.0 => Ok(q),
        _ => Err(format!("`{text}`: give a speed with its unit, e.g. 10rpm")),
    }
}

/// What a run writes besides the console.
#[derive(Debug, Clone, Default, Args)]
#[command(next_help_heading = "Output")]
pub struct OutputArgs {
    /// Print every telegram sent and received, with its time and meaning, to standard error.
    #[arg(short, long)]
    pub verbose: bool,
    /// Write every telegram to FILE as the run goes (`drivescript decode` reads it back).
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Stream every sample to FILE: time since the start, UTC time, step, object, value,
    /// unit (one row per value); flushed at least every 250 ms.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// --csv and the `csv:` files of sample steps (and of a script's `sample`) with one
    /// column per object instead of one row per value.
    #[arg(long)]
    pub csv_wide: bool,
    /// Write a JUnit XML report: one test case per check, for CI servers.
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// Write a self-contained HTML report with plots of every sampled series.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    /// Plain lines only: no live progress bar.
    #[arg(long, alias = "no-progress")]
    pub quiet: bool,
    /// Colour PASS/FAIL and the verdict: auto (on a terminal, unless NO_COLOR is set),
    /// always, never.
    #[arg(long, value_name = "WHEN", value_enum, default_value_t = ColorWhen::Auto)]
    pub color: ColorWhen,
}

/// `--color`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorWhen {
    #[default]
    Auto,
    Always,
    Never,
}

impl ColorWhen {
    /// `None` for auto: the terminal and `NO_COLOR` decide.
    pub fn choice(self) -> Option<bool> {
        match self {
            ColorWhen::Auto => None,
            ColorWhen::Always => Some(true),
            ColorWhen::Never => Some(false),
        }
    }
}

fn parse_set(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(format!("`{text}`: write NAME=VALUE, e.g. speed=8000rpm")),
    }
}

fn print_invalid(e: &RecipeInvalid) {
    eprint!("{}", e.render(std::io::stderr().is_terminal()));
}

pub fn check(args: &CheckArgs) -> i32 {
    let mut code = PASSED;
    let mut last_error = String::new();
    for path in &args.recipes {
        // Per recipe: each may have its own drivescript-limits.yaml next to it. A broken
        // --dictionary or --limits file is said once, not once per recipe.
        let dictionary = match args.dictionary.load_for(&Registry::builtin(), Some(path)) {
            Ok(d) => d,
            Err(text) => {
                if text != last_error {
                    eprint!("{text}");
                    last_error = text;
                }
                code = INVALID;
                continue;
            }
        };
        if crate::script::is_script(path) {
            code = code.max(super::script_commands::check_script(
                path,
                &dictionary,
                &args.dictionary,
                &args.set,
                &args.connection,
            ));
            continue;
        }
        // A recipe with `drives:` is checked against each drive's own dictionary.
        let declared = declared_drives(path);
        let drive_dicts = if declared.is_empty() {
            Vec::new()
        } else {
            match drive_dictionaries(&args.dictionary, &Registry::builtin(), path, &declared) {
                Ok(d) => d,
                Err(text) => {
                    eprint!("{text}");
                    code = INVALID;
                    continue;
                }
            }
        };
        let dictionary = drive_dicts.first().map_or(dictionary, |(_, d)| d.clone());
        match load_recipe_for(
            path,
            &dictionary,
            &drive_dicts,
            &Registry::builtin().address_keys(),
            &args.set,
        ) {
            Ok(recipe) if !recipe.drives.is_empty() => {
                println!(
                    "ok  {} — {} ({} steps{}, drives {})",
                    path.display(),
                    recipe.name,
                    count_steps(&recipe),
                    finally_note(&recipe),
                    recipe
                        .drives
                        .iter()
                        .map(|d| format!("{}: {}", d.name, d.drive))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                print_safe_stop_choices(path, &recipe.safe_stop, recipe.leave_enabled);
            }
            Ok(recipe) => {
                println!(
                    "ok  {} — {} ({} steps{})",
                    path.display(),
                    recipe.name,
                    count_steps(&recipe),
                    finally_note(&recipe)
                );
                print_safe_stop_choices(path, &recipe.safe_stop, recipe.leave_enabled);
                if let Some(limits) = dictionary.bench_limits() {
                    println!("    bench limits {} ({})", limits.summary(), limits.source());
                }
                if !args.connection.is_simulated() {
                    code = code.max(super::drive_limits::check_and_print(
                        &recipe,
                        dictionary,
                        &args.connection,
                    ));
                }
            }
            Err(e) => {
                print_invalid(&e);
                code = INVALID;
            }
        }
    }
    code
}

fn count_steps(recipe: &Recipe) -> usize {
    recipe.steps.len()
}

/// What `check` says about a recipe's or script's opt-out from braking and about
/// `leave_enabled`, so that neither is silent.
pub(super) fn print_safe_stop_choices(path: &std::path::Path, choice: &SafeStopChoice, leave_enabled: bool) {
    if leave_enabled {
        println!(
            "    leave_enabled: a run that succeeds leaves the drive as its steps left it (no brake, \
             no finally); every other ending stops it. `drivescript stop` stops it later"
        );
    }
    if let Some((line, column)) = choice.no_brake_at {
        println!(
            "    safe stop does not brake: brake_to_standstill is false at {}:{line}:{column}; \
             a drive still turning at the end is disabled at speed and coasts",
            path.display()
        );
    }
}

fn finally_note(recipe: &Recipe) -> &'static str {
    match &recipe.finally {
        None => ", default finally",
        Some(s) if s.is_empty() => ", empty finally",
        Some(_) => "",
    }
}

pub fn run(args: &RunArgs) -> i32 {
    let stop = stop_signals::install(true);
    panic_notice::install();
    let registry = Registry::builtin();
    let several = args.recipes.len() > 1;
    let mut worst = PASSED;
    let mut verdicts = Vec::new();
    for (i, recipe) in args.recipes.iter().enumerate() {
        if several {
            println!(
                "{}== recipe {} of {}: {}",
                if i > 0 { "\n" } else { "" },
                i + 1,
                args.recipes.len(),
                recipe.display()
            );
        }
        let outputs = outputs_for(
            &args.outputs,
            &args.output_dir,
            several.then_some((i + 1, recipe.as_path())),
        );
        let request = RunRequest {
            registry: &registry,
            recipe,
            set: &args.set,
            fast: args.fast,
            output_dir: args.output_dir.clone(),
            dictionary: &args.dictionary,
            connection: &args.connection,
            outputs: &outputs,
            // Nobody reads the simulated drive's request log from the command line.
            prepare_simulator: Some(&|sim, _| {
                sim.lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .set_logging(false)
            }),
            stop: stop.clone(),
            safe_stop: args.safe_stop.clone(),
            terminal: std::io::stdout().is_terminal(),
        };
        let mut stdout = std::io::stdout();
        let mut stderr = std::io::stderr();
        let result = run_recipe(&request, &mut stdout, &mut stderr);
        print_outputs(&outputs, result.report.as_ref());
        verdicts.push((recipe.display().to_string(), result.exit_code));
        worst = worse(worst, result.exit_code);
        // A stop signal or a panic ends the whole command, after this recipe's safe stop.
        if result.exit_code >= 128 || result.exit_code == crate::session::PANIC_EXIT {
            break;
        }
    }
    if several {
        println!("\n== {} recipe(s):", verdicts.len());
        for (path, code) in &verdicts {
            println!("   exit code {code}  {path}");
        }
        println!("exit code {worst} (the worst of them)");
    }
    worst
}

/// A hook that gets the simulated drive and the run's clock before the run starts.
pub type PrepareSimulator = dyn Fn(&Arc<Mutex<dyn SimulatedDrive>>, &SharedClock);

/// Everything a run needs; the command line fills it from its options, the tests directly.
pub struct RunRequest<'a> {
    /// The drive families to pick from (the built-in ones; tests add their own).
    pub registry: &'a Registry,
    pub recipe: &'a Path,
    pub set: &'a [(String, String)],
    /// Virtual time (simulated drive only).
    pub fast: bool,
    pub output_dir: PathBuf,
    pub dictionary: &'a DictionaryArgs,
    pub connection: &'a ConnectionArgs,
    pub outputs: &'a OutputArgs,
    /// Called with the simulated drive and the run's clock before the run (tests inject
    /// faults here); with `drives:`, once for each simulated drive in the order declared.
    pub prepare_simulator: Option<&'a PrepareSimulator>,
    /// Stop requests (signals, or scheduled by tests).
    pub stop: Arc<StopRequests>,
    /// The command line's choices for the safe stop (over the recipe's and the defaults).
    pub safe_stop: SafeStopArgs,
    /// Whether standard output is a terminal (live progress).
    pub terminal: bool,
}

/// What a run produced.
pub struct RunResult {
    pub exit_code: i32,
    /// `None` when the run never started (invalid recipe, port not available).
    pub report: Option<RunReport>,
    /// The simulated drive (the first declared one of a recipe with `drives:`).
    pub simulator: Option<Arc<Mutex<dyn SimulatedDrive>>>,
    /// Every simulated drive by the recipe's name for it (empty name: the one drive).
    pub simulators: Vec<(String, Arc<Mutex<dyn SimulatedDrive>>)>,
}

impl RunResult {
    /// A run that never started.
    pub fn refused(exit_code: i32) -> Self {
        RunResult {
            exit_code,
            report: None,
            simulator: None,
            simulators: Vec::new(),
        }
    }
}

/// Checks and runs a recipe, writing the console output to `out` and problems to `err`.
pub fn run_recipe(request: &RunRequest, out: &mut dyn Write, err: &mut dyn Write) -> RunResult {
    if crate::script::is_script(request.recipe) {
        return super::script_commands::run_script(request, out, err);
    }
    let refused = |code| RunResult::refused(code);
    // A recipe with `drives:` names a dictionary per drive; the first is the recipe's.
    let declared = declared_drives(request.recipe);
    let loaded = if declared.is_empty() {
        request
            .dictionary
            .load_for(request.registry, Some(request.recipe))
            .map(|d| (d, Vec::new()))
    } else {
        drive_dictionaries(request.dictionary, request.registry, request.recipe, &declared)
            .map(|all| (all[0].1.clone(), all))
    };
    let (dictionary, drive_dicts) = match loaded {
        Ok(d) => d,
        Err(text) => {
            let _ = write!(err, "{text}");
            return not_run(request, None, INVALID, &text, err);
        }
    };
    let recipe = match load_recipe_for(
        request.recipe,
        &dictionary,
        &drive_dicts,
        &request.registry.address_keys(),
        request.set,
    ) {
        Ok(r) => r,
        Err(e) => {
            let text = e.render(false);
            let _ = write!(err, "{text}");
            return not_run(request, None, INVALID, &text, err);
        }
    };
    let planned = planned_checks(&recipe);
    let invalid = |text: String, err: &mut dyn Write| {
        let _ = writeln!(err, "{text}");
        not_run(request, Some((&recipe, &planned)), INVALID, &text, err)
    };
    if request.fast && !request.connection.is_simulated() {
        return invalid("error: --fast (virtual time) works only with the built-in simulated drive; a real drive runs in real time".into(), err);
    }
    if !recipe.drives.is_empty() {
        return run_several(request, &recipe, &drive_dicts, &planned, out, err);
    }
    // Files are opened before anything is sent: a path that cannot be written is an
    // invalid command line, not a half-run recipe.
    let outputs = request.outputs;
    let family = match request.registry.family(dictionary.family()) {
        Ok(f) => f,
        Err(e) => return invalid(format!("error: {e}"), err),
    };
    let address = match request.connection.check(family.as_ref()) {
        Ok(a) => a.shown,
        Err(e) => return invalid(format!("error: {e}"), err),
    };
    let header = trace_header(
        family.as_ref(),
        &dictionary,
        &request.dictionary.extra,
        request.connection,
        address,
    );
    let telegrams = match telegram_outputs(outputs, family.as_ref(), &dictionary, &header) {
        Ok(t) => t,
        Err(text) => return invalid(text, err),
    };
    let mut csv = match open_csv(
        outputs,
        outputs.csv_wide.then_some(&sampled_objects(&recipe)[..]),
        false,
    ) {
        Ok(c) => c,
        Err(text) => return invalid(text, err),
    };
    if let Err(text) = write_placeholders(outputs, &recipe.name, &recipe.path) {
        let _ = writeln!(err, "{text}");
        return refused(INVALID);
    }
    // The recipe's `link:` settings under the command line's, checked before anything is
    // opened: a wrong setting is an invalid recipe or command line (exit 2), not a
    // communication failure.
    let connection = request.connection.with_defaults(&recipe.link);
    if let Ok(family) = request.registry.family(dictionary.family()) {
        if let Err(e) = connection.check(family.as_ref()) {
            let _ = writeln!(
                err,
                "error: {e} (link settings come from the recipe's `link:` and the command line)"
            );
            return refused(INVALID);
        }
    }
    let mut open = match open_drive(
        request.registry,
        &connection,
        dictionary,
        request.fast,
        telegrams.into_observer(),
        Some(request.stop.clone()),
    ) {
        Ok(o) => o,
        Err(text) => {
            let _ = writeln!(err, "{text}");
            return not_run(request, Some((&recipe, &planned)), COMMUNICATION, &text, err);
        }
    };
    // A drive that never answers is said once, early, with what to check, instead of
    // every step and the safe stop each waiting out their retries.
    if open.simulator.is_none() {
        if let Err(crate::drive::DriveError::Access(e)) = open.drive.state() {
            if e.is_no_reply() {
                let text = silent_drive(request.connection, &e.to_string());
                let _ = writeln!(err, "{text}");
                return not_run(request, Some((&recipe, &planned)), COMMUNICATION, &text, err);
            }
        }
    }
    if let (Some(sim), Some(prepare)) = (&open.simulator, request.prepare_simulator) {
        prepare(sim, open.drive.clock());
    }
    if open.simulator.is_some() {
        let _ = writeln!(out, "using {}", open.description);
    }
    if let Err(code) = within_drive_limits(
        &crate::recipe::written_values(&recipe),
        &mut open.drive,
        &recipe.path,
        &request.stop,
        out,
        err,
    ) {
        return not_run(request, Some((&recipe, &planned)), code.0, &code.1, err);
    }
    let virtual_time = request.fast && open.simulator.is_some();
    let planned_time = crate::recipe::longest_time_of(&recipe.steps);
    let look = Look::of(outputs, request.terminal, virtual_time, true, Some(planned_time));
    let report = observed(out, &look, csv.as_mut(), |observers| {
        Runner::new(&mut open.drive, observers, &request.stop, &recipe)
            .with_output_dir(request.output_dir.clone())
            .with_csv_wide(outputs.csv_wide)
            .with_settings(request.safe_stop.settings(&recipe.safe_stop))
            .run(&recipe)
    });
    finish_reports(&report, &planned, csv.as_ref(), outputs, err);
    RunResult {
        exit_code: report.exit_code(),
        report: Some(report),
        simulators: open
            .simulator
            .iter()
            .map(|s| (String::new(), s.clone()))
            .collect(),
        simulator: open.simulator,
    }
}

/// Before the first telegram that moves anything: the values `values` write compared with
/// the limits the drive itself reports, as `check --port` compares them (families whose
/// drives report none are asked nothing and nothing is said). `Err` holds the exit code
/// and the reason for the not-run reports, already said on `err`.
pub fn within_drive_limits(
    values: &[crate::recipe::WrittenValue],
    drive: &mut crate::drive::Drive,
    path: &str,
    stop: &StopRequests,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<(), (i32, String)> {
    let check = super::drive_limits::compare(values, drive);
    // A stop signal while the limits were read ends the run with that signal's code; the
    // unanswered read is no communication failure.
    if let (Err(_), Some(signal)) = (&check, stop.first()) {
        let why = format!(
            "stopped by {} while the drive's limits were read; nothing was sent to move the drive",
            signal.describe()
        );
        let _ = writeln!(err, "{why}");
        return Err((signal.exit_code(), why));
    }
    match super::drive_limits::report(&check, path, false, out, err) {
        (PASSED, _) => Ok(()),
        (code, why) => Err((code, why)),
    }
}

/// A recipe with `drives:`: every drive opened (the ones on one connection on one bus),
/// then the same reports and safe stop as for one drive, over all of them.
fn run_several(
    request: &RunRequest,
    recipe: &Recipe,
    drive_dicts: &[(String, Arc<crate::dictionary::Dictionary>)],
    planned: &[crate::session::PlannedCheck],
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> RunResult {
    let invalid = |text: String, err: &mut dyn Write| {
        let _ = writeln!(err, "{text}");
        not_run(request, Some((recipe, planned)), INVALID, &text, err)
    };
    let outputs = request.outputs;
    let connection = request.connection.with_defaults(&recipe.link);
    let telegrams = match several_checked(request, &connection, &recipe.drives, drive_dicts) {
        Ok(t) => t,
        Err(text) => return invalid(text, err),
    };
    let mut csv = match open_csv(
        outputs,
        outputs.csv_wide.then_some(&sampled_objects(recipe)[..]),
        true,
    ) {
        Ok(c) => c,
        Err(text) => return invalid(text, err),
    };
    if let Err(text) = write_placeholders(outputs, &recipe.name, &recipe.path) {
        let _ = writeln!(err, "{text}");
        return RunResult::refused(INVALID);
    }
    let mut open = match several_opened(request, &connection, &recipe.drives, drive_dicts, &telegrams) {
        Ok(o) => o,
        Err(text) => {
            let _ = writeln!(err, "{text}");
            return not_run(request, Some((recipe, planned)), COMMUNICATION, &text, err);
        }
    };
    if !open.simulators.is_empty() {
        let _ = writeln!(out, "using {}", open.description);
    }
    // Each drive's limits for the values written to it (`left.speed_setpoint`).
    let written = crate::recipe::written_values(recipe);
    for (name, drive) in open.drives.iter_mut() {
        let prefix = format!("{name}.");
        let own: Vec<_> = written
            .iter()
            .filter(|w| w.object.name.starts_with(&prefix))
            .cloned()
            .collect();
        if let Err((code, why)) = within_drive_limits(&own, drive, &recipe.path, &request.stop, out, err) {
            return not_run(request, Some((recipe, planned)), code, &why, err);
        }
    }
    let virtual_time = request.fast && !open.simulators.is_empty();
    let planned_time = crate::recipe::longest_time_of(&recipe.steps);
    let look = Look::of(outputs, request.terminal, virtual_time, true, Some(planned_time));
    let report = observed(out, &look, csv.as_mut(), |observers| {
        let drives = open.drives.iter_mut().map(|(n, d)| (n.clone(), d)).collect();
        Runner::with_drives(drives, observers, &request.stop, recipe)
            .with_output_dir(request.output_dir.clone())
            .with_csv_wide(outputs.csv_wide)
            .with_settings(request.safe_stop.settings(&recipe.safe_stop))
            .run(recipe)
    });
    finish_reports(&report, planned, csv.as_ref(), outputs, err);
    RunResult {
        exit_code: report.exit_code(),
        report: Some(report),
        simulator: open.simulators.first().map(|(_, s)| s.clone()),
        simulators: open.simulators,
    }
}

#[derive(Debug, Args)]
/// Print the JSON Schema of recipes, for editor completion of keys, object names and
/// states. Recipes point their editor at it with a first line
/// `# yaml-language-server: $schema=../recipe.schema.json`.
pub struct SchemaArgs {
    #[command(flatten)]
    dictionary: DictionaryArgs,
}

pub fn schema(args: &SchemaArgs) -> i32 {
    match args.dictionary.load() {
        Ok(d) => {
            let text = serde_json::to_string_pretty(&crate::recipe::recipe_schema(
                &d,
                &Registry::builtin().address_keys(),
            ))
            .unwrap_or_default();
            println!("{text}");
            PASSED
        }
        Err(text) => {
            eprint!("{text}");
            INVALID
        }
    }
}
