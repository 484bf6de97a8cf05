//! `drivescript maintain`: its arguments and the typed `yes` on a terminal; the action
//! itself, with the interlock of the drive layer, is `run::run_maintain`'s.

use super::stop_signals;
use crate::family::Registry;
use crate::run::{run_maintain, ConnectionArgs, DictionaryArgs, MaintainRequest};
use clap::Args;
use std::io::{BufRead, IsTerminal, Read, Write};

#[derive(Debug, Args)]
/// Carry out or list the drive family's maintenance actions (reset, init, ...)
///
/// Carry out one of the drive family's maintenance actions, or list them (no ACTION).
/// lenze-931: `reset` (RESET!, hardware reset), `init` (INIT!, default parameter set),
/// `load` (SEP!, parameter set from flash), `baud RATE` (BAUDbbbb). Every one of these is
/// destructive: it is refused while the drive is enabled when its state can be read, and
/// needs --force (or typing `yes` on a terminal). Where the state cannot be read (the
/// 931's dictionary has no device-control profile) only --force carries it out. Without
/// --port or --tcp it goes to the built-in simulated drive.
pub struct MaintainArgs {
    /// The action (`drivescript maintain --drive lenze-931` lists them).
    #[arg(value_name = "ACTION")]
    action: Option<String>,
    /// The action's value, for an action that takes one (baud: the new rate).
    #[arg(value_name = "VALUE")]
    value: Option<String>,
    /// Carry out a destructive action without asking; needed where the drive's state
    /// cannot be read. Never overrides the refusal while the drive is enabled.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

pub fn maintain(args: &MaintainArgs, registry: &Registry) -> i32 {
    let stop = stop_signals::install(false);
    let waiting = stop.clone();
    let mut ask = move |question: &str| -> bool {
        eprint!("{question} ");
        let _ = std::io::stderr().flush();
        // The line is read on a thread of its own, so that Ctrl-C ends the wait at once
        // (the signal handler only records the request).
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut answer = String::new();
            // A line at most: the answer is `yes` or anything else.
            let read = std::io::stdin().lock().take(256).read_line(&mut answer);
            let _ = tx.send(read.is_ok() && answer.trim() == "yes");
        });
        loop {
            match rx.recv_timeout(std::time::Duration::from_millis(50)) {
                Ok(yes) => return yes,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) if waiting.first().is_none() => {}
                Err(_) => {
                    eprintln!();
                    return false;
                }
            }
        }
    };
    let terminal = std::io::stdin().is_terminal() && std::io::stderr().is_terminal();
    let request = MaintainRequest {
        registry,
        dictionary: &args.dictionary,
        connection: &args.connection,
        action: args.action.as_deref(),
        value: args.value.as_deref(),
        force: args.force,
        confirm: if terminal { Some(&mut ask) } else { None },
        stop,
        prepare_simulator: None,
    };
    run_maintain(request, &mut std::io::stdout(), &mut std::io::stderr()).exit_code
}
