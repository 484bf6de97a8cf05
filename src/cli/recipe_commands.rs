//! `drivescript check` and `drivescript run`: validate recipes and scripts without a port
//! (`run::check`), and run them with the safe stop at every ending (`run::run_many`).
//! Parses and prints; the checks and the run are the library's.

use super::{safe_stop_notes, stop_signals};
use crate::family::Registry;
use crate::run::{
    self, drive_limits, outputs_named, parse_set, run_many, CheckRequest, Checked, ConnectionArgs,
    DictionaryArgs, RunOperator, RunOptions, RunPlan, RunRequest, TerminalInput, INVALID, PASSED,
};
use clap::Args;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
/// Validate recipes against the dictionary; nothing is sent to a drive
///
/// Validate recipes against the dictionary without opening any port: object names, units,
/// limits, durations, parameters, states, included files, unknown keys. Reports every
/// problem at once; exit code 2 if there is any. With --port or --tcp it also reads the
/// minimum and maximum of every object the recipe writes from the drive (families whose
/// drives report them, e.g. lenze-931) and refuses values outside; only reads are sent.
/// A `.rhai` file is a Rhai script: its syntax and the drive calls written with literals
/// (with --port, its literal values against the drive's limits too).
pub struct CheckArgs {
    /// Recipe files (`.yaml`) or Rhai scripts (`.rhai`).
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
/// Run recipes or scripts on a drive or the simulator, always ending in the safe stop
///
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
    /// Recipe files or Rhai scripts (`.yaml`, `.rhai`), run one after the other.
    #[arg(value_name = "RECIPE", required = true)]
    recipes: Vec<PathBuf>,
    #[command(flatten)]
    options: RunOptions,
}

pub fn check(args: &CheckArgs, registry: &Registry) -> i32 {
    let colour = std::io::stderr().is_terminal();
    let mut code = PASSED;
    let mut last_error = String::new();
    let mut noted: Vec<String> = Vec::new();
    for path in &args.recipes {
        // Per file: each may have its own drivescript-limits.yaml next to it. A note on a
        // --dictionary file is said once, not once per file.
        let request = CheckRequest {
            registry,
            file: path,
            set: &args.set,
            dictionary: &args.dictionary,
            connection: &args.connection,
        };
        match run::check(&request, &mut std::io::stderr()) {
            Ok(checked) => {
                let dictionaries = std::iter::once(&checked.loaded.dictionary)
                    .chain(checked.loaded.drive_dictionaries.iter().map(|(_, d)| d));
                for note in dictionaries.flat_map(|d| d.notes()) {
                    let text = format!("note: {}", note.located());
                    if !noted.contains(&text) {
                        eprintln!("{text}");
                        if let Some(help) = note.help() {
                            eprintln!("  help: {help}");
                        }
                        noted.push(text);
                    }
                }
                for note in &checked.quantised {
                    eprintln!("note: {note}");
                }
                code = code.max(print_checked(path, &checked))
            }
            Err(e) => {
                // A broken --dictionary or --limits file is said once, not once per file.
                let text = e.render(colour);
                if text != last_error {
                    eprint!("{text}");
                    last_error = text;
                }
                code = code.max(e.exit_code());
            }
        }
    }
    code
}

/// `ok  path — name (…)`, the notes on how it ends, the bench limits and what the drive's
/// own limits came to; the exit code.
fn print_checked(path: &Path, checked: &Checked) -> i32 {
    let plan = &checked.loaded.plan;
    let what = match plan {
        RunPlan::Recipe(recipe) => {
            let finally = match &recipe.finally {
                None => ", default finally",
                Some(s) if s.is_empty() => ", empty finally",
                Some(_) => "",
            };
            let drives = recipe
                .drives
                .iter()
                .map(|d| format!("{}: {}", d.name, d.drive))
                .collect::<Vec<_>>()
                .join(", ");
            let drives = if drives.is_empty() {
                drives
            } else {
                format!(", drives {drives}")
            };
            format!("{} steps{finally}{drives}", recipe.steps.len())
        }
        RunPlan::Script(script) => format!(
            "script, {} calls{}",
            script.calls,
            if script.has_finally {
                ", its own finally"
            } else {
                ", default finally"
            }
        ),
    };
    println!("ok  {} — {} ({what})", path.display(), plan.name());
    safe_stop_notes::print(path, plan.safe_stop(), plan.leave_enabled());
    for leftover in &checked.leftover_setpoints {
        eprintln!("warning: {leftover}");
    }
    // The names `--answer NAME=VALUE` and an answers file give answers by.
    for (prompt, origin) in plan.prompts() {
        println!("    asks {}: {prompt} ({origin})", prompt.name);
    }
    if let Some(at) = plan.compares_with_last_pass() {
        let sets_serial = plan.prompts().into_iter().find(|(p, _)| p.sets("serial"));
        let from = match sets_serial {
            Some((p, origin)) => format!("--unit serial=… or the operator step {} ({origin})", p.name),
            None => "--unit serial=… (no operator step sets it: a run without it is refused)".into(),
        };
        println!("    compares with the unit's last passed run ({at}); the serial from {from}");
    }
    if let Some(limits) = checked.bench_limits() {
        println!("    bench limits {} ({})", limits.summary(), limits.source());
    }
    match &checked.drive_limits {
        Some(compared) => {
            drive_limits::report(
                compared,
                plan.path(),
                true,
                &mut std::io::stdout(),
                &mut std::io::stderr(),
            )
            .0
        }
        None => PASSED,
    }
}

pub fn run(args: &RunArgs, registry: &Registry) -> i32 {
    let options = &args.options;
    // A part an answer given beforehand sets is known before the files are opened (one
    // recipe: with several, each may set it differently and the shared files are one).
    let unit = match args.recipes.as_slice() {
        [one] => run::unit_before_start(
            registry,
            one,
            &options.set,
            &options.dictionary,
            &options.operator,
        ),
        _ => options.operator.identity(),
    };
    let outputs = match outputs_named(&options.outputs, &unit, std::time::SystemTime::now()) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}; nothing was sent");
            return INVALID;
        }
    };
    let stop = stop_signals::install_for_a_drive();
    let request = RunRequest {
        terminal: std::io::stdout().is_terminal(),
        input: RunOperator::stdin_is_terminal().then(TerminalInput::stdin),
        observers: options
            .recorder(&args.recipes, registry, &outputs, stop.clone())
            .into_iter()
            .collect(),
        ..options.request(registry, &outputs, &options.operator, stop)
    };
    run_many(
        &args.recipes,
        &request,
        &mut std::io::stdout(),
        &mut std::io::stderr(),
    )
}

#[derive(Debug, Args)]
/// Print the JSON Schema of recipes for one dictionary (editor completion)
///
/// Print the JSON Schema of recipes for one dictionary, for editor completion of keys,
/// object names and states. Recipes point their editor at it with a first line
/// `# yaml-language-server: $schema=../schemas/sd2.schema.json`.
pub struct SchemaArgs {
    /// Print the recipe reference as Markdown instead (the manual's `reference/recipe.md`).
    #[arg(long)]
    reference: bool,
    #[command(flatten)]
    dictionary: DictionaryArgs,
}

pub fn schema(args: &SchemaArgs, registry: &Registry) -> i32 {
    match args.dictionary.load_for(registry, None) {
        Ok(d) if args.reference => {
            print!(
                "{}",
                crate::recipe::recipe_reference(&d, &registry.address_keys())
            );
            PASSED
        }
        Ok(d) => {
            let text =
                serde_json::to_string_pretty(&crate::recipe::recipe_schema(&d, &registry.address_keys()))
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
