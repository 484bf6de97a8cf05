//! The ending of a run that never started: an invalid recipe or command line (exit code 2)
//! or a drive that cannot be reached (3). Writes the JUnit and HTML reports that were asked
//! for, so CI reads this run's failure and never an earlier report, and words the message
//! for a drive that does not answer.

use super::run_plan::RunPlan;
use super::{ConnectionArgs, RunRequest, RunResult, COMMUNICATION};
use crate::bus::BusKind;
use crate::dictionary::Dictionary;
use crate::family::Registry;
use crate::report::{html_not_run, junit_document, junit_not_run_suite, write_atomically};
use crate::session::{PlannedCheck, RunInfo};
use std::io::Write;

/// The message for a drive that did not answer its first request, naming the address as
/// the user typed it, the four likely causes (another family's drive on the line among
/// them) and the family's own advice. `dictionary` is the one drivescript spoke with;
/// `what` is what did not start (`recipe`, `script`).
pub fn silent_drive(
    registry: &Registry,
    dictionary: &Dictionary,
    connection: &ConnectionArgs,
    what: &str,
    detail: &str,
) -> String {
    let family = registry.family(dictionary.family()).ok();
    let address = connection
        .address_given()
        .unwrap_or_else(|| "no --address, so the family's default address".to_string());
    let line = match (&connection.port, &connection.tcp) {
        (Some(p), _) => format!("--port {p}"),
        (None, Some(t)) => format!("--tcp {t}"),
        (None, None) => "the port".to_string(),
    };
    let baud = match (connection.baud, &family) {
        (Some(b), _) => format!("--baud {b}"),
        (None, Some(f)) if f.bus_kind() == BusKind::Bytes => {
            format!("no --baud, so the family's default {}", f.serial_settings())
        }
        (None, _) => "no --baud, so the family's default".to_string(),
    };
    let notation = family
        .as_ref()
        .map_or("see `drivescript run --help` for the notation", |f| {
            f.address_help()
        });
    let advice = family.as_ref().map(|f| f.no_reply_advice());
    // The link's no-reply error already ends with the same advice: say it once.
    let detail = advice
        .and_then(|a| detail.strip_suffix(a))
        .map_or(detail, |d| d.trim_end_matches([';', ' ']));
    let advice = advice
        .map(|a| format!("For a drive of this family: {a}\n"))
        .unwrap_or_default();
    // Over TCP the line is a network connection: what a serial line would be is the
    // server's (a serial server's baud rate, a gateway's RS485 side).
    let (second, third) = match &connection.tcp {
        Some(_) => (
            format!("the server: {line} must be the drive's, its gateway's or its serial server's address and port; a serial server's own baud rate and parity must match the drive's"),
            "the network and what is behind it: the server running, reachable and not busy with another client, the drive's power".to_string(),
        ),
        None => (
            format!("the baud rate: you gave {baud}; it must match the drive's"),
            format!("the line: the cable or adapter, RS485 wiring and termination, the drive's power, or a different {line}"),
        ),
    };
    format!(
        "error: the drive does not answer ({address}, {line}); nothing was written to it and the {what} did not start. \
         Its state is unknown to drivescript: if it may still be running from earlier, check it by hand.\n\
         The likely causes:\n  \
         1. the address: you gave {address}; it must match the drive's address setting ({notation})\n  \
         2. {second}\n  \
         3. {third}\n  \
         4. the drive family: {}\n\
         {advice}detail: {detail}",
        another_family(registry, dictionary)
    )
}

/// A drive of another family on the line as the cause of silence: which family and
/// dictionary drivescript spoke, and how to name the right one.
pub fn another_family(registry: &Registry, dictionary: &Dictionary) -> String {
    let spoken = format!("the `{}` dictionary", dictionary.name());
    let title = registry
        .family(dictionary.family())
        .map_or_else(|_| dictionary.family().to_string(), |f| f.title().to_string());
    format!(
        "drivescript spoke {title} with {spoken}; a drive of another family on the line does not answer that: \
         give the drive's own dictionary with --drive (a recipe: `drive:`); built in: {}",
        registry.dictionary_names().join(", ")
    )
}

/// [`silent_drive`] for the file of `request`, whose drive spoke with `dictionary`.
pub fn silent_drive_of(request: &RunRequest, dictionary: &Dictionary, detail: &str) -> String {
    let what = if crate::script::is_script(request.file) {
        "script"
    } else {
        "recipe"
    };
    silent_drive(request.registry, dictionary, request.connection, what, detail)
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
    recorded(request, plan.map(|(p, _)| p), code, why);
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

/// Tells the run's observers (the results store) that the run never started, with the
/// unit as far as the command line and the answers given beforehand know it: an attempt
/// on a unit stays visible in its history.
pub(super) fn recorded(request: &RunRequest, plan: Option<&RunPlan>, code: i32, why: &str) {
    let prompts = plan.map(RunPlan::prompts).unwrap_or_default();
    let given = request.operator.given().unwrap_or_default();
    let run = RunInfo {
        kind: if crate::script::is_script(request.file) {
            "script"
        } else {
            "recipe"
        },
        name: plan.map_or_else(|| request.file.display().to_string(), |p| p.name().to_string()),
        path: plan.map_or_else(|| request.file.display().to_string(), |p| p.path().to_string()),
        params: request.set.to_vec(),
        unit: request.operator.identity_with_answers(&prompts, &given),
        text_sha256: match plan {
            Some(RunPlan::Recipe(r)) => Some(r.text_sha256.clone()),
            _ => None,
        },
    };
    for observer in &request.observers {
        observer
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .run_refused(&run, code, why);
    }
}
