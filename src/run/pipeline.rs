//! The one run pipeline, for a recipe or a script with one drive or several: load and
//! check, open the output files, open the drives, say early when one never answers,
//! compare the values written with the drive's own limits, run with the safe stop at every
//! ending, and write every report. A run that cannot start still writes its not-run JUnit
//! and HTML reports. Decides exit codes; must not parse a command line.

use super::answers_check::answers_checked;
use super::drive_limits::within_drive_limits;
use super::drive_set::{named_drives_checked, named_drives_opened, OpenDrives};
use super::latency_note::latency_note;
use super::line_exchange::LineExchange;
use super::link_range_check::within_link_range;
use super::not_run::{not_run, recorded, silent_drive_of};
use super::run_plan::{LoadedPlan, RunPlan, SessionSettings};
use super::run_setup::{
    finish_reports, observed, open_csv, telegram_outputs, trace_header, write_placeholders, Look,
};
use super::{
    open_drive, sim_checked, ConnectionArgs, RunError, RunOperator, RunRequest, RunResult, COMMUNICATION,
    INVALID,
};
use crate::report::{junit_suite, TelegramFanOut};
use std::io::Write;

/// Checks and runs `request.file`, writing the console output to `out` and problems to
/// `err`.
pub fn run(request: &RunRequest, out: &mut dyn Write, err: &mut dyn Write) -> RunResult {
    let loaded = match RunPlan::load(request) {
        Ok(l) => l,
        Err(e) => {
            let text = e.to_string();
            let _ = write!(err, "{text}");
            return not_run(request, None, INVALID, &text, err);
        }
    };
    let plan = &loaded.plan;
    let planned = plan.planned_checks();
    let refuse = |code: i32, text: &str, err: &mut dyn Write| {
        let _ = writeln!(err, "{text}");
        not_run(request, Some((plan, &planned)), code, text, err)
    };
    if request.fast && !request.connection.is_simulated() {
        return refuse(INVALID, "error: --fast (virtual time) works only with the built-in simulated drive; a real drive runs in real time", err);
    }
    // Every operator step answered or askable, and every answer one its step accepts,
    // before anything is opened.
    let prompts = plan.prompts();
    let given = match request.operator.given() {
        Ok(g) => g,
        Err(e) => return refuse(INVALID, &e.to_string(), err),
    };
    let complete = matches!(plan, RunPlan::Recipe(_));
    if let Err(e) = answers_checked(
        &prompts,
        complete,
        &given,
        request.input.is_some(),
        &request.operator.identity(),
    ) {
        return refuse(INVALID, &e.to_string(), err);
    }
    let unit = match start_identity(plan, request, &prompts, &given) {
        Ok(u) => u,
        Err(e) => return refuse(INVALID, &e.to_string(), err),
    };
    // The file's link settings under the command line's, checked before anything is
    // opened: a wrong setting is an invalid file or command line (exit 2), not a
    // communication failure.
    let connection = request.connection.with_defaults(plan.link());
    let several = !plan.drives().is_empty();
    let telegrams = match checked(request, &loaded, &connection) {
        Ok(t) => t,
        Err(e) => return refuse(INVALID, &e.to_string(), err),
    };
    // Values the link's settings cannot carry, refused before the port opens.
    if let Err(e) = within_link_range(&plan.written_values(), &loaded, request.registry, &connection) {
        return refuse(INVALID, &e.to_string(), err);
    }
    // Watches that would leave the steps too little of the line, likewise.
    if let Err(e) = super::watches_fit_the_line(&loaded, request.registry, &connection) {
        return refuse(INVALID, &e.to_string(), err);
    }
    // Files are opened before anything is sent: a path that cannot be written is an
    // invalid command line, not a half-run file.
    let outputs = request.outputs;
    let wide = plan.wide_columns().filter(|_| outputs.csv_wide);
    let mut csv = match open_csv(outputs, wide.as_deref(), several) {
        Ok(c) => c,
        Err(e) => return refuse(INVALID, &e.to_string(), err),
    };
    if let Err(e) = write_placeholders(outputs, plan.name(), plan.path()) {
        // The not-run reports would fail the same way; the unit's history still keeps it.
        let _ = writeln!(err, "{e}");
        recorded(request, Some(plan), INVALID, e.to_string().trim_end());
        return RunResult::refused(INVALID);
    }
    let mut open = match opened(request, &loaded, &connection, telegrams) {
        Ok(o) => o,
        Err(e) => return refuse(COMMUNICATION, &e.to_string(), err),
    };
    let sampled: Vec<String> = plan
        .wide_columns()
        .unwrap_or_default()
        .into_iter()
        .map(|o| o.name)
        .collect();
    let exchange = || LineExchange::measure(request.registry, &connection, &loaded.dictionary, &sampled);
    if let Some(note) = connection
        .port
        .as_deref()
        .and_then(|port| latency_note(port, plan.shortest_sample_interval(), exchange))
    {
        let _ = writeln!(err, "{note}");
    }
    if let RunPlan::Recipe(recipe) = plan {
        if !recipe.drive_named && !outputs.quiet {
            let _ = writeln!(
                out,
                "{} names no `drive:`: using the {} dictionary (write `drive:` in the recipe, or give --drive)",
                plan.path(),
                loaded.dictionary.name()
            );
        }
    }
    let replay = connection.replay.is_some();
    if (!open.simulators.is_empty() || replay) && !outputs.quiet {
        let _ = writeln!(out, "using {}", open.description);
    }
    // Each drive's limits for the values written to it (`left.speed_setpoint`).
    let written = plan.written_values();
    for (name, drive) in open.drives.iter_mut() {
        let prefix = format!("{name}.");
        let own: Vec<_> = written
            .iter()
            .filter(|w| name.is_empty() || w.object.name.starts_with(&prefix))
            .cloned()
            .collect();
        // The limits read are news to a person, not to a CI log; refusals go to `err`.
        let said: &mut dyn Write = match outputs.quiet {
            true => &mut std::io::sink(),
            false => &mut *out,
        };
        if let Err((code, why)) = within_drive_limits(&own, drive, plan.path(), &request.stop, said, err) {
            return not_run(request, Some((plan, &planned)), code, &why, err);
        }
    }
    let virtual_time = (request.fast && !open.simulators.is_empty()) || replay;
    let mut look = Look::of(
        outputs,
        request.terminal,
        virtual_time,
        plan.colored(),
        plan.planned_time(),
    );
    // A live line redrawn under a question would garble what the operator types.
    look.live &= prompts.is_empty();
    let settings = SessionSettings {
        safe_stop: request.safe_stop.settings(plan.safe_stop()),
        output_dir: request.output_dir.clone(),
        csv_wide: outputs.csv_wide,
        unit,
        operator: Box::new(RunOperator::new(given, request.input.clone())),
        history: request.history.clone(),
    };
    let report = observed(out, &look, csv.as_mut(), &request.observers, |observers| {
        let drives = open.drives.iter_mut().map(|(n, d)| (n.clone(), d)).collect();
        plan.run(drives, observers, &request.stop, settings, err)
    });
    finish_reports(&report, &planned, csv.as_ref(), outputs, err);
    RunResult {
        junit: Some(junit_suite(&report, &planned)),
        exit_code: report.exit_code(),
        report: Some(report),
        simulator: open.simulators.first().map(|(_, s)| s.clone()),
        simulators: open.simulators,
    }
}

