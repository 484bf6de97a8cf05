//! A maintenance action of the drive family (Lenze 931: reset, init, load, baud), listed
//! without an action and carried out with one. A destructive action goes through the
//! drive layer's interlock (never while the drive is enabled; where its state cannot be
//! read, only with `force`) and, without `force`, a confirmation by whoever the caller
//! asks. Knows no family's commands: the family names its actions and carries them out.

use super::{open_drive, ConnectionArgs, DictionaryArgs, RunError, COMMUNICATION, INVALID, PASSED};
use crate::diag::{did_you_mean, suggestion_text};
use crate::drive::{AccessError, DriveError, MaintenanceAction};
use crate::family::Registry;
use crate::sim::SimulatedDrive;
use crate::stop_request::StopRequests;
use std::io::Write;
use std::sync::{Arc, Mutex};

/// A hook that gets the simulated drive before anything is sent to it.
pub type PrepareMaintained<'a> = dyn Fn(&Arc<Mutex<dyn SimulatedDrive>>) + 'a;

/// What one `maintain` needs; the command line fills it, tests directly.
pub struct MaintainRequest<'a> {
    pub registry: &'a Registry,
    pub dictionary: &'a DictionaryArgs,
    pub connection: &'a ConnectionArgs,
    pub action: Option<&'a str>,
    pub value: Option<&'a str>,
    pub force: bool,
    /// Asks the user to confirm (the question); `None` when nobody can be asked.
    pub confirm: Option<&'a mut dyn FnMut(&str) -> bool>,
    pub stop: Arc<StopRequests>,
    /// Called with the simulated drive before anything is sent (tests inject faults).
    pub prepare_simulator: Option<&'a PrepareMaintained<'a>>,
}

/// The exit code and the simulated drive, when one was used.
pub struct MaintainResult {
    pub exit_code: i32,
    pub simulator: Option<Arc<Mutex<dyn SimulatedDrive>>>,
}

