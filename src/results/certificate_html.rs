//! The commissioning certificate: one self-contained HTML page of one unit over all its
//! stored runs (`results report --unit SERIAL`), or of one run (`results report RUN`), in
//! the run report's style: who and what was tested, a row per run with its verdict, then
//! each run's checks, plots and end state. Escapes every text; references nothing outside.

use super::stored_run::{stored_limits, stored_measured};
use super::{PageLinks, StoredRun};
use crate::report::{esc, plot_svg, IDENTITY_NOT_READ, REPORT_CSS};
use crate::session::{key_of_name, with_unit, Series};
use std::fmt::Write as _;

/// The page for the unit `serial` over `runs` (oldest first).
pub fn unit_certificate(serial: &str, runs: &[StoredRun], links: PageLinks) -> String {
    let title = format!("Unit {serial}");
    let mut h = page_start(&title);
    h.push_str(&links.nav());
    // An attempt refused before it started says nothing of the unit, nor does a voided run.
    let latest = runs
        .iter()
        .rev()
        .find(|r| r.started() && r.void.is_none())
        .or(runs.iter().rev().find(|r| r.void.is_none()));
    let verdict = latest.map_or("no runs", |r| r.verdict());
    let voided = runs.iter().filter(|r| r.void.is_some()).count();
    let _ = writeln!(
        h,
        "<header>\n<h1>{}</h1>\n<p class=\"verdict {}\" id=\"verdict\">{} {}{}</p>\n\
         <p class=\"why\">{} run(s) recorded{}; the latest that started ended {}.</p>\n</header>",
        esc(&title),
        class(verdict),
        if verdict == "passed" { "✔" } else { "✘" },
        esc(&verdict.to_uppercase()),
        simulated_mark(latest),
        runs.len(),
        match voided {
            0 => String::new(),
            n => format!(", {n} of them voided (kept, marked VOID, and not counted)"),
        },
        esc(verdict)
    );
    h.push_str("<section>\n<h2>Unit</h2>\n<table class=\"facts\">\n");
    let last_of = |f: fn(&StoredRun) -> Option<&String>| {
        runs.iter()
            .rev()
            .find_map(f)
            .cloned()
            .unwrap_or_else(|| "not recorded".into())
    };
    let facts = [
        ("Serial number", serial.to_string()),
        ("Part", last_of(|r| r.run.unit.part.as_ref())),
        (
            "Drive identity",
            last_of(|r| r.end.as_ref().and_then(|e| e.drive_identity.as_ref())),
        ),
        (
            "Stations",
            joined(runs.iter().filter_map(|r| r.run.unit.station.clone())),
        ),
        (
            "Operators",
            joined(runs.iter().filter_map(|r| r.run.unit.operator.clone())),
        ),
    ];
    facts_rows(&mut h, &facts);
    h.push_str("</table>\n</section>\n<section>\n<h2>Runs</h2>\n<table id=\"runs\">\n<thead><tr><th>Started (UTC)</th><th>Recipe</th><th>Verdict</th><th>Checks</th><th>Station</th><th>Operator</th><th>Run</th></tr></thead>\n<tbody>\n");
    for r in runs {
        let failed = r.checks.iter().filter(|c| !c.passed).count();
        let _ = writeln!(
            h,
            "<tr class=\"{}\"><td>{}</td><td>{}</td><td class=\"verdict-cell {}\">{}</td><td class=\"num\">{} passed, {failed} failed</td><td>{}</td><td>{}</td><td class=\"step\">{}</td></tr>",
            if r.verdict() == "passed" { "" } else { "fail" },
            esc(&shown_time(&r.run.started_at)),
            esc(&r.run.recipe),
            if r.verdict() == "passed" { "ok" } else { "fail" },
            verdict_html(r),
            r.checks.len() - failed,
            esc(r.run.unit.station.as_deref().unwrap_or("")),
            esc(r.run.unit.operator.as_deref().unwrap_or("")),
            match links {
                // On a file, the run's section further down; served, its own page.
                PageLinks::None => format!("<a href=\"#run-{0}\"><code>{0}</code></a>", esc(&r.run.id)),
                PageLinks::Served { .. } => links.run(&r.run.id, &format!("<code>{}</code>", esc(&r.run.id))),
            },
        );
    }
    h.push_str("</tbody>\n</table>\n</section>\n");
    let mut plot = 0;
    for r in runs {
        run_section(&mut h, r, &mut plot, links);
    }
    page_end(h)
}