/// Before anything opens: the drives' addresses and link settings, and the `--trace` and
/// `-v` outputs. On failure, the message (exit code 2).
fn checked(
    request: &RunRequest,
    loaded: &LoadedPlan,
    connection: &ConnectionArgs,
) -> Result<Telegrams, RunError> {
    let drives = loaded.plan.drives();
    if !drives.is_empty() && connection.replay.is_some() {
        return Err(RunError::Invalid(format!(
            "error: --replay stands in for one drive; {} declares several (`drives:`)",
            loaded.plan.path()
        )));
    }
    sim_checked(connection, request.registry, loaded)?;
    if !drives.is_empty() {
        return named_drives_checked(request, connection, drives, &loaded.drive_dictionaries)
            .map(Telegrams::Shared);
    }
    let dictionary = &loaded.dictionary;
    let family = request
        .registry
        .family(dictionary.family())
        .map_err(|e| RunError::Invalid(format!("error: {e}")))?;
    // Only the merged settings: the command line alone can lack what the file gives
    // (`--channel cyclic` with the file's `velocity_scaling`).
    let address = connection.check(request.registry, family.as_ref()).map_err(|e| {
        RunError::Invalid(format!(
            "error: {e} (link settings come from {} and the command line)",
            loaded.plan.link_source()
        ))
    })?;
    let header = trace_header(
        family.as_ref(),
        dictionary,
        &request.dictionary.extra,
        connection,
        address.shown,
    );
    telegram_outputs(request.outputs, family.as_ref(), dictionary, &header).map(Telegrams::One)
}