/// Lists the actions, or checks, asks about and carries out the one named, writing what
/// happened to `out` and problems to `err`.
pub fn run_maintain(
    mut request: MaintainRequest,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> MaintainResult {
    let done = |exit_code| MaintainResult {
        exit_code,
        simulator: None,
    };
    let dictionary = match request.dictionary.load_for(request.registry, None) {
        Ok(d) => d,
        Err(text) => {
            let _ = write!(err, "{text}");
            return done(INVALID);
        }
    };
    let family = match request.registry.family(dictionary.family()) {
        Ok(f) => f,
        Err(e) => {
            let _ = writeln!(err, "error: {e}");
            return done(INVALID);
        }
    };
    let actions = family.maintenance_actions();
    let Some(name) = request.action else {
        list(family.id(), actions, out);
        return done(PASSED);
    };
    let action = match find(family.id(), actions, name) {
        Ok(a) => a,
        Err(text) => {
            let _ = writeln!(err, "{text}");
            return done(INVALID);
        }
    };
    let argument = match (action.argument, request.value) {
        (Some(what), Some(text)) => match text.trim().parse::<u32>() {
            Ok(n) if n > 0 => Some(n),
            _ => {
                let _ = writeln!(
                    err,
                    "error: `{text}` is no {what} for {}: give a whole number above 0; nothing was sent",
                    action.name
                );
                return done(INVALID);
            }
        },
        (Some(what), None) => {
            let _ = writeln!(
                err,
                "error: {} needs its {what}: `drivescript maintain --drive {} {} {what}`; nothing was sent",
                action.name,
                family.id(),
                action.name
            );
            return done(INVALID);
        }
        (None, Some(text)) => {
            let _ = writeln!(
                err,
                "error: {} takes no value, but `{text}` was given; nothing was sent",
                action.name
            );
            return done(INVALID);
        }
        (None, None) => None,
    };
    if let Err(e) = request.connection.check(request.registry, family.as_ref()) {
        let _ = writeln!(err, "error: {e}");
        return done(INVALID);
    }
    let mut open = match open_drive(
        request.registry,
        request.connection,
        dictionary,
        true,
        None,
        Some(request.stop.clone()),
    ) {
        Ok(o) => o,
        Err(text) => {
            let _ = writeln!(err, "{text}");
            return done(COMMUNICATION);
        }
    };
    let simulator = open.simulator.clone();
    let done = |exit_code| MaintainResult {
        exit_code,
        simulator: simulator.clone(),
    };
    if let (Some(sim), Some(prepare)) = (&open.simulator, request.prepare_simulator) {
        prepare(sim);
    }
    if open.simulator.is_some() {
        let _ = writeln!(out, "using {}", open.description);
    }
    let port = open.drive.port();
    let refused = |text: String, err: &mut dyn Write| {
        let _ = writeln!(err, "error: {text}; nothing was sent");
        done(INVALID)
    };
    let mut clearance = match open.drive.clear_for_maintenance(action, argument, request.force) {
        Ok(c) => c,
        Err(e @ DriveError::EnabledForMaintenance { .. }) => {
            return refused(
                format!(
                    "{e}; disable it first with `drivescript stop` and the same connection options (or the drive's own controls)"
                ),
                err,
            );
        }
        Err(e @ DriveError::MaintenanceStateUnknown { .. }) => {
            return refused(
                format!("{e}. Make sure the drive is disabled and the motor at rest, then give --force"),
                err,
            );
        }
        Err(e) => return refused(e.to_string(), err),
    };
    let shown = clearance.shown();
    if let Some(cannot) = clearance.unchecked() {
        let _ = writeln!(err, "warning: {cannot}; going on because of --force");
    }
    if let (Some(why), Some(state), false) = (action.destructive, clearance.state(), request.force) {
        let question = format!("{shown} on {port}: {why}. The drive is in {state}. Type yes to go on:");
        let confirmed = request.confirm.as_mut().is_some_and(|ask| ask(&question));
        if let Some(signal) = request.stop.first() {
            let _ = writeln!(err, "stopped by {}; nothing was sent", signal.describe());
            return done(signal.exit_code());
        }
        if !confirmed {
            return refused(
                match request.confirm {
                    Some(_) => format!("{shown} was not confirmed"),
                    None => format!(
                        "{shown} is destructive ({why}): give --force, or run it on a terminal to confirm"
                    ),
                },
                err,
            );
        }
        // The question may have waited long: someone may have enabled the drive
        // meanwhile (its own terminals, a PLC). The clearance is given again, now.
        clearance = match open.drive.clear_for_maintenance(action, argument, false) {
            Ok(c) => c,
            Err(DriveError::EnabledForMaintenance { state, .. }) => {
                return refused(format!("the drive went to {state} while the question was open, and {shown} is refused while it is enabled ({why})"), err);
            }
            Err(DriveError::MaintenanceStateUnknown { cause, .. }) => {
                return refused(
                    format!("the drive's state could not be read again after the confirmation ({cause})"),
                    err,
                );
            }
            Err(e) => return refused(e.to_string(), err),
        };
    }
    let sent = match (action.argument, argument) {
        (Some(what), Some(n)) => format!("{} with {what} {n}", action.command),
        _ => action.command.to_string(),
    };
    if let Some(signal) = request.stop.first() {
        let _ = writeln!(err, "stopped by {}; nothing was sent", signal.describe());
        return done(signal.exit_code());
    }
    let _ = writeln!(out, "{shown}: sending {sent} to {port}");
    match open.drive.maintain(clearance) {
        None => {
            let _ = writeln!(err, "error: {port} cannot carry out {shown}; nothing was sent");
            done(INVALID)
        }
        Some(Ok(outcome)) => {
            let _ = writeln!(out, "done: the drive answered `{}`", outcome.reply);
            if let Some(rate) = outcome.line_rate {
                let _ = writeln!(out, "{}", reconnect(request.connection, rate));
            }
            done(PASSED)
        }
        Some(Err(e)) => {
            let _ = writeln!(err, "error: {shown} failed: {e}");
            // No reply, or one that could not be read (at another rate it is garbage):
            // the drive may have acted.
            // A stop signal ends the wait for an answer to a command already sent: unknown too.
            let unknown = matches!(&e, DriveError::Interrupted)
                || matches!(&e, DriveError::Access(a) if a.is_no_reply() || matches!(a, AccessError::BadReply { .. } | AccessError::Interrupted { .. }));
            if unknown {
                let hint = match argument.filter(|_| action.changes_line_rate) {
                    Some(rate) => format!(
                        "the drive may already talk at the new rate: try again with --baud {rate} (e.g. `drivescript maintain --drive {} … --baud {rate}`) before repeating {shown}",
                        family.id()
                    ),
                    None => format!(
                        "whether the drive carried out {shown} is unknown: check the drive before repeating it (a drive that restarts may answer later than --timeout allows)"
                    ),
                };
                let _ = writeln!(err, "{hint}");
            }
            // A stop signal ends the wait for the reply: the signal's exit code.
            done(request.stop.first().map_or(COMMUNICATION, |s| s.exit_code()))
        }
    }
}

/// `drivescript maintain` without an action: the family's actions, or that it has none.
fn list(family: &str, actions: &[MaintenanceAction], out: &mut dyn Write) {
    if actions.is_empty() {
        let _ = writeln!(out, "the {family} family has no maintenance actions");
        return;
    }
    let _ = writeln!(out, "maintenance actions of {family}:");
    for a in actions {
        let name = match a.argument {
            Some(arg) => format!("{} {arg}", a.name),
            None => a.name.to_string(),
        };
        let _ = writeln!(out, "  {name:<10} {:<9} {}", a.command, a.summary);
        if let Some(why) = a.destructive {
            let _ = writeln!(
                out,
                "  {:<10} {:<9} destructive: {why}; needs --force or a confirmation",
                "", ""
            );
        }
    }
}

fn find<'a>(
    family: &str,
    actions: &'a [MaintenanceAction],
    name: &str,
) -> Result<&'a MaintenanceAction, RunError> {
    if actions.is_empty() {
        return Err(RunError::Invalid(format!(
            "error: the {family} family has no maintenance actions; nothing was sent"
        )));
    }
    actions.iter().find(|a| a.name == name).ok_or_else(|| {
        let names: Vec<&str> = actions.iter().map(|a| a.name).collect();
        let hint = suggestion_text(&did_you_mean(name, names.iter().copied()))
            .map(|s| format!(" {s}"))
            .unwrap_or_default();
        RunError::Invalid(format!(
            "error: {family} has no maintenance action `{name}`;{hint} the actions are: {}; nothing was sent",
            names.join(", ")
        ))
    })
}

/// What to do after the line's rate changed, for the connection used.
fn reconnect(connection: &ConnectionArgs, rate: u32) -> String {
    let how = match (&connection.port, &connection.tcp) {
        (Some(port), _) => format!("reconnect with --port {port} --baud {rate} on every command from now on"),
        (None, Some(_)) => format!(
            "set the serial device server's port to {rate} baud (the --tcp connection itself is unchanged)"
        ),
        (None, None) => "the simulated line keeps working at any rate".to_string(),
    };
    format!("the drive now talks at {rate} baud, not at the rate used so far: {how}")
}