/// The page of one stored run.
pub fn run_certificate(run: &StoredRun, links: PageLinks) -> String {
    let title = format!("{} — run {}", run.run.recipe, run.run.id);
    let mut h = page_start(&title);
    h.push_str(&links.nav());
    let unit = match &run.run.unit.serial {
        Some(serial) => format!(
            "\n<p class=\"why\" id=\"unit\">Unit {}</p>",
            links.unit(serial, &esc(serial))
        ),
        None => String::new(),
    };
    let _ = writeln!(
        h,
        "<header>\n<h1>{}</h1>\n<p class=\"verdict {}\" id=\"verdict\">{} {}</p>{unit}\n</header>",
        esc(&run.run.recipe),
        class(run.verdict()),
        if run.verdict() == "passed" { "✔" } else { "✘" },
        verdict_html(run)
    );
    run_section(&mut h, run, &mut 0, links);
    page_end(h)
}

pub(super) fn page_start(title: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"drivescript {}\">\n<title>{}</title>\n\
         <style>{REPORT_CSS}</style>\n</head>\n<body>\n",
        env!("CARGO_PKG_VERSION"),
        esc(title)
    )
}

/// ` <span class="simulated">SIMULATED DRIVE</span>` beside the verdict of a run on the
/// built-in simulated drive: no reader may take it for a real unit's.
fn simulated_mark(run: Option<&StoredRun>) -> &'static str {
    match run.is_some_and(|r| r.run.simulated) {
        true => " <span class=\"simulated\">(SIMULATED DRIVE)</span>",
        false => "",
    }
}

/// The verdict in capitals, marked simulated and void where the run is.
pub(super) fn verdict_html(r: &StoredRun) -> String {
    let mut v = esc(&r.verdict().to_uppercase());
    v.push_str(simulated_mark(Some(r)));
    if r.void.is_some() {
        v.push_str(" <span class=\"void\">VOID</span>");
    }
    v
}

/// Lines to sign: who tested and who approved, each with name, date and signature.
fn approval_block(h: &mut String) {
    h.push_str(
        "<section class=\"approval\" id=\"approval\">\n<h2>Approval</h2>\n<table class=\"approval\">\n\
         <thead><tr><th></th><th>Name</th><th>Date</th><th>Signature</th></tr></thead>\n<tbody>\n",
    );
    for role in ["Tested by", "Approved by"] {
        let _ = writeln!(
            h,
            "<tr><th scope=\"row\">{role}</th><td class=\"sign\"></td><td class=\"sign\"></td><td class=\"sign\"></td></tr>"
        );
    }
    h.push_str("</tbody>\n</table>\n</section>\n");
}