/// The telegram outputs of a run: one drive's, or shared by several drives.
enum Telegrams {
    One(TelegramFanOut),
    Shared(super::run_setup::SharedTelegrams),
}

/// Opens the drives, says early when one never answers, and hands each simulated drive
/// to the request's `prepare_simulator`. On failure, the message (exit code 3).
fn opened(
    request: &RunRequest,
    loaded: &LoadedPlan,
    connection: &ConnectionArgs,
    telegrams: Telegrams,
) -> Result<OpenDrives, RunError> {
    let telegrams = match telegrams {
        Telegrams::Shared(shared) => {
            return named_drives_opened(
                request,
                connection,
                loaded.plan.drives(),
                &loaded.drive_dictionaries,
                &shared,
            )
        }
        Telegrams::One(t) => t,
    };
    let mut open = open_drive(
        request.registry,
        connection,
        loaded.dictionary.clone(),
        request.fast,
        telegrams.into_observer(),
        Some(request.stop.clone()),
    )?;
    // A drive that never answers is said once, early, with what to check, instead of
    // every step and the safe stop each waiting out their retries.
    // (A replay answers only what the capture holds: it says itself what it lacks.)
    if open.simulator.is_none() && connection.replay.is_none() {
        if let Err(crate::drive::DriveError::Access(e)) = open.drive.state() {
            if e.is_no_reply() {
                return Err(RunError::Unreachable(silent_drive_of(
                    request,
                    open.drive.dictionary(),
                    &e.to_string(),
                )));
            }
        }
    }
    if let (Some(sim), Some(prepare)) = (&open.simulator, request.prepare_simulator) {
        prepare(sim, open.drive.clock());
    }
    let clock = open.drive.clock().clone();
    Ok(OpenDrives {
        drives: vec![(String::new(), open.drive)],
        simulators: open.simulator.map(|s| (String::new(), s)).into_iter().collect(),
        description: open.description,
        clock,
    })
}

/// The unit as known at the start. A plan that compares with the unit's last passed run
/// needs its serial: from `--unit serial=…`, from an answer given beforehand to the step
/// that sets it (then known at the start, so the lookup comes before anything moves), or
/// from an operator step during the run; with none of them it is refused.
fn start_identity(
    plan: &RunPlan,
    request: &RunRequest,
    prompts: &[(crate::session::Prompt, crate::session::StepOrigin)],
    given: &[(String, crate::session::Given)],
) -> Result<crate::session::UnitIdentity, RunError> {
    let Some(at) = plan.compares_with_last_pass() else {
        return Ok(request.operator.identity());
    };
    let unit = request.operator.identity_with_answers(prompts, given);
    if unit.serial.is_none() && !prompts.iter().any(|(p, _)| p.sets("serial")) {
        return Err(RunError::Invalid(format!(
            "error: {at}: `compared_with_last_pass` compares with the unit's last passed run, but nothing gives the unit's serial number; give --unit serial=…, or ask for it with an operator step (`enter_text` with `sets: serial`) before the check; nothing was sent"
        )));
    }
    Ok(unit)
}
