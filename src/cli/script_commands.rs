//! `check` and `run` for Rhai scripts (`.rhai`): the same dictionary, connection, outputs
//! and safe stop as recipes, with the script front end in place of the recipe interpreter.
//! `check` never opens a port. Turns results into text and exit codes.

use super::recipe_commands::{RunRequest, RunResult};
use super::{COMMUNICATION, INVALID, PASSED};
use crate::dictionary::Dictionary;
use crate::recipe::{Observers, SafeStopChoice};
use crate::report::{
    write_html, write_html_unfinished, write_junit, write_junit_unfinished, ConsoleReporter, CsvRecorder,
    ProgressReporter, TelegramFanOut, TraceWriter,
};
use crate::script::{load_script, ScriptRunner};
use std::io::{IsTerminal, Write};
use std::path::Path;

/// Checks one script against `dictionary`; prints `ok` or its problems; the exit code.
pub fn check_script(path: &Path, dictionary: &Dictionary, set: &[(String, String)]) -> i32 {
    match load_script(path, dictionary, set) {
        Ok(script) => {
            println!(
                "ok  {} — {} (script, {} calls{})",
                path.display(),
                script.name,
                script.calls,
                if script.has_finally {
                    ", its own finally"
                } else {
                    ", default finally"
                }
            );
            if let Some(limits) = dictionary.bench_limits() {
                println!("    bench limits {} ({})", limits.summary(), limits.source());
            }
            PASSED
        }
        Err(e) => {
            eprint!("{}", e.render(std::io::stderr().is_terminal()));
            INVALID
        }
    }
}

/// Checks and runs a script, writing the console output to `out` and problems to `err`.
pub fn run_script(request: &RunRequest, out: &mut dyn Write, err: &mut dyn Write) -> RunResult {
    let refused = |code| RunResult {
        exit_code: code,
        report: None,
        simulator: None,
    };
    let dictionary = match request
        .dictionary
        .load_for(request.registry, Some(request.recipe))
    {
        Ok(d) => d,
        Err(text) => {
            let _ = write!(err, "{text}");
            return refused(INVALID);
        }
    };
    let script = match load_script(request.recipe, &dictionary, request.set) {
        Ok(s) => s,
        Err(e) => {
            let _ = write!(err, "{}", e.render(false));
            return refused(INVALID);
        }
    };
    if request.fast && !request.connection.is_simulated() {
        let _ = writeln!(err, "error: --fast (virtual time) works only with the built-in simulated drive; a real drive runs in real time");
        return refused(INVALID);
    }
    let outputs = request.outputs;
    let family = match request.registry.family(dictionary.family()) {
        Ok(f) => f,
        Err(e) => {
            let _ = writeln!(err, "error: {e}");
            return refused(INVALID);
        }
    };
    // The script's `//! link:` settings under the command line's, as for a recipe.
    let connection = request.connection.with_defaults(&script.link);
    if let Err(e) = connection.check(family.as_ref()) {
        let _ = writeln!(err, "error: {e}");
        return refused(INVALID);
    }
    let mut telegrams = TelegramFanOut::new();
    if let Some(path) = &outputs.trace {
        match TraceWriter::create(path, family.explainer(dictionary.clone())) {
            Ok(t) => telegrams.push(Box::new(t)),
            Err(e) => {
                let _ = writeln!(err, "error: {e}");
                return refused(INVALID);
            }
        }
    }
    if outputs.verbose {
        telegrams.push(Box::new(TraceWriter::new(
            std::io::stderr(),
            family.explainer(dictionary.clone()),
        )));
    }
    let mut csv = match &outputs.csv {
        // A script chooses what it samples as it runs, so its CSV is the long layout.
        Some(path) => match CsvRecorder::create(path, None) {
            Ok(c) => Some(c),
            Err(e) => {
                let _ = writeln!(err, "error: {e}");
                return refused(INVALID);
            }
        },
        None => None,
    };
    // As for recipes: an old report is replaced at once by one saying this run has not
    // finished, so a run killed beyond any safe stop never leaves an old PASS.
    let placeholders = [
        outputs
            .junit
            .as_ref()
            .map(|p| write_junit_unfinished(&script.name, &script.path, p)),
        outputs
            .report
            .as_ref()
            .map(|p| write_html_unfinished(&script.name, &script.path, p)),
    ];
    if let Some(e) = placeholders.into_iter().flatten().find_map(Result::err) {
        let _ = writeln!(err, "error: {e}");
        return refused(INVALID);
    }
    let mut open = match super::drive_args::open_drive(
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
            return refused(COMMUNICATION);
        }
    };
    if let (Some(sim), Some(prepare)) = (&open.simulator, request.prepare_simulator) {
        prepare(sim, open.drive.clock());
    }
    if open.simulator.is_some() {
        let _ = writeln!(out, "using {}", open.description);
    }
    let virtual_time = request.fast && open.simulator.is_some();
    let live = request.terminal && !outputs.quiet && !outputs.verbose;
    let mut console = ConsoleReporter::new(&mut *out, virtual_time);
    let mut progress = live.then(|| ProgressReporter::stdout(virtual_time));
    let report = {
        let mut observers = Observers::default();
        match progress.as_mut() {
            Some(p) => observers.push(p),
            None => observers.push(&mut console),
        }
        if let Some(c) = csv.as_mut() {
            observers.push(c);
        }
        ScriptRunner::new(&mut open.drive, &mut observers, request.stop.clone())
            .with_output_dir(request.output_dir.clone())
            .with_settings(request.safe_stop.settings(&SafeStopChoice::default()))
            .run(&script, err)
    };
    if let Some(e) = csv.as_ref().and_then(|c| c.error()) {
        let _ = writeln!(err, "warning: {e}");
    }
    if let Some(path) = &outputs.junit {
        if let Err(e) = write_junit(&report, &[], path) {
            let _ = writeln!(err, "error: {e}");
        }
    }
    if let Some(path) = &outputs.report {
        if let Err(e) = write_html(&report, path) {
            let _ = writeln!(err, "error: {e}");
        }
    }
    RunResult {
        exit_code: report.exit_code(),
        report: Some(report),
        simulator: open.simulator,
    }
}
