//! The command line: argument parsing and one module per subcommand. Each subcommand
//! fills the library's requests from its options, calls the library (`run` for runs, checks
//! and maintenance; `drive`, `parameters`, `report` directly for the one-off commands) with
//! the registry `main` built, and turns the results into text and exit codes; plus the
//! process-wide parts: stop signals and the panic notice. Must not build telegrams, touch
//! ports, name a family, or define a type the library needs; nothing in the library
//! imports it.

/// The widest column a listing aligns (object names in `read` and `diff`): wider names
/// push their own row only. Also keeps every width far below the 65 535 `format!` pads.
const MAX_ALIGNED_WIDTH: usize = 80;

mod anonymise_command;
mod backup_command;
mod decode_command;
mod diff_command;
mod held_value;
mod help_text;
pub mod listen_args;
mod maintain_command;
mod man_page;
mod object_commands;
mod objects_command;
mod panic_notice;
mod parameter_commands;
mod recipe_commands;
mod restore_command;
mod results_command;
mod results_listing;
mod results_quality;
mod results_serve;
mod safe_stop_notes;
mod simulate_command;
mod station_command;
mod stop_command;
mod stop_signals;
mod text_table;

use crate::family::Registry;
use crate::run::{INVALID, PASSED};

use clap::{Parser, Subcommand};

/// `drivescript 0.1.0 (commit 1a2b3c4d5e, built 2026-11-22)`, from build.rs.
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("DRIVESCRIPT_COMMIT"),
    ", built ",
    env!("DRIVESCRIPT_BUILD_DATE"),
    ")"
);

/// Shown under `drivescript --help`: what users type first, and what the exit codes mean.
const EXAMPLES: &str = "\
Examples:
  drivescript run recipes/commissioning.yaml --fast        simulated drive, virtual time
  drivescript run recipes/acceptance-test.yaml --port /dev/ttyUSB0 --junit junit.xml
  drivescript run a.yaml b.yaml --fast                     several recipes, one exit code
  drivescript check recipes/*.yaml                         validate only; nothing is sent
  drivescript write speed_setpoint 6000 rpm --port /dev/ttyUSB0
  drivescript stop --port /dev/ttyUSB0                     brake, disable and verify a drive
  drivescript decode run.trace                             explain a --trace file

Exit codes:
  0  passed                    1  an expectation failed
  2  recipe or command line invalid (nothing was sent)
  3  communication failure, drive fault, or a safe stop that could not be confirmed
  128+N  stopped by signal N after the safe stop (130 Ctrl-C, 143 SIGTERM)
  101  internal error (panic), after the safe stop";

/// Commission and test servo and spindle drives over their serial protocols.
#[derive(Debug, Parser)]
#[command(name = "drivescript", version = VERSION, about, max_term_width = 100, after_help = EXAMPLES)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    Run(Box<recipe_commands::RunArgs>),
    Check(recipe_commands::CheckArgs),
    Read(object_commands::ReadArgs),
    Write(object_commands::WriteArgs),
    State(object_commands::StateArgs),
    Stop(stop_command::StopArgs),
    Objects(objects_command::ObjectsArgs),
    Decode(decode_command::DecodeArgs),
    Simulate(simulate_command::SimulateArgs),
    Anonymise(anonymise_command::AnonymiseArgs),
    Ports(object_commands::PortsArgs),
    Backup(backup_command::BackupArgs),
    Diff(diff_command::DiffArgs),
    Restore(restore_command::RestoreArgs),
    Maintain(maintain_command::MaintainArgs),
    Schema(recipe_commands::SchemaArgs),
    Results(results_command::ResultsArgs),
    Station(Box<station_command::StationArgs>),
    Completions(CompletionsArgs),
    Man(man_page::ManArgs),
}

#[derive(Debug, clap::Args)]
/// Print a shell completion script (bash, zsh, fish, elvish, powershell)
///
/// Print a shell completion script, e.g. `drivescript completions bash >
/// ~/.local/share/bash-completion/completions/drivescript`.
struct CompletionsArgs {
    shell: clap_complete::Shell,
}

/// The command line, with the help texts that list what `registry` holds.
fn command(registry: &Registry) -> clap::Command {
    use clap::CommandFactory;
    let protocols = decode_command::protocol_help(registry);
    let command = Cli::command()
        .mut_subcommand("decode", |c| c.mut_arg("protocol", |a| a.help(protocols)))
        .mut_subcommand("run", |c| c.after_long_help(help_text::RUN_EXAMPLES));
    help_text::short_and_long(command)
}

/// Runs the command line with the drive families of `registry` and returns the process
/// exit code.
pub fn main(registry: &Registry) -> i32 {
    use clap::FromArgMatches;
    let parsed = command(registry)
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { INVALID } else { PASSED };
        }
    };
    write_limits_are_errors();
    // The commands that move a drive keep SIGPIPE ignored: a closed pipe must not end the
    // process before or during its safe stop.
    if !matches!(
        cli.command,
        Command::Run(_) | Command::Stop(_) | Command::Maintain(_) | Command::Restore(_) | Command::Station(_)
    ) {
        quiet_on_closed_pipe();
    }
    match cli.command {
        Command::Run(args) => recipe_commands::run(&args, registry),
        Command::Check(args) => recipe_commands::check(&args, registry),
        Command::Read(args) => object_commands::read(&args, registry),
        Command::Write(args) => object_commands::write(&args, registry),
        Command::State(args) => object_commands::state(&args, registry),
        Command::Stop(args) => stop_command::stop(&args, registry),
        Command::Objects(args) => objects_command::objects(&args, registry),
        Command::Ports(args) => object_commands::ports(&args),
        Command::Backup(args) => backup_command::backup(&args, registry),
        Command::Diff(args) => diff_command::diff(&args, registry),
        Command::Restore(args) => restore_command::restore(&args, registry),
        Command::Maintain(args) => maintain_command::maintain(&args, registry),
        Command::Schema(args) => recipe_commands::schema(&args, registry),
        Command::Results(args) => results_command::results(&args),
        Command::Station(args) => station_command::station(&args, registry),
        Command::Completions(args) => {
            use std::io::Write;
            let mut script = Vec::new();
            clap_complete::generate(args.shell, &mut command(registry), "drivescript", &mut script);
            let _ = std::io::stdout().write_all(&script);
            PASSED
        }
        Command::Man(args) => man_page::man(&args, command(registry)),
        Command::Decode(args) => decode_command::run(&args, registry),
        Command::Simulate(args) => simulate_command::run(&args, registry),
        Command::Anonymise(args) => anonymise_command::anonymise(&args, registry),
    }
}

/// A file that reaches the file-size limit (`ulimit -f`: the results store's log, a CSV, a
/// trace) would otherwise end the process by SIGXFSZ, the safe stop with it; ignored, the
/// write fails with an error the recorder or the reporter says, and the stop goes on.
fn write_limits_are_errors() {
    #[cfg(unix)]
    // SAFETY: setting the disposition of one signal at start-up, before any other thread
    // exists; no handler code runs.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// `drivescript objects | head` must end quietly when `head` closes the pipe, as other
/// Unix tools do, instead of panicking in `println!`. Not for `run`: a run killed by a
/// closed pipe would skip the safe stop, so `run` keeps SIGPIPE ignored and its console
/// output ignores a closed pipe instead.
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of one signal at start-up, before any
    // other thread exists; no handler code runs.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
