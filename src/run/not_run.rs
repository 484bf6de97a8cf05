//! The ending of a run that never started: an invalid recipe or command line (exit code 2)
//! or a drive that cannot be reached (3). Writes the JUnit and HTML reports that were asked
//! for, so CI reads this run's failure and never an earlier report, and words the message
//! for a drive that does not answer.

use super::run_plan::RunPlan;
use super::{ConnectionArgs, RunRequest, RunResult, COMMUNICATION};
use crate::report::{html_not_run, junit_document, junit_not_run_suite, write_atomically};
use crate::session::PlannedCheck;
use std::io::Write;

/// The message for a drive that did not answer its first request, naming the address as
/// the user typed it and the three likely causes.
/// `what` is what did not start (`recipe`, `script`).
pub fn silent_drive(connection: &ConnectionArgs, what: &str, detail: &str) -> String {
    let address = connection
        .address_given()
        .unwrap_or_else(|| "no --address, so the family's default address".to_string());
    let line = match (&connection.port, &connection.tcp) {
        (Some(p), _) => format!("--port {p}"),
        (None, Some(t)) => format!("--tcp {t}"),
        (None, None) => "the port".to_string(),
    };
    let baud = match connection.baud {
        Some(b) => format!("--baud {b}"),
        None => "no --baud, so the family's default".to_string(),
    };
    format!(
        "error: the drive does not answer ({address}, {line}); nothing was written to it and the {what} did not start. \
         Its state is unknown to drivescript: if it may still be running from earlier, check it by hand.\n\
         The three likely causes:\n  \
         1. the address: you gave {address}; it must match the drive's address setting (see `drivescript run --help` for the notation)\n  \
         2. the baud rate: you gave {baud}; it must match the drive's\n  \
         3. the line: the cable or adapter, RS485 wiring and termination, the drive's power, or a different {line}\n\
         detail: {detail}"
    )
}

/// [`silent_drive`] for the file of `request`.
pub fn silent_drive_of(request: &RunRequest, detail: &str) -> String {
    let what = if crate::script::is_script(request.file) {
        "script"
    } else {
        "recipe"
    };
    silent_drive(request.connection, what, detail)
}

/// The JUnit and HTML reports (when asked for) of a run that never started, so that CI
/// reads this run's failure and not an earlier report; then the result with `code`.
pub fn not_run(
    request: &RunRequest,
    plan: Option<(&RunPlan, &[PlannedCheck])>,
    code: i32,
    why: &str,
    err: &mut dyn Write,
) -> RunResult {
    let path = request.file.display().to_string();
    let (name, recipe_path, planned) = match plan {
        Some((p, planned)) => (p.name().to_string(), p.path().to_string(), planned),
        None => (path.clone(), path, &[][..]),
    };
    let (kind, word) = if code == COMMUNICATION {
        ("communication", "ERROR")
    } else {
        ("invalid", "INVALID")
    };
    let why = why.trim_end();
    let outputs = request.outputs;
    let suite = junit_not_run_suite(&name, &recipe_path, kind, why, planned);
    if let Some(p) = &outputs.junit {
        if let Err(e) = write_atomically(p, &junit_document(std::slice::from_ref(&suite))) {
            let _ = writeln!(err, "error: {e}");
        }
    }
    if let Some(p) = &outputs.report {
        if let Err(e) = write_atomically(p, &html_not_run(&name, &recipe_path, word, why)) {
            let _ = writeln!(err, "error: {e}");
        }
    }
    RunResult {
        junit: Some(suite),
        ..RunResult::refused(code)
    }
}