fn page_end(mut h: String) -> String {
    approval_block(&mut h);
    let _ = write!(
        h,
        "<footer>Written by drivescript {} from its results store.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}

/// `failed` for every verdict but passed, as the run report's classes.
fn class(verdict: &str) -> &'static str {
    match verdict {
        "passed" => "passed",
        "error" => "error",
        "interrupted" => "interrupted",
        "panic" => "panic",
        _ => "failed",
    }
}

/// `2026-11-25 02:10:53 UTC` from the stored RFC 3339 text.
pub(super) fn shown_time(utc: &str) -> String {
    let t = utc.replace('T', " ");
    match t.split_once('.') {
        Some((seconds, _)) => format!("{seconds} UTC"),
        None => t.replace('Z', " UTC"),
    }
}

fn joined(items: impl Iterator<Item = String>) -> String {
    let mut seen: Vec<String> = Vec::new();
    for i in items {
        if !seen.contains(&i) {
            seen.push(i);
        }
    }
    if seen.is_empty() {
        "not recorded".into()
    } else {
        seen.join(", ")
    }
}

fn facts_rows(h: &mut String, facts: &[(&str, String)]) {
    for (name, value) in facts {
        let _ = writeln!(h, "<tr><th scope=\"row\">{name}</th><td>{}</td></tr>", esc(value));
    }
}

fn run_section(h: &mut String, r: &StoredRun, plot: &mut usize, links: PageLinks) {
    let _ = writeln!(
        h,
        "<section id=\"run-{}\">\n<h2>{} — {} — {}</h2>",
        esc(&r.run.id),
        esc(&shown_time(&r.run.started_at)),
        esc(&r.run.recipe),
        verdict_html(r)
    );
    if let Some(v) = &r.void {
        let _ = writeln!(
            h,
            "<p class=\"void\" id=\"void-{}\">VOID — voided by {} at {}: {}. The run is kept as it was recorded and counts toward no yield or trend.</p>",
            esc(&r.run.id),
            esc(&v.voided_by),
            esc(&shown_time(&v.voided_at)),
            esc(&v.why)
        );
    }
    h.push_str("<table class=\"facts\">\n");
    let params = r
        .run
        .params
        .iter()
        .map(|(n, v)| format!("{n} = {v}"))
        .collect::<Vec<_>>()
        .join(", ");
    let end = r.end.as_ref();
    let left = match end {
        None => "not recorded: the run never finished (killed or power cut)".to_string(),
        // A run refused before it started sent nothing: there was no safe stop to confirm.
        Some(_) if !r.started() => "not started: nothing was sent to the drive".to_string(),
        Some(e) => {
            let state = e.final_state.clone().unwrap_or_else(|| "unknown state".into());
            let speed = e
                .final_speed
                .map(|v| format!(" at {}", with_unit(v, e.speed_unit.as_deref())))
                .unwrap_or_default();
            let confirmed = if e.stop_confirmed {
                "confirmed"
            } else {
                "NOT CONFIRMED"
            };
            format!(
                "{state}{speed} (stop {confirmed}{})",
                if e.coasting { ", still coasting" } else { "" }
            )
        }
    };
    let facts = [
        ("Run", r.run.id.clone()),
        ("Recipe file", r.run.recipe_path.clone()),
        (
            "Recipe SHA-256",
            r.run.recipe_sha256.clone().unwrap_or_else(|| "not read".into()),
        ),
        ("Drive", r.run.drive.clone()),
        (
            "Drive identity",
            match end {
                Some(e) => e
                    .drive_identity
                    .clone()
                    .unwrap_or_else(|| IDENTITY_NOT_READ.into()),
                None => "not recorded: the run never finished".into(),
            },
        ),
        (
            "Dictionary (family)",
            match (&r.run.dictionary, &r.run.family) {
                (Some(d), Some(f)) => format!("{d} ({f})"),
                _ => "not recorded".into(),
            },
        ),
        (
            "Simulated",
            if r.run.simulated {
                "yes (built-in simulated drive)".into()
            } else {
                "no".into()
            },
        ),
        (
            "Parameters",
            if params.is_empty() { "none".into() } else { params },
        ),
        (
            "Ended (UTC)",
            end.map_or_else(|| "—".into(), |e| shown_time(&e.ended_at)),
        ),
        (
            "Exit code",
            end.map_or_else(|| "—".into(), |e| e.exit_code.to_string()),
        ),
        ("After the safe stop", left),
        // Why a run did not pass: a drive fault with its EMCY code and text, a refusal.
        (
            "Reason",
            end.and_then(|e| e.reason.clone()).unwrap_or_else(|| "—".into()),
        ),
        ("Tool", format!("drivescript {}", r.run.tool_version)),
    ];
    facts_rows(h, &facts);
    h.push_str("</table>\n");
    if !r.checks.is_empty() {
        h.push_str("<table class=\"checks\">\n<thead><tr><th>Check</th><th>Measured</th><th>Limits</th><th>Result</th><th>Step</th></tr></thead>\n<tbody>\n");
        for c in &r.checks {
            let measured = stored_measured(&c.name, c.measured, c.unit.as_deref(), c.decimals)
                .or_else(|| c.measured_text.clone())
                .unwrap_or_else(|| "—".into());
            let key = c.key.clone().or_else(|| key_of_name(&c.name)).unwrap_or_default();
            let limits = stored_limits(&c.name, &key, c.limits, c.unit.as_deref(), c.inclusive)
                .unwrap_or_else(|| "—".into());
            // A comparison with the last pass says against what (its value is the change,
            // `+5 K` beside a check of 30 °C), and a check that measured nothing says why.
            let why = match (&c.reference_run, c.measured, &c.measured_text) {
                (None, Some(_), _) | (None, _, Some(_)) => String::new(),
                _ => format!("<br><small>{}</small>", esc(&c.message)),
            };
            let _ = writeln!(
                h,
                "<tr{}><td>{}{}{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"step {}\">{}</td><td class=\"step\">{}</td></tr>",
                match (c.passed, c.marginal) {
                    (true, false) => "",
                    (true, true) => " class=\"marginal\"",
                    (false, _) => " class=\"fail\"",
                },
                esc(&c.name),
                links.check_pages(
                    &super::CheckIdentity::of(&r.run.recipe, &c.stage, &c.step, &key).case_name(),
                    &r.run.recipe
                ),
                why,
                esc(&measured),
                esc(&limits),
                if c.passed { "ok" } else { "fail" },
                match (c.passed, c.marginal) {
                    (true, false) => "PASS",
                    (true, true) => "MARGINAL",
                    (false, _) => "FAIL",
                },
                esc(&c.step)
            );
        }
        h.push_str("</tbody>\n</table>\n");
    }
    for s in end.map(|e| e.series.as_slice()).unwrap_or_default() {
        let series = Series {
            object: s.object.clone(),
            unit: s.unit.clone(),
            step: s.step.clone(),
            points: s.points.clone(),
            samples: None,
            marks: None,
        };
        *plot += 1;
        let _ = writeln!(
            h,
            "<figure>{}<figcaption>{} sampled at step {}</figcaption></figure>",
            plot_svg(&series, &[], *plot),
            esc(&s.object),
            esc(&s.step)
        );
    }
    h.push_str("</section>\n");
}
