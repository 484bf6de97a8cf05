//! `check` for Rhai scripts (`.rhai`): the same dictionary and connection as recipes, with
//! the script front end in place of the recipe loader (a script runs through the one run
//! pipeline, `run::run`). Never opens a port except to read the drive's limits. Turns
//! results into text and exit codes.

use crate::dictionary::Dictionary;
use crate::family::Registry;
use crate::run::{drive_dictionaries, ConnectionArgs, DictionaryArgs, INVALID, PASSED};
use crate::script::{declared_script_drives, load_script_for};
use std::io::IsTerminal;
use std::path::Path;
use std::sync::Arc;

/// Checks one script against `dictionary`; prints `ok` or its problems; the exit code.
/// `dictionary_args` (the command line's `--dictionary`, `--limits`) load the dictionary of
/// each drive a script's `//! drives:` declares.
pub fn check_script(
    registry: &Registry,
    path: &Path,
    dictionary: &Dictionary,
    dictionary_args: &DictionaryArgs,
    set: &[(String, String)],
    connection: &ConnectionArgs,
) -> i32 {
    // A script with `//! drives:` is checked against each drive's own dictionary.
    let declared = declared_script_drives(path);
    let drive_dicts = if declared.is_empty() {
        Vec::new()
    } else {
        match drive_dictionaries(dictionary_args, registry, path, &declared) {
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
            super::safe_stop_notes::print(path, &script.safe_stop, script.leave_enabled);
            if let Some(limits) = dictionary.bench_limits() {
                println!("    bench limits {} ({})", limits.summary(), limits.source());
            }
            // As for a recipe, `check --port` reads no limits from several drives.
            if connection.is_simulated() || script.written.is_empty() || !script.drives.is_empty() {
                return PASSED;
            }
            crate::run::drive_limits::check_against_drive(
                registry,
                &script.written,
                &script.path,
                Arc::new(dictionary.clone()),
                connection,
                &mut std::io::stdout(),
                &mut std::io::stderr(),
            )
        }
        Err(e) => {
            eprint!("{}", e.render(std::io::stderr().is_terminal()));
            INVALID
        }
    }
}
