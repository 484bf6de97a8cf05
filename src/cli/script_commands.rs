//! `check` and `run` for Rhai scripts (`.rhai`): the same dictionary, connection, outputs
//! and safe stop as recipes, with the script front end in place of the recipe interpreter.
//! `check` never opens a port. Turns results into text and exit codes.

use super::drive_set::{drive_dictionaries, several_checked, several_opened};
use super::recipe_commands::{RunRequest, RunResult};
use super::run_setup::{
    finish_reports, observed, open_csv, telegram_outputs, trace_header, write_placeholders, Look,
};
use super::{COMMUNICATION, INVALID, PASSED};
use crate::dictionary::Dictionary;
use crate::script::{declared_script_drives, load_script_for, Script, ScriptRunner};
use std::io::{IsTerminal, Write};
use std::path::Path;
use std::sync::Arc;

/// Checks one script against `dictionary`; prints `ok` or its problems; the exit code.
/// `dictionary_args` (the command line's `--dictionary`, `--limits`) load the dictionary of
/// each drive a script's `//! drives:` declares.
pub fn check_script(
    path: &Path,
    dictionary: &Dictionary,
    dictionary_args: &super::drive_args::DictionaryArgs,
    set: &[(String, String)],
    connection: &super::ConnectionArgs,
) -> i32 {
    // A script with `//! drives:` is checked against each drive's own dictionary.
    let declared = declared_script_drives(path);
    let drive_dicts = if declared.is_empty() {
        Vec::new()
    } else {
        match drive_dictionaries(
            dictionary_args,
            &crate::family::Registry::builtin(),
            path,
            &declared,
        ) {
            Ok(d) => d,
            Err(text) => {
                eprint!("{text}");
                return INVALID;
            }
        }
    };
    let dictionary = drive_dicts.first().map_or(dictionary, |(_, d)| d.as_ref());
    match load_script_for(path, dictionary, &drive_dicts, set) {
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
            super::recipe_commands::print_safe_stop_choices(path, &script.safe_stop, script.leave_enabled);
            if let Some(limits) = dictionary.bench_limits() {
                println!("    bench limits {} ({})", limits.summary(), limits.source());
            }
            if connection.is_simulated() || script.written.is_empty() {
                return PASSED;
            }
            super::drive_limits::check_values_and_print(
                &script.written,
                &script.path,
                Arc::new(dictionary.clone()),
                connection,
            )
        }
        Err(e) => {
            eprint!("{}", e.render(std::io::stderr().is_terminal()));
            INVALID
        }
    }
}

