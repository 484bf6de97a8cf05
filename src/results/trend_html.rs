//! `results trend CHECK --html FILE`: one check's measured value across runs as an SVG
//! plot over time (since the first run shown) with its latest limits, and a table of every
//! point. The run report's style and plot; self-contained.

use super::TrendPoint;
use crate::report::{esc, plot_svg, REPORT_CSS};
use crate::session::{with_unit, CheckResult, Series};
use std::fmt::Write as _;

/// Seconds between two stored UTC times (`None` if either cannot be read).
fn seconds_between(from: &str, to: &str) -> Option<f64> {
    let a = humantime::parse_rfc3339_weak(from).ok()?;
    let b = humantime::parse_rfc3339_weak(to).ok()?;
    Some(b.duration_since(a).unwrap_or_default().as_secs_f64())
}

/// The page.
pub fn trend_page(check: &str, points: &[TrendPoint]) -> String {
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"generator\" content=\"drivescript {}\">\n<title>Trend of {}</title>\n\
         <style>{REPORT_CSS}</style>\n</head>\n<body>\n<header>\n<h1>Trend of {}</h1>\n",
        env!("CARGO_PKG_VERSION"),
        esc(check),
        esc(check)
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
        object: check.to_string(),
        unit: unit.clone(),
        step: String::new(),
        points: points
            .iter()
            .filter_map(|p| Some((seconds_between(&first, &p.started_at)?, p.measured?)))
            .collect(),
        samples: None,
        marks: None,
    };
    let latest = points.last();
    let limits = CheckResult {
        unit: unit.clone(),
        low: latest.and_then(|p| p.low),
        high: latest.and_then(|p| p.high),
        object: Some(check.to_string()),
        ..CheckResult::named(check, true)
    };
    let _ = writeln!(
        h,
        "<section>\n<h2>Plot</h2>\n<figure>{}<figcaption>{} per run, over the time since the first run shown ({}); dashed: the latest limits.</figcaption></figure>\n</section>",
        plot_svg(&series, &[&limits], 1),
        esc(check),
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
