//! `results list` and `results show`: a store's runs as a table and one run in full, with
//! what a reader must not miss (simulated, unsynced, VOID, a stop not confirmed) beside
//! the verdict. Prints only; what a run holds came from outside and never acts on the
//! terminal.

use super::text_table::table_lines;
use crate::report::visible;
use crate::results::{export, RunFilter, Spool, Store, StoreError};
use crate::run::PASSED;

/// The runs of `filter`, those with records still in this bench's `spool` marked
/// unsynced (not yet, or not wholly, in the store).
pub(super) fn list(
    store: &mut Store,
    filter: &RunFilter,
    json: bool,
    spool: &Spool,
) -> Result<i32, StoreError> {
    let runs = store.list(filter)?;
    let unsynced = spool.runs();
    let waiting = (!unsynced.is_empty()).then(|| {
        format!(
            "{} run(s) kept on this bench, not yet in {} — `drivescript results sync` delivers them (kept in {})",
            unsynced.len(),
            store.name(),
            spool.path().display()
        )
    });
    if json {
        let list: Vec<serde_json::Value> = runs
            .iter()
            .map(|r| {
                let mut v = export::run_json(r);
                if let Some(o) = v.as_object_mut() {
                    o.insert("unsynced".into(), unsynced.contains(&r.run.id).into());
                }
                v
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&list).unwrap_or_default());
        if let Some(w) = waiting {
            eprintln!("{w}");
        }
        return Ok(PASSED);
    }
    let rows: Vec<Vec<String>> = runs
        .iter()
        .map(|r| {
            vec![
                r.run.id.clone(),
                r.run.started_at.clone(),
                if unsynced.contains(&r.run.id) {
                    format!("{} (unsynced)", listed_verdict(r))
                } else {
                    listed_verdict(r)
                },
                r.run.recipe.clone(),
                r.run.unit.serial.clone().unwrap_or_default(),
                r.run.unit.station.clone().unwrap_or_default(),
                if r.run.simulated {
                    "simulated".into()
                } else {
                    r.run.drive.clone()
                },
            ]
        })
        .collect();
    for line in table_lines(
        &[
            "run",
            "started (UTC)",
            "verdict",
            "recipe",
            "unit",
            "station",
            "drive",
        ],
        &rows,
    ) {
        println!("{line}");
    }
    if let Some(w) = waiting {
        println!("{w}");
    }
    if runs.is_empty() {
        println!(
            "no runs{} in {}",
            if filter.simulated {
                ""
            } else {
                " (runs on the simulated drive are hidden: --simulated)"
            },
            store.name()
        );
    }
    Ok(PASSED)
}

/// `PASSED`, `PASSED (simulated)`, `FAILED — VOID`: the verdict with what a reader must
/// not miss beside it.
fn listed_verdict(r: &crate::results::StoredRun) -> String {
    let mut v = r.verdict().to_uppercase();
    if r.run.simulated {
        v.push_str(" (simulated)");
    }
    if r.void.is_some() {
        v.push_str(" — VOID");
    }
    v
}

