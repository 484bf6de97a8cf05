//! `--report FILE.html`: the run report as ONE self-contained HTML page to hand over after
//! commissioning: recipe, drive, parameters, verdict, every step and check, the safe stop,
//! and the plots section. Must not reference anything outside the file (no network, fonts,
//! scripts or images), must print well in black and white, and escapes every text that
//! comes from recipes, drives or messages. Draws no plot itself (see [`super::plot_section`]).

use super::html_text::{check_title, duration_text, esc, limits_cell, measured_cell, short_origin};
use super::plot_section::plots;
use crate::report::atomic_write::write_atomically;
use crate::report::case_names::case_names;
use crate::report::junit_report::unexplained_failures;
use crate::session::MAX_RECORDS;
use crate::session::{CheckResult, RunReport, StepRecord, Verdict};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

/// The HTML page of a run.
/// What a run without a drive identity says: its dictionary names no identity object the
/// drive answered (a family without one, such as a Modbus inverter whose manual gives no
/// identification register), or the run was refused before it looked.
pub const IDENTITY_NOT_READ: &str = "not read: the drive answered no identity object its dictionary names";

pub fn html_report(report: &RunReport) -> String {
    let r = report;
    let mut h = String::with_capacity(16 * 1024);
    let verdict = r.verdict.word();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"drivescript {}\">\n<title>{} — {verdict}</title>\n\
         <style>{CSS}</style>\n</head>\n<body>\n",
        env!("CARGO_PKG_VERSION"),
        esc(&r.recipe)
    );
    header(&mut h, r);
    failed_summary(&mut h, r);
    checks(&mut h, r);
    plots(&mut h, r);
    super::timeline::timeline(&mut h, r);
    steps(&mut h, r);
    safe_stop(&mut h, r);
    let _ = write!(
        h,
        "<footer>Written by drivescript {} from the run's report.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}

/// Writes [`html_report`] to `path` atomically (via `path.tmp`), creating the directory.
pub fn write_html(report: &RunReport, path: &Path) -> Result<(), crate::report::ReportWriteError> {
    write_atomically(path, &html_report(report))
}

/// The page's styles, screen and print, kept as a stylesheet so that it can be read and
/// edited as one.
pub const CSS: &str = include_str!("html_report.css");

fn header(h: &mut String, r: &RunReport) {
    let class = r.verdict.word().to_lowercase();
    let mark = if r.verdict == Verdict::Passed {
        "✔"
    } else {
        "✘"
    };
    let _ = write!(
        h,
        "<header>\n<h1>{}</h1>\n<p class=\"verdict {class}\" id=\"verdict\">{mark} {}{}</p>\n",
        esc(&r.recipe),
        r.verdict.word(),
        if r.simulated() {
            " <span class=\"simulated\">(SIMULATED DRIVE)</span>"
        } else {
            ""
        }
    );
    let why = match &r.verdict {
        Verdict::Passed => match r.checks.iter().filter(|c| c.marginal).count() {
            0 => format!("All {} check(s) passed.", r.checks.len()),
            n => format!(
                "All {} check(s) passed; {n} marginal (outside a warning band).",
                r.checks.len()
            ),
        },
        Verdict::Failed => format!("{} of {} check(s) failed.", r.checks_failed(), r.checks.len()),
        Verdict::Error(m) => format!("Communication failure or drive fault: {m}"),
        Verdict::Interrupted(s) => format!(
            "Interrupted by {}; the safe stop ran before the program ended.",
            s.describe()
        ),
        Verdict::Panicked(m) => format!("Internal error (panic: {m}); the safe stop ran after it."),
    };
    let _ = writeln!(h, "<p class=\"why\">{}</p>\n</header>", esc(&why));

    h.push_str("<section>\n<h2>Run</h2>\n<table class=\"facts\">\n");
    let params = if r.params.is_empty() {
        "none".to_string()
    } else {
        r.params
            .iter()
            .map(|(n, v)| format!("{n} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let facts = [
        ("Recipe", r.recipe.clone()),
        ("Recipe file", r.recipe_path.clone()),
        (
            "Recipe SHA-256",
            r.recipe_sha256.clone().unwrap_or_else(|| "not computed".into()),
        ),
        ("Tool", format!("drivescript {}", env!("CARGO_PKG_VERSION"))),
        ("Drive", r.drive.clone()),
        (
            "Drive identity",
            r.identity.clone().unwrap_or_else(|| IDENTITY_NOT_READ.into()),
        ),
        (
            "Unit under test",
            if r.unit.is_empty() {
                "not given".to_string()
            } else {
                r.unit.to_string()
            },
        ),
        ("Parameters", params),
        (
            "Started (UTC)",
            humantime::format_rfc3339_seconds(r.started_at)
                .to_string()
                .replace('T', " ")
                .replace('Z', " UTC"),
        ),
        ("Duration", duration_text(r.duration)),
        (
            "Verdict",
            format!("{} (exit code {})", r.verdict.word(), r.exit_code()),
        ),
        (
            "Checks",
            match r.checks.iter().filter(|c| c.marginal).count() {
                0 => format!("{} passed, {} failed", r.checks_passed(), r.checks_failed()),
                n => format!(
                    "{} passed ({n} marginal), {} failed",
                    r.checks_passed(),
                    r.checks_failed()
                ),
            },
        ),
        ("After the safe stop", r.drive_left()),
    ];
    for (name, value) in facts {
        let _ = writeln!(
            h,
            "<tr><th scope=\"row\">{name}</th><td>{}</td></tr>",
            esc(&value)
        );
    }
    h.push_str("</table>\n</section>\n");
}

/// The failed checks and the steps that failed on their own, first thing after the
/// verdict, so a reader sees at once what to look at.
fn failed_summary(h: &mut String, r: &RunReport) {
    let failed: Vec<&CheckResult> = r.checks.iter().filter(|c| !c.passed && !c.retried).collect();
    let steps = unexplained_failures(r);
    if failed.is_empty() && steps.is_empty() {
        return;
    }
    h.push_str("<section id=\"failures\">\n<h2>What failed</h2>\n<ul>\n");
    for c in failed {
        let stage = if c.stage.is_empty() {
            String::new()
        } else {
            format!("{} / ", c.stage)
        };
        let _ = writeln!(
            h,
            "<li><span class=\"fail\">FAIL</span> {}{}: measured {}, limits {} — {}</li>",
            esc(&stage),
            esc(&check_title(c)),
            esc(&measured_cell(r, c)),
            esc(&limits_cell(r, c)),
            esc(&c.message)
        );
    }
    for s in steps {
        let _ = writeln!(
            h,
            "<li><span class=\"fail\">FAIL</span> step {} {}: {}</li>",
            esc(&s.id),
            esc(&s.label),
            esc(&s.detail)
        );
    }
    h.push_str("</ul>\n</section>\n");
}

/// Opens the section `id` headed `title` with a table of `columns` (heading, width in %),
/// up to its body; when there is nothing to show, the section says `empty` instead, is
/// closed, and the answer is false (no table to fill).
fn table_section(
    h: &mut String,
    (id, title): (&str, &str),
    columns: &[(&str, u32)],
    empty: Option<&str>,
) -> bool {
    h.push_str(&format!("<section id=\"{id}\">\n<h2>{title}</h2>\n"));
    if let Some(when_empty) = empty {
        h.push_str(&format!("<p>{when_empty}</p>\n</section>\n"));
        return false;
    }
    h.push_str("<table>\n<colgroup>");
    for (_, width) in columns {
        h.push_str(&format!("<col style=\"width:{width}%\">"));
    }
    h.push_str("</colgroup>\n<thead><tr>");
    for (heading, _) in columns {
        h.push_str(&format!("<th>{heading}</th>"));
    }
    h.push_str("</tr></thead>\n<tbody>\n");
    true
}

/// The heading of checks that are in no repeat or include, after some that are.
const OUTSIDE_STAGES: &str = "not in a repeat or include";

fn checks(h: &mut String, r: &RunReport) {
    #[rustfmt::skip]
    let columns = [("Check", 23), ("Measured", 15), ("Limits", 19), ("Result", 9), ("Details", 21), ("Where", 13)];
    let empty = r.checks.is_empty().then_some("The recipe has no checks.");
    if !table_section(h, ("checks", "Checks"), &columns, empty) {
        return;
    }
    // Grouped by stage as they ran (a new group where the stage changes); names unique
    // within their stage.
    let mut groups: Vec<(&str, Vec<&CheckResult>)> = Vec::new();
    for c in &r.checks {
        match groups.last_mut() {
            Some((stage, list)) if *stage == c.stage => list.push(c),
            _ => groups.push((&c.stage, vec![c])),
        }
    }
    for (k, (stage, group)) in groups.into_iter().enumerate() {
        // Checks outside any repeat or include get a heading of their own once a group
        // stands before them, or they would read as part of that group.
        let heading = match stage {
            "" if k > 0 => Some(OUTSIDE_STAGES),
            "" => None,
            s => Some(s),
        };
        if let Some(stage) = heading {
            let failed = group.iter().filter(|c| !c.passed && !c.retried).count();
            let mark = if failed > 0 {
                format!(" — <span class=\"fail\">{failed} FAILED</span>")
            } else {
                String::new()
            };
            let _ = writeln!(
                h,
                "<tr class=\"group\"><th colspan=\"6\">{}{mark}</th></tr>",
                esc(stage)
            );
        }
        let titles: Vec<(String, String)> = group.iter().map(|c| (check_title(c), c.step.clone())).collect();
        for (c, title) in group.iter().zip(case_names(&titles)) {
            let (row, mark) = match (c.passed, c.marginal, c.retried) {
                (false, _, true) => ("retried", "<span class=\"retried\">FAIL, RETRIED</span>"),
                (true, false, _) => ("pass", "<span class=\"ok\">PASS</span>"),
                (true, true, _) => ("marginal", "<span class=\"warn\">MARGINAL</span>"),
                (false, _, false) => ("fail", "<span class=\"fail\">FAIL</span>"),
            };
            let _ = writeln!(
                h,
                "<tr class=\"{row}\"><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                 <td>{mark}</td><td>{}</td><td><code title=\"{}\">{}</code></td></tr>",
                esc(&title),
                esc(&measured_cell(r, c)),
                esc(&limits_cell(r, c)),
                esc(&c.message),
                esc(&c.origin.to_string()),
                esc(&short_origin(&c.origin.to_string()))
            );
        }
    }
    h.push_str("</tbody>\n</table>\n</section>\n");
}

/// The steps in the order they ran, each container (repeat, include) before the steps it
/// holds (the run records it after them, when it ends), with its depth; a container is
/// marked failed when a step inside it failed.
pub fn steps_in_order(steps: &[StepRecord]) -> Vec<(&StepRecord, usize, bool)> {
    let holds = |outer: &StepRecord, inner: &StepRecord| {
        inner.phase == outer.phase
            && (inner.id.starts_with(&format!("{}.", outer.id))
                || inner.id.starts_with(&format!("{}[", outer.id)))
    };
    let mut out: Vec<&StepRecord> = Vec::with_capacity(steps.len());
    for s in steps {
        let mut at = out.len();
        while at > 0 && holds(s, out[at - 1]) {
            at -= 1;
        }
        out.insert(at, s);
    }
    out.iter()
        .enumerate()
        .map(|(i, s)| {
            let depth = out[..i].iter().filter(|o| holds(o, s)).count();
            let inner_failed = out[i + 1..].iter().take_while(|o| holds(s, o)).any(|o| !o.ok);
            (*s, depth, s.ok && !inner_failed)
        })
        .collect()
}

fn steps(h: &mut String, r: &RunReport) {
    #[rustfmt::skip]
    let columns = [("#", 7), ("Phase", 8), ("Step", 24), ("Result", 10), ("Detail", 25), ("Start", 13), ("Duration", 13)];
    let empty = r.steps.is_empty().then_some("No step ran.");
    if !table_section(h, ("steps", "Steps"), &columns, empty) {
        return;
    }
    let start = r.steps.iter().map(|s| s.started).min().unwrap_or_default();
    for (s, depth, ok) in steps_in_order(&r.steps) {
        step_row(h, s, depth, ok, start);
    }
    h.push_str("</tbody>\n</table>\n");
    if r.omitted_steps > 0 || r.omitted_checks > 0 {
        let _ = writeln!(
            h,
            "<p>{} further passed step(s) and {} passed check(s) inside repeats are not listed \
             (the report keeps {MAX_RECORDS} of each; every failure is listed).</p>",
            r.omitted_steps, r.omitted_checks
        );
    }
    h.push_str("</section>\n");
}

fn step_row(h: &mut String, s: &StepRecord, depth: usize, ok: bool, start: Duration) {
    let (row, mark) = match (s.ok, ok) {
        (true, true) => ("ok", "<span class=\"ok\">ok</span>"),
        (true, false) => ("fail", "<span class=\"fail\">FAIL</span> (inside)"),
        (false, _) => ("fail", "<span class=\"fail\">FAIL</span>"),
    };
    let indent = depth.min(3);
    let _ = writeln!(
        h,
        "<tr class=\"{row}\"><td class=\"num step\">{}</td><td>{}</td><td class=\"indent-{indent}\">{}</td><td>{mark}</td>\
         <td>{}</td><td class=\"num time\">{}</td><td class=\"num time\">{}</td></tr>",
        esc(&s.id),
        esc(s.phase),
        esc(&s.label),
        esc(&s.detail),
        esc(&duration_text(s.started.saturating_sub(start))),
        esc(&duration_text(s.duration))
    );
}

fn safe_stop(h: &mut String, r: &RunReport) {
    h.push_str("<section id=\"safe-stop\">\n<h2>Safe stop</h2>\n");
    if r.safe_stop.is_empty() {
        h.push_str("<p>No notes.</p>\n");
    } else {
        h.push_str("<ul>\n");
        for note in &r.safe_stop {
            let _ = writeln!(h, "<li>{}</li>", esc(note));
        }
        h.push_str("</ul>\n");
    }
    let warning = if r.check_by_hand() {
        "<p class=\"fail\"><strong>CHECK THE DRIVE BY HAND:</strong> the safe stop could not be confirmed.</p>\n"
    } else {
        ""
    };
    let _ = writeln!(
        h,
        "<p><strong>{}</strong></p>\n{warning}</section>",
        esc(&r.drive_left())
    );
}
