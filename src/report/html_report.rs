//! `--report FILE.html`: the run report as ONE self-contained HTML page to hand over after
//! commissioning: recipe, drive, parameters, verdict, every step and check, the safe stop,
//! and an inline SVG plot per sampled series with the checks' limits. Must not reference
//! anything outside the file (no network, fonts, scripts or images), must print well in
//! black and white, and escapes every text that comes from recipes, drives or messages.

use super::atomic_write::write_atomically;
use super::junit_report::{stable_check_name, unexplained_failures, UniqueNames};
use crate::session::{number, CheckResult, RunReport, Series, StepRecord, Verdict};
use crate::session::{with_unit, MAX_RECORDS};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

/// Most points a plot's polyline holds; longer series keep the min and max of each bucket.
pub const MAX_PLOT_POINTS: usize = 2000;

/// The HTML page of a run.
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
pub fn write_html(report: &RunReport, path: &Path) -> Result<(), String> {
    write_atomically(path, &html_report(report))
}

const CSS: &str = "
body { font-family: system-ui, -apple-system, 'Segoe UI', Roboto, Helvetica, Arial, sans-serif;
       margin: 2em auto; max-width: 1100px; padding: 0 1em; color: #111; line-height: 1.4; }
h1 { margin-bottom: 0.2em; }
h2 { border-bottom: 1px solid #999; padding-bottom: 0.1em; margin-top: 1.6em; }
table { border-collapse: collapse; width: 100%; margin: 0.5em 0; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.5em; text-align: left; vertical-align: top;
         overflow-wrap: anywhere; }
th { background: #eee; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.facts th { width: 12em; }
tr.group th { background: #f4f4f4; font-weight: bold; text-align: left; }
td.step { white-space: nowrap; }
td.indent-1 { padding-left: 1.5em; } td.indent-2 { padding-left: 2.5em; }
td.indent-3 { padding-left: 3.5em; }
.verdict { display: inline-block; font-size: 2.2em; font-weight: bold; letter-spacing: 0.05em;
           padding: 0.15em 0.6em; border: 4px solid; margin: 0.3em 0; }
.verdict.passed { color: #0a5a1e; background: #dff3e4; border-style: solid; }
.verdict.failed, .verdict.error, .verdict.interrupted, .verdict.panic { color: #8b0000;
           background: #fbe0e0; border-style: double; border-width: 6px; }
.why { font-size: 1.1em; font-weight: bold; }
.ok { color: #0a5a1e; }
.fail { color: #8b0000; font-weight: bold; }
tr.fail td { background: #fdf0f0; }
section#failures { border: 2px solid #8b0000; padding: 0 1em 0.5em; margin-top: 1em; }
section#failures h2 { border: none; margin-top: 0.5em; }
code { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: 0.95em; }
figure { margin: 1em 0; }
figcaption { font-size: 0.9em; color: #333; }
ul.stat-checks { margin: 0.2em 0 0 0; font-size: 0.9em; }
svg.plot { display: block; width: 100%; max-width: 760px; height: auto; border: 1px solid #ccc;
           background: #fff; box-sizing: border-box; }
svg.plot text { font-family: system-ui, Helvetica, Arial, sans-serif; font-size: 11px; fill: #111; }
svg.plot .grid { stroke: #ddd; stroke-width: 1; }
svg.plot .axis { stroke: #111; stroke-width: 1; }
svg.plot .data { fill: none; stroke: #1f4fa0; stroke-width: 1.5; }
svg.plot .limit { stroke: #b00000; stroke-width: 1.2; stroke-dasharray: 6 4; }
svg.plot text.limit-label { fill: #b00000; }
footer { margin-top: 2em; font-size: 0.8em; color: #555; }
@page { size: A4; margin: 16mm 14mm 18mm 14mm;
        @bottom-right { content: 'page ' counter(page) ' of ' counter(pages); font-size: 9pt; } }
@media print {
  body { margin: 0; max-width: none; color: #000; font-size: 10pt; padding: 0; }
  table { table-layout: fixed; font-size: 9pt; }
  td.num { white-space: normal; }
  td.time, td.step { white-space: nowrap; font-size: 8.5pt; }
  tr.group { break-after: avoid; page-break-after: avoid; }
  th, tr.fail td, tr.group th, .verdict, .verdict.passed, .verdict.failed, .verdict.error,
  .verdict.interrupted, svg.plot { background: none !important; }
  .verdict, .ok, .fail, svg.plot text.limit-label { color: #000 !important; }
  svg.plot text.limit-label { fill: #000; font-style: italic; }
  svg.plot .data { stroke: #000; stroke-width: 1.2; }
  svg.plot .limit { stroke: #000; stroke-width: 0.8; stroke-dasharray: 2 3; }
  svg.plot .grid { stroke: #ccc; }
  svg.plot { width: 100% !important; max-width: 100%; border-color: #999; }
  figure, tr, .verdict, section#failures { break-inside: avoid; page-break-inside: avoid; }
  thead { display: table-header-group; }
  h2 { break-after: avoid; page-break-after: avoid; }
  footer { color: #000; }
}
";

fn header(h: &mut String, r: &RunReport) {
    let class = r.verdict.word().to_lowercase();
    let mark = if r.verdict == Verdict::Passed {
        "✔"
    } else {
        "✘"
    };
    let _ = write!(
        h,
        "<header>\n<h1>{}</h1>\n<p class=\"verdict {class}\" id=\"verdict\">{mark} {}</p>\n",
        esc(&r.recipe),
        r.verdict.word()
    );
    let why = match &r.verdict {
        Verdict::Passed => format!("All {} check(s) passed.", r.checks.len()),
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
        ("Drive", r.drive.clone()),
        (
            "Drive identity",
            r.identity.clone().unwrap_or_else(|| "not read".into()),
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
            format!("{} passed, {} failed", r.checks_passed(), r.checks_failed()),
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
    let failed: Vec<&CheckResult> = r.checks.iter().filter(|c| !c.passed).collect();
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

/// A check's name without its limits (they have their own column).
fn check_title(c: &CheckResult) -> String {
    stable_check_name(&c.name, c.object.as_deref(), c.statistic.as_deref())
}

/// Decimals that show one count of the dictionary's resolution: 0.001 → 3, 1 → 0.
pub fn decimals(resolution: f64) -> usize {
    if !(resolution.is_finite() && resolution > 0.0) {
        return 3;
    }
    (-(resolution.log10() + 1e-9).floor()).clamp(0.0, 9.0) as usize
}

/// `v` with its unit at the resolution of `object` (three decimals when unknown, trailing
/// zeros dropped then).
fn value_text(r: &RunReport, object: Option<&str>, v: f64, unit: Option<&str>) -> String {
    let text = match object.and_then(|o| r.resolution(o)) {
        Some(res) => format!("{v:.*}", decimals(res)),
        None => number((v * 1000.0).round() / 1000.0),
    };
    match unit {
        Some(u) => format!("{text} {u}"),
        None => text,
    }
}

fn measured_cell(r: &RunReport, c: &CheckResult) -> String {
    match (c.measured, &c.measured_text) {
        (Some(v), _) => value_text(r, c.object.as_deref(), v, c.unit.as_deref()),
        (None, Some(t)) => t.clone(),
        (None, None) => "—".into(),
    }
}

/// `speed-stage.yaml:15:5` for `/long/path/includes/speed-stage.yaml:15:5`: the page is
/// read beside the recipe; the full place is in the cell's title.
fn short_origin(origin: &str) -> String {
    origin.rsplit('/').next().unwrap_or(origin).to_string()
}

/// Limits as the recipe wrote them (no padding to the resolution).
fn limits_cell(_r: &RunReport, c: &CheckResult) -> String {
    let v = |x: f64| number(x);
    let u = c.unit.as_deref().map(|u| format!(" {u}")).unwrap_or_default();
    match (c.low, c.high) {
        (Some(lo), Some(hi)) if lo == hi => format!("= {}{u}", v(lo)),
        (Some(lo), Some(hi)) => format!("{} .. {}{u}", v(lo), v(hi)),
        (Some(lo), None) => format!("> {}{u}", v(lo)),
        (None, Some(hi)) => format!("< {}{u}", v(hi)),
        (None, None) => "—".into(),
    }
}

fn checks(h: &mut String, r: &RunReport) {
    h.push_str("<section id=\"checks\">\n<h2>Checks</h2>\n");
    if r.checks.is_empty() {
        h.push_str("<p>The recipe has no checks.</p>\n</section>\n");
        return;
    }
    h.push_str(
        "<table>\n<colgroup><col style=\"width:23%\"><col style=\"width:15%\"><col style=\"width:19%\">\
         <col style=\"width:9%\"><col style=\"width:21%\"><col style=\"width:13%\"></colgroup>\n\
         <thead><tr><th>Check</th><th>Measured</th><th>Limits</th><th>Result</th>\
         <th>Details</th><th>Where</th></tr></thead>\n<tbody>\n",
    );
    // Grouped by stage as they ran (a new group where the stage changes); names unique
    // within their stage.
    let mut groups: Vec<(&str, Vec<&CheckResult>)> = Vec::new();
    for c in &r.checks {
        match groups.last_mut() {
            Some((stage, list)) if *stage == c.stage => list.push(c),
            _ => groups.push((&c.stage, vec![c])),
        }
    }
    for (stage, group) in groups {
        let mut names = UniqueNames::default();
        if !stage.is_empty() {
            let failed = group.iter().filter(|c| !c.passed).count();
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
        for c in group {
            let (row, mark) = if c.passed {
                ("pass", "<span class=\"ok\">PASS</span>")
            } else {
                ("fail", "<span class=\"fail\">FAIL</span>")
            };
            let _ = writeln!(
                h,
                "<tr class=\"{row}\"><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                 <td>{mark}</td><td>{}</td><td><code title=\"{}\">{}</code></td></tr>",
                esc(&names.unique(check_title(c))),
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
    h.push_str("<section id=\"steps\">\n<h2>Steps</h2>\n");
    if r.steps.is_empty() {
        h.push_str("<p>No step ran.</p>\n</section>\n");
        return;
    }
    h.push_str(
        "<table>\n<colgroup><col style=\"width:7%\"><col style=\"width:8%\"><col style=\"width:24%\">\
         <col style=\"width:10%\"><col style=\"width:25%\"><col style=\"width:13%\"><col style=\"width:13%\"></colgroup>\n\
         <thead><tr><th>#</th><th>Phase</th><th>Step</th><th>Result</th><th>Detail</th>\
         <th>Start</th><th>Duration</th></tr></thead>\n<tbody>\n",
    );
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

/// Whether a check's limits are levels of the plotted value (the value itself, its mean,
/// min or max) rather than of a statistic about its spread (ripple, std), which is shown
/// as text under the plot.
fn is_level(c: &CheckResult) -> bool {
    matches!(c.statistic.as_deref(), None | Some("mean" | "min" | "max"))
}

fn plots(h: &mut String, r: &RunReport) {
    if r.series.is_empty() {
        return;
    }
    h.push_str("<section id=\"plots\">\n<h2>Sampled values</h2>\n");
    for (i, s) in r.series.iter().enumerate() {
        // Only the checks computed over this very window.
        let window: Vec<&CheckResult> = r
            .checks
            .iter()
            .filter(|c| {
                c.object.as_deref() == Some(s.object.as_str()) && c.window.as_deref() == Some(s.step.as_str())
            })
            .collect();
        let levels: Vec<&CheckResult> = window.iter().copied().filter(|c| is_level(c)).collect();
        h.push_str("<figure>\n");
        h.push_str(&plot_svg(s, &levels, i));
        let shown = downsample(&finite(&s.points)).len();
        let how = if shown < s.points.len() {
            format!(
                "{shown} of {} points shown (min and max of each interval)",
                s.points.len()
            )
        } else {
            format!("{} points", s.points.len())
        };
        let _ = writeln!(
            h,
            "<figcaption>{} sampled by step {}: {}{}",
            esc(&axis_title(&s.object, s.unit.as_deref())),
            esc(&s.step),
            esc(&how),
            esc(&stats_text(r, s))
        );
        let spread: Vec<&CheckResult> = window.iter().copied().filter(|c| !is_level(c)).collect();
        if !spread.is_empty() {
            h.push_str("<ul class=\"stat-checks\">\n");
            for c in spread {
                let mark = if c.passed {
                    "<span class=\"ok\">PASS</span>"
                } else {
                    "<span class=\"fail\">FAIL</span>"
                };
                let _ = writeln!(
                    h,
                    "<li>{mark} {}: {} (limits {})</li>",
                    esc(&check_title(c)),
                    esc(&measured_cell(r, c)),
                    esc(&limits_cell(r, c))
                );
            }
            h.push_str("</ul>\n");
        }
        h.push_str("</figcaption>\n</figure>\n");
    }
    h.push_str("</section>\n");
}

fn stats_text(r: &RunReport, s: &Series) -> String {
    let values: Vec<f64> = finite(&s.points).iter().map(|p| p.1).collect();
    if values.is_empty() {
        return String::new();
    }
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let u = s.unit.as_deref();
    let v = |x: f64| value_text(r, Some(&s.object), x, u);
    format!("; min {}, mean {}, max {}", v(min), v(mean), v(max))
}

// Plot geometry (SVG user units).
const W: f64 = 760.0;
const H: f64 = 320.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 165.0;
const TOP: f64 = 16.0;
const BOTTOM: f64 = 52.0;

/// An SVG line plot of a series with the limits of `checks`. The polyline's `points` hold
/// the data itself (time in s, value); a transform maps them onto the plot area.
pub fn plot_svg(series: &Series, checks: &[&CheckResult], id: usize) -> String {
    let mut s = String::new();
    let title = axis_title(&series.object, series.unit.as_deref());
    let _ = writeln!(
        s,
        "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {W} {H}\" \
         font-family=\"Helvetica, Arial, sans-serif\" font-size=\"11\" \
         width=\"{W}\" height=\"{H}\" role=\"img\" aria-label=\"{}\">",
        esc(&format!("{title} over time"))
    );
    let _ = writeln!(s, "<title>{}</title>", esc(&format!("{title} over time")));
    let points = finite(&series.points);
    if points.is_empty() {
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no samples</text>\n</svg>",
            W / 2.0,
            H / 2.0
        );
        return s;
    }
    // Limits of the checks on this object: (value, label), each value once.
    let mut limits: Vec<(f64, String)> = Vec::new();
    for c in checks {
        let stat = c.statistic.clone().map(|s| format!("{s} ")).unwrap_or_default();
        let u = c.unit.as_deref().or(series.unit.as_deref());
        let marks: Vec<(f64, String)> = match (c.low, c.high) {
            (Some(lo), Some(hi)) if lo == hi => vec![(lo, format!("{stat}= {}", with_unit(lo, u)))],
            (lo, hi) => lo
                .map(|v| (v, format!("{stat}≥ {}", with_unit(v, u))))
                .into_iter()
                .chain(hi.map(|v| (v, format!("{stat}≤ {}", with_unit(v, u)))))
                .collect(),
        };
        for (v, label) in marks {
            if v.is_finite() && !limits.iter().any(|(w, _)| *w == v) {
                limits.push((v, label));
            }
        }
    }

    let (t0, t1) = padded_range(points.iter().map(|p| p.0), 0.0);
    // The data decides the range; a limit close to it widens it, one far off is marked at
    // the edge, so ±0.5 % of data never shrinks to a flat line under a distant limit.
    let (d0, d1) = padded_range(points.iter().map(|p| p.1), 0.05);
    let reach = (d1 - d0) * 0.5;
    let near: Vec<f64> = limits
        .iter()
        .map(|l| l.0)
        .filter(|v| *v >= d0 - reach && *v <= d1 + reach)
        .collect();
    let (v0, v1) = if near.is_empty() {
        (d0, d1)
    } else {
        padded_range(points.iter().map(|p| p.1).chain(near.iter().copied()), 0.05)
    };
    let (x_left, x_right, y_top, y_bottom) = (LEFT, W - RIGHT, TOP, H - BOTTOM);
    let sx = (x_right - x_left) / (t1 - t0);
    let sy = (y_bottom - y_top) / (v1 - v0);
    let x = |t: f64| x_left + (t - t0) * sx;
    let y = |v: f64| y_bottom - (v - v0) * sy;

    // Grid and tick labels.
    let (time_unit, time_div) = time_unit(t1 - t0);
    for tick in ticks(t0 / time_div, t1 / time_div) {
        let px = x(tick * time_div);
        let _ = writeln!(
            s,
            "<line class=\"grid\" stroke=\"#ddd\" x1=\"{px:.2}\" y1=\"{y_top}\" x2=\"{px:.2}\" y2=\"{y_bottom}\"/>\
             <text x=\"{px:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            y_bottom + 16.0,
            number(round_to(tick, 9))
        );
    }
    for tick in ticks(v0, v1) {
        let py = y(tick);
        let _ = writeln!(
            s,
            "<line class=\"grid\" stroke=\"#ddd\" x1=\"{x_left}\" y1=\"{py:.2}\" x2=\"{x_right}\" y2=\"{py:.2}\"/>\
             <text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
            x_left - 6.0,
            py + 4.0,
            number(round_to(tick, 9))
        );
    }
    // Axes and their titles.
    let _ = writeln!(
        s,
        "<line class=\"axis\" stroke=\"#111\" x1=\"{x_left}\" y1=\"{y_bottom}\" x2=\"{x_right}\" y2=\"{y_bottom}\"/>\
         <line class=\"axis\" stroke=\"#111\" x1=\"{x_left}\" y1=\"{y_top}\" x2=\"{x_left}\" y2=\"{y_bottom}\"/>"
    );
    let _ = writeln!(
        s,
        "<text class=\"axis-title\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">time [{time_unit}]</text>",
        (x_left + x_right) / 2.0,
        H - 12.0
    );
    let (tx, ty) = (16.0, (y_top + y_bottom) / 2.0);
    let _ = writeln!(
        s,
        "<text class=\"axis-title\" x=\"{tx}\" y=\"{ty:.2}\" text-anchor=\"middle\" \
         transform=\"rotate(-90 {tx} {ty:.2})\">{}</text>",
        esc(&title)
    );

    // The data, clipped to the plot area, in data coordinates.
    let _ = writeln!(
        s,
        "<clipPath id=\"plot-area-{id}\"><rect x=\"{x_left}\" y=\"{y_top}\" width=\"{:.2}\" height=\"{:.2}\"/></clipPath>",
        x_right - x_left,
        y_bottom - y_top
    );
    let _ = write!(
        s,
        "<g clip-path=\"url(#plot-area-{id})\">\n<polyline class=\"data\" fill=\"none\" stroke=\"#1f4fa0\" stroke-width=\"1.5\" \
         vector-effect=\"non-scaling-stroke\" \
         transform=\"matrix({sx} 0 0 {} {} {})\" points=\"",
        -sy,
        x_left - t0 * sx,
        y_bottom + v0 * sy
    );
    for (k, (t, v)) in downsample(&points).iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{},{}", number(*t), number(*v));
    }
    s.push_str("\"/>\n");
    // Limits: dashed lines across inside the range, labelled on the right; a limit outside
    // the range is a label at the edge it lies beyond, with an arrow.
    for (v, _) in limits.iter().filter(|(v, _)| (v0..=v1).contains(v)) {
        let py = y(*v);
        let _ = writeln!(
            s,
            "<line class=\"limit\" stroke=\"#b00000\" stroke-dasharray=\"6 4\" x1=\"{x_left}\" y1=\"{py:.2}\" x2=\"{x_right}\" y2=\"{py:.2}\"/>"
        );
    }
    s.push_str("</g>\n");
    let mut labels: Vec<(f64, String)> = limits
        .iter()
        .map(|(v, label)| {
            if *v > v1 {
                (y_top + 4.0, format!("↑ {label}"))
            } else if *v < v0 {
                (y_bottom, format!("↓ {label}"))
            } else {
                (y(*v) + 4.0, label.clone())
            }
        })
        .collect();
    spread_labels(&mut labels, 13.0, y_top + 4.0, y_bottom);
    for (py, label) in &labels {
        let _ = writeln!(
            s,
            "<text class=\"limit-label\" fill=\"#b00000\" x=\"{:.2}\" y=\"{py:.2}\">{}</text>",
            x_right + 4.0,
            esc(label)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// Moves label baselines apart so that no two are closer than `gap`, keeping them between
/// `top` and `bottom` where there is room; the order of the labels is kept.
pub fn spread_labels(labels: &mut [(f64, String)], gap: f64, top: f64, bottom: f64) {
    labels.sort_by(|a, b| a.0.total_cmp(&b.0));
    for i in 1..labels.len() {
        if labels[i].0 < labels[i - 1].0 + gap {
            labels[i].0 = labels[i - 1].0 + gap;
        }
    }
    // Pushed past the bottom: shift the whole stack up as far as the top allows.
    if let Some(last) = labels.last().map(|l| l.0) {
        let over = (last - bottom).max(0.0);
        let room = labels.first().map_or(0.0, |l| (l.0 - top).max(0.0));
        let shift = over.min(room);
        for l in labels.iter_mut() {
            l.0 -= shift;
        }
        for i in (0..labels.len().saturating_sub(1)).rev() {
            if labels[i].0 > labels[i + 1].0 - gap {
                labels[i].0 = labels[i + 1].0 - gap;
            }
        }
    }
}

fn finite(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(t, v)| t.is_finite() && v.is_finite())
        .collect()
}

/// At most [`MAX_PLOT_POINTS`] points: all of them, or per bucket of consecutive points
/// its minimum and maximum in time order, so peaks stay visible.
pub fn downsample(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if points.len() <= MAX_PLOT_POINTS {
        return points.to_vec();
    }
    let buckets = MAX_PLOT_POINTS / 2;
    let mut out = Vec::with_capacity(MAX_PLOT_POINTS);
    for b in 0..buckets {
        let start = b * points.len() / buckets;
        let end = ((b + 1) * points.len() / buckets).min(points.len());
        let chunk = &points[start..end];
        if chunk.is_empty() {
            continue;
        }
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[lo].1 {
                lo = i;
            }
            if p.1 > chunk[hi].1 {
                hi = i;
            }
        }
        let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(chunk[a]);
        if b != a {
            out.push(chunk[b]);
        }
    }
    out
}

/// The range of `values`, widened by `pad` of its width on each side; never empty.
fn padded_range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() || !hi.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo <= f64::EPSILON * hi.abs().max(1.0) {
        let half = (lo.abs() * 0.01).max(0.5);
        return (lo - half, hi + half);
    }
    let margin = (hi - lo) * pad;
    (lo - margin, hi + margin)
}

/// Four to nine round tick values (1, 2 or 5 × 10^n apart) inside `lo..=hi`.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let raw = (hi - lo) / 8.0;
    if raw <= 0.0 || !raw.is_finite() {
        return vec![lo];
    }
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn round_to(v: f64, decimals: i32) -> f64 {
    let f = 10f64.powi(decimals);
    (v * f).round() / f
}

/// Seconds for short series, minutes or hours for run-ins.
fn time_unit(span_s: f64) -> (&'static str, f64) {
    if span_s > 3.0 * 3600.0 {
        ("h", 3600.0)
    } else if span_s > 600.0 {
        ("min", 60.0)
    } else {
        ("s", 1.0)
    }
}

fn axis_title(object: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{object} [{u}]"),
        None => object.to_string(),
    }
}

/// One format for every duration and time of the page: `0:01:05.250` (h:mm:ss.mmm).
pub fn duration_text(d: Duration) -> String {
    let ms = d.as_millis();
    let (h, rest) = (ms / 3_600_000, ms % 3_600_000);
    let (m, rest) = (rest / 60_000, rest % 60_000);
    format!("{h}:{m:02}:{:02}.{:03}", rest / 1000, rest % 1000)
}

/// Text for HTML content and attribute values.
pub fn esc(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_series_are_downsampled_keeping_peaks() {
        let mut points: Vec<(f64, f64)> = (0..100_000).map(|i| (f64::from(i) * 0.01, 1.0)).collect();
        points[54_321].1 = 99.0;
        points[77_777].1 = -42.0;
        let d = downsample(&points);
        assert!(
            d.len() <= MAX_PLOT_POINTS && d.len() > MAX_PLOT_POINTS / 2,
            "{}",
            d.len()
        );
        assert!(d.contains(&points[54_321]) && d.contains(&points[77_777]));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0), "in time order");
    }

    #[test]
    fn values_durations_and_labels() {
        assert_eq!(
            (decimals(0.001), decimals(0.1), decimals(1.0), decimals(10.0)),
            (3, 1, 0, 0)
        );
        assert_eq!(duration_text(Duration::from_millis(250)), "0:00:00.250");
        assert_eq!(duration_text(Duration::from_millis(8_465_007)), "2:21:05.007");
        let mut labels: Vec<(f64, String)> = [(100.0, "a"), (101.0, "b"), (99.0, "c"), (300.0, "d")]
            .map(|(y, l)| (y, l.to_string()))
            .into();
        spread_labels(&mut labels, 13.0, 20.0, 300.0);
        let ys: Vec<f64> = labels.iter().map(|l| l.0).collect();
        assert!(ys.windows(2).all(|w| w[1] - w[0] >= 13.0 - 1e-9), "{ys:?}");
        assert!(ys.iter().all(|y| (20.0..=300.0).contains(y)), "{ys:?}");
        assert_eq!(labels[0].1, "c", "order kept");
    }

    #[test]
    fn ticks_are_round() {
        assert_eq!(ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(
            ticks(5967.0, 6033.0),
            vec![5970.0, 5980.0, 5990.0, 6000.0, 6010.0, 6020.0, 6030.0]
        );
        assert_eq!(
            esc("<a href='x'>&\"</a>"),
            "&lt;a href=&#39;x&#39;&gt;&amp;&quot;&lt;/a&gt;"
        );
    }
}