pub(super) fn show(store: &mut Store, id: &str, json: bool) -> Result<i32, StoreError> {
    // What a run holds came from outside (serial numbers, answers, a drive's replies): it
    // never acts on the terminal.
    macro_rules! shown {
        ($($t:tt)*) => { println!("{}", visible(&format!($($t)*))) };
    }
    let r = store.run(id)?;
    if json {
        shown!(
            "{}",
            serde_json::to_string_pretty(&export::run_json(&r)).unwrap_or_default()
        );
        return Ok(PASSED);
    }
    shown!("run      {}", r.run.id);
    shown!(
        "recipe   {} ({}, sha256 {})",
        r.run.recipe,
        r.run.recipe_path,
        r.run.recipe_sha256.as_deref().unwrap_or("not read")
    );
    shown!(
        "drive    {}{}",
        r.run.drive,
        if r.run.simulated { " (simulated)" } else { "" }
    );
    let unit = &r.run.unit;
    for (name, value) in [
        ("unit", &unit.serial),
        ("part", &unit.part),
        ("operator", &unit.operator),
        ("station", &unit.station),
    ] {
        if let Some(v) = value {
            shown!("{name:<8} {v}");
        }
    }
    if !r.run.params.is_empty() {
        let p: Vec<String> = r.run.params.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        shown!("params   {}", p.join(", "));
    }
    shown!("started  {}", r.run.started_at);
    if let Some(v) = &r.void {
        shown!("VOID     voided by {} at {}: {}", v.voided_by, v.voided_at, v.why);
    }
    for s in &r.steps {
        shown!(
            "  {:>6}  {}  {}  {}",
            s.step,
            if s.ok { "ok  " } else { "FAIL" },
            s.label,
            s.detail
        );
    }
    for c in &r.checks {
        shown!(
            "        {}  {}: {}",
            match (c.passed, c.marginal) {
                (true, false) => "PASS",
                (true, true) => "MARGINAL",
                (false, _) => "FAIL",
            },
            c.name,
            c.message
        );
        if let (Some(run), Some(value)) = (&c.reference_run, c.reference_value) {
            shown!(
                "                  reference: run {run} of {}, measured {}",
                c.reference_at.as_deref().unwrap_or("an unknown time"),
                crate::session::number(value)
            );
        }
    }
    match &r.end {
        Some(e) => {
            if let Some(line) = drive_left(e, r.started()) {
                shown!("{line}");
            }
            shown!(
                "ended    {} — {} (exit code {})",
                e.ended_at,
                e.verdict.to_uppercase(),
                e.exit_code
            );
            if let Some(reason) = &e.reason {
                shown!("reason   {reason}");
            }
        }
        None => shown!("INCOMPLETE — the run never finished (killed, power cut, or still running)"),
    }
    Ok(PASSED)
}

/// What the safe stop left the drive in, as stored: a stop not confirmed is said even when
/// the drive's state could not be read (then there is no state to name). A run refused
/// before it started stopped nothing.
fn drive_left(e: &crate::results::EndRow, started: bool) -> Option<String> {
    let unconfirmed = if e.stop_confirmed {
        ""
    } else {
        " — stop NOT confirmed"
    };
    match &e.final_state {
        Some(state) => {
            let speed = e
                .final_speed
                .map(|v| format!(" at {}", crate::session::with_unit(v, e.speed_unit.as_deref())))
                .unwrap_or_default();
            Some(format!("drive left in {state}{speed}{unconfirmed}"))
        }
        None if started && !e.stop_confirmed => Some(format!(
            "drive left in a state that could not be read back{unconfirmed}"
        )),
        None => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::EndRow;

    #[test]
    fn a_stop_not_confirmed_is_said_when_the_state_could_not_be_read() {
        let end = EndRow {
            verdict: "error".into(),
            stop_confirmed: false,
            ..EndRow::default()
        };
        let line = drive_left(&end, true).unwrap_or_default();
        assert!(line.contains("stop NOT confirmed"), "{line}");
    }

    #[test]
    fn a_confirmed_stop_and_a_refused_run_say_no_more_than_they_know() {
        let confirmed = EndRow {
            final_state: Some("switch on disabled".into()),
            final_speed: Some(0.0),
            speed_unit: Some("rpm".into()),
            stop_confirmed: true,
            ..EndRow::default()
        };
        assert_eq!(
            drive_left(&confirmed, true).as_deref(),
            Some("drive left in switch on disabled at 0 rpm")
        );
        let refused = EndRow {
            verdict: "refused".into(),
            ..EndRow::default()
        };
        assert_eq!(drive_left(&refused, false), None);
        let no_device_control = EndRow {
            stop_confirmed: true,
            ..EndRow::default()
        };
        assert_eq!(drive_left(&no_device_control, true), None);
    }
}
