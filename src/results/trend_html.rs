//! `results trend CHECK --html FILE`: one check's measured value across runs as an SVG
//! plot over time (since the first run shown) with the limits each run had (a step line
//! where they were changed), and a table of every point. The run report's style and plot;
//! self-contained.

use super::TrendPoint;
use crate::report::{esc, plot_svg_with_limits, LimitLine, REPORT_CSS};
use crate::session::{with_unit, Series};
use std::fmt::Write as _;

/// Seconds between two stored UTC times (`None` if either cannot be read).
fn seconds_between(from: &str, to: &str) -> Option<f64> {
    let a = humantime::parse_rfc3339_weak(from).ok()?;
    let b = humantime::parse_rfc3339_weak(to).ok()?;
    Some(b.duration_since(a).unwrap_or_default().as_secs_f64())
}

#[derive(Clone, Copy)]
enum Side {
    Low,
    High,
}

/// The `side` limit of every point as a line over the plot's time: each run's value from
/// its start on (the first's from the left edge), a value unchanged since the run before
/// drawn on, so a limit no run changed is a line across. `None` when no run had one.
fn limit_line(
    points: &[TrendPoint],
    first: &str,
    side: Side,
    sign: &str,
    unit: Option<&str>,
) -> Option<LimitLine> {
    let mut steps: Vec<(f64, Option<f64>)> = Vec::new();
    for p in points {
        let Some(t) = seconds_between(first, &p.started_at) else {
            continue;
        };
        let v = match side {
            Side::Low => p.low,
            Side::High => p.high,
        };
        if steps.last().is_none_or(|last| last.1 != v) {
            steps.push((t, v));
        }
    }
    let last = steps.iter().rev().find_map(|s| s.1)?;
    // The first run's limit reaches back to the plot's left edge.
    if let Some(start) = steps.first_mut() {
        start.0 = f64::NEG_INFINITY;
    }
    Some(LimitLine {
        steps,
        label: format!("{sign} {}", with_unit(last, unit)),
    })
}

/// The page of the trend of `check` (as asked for: a key or a check's full name).
pub fn trend_page(check: &str, points: &[TrendPoint]) -> String {
    // The check's key when every point shares it: what the page is the trend of.
    let title = match points.first() {
        Some(p) if points.iter().all(|q| q.key == p.key) => p.key.clone(),
        _ => check.to_string(),
    };
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"generator\" content=\"drivescript {}\">\n<title>Trend of {}</title>\n\
         <style>{REPORT_CSS}</style>\n</head>\n<body>\n<header>\n<h1>Trend of {}</h1>\n",
        env!("CARGO_PKG_VERSION"),
        esc(&title),
        esc(&title)
    );
    let failed = points.iter().filter(|p| !p.passed).count();
    let _ = writeln!(
        h,
        "<p class=\"why\">{} value(s) from {} run(s); {failed} failed.</p>\n</header>",
        points.len(),
        {
            let mut runs: Vec<&str> = points.iter().map(|p| p.run.as_str()).collect();
            runs.dedup();
            runs.len()
        }
    );
    let first = points.first().map(|p| p.started_at.clone()).unwrap_or_default();
    let unit = points.iter().find_map(|p| p.unit.clone());
    let series = Series {
        object: title.clone(),
        unit: unit.clone(),
        step: String::new(),
        points: points
            .iter()
            .filter_map(|p| Some((seconds_between(&first, &p.started_at)?, p.measured?)))
            .collect(),
        samples: None,
        marks: None,
    };
    let limits: Vec<LimitLine> = [("≥", Side::Low), ("≤", Side::High)]
        .into_iter()
        .filter_map(|(sign, side)| limit_line(points, &first, side, sign, unit.as_deref()))
        .collect();
    let _ = writeln!(
        h,
        "<section>\n<h2>Plot</h2>\n<figure>{}<figcaption>{} per run, over the time since the first run shown ({}); dashed: the limits each run had.</figcaption></figure>\n</section>",
        plot_svg_with_limits(&series, &limits, 1),
        esc(&title),
        esc(&first)
    );
    h.push_str("<section>\n<h2>Values</h2>\n<table id=\"values\">\n<thead><tr><th>Started (UTC)</th><th>Unit</th><th>Measured</th><th>Limits</th><th>Result</th><th>Run</th></tr></thead>\n<tbody>\n");
    for p in points {
        let limits = match (p.low, p.high) {
            (Some(lo), Some(hi)) => format!("{lo} .. {hi}"),
            (Some(lo), None) => format!("≥ {lo}"),
            (None, Some(hi)) => format!("≤ {hi}"),
            _ => "—".into(),
        };
        let _ = writeln!(
            h,
            "<tr{}><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"{}\">{}</td><td><code>{}</code></td></tr>",
            if p.passed { "" } else { " class=\"fail\"" },
            esc(&p.started_at),
            esc(p.serial.as_deref().unwrap_or("")),
            p.measured.map(|v| esc(&with_unit(v, p.unit.as_deref()))).unwrap_or_else(|| "—".into()),
            esc(&limits),
            if p.passed { "ok" } else { "fail" },
            if p.passed { "PASS" } else { "FAIL" },
            esc(&p.run)
        );
    }
    let _ = write!(
        h,
        "</tbody>\n</table>\n</section>\n<footer>Written by drivescript {} from its results store.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}