/// Checks and runs a script, writing the console output to `out` and problems to `err`.
/// The set-up around the session is the recipes' (`run_setup`); a script's problems
/// before the run write no not-run reports, and its console is not coloured.
pub fn run_script(request: &RunRequest, out: &mut dyn Write, err: &mut dyn Write) -> RunResult {
    let refused = |text: String, code, err: &mut dyn Write| {
        let _ = writeln!(err, "{text}");
        RunResult::refused(code)
    };
    // A script with `//! drives:` names a dictionary per drive; the first is the script's.
    let declared = declared_script_drives(request.recipe);
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
            return RunResult::refused(INVALID);
        }
    };
    let script = match load_script_for(request.recipe, &dictionary, &drive_dicts, request.set) {
        Ok(s) => s,
        Err(e) => {
            let _ = write!(err, "{}", e.render(false));
            return RunResult::refused(INVALID);
        }
    };
    if request.fast && !request.connection.is_simulated() {
        return refused("error: --fast (virtual time) works only with the built-in simulated drive; a real drive runs in real time".into(), INVALID, err);
    }
    if !script.drives.is_empty() {
        return run_several(request, &script, &drive_dicts, out, err);
    }
    let outputs = request.outputs;
    let family = match request.registry.family(dictionary.family()) {
        Ok(f) => f,
        Err(e) => return refused(format!("error: {e}"), INVALID, err),
    };
    // The script's `//! link:` settings under the command line's, as for a recipe.
    let connection = request.connection.with_defaults(&script.link);
    let address = match connection.check(family.as_ref()) {
        Ok(a) => a.shown,
        Err(e) => return refused(format!("error: {e}"), INVALID, err),
    };
    let header = trace_header(
        family.as_ref(),
        &dictionary,
        &request.dictionary.extra,
        &connection,
        address,
    );
    let telegrams = match telegram_outputs(outputs, family.as_ref(), &dictionary, &header) {
        Ok(t) => t,
        Err(text) => return refused(text, INVALID, err),
    };
    // A script chooses what it samples as it runs, so its CSV is the long layout.
    let mut csv = match open_csv(outputs, None, false) {
        Ok(c) => c,
        Err(text) => return refused(text, INVALID, err),
    };
    if let Err(text) = write_placeholders(outputs, &script.name, &script.path) {
        return refused(text, INVALID, err);
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
        Err(text) => return refused(text, COMMUNICATION, err),
    };
    if let (Some(sim), Some(prepare)) = (&open.simulator, request.prepare_simulator) {
        prepare(sim, open.drive.clock());
    }
    if open.simulator.is_some() {
        let _ = writeln!(out, "using {}", open.description);
    }
    if let Err((code, _)) = super::recipe_commands::within_drive_limits(
        &script.written,
        &mut open.drive,
        &script.path,
        &request.stop,
        out,
        err,
    ) {
        return RunResult::refused(code);
    }
    let virtual_time = request.fast && open.simulator.is_some();
    let look = Look::of(outputs, request.terminal, virtual_time, false, None);
    let report = observed(out, &look, csv.as_mut(), |observers| {
        ScriptRunner::new(&mut open.drive, observers, request.stop.clone())
            .with_output_dir(request.output_dir.clone())
            .with_csv_wide(outputs.csv_wide)
            .with_settings(request.safe_stop.settings(&script.safe_stop))
            .run(&script, err)
    });
    finish_reports(&report, &[], csv.as_ref(), outputs, err);
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

/// A script with `//! drives:`: the drives opened as a recipe's `drives:` are (those on
/// the command line's connection on one bus), `drive("left")` in the script each of them.
fn run_several(
    request: &RunRequest,
    script: &Script,
    drive_dicts: &[(String, Arc<Dictionary>)],
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> RunResult {
    let refused = |text: String, code, err: &mut dyn Write| {
        let _ = writeln!(err, "{text}");
        RunResult::refused(code)
    };
    let outputs = request.outputs;
    // The script's `//! link:` settings under the command line's, as for one drive.
    let merged = request.connection.with_defaults(&script.link);
    let connection = &merged;
    let telegrams = match several_checked(request, connection, &script.drives, drive_dicts) {
        Ok(t) => t,
        Err(text) => return refused(text, INVALID, err),
    };
    let mut csv = match open_csv(outputs, None, true) {
        Ok(c) => c,
        Err(text) => return refused(text, INVALID, err),
    };
    if let Err(text) = write_placeholders(outputs, &script.name, &script.path) {
        return refused(text, INVALID, err);
    }
    let mut open = match several_opened(request, connection, &script.drives, drive_dicts, &telegrams) {
        Ok(o) => o,
        Err(text) => return refused(text, COMMUNICATION, err),
    };
    if !open.simulators.is_empty() {
        let _ = writeln!(out, "using {}", open.description);
    }
    let virtual_time = request.fast && !open.simulators.is_empty();
    let look = Look::of(outputs, request.terminal, virtual_time, false, None);
    let report = observed(out, &look, csv.as_mut(), |observers| {
        let drives = open.drives.iter_mut().map(|(n, d)| (n.clone(), d)).collect();
        ScriptRunner::with_drives(drives, observers, request.stop.clone())
            .with_output_dir(request.output_dir.clone())
            .with_csv_wide(outputs.csv_wide)
            .with_settings(request.safe_stop.settings(&script.safe_stop))
            .run(script, err)
    });
    finish_reports(&report, &[], csv.as_ref(), outputs, err);
    RunResult {
        exit_code: report.exit_code(),
        report: Some(report),
        simulator: open.simulators.first().map(|(_, s)| s.clone()),
        simulators: open.simulators,
    }
}
