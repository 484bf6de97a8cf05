//! `results trend CHECK --html FILE`: one check's measured value across runs as an SVG
//! plot over time (dates when the runs span days, else the time since the first) — a
//! marker per run, coloured by unit among few, a failed or marginal run as the run report
//! marks it — with the limits each run had (a tick across each run's marker, a step line
//! where they were changed), and a
//! table of every value. The run report's style; self-contained and bounded: at most
//! [`MAX_PLOT_POINTS`] values, the newest, saying what is left out.

use super::stored_run::stored_limits;
use super::{PageLinks, TrendPoint};
use crate::report::{
    esc, trend_svg, unit_colour, LimitLine, Outcome, TrendMark, TrendPlot, MAX_PLOT_POINTS, REPORT_CSS,
    UNIT_COLOURS,
};
use crate::session::Limits;
use crate::session::COMPARED;
use std::fmt::Write as _;
use std::time::UNIX_EPOCH;

/// A stored UTC time as seconds since 1970 (`None` if it cannot be read).
fn seconds_of(utc: &str) -> Option<f64> {
    let at = humantime::parse_rfc3339_weak(utc).ok()?;
    Some(at.duration_since(UNIX_EPOCH).ok()?.as_secs_f64())
}

#[derive(Clone, Copy)]
enum Side {
    Low,
    High,
}

/// The `side` limit of every point as a line over the runs' times: each run's value from
/// its start on (the first's from the left edge), a value unchanged since the run before
/// drawn on, so a limit no run changed is a line across; labelled as the last run that
/// had one wrote it. `None` when no run had one.
fn limit_line(points: &[TrendPoint], side: Side) -> Option<LimitLine> {
    let limit = |p: &TrendPoint| match side {
        Side::Low => p.check.limits.low,
        Side::High => p.check.limits.high,
    };
    let mut steps: Vec<(f64, Option<f64>)> = Vec::new();
    for p in points {
        let Some(t) = seconds_of(&p.run.started_at) else {
            continue;
        };
        if steps.last().is_none_or(|last| last.1 != limit(p)) {
            steps.push((t, limit(p)));
        }
    }
    let last = points.iter().rev().find(|p| limit(p).is_some())?;
    let one_side = match side {
        Side::Low => Limits::new(last.check.limits.low, None),
        Side::High => Limits::new(None, last.check.limits.high),
    };
    let c = &last.check;
    let label = stored_limits(&c.name, last.key(), one_side, c.unit.as_deref(), c.inclusive)?;
    // The first run's limit reaches back to the plot's left edge.
    if let Some(start) = steps.first_mut() {
        start.0 = f64::NEG_INFINITY;
    }
    Some(LimitLine { steps, label })
}

/// The value axis' title: the unit (`[K]`), a comparison's `change [%]`.
fn value_title(points: &[TrendPoint]) -> String {
    let mut units: Vec<&str> = Vec::new();
    for u in points
        .iter()
        .filter(|p| p.check.measured.is_some())
        .filter_map(|p| p.check.unit.as_deref())
    {
        if !units.contains(&u) {
            units.push(u);
        }
    }
    let change = points.iter().any(|p| p.check.name.ends_with(COMPARED));
    match (units.is_empty(), change) {
        (true, true) => "change".into(),
        (true, false) => "value".into(),
        (false, true) => format!("change [{}]", units.join(", ")),
        (false, false) => format!("[{}]", units.join(", ")),
    }
}

/// The units (serials) of `points` in the order they first appear.
fn units_of(points: &[TrendPoint]) -> Vec<&str> {
    let mut units: Vec<&str> = Vec::new();
    for p in points {
        let serial = serial_text(p);
        if !units.contains(&serial) {
            units.push(serial);
        }
    }
    units
}

fn serial_text(p: &TrendPoint) -> &str {
    p.run.unit.serial.as_deref().unwrap_or("no serial")
}

/// A marker per point that measured a value at a readable time.
fn marks(points: &[TrendPoint], units: &[&str]) -> Vec<TrendMark> {
    points
        .iter()
        .filter_map(|p| {
            Some(TrendMark {
                at: seconds_of(&p.run.started_at)?,
                value: p.check.measured.filter(|v| v.is_finite())?,
                outcome: match (p.check.passed, p.check.marginal) {
                    (true, false) => Outcome::Passed,
                    (true, true) => Outcome::Marginal,
                    (false, _) => Outcome::Failed,
                },
                unit: units.iter().position(|u| *u == serial_text(p)).unwrap_or(0),
                tip: format!(
                    "{} · {} · {}{} · {} · run {}",
                    p.run.started_at,
                    serial_text(p),
                    p.measured_text(),
                    p.limits_text()
                        .map_or(String::new(), |l| format!(" (limits {l})")),
                    p.verdict(),
                    p.run.id
                ),
                limits: (p.check.limits.low, p.check.limits.high),
            })
        })
        .collect()
}

/// The page of the trend of `check` (as asked for: a key or a check's full name).
pub fn trend_page(check: &str, all: &[TrendPoint], links: PageLinks) -> String {
    // The check's key when every point shares it: what the page is the trend of.
    let title = match all.first() {
        Some(p) if all.iter().all(|q| q.key() == p.key()) => p.key().to_string(),
        _ => check.to_string(),
    };
    let points = &all[all.len().saturating_sub(MAX_PLOT_POINTS)..];
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"generator\" content=\"drivescript {}\">\n<title>Trend of {}</title>\n\
         <style>{REPORT_CSS}</style>\n</head>\n<body>\n{}<header>\n<h1>Trend of {}</h1>\n",
        env!("CARGO_PKG_VERSION"),
        esc(&title),
        links.nav(),
        esc(&title)
    );
    let units = units_of(points);
    let mut runs: Vec<&str> = points.iter().map(|p| p.run.id.as_str()).collect();
    runs.dedup();
    let count = |f: fn(&TrendPoint) -> bool| points.iter().filter(|p| f(p)).count();
    let _ = writeln!(
        h,
        "<p class=\"why\">{} value(s) from {} run(s) of {} unit(s); {} failed, {} marginal.</p>",
        points.len(),
        runs.len(),
        units.len(),
        count(|p| !p.check.passed),
        count(|p| p.check.passed && p.check.marginal)
    );
    let left = &all[..all.len() - points.len()];
    if let (Some(oldest), Some(newest)) = (left.first(), left.last()) {
        let _ = writeln!(
            h,
            "<p class=\"why\">Only the newest {} of {} values are shown: the {} from {} to {} are left out. Narrow the trend with <code>--since</code>, <code>--unit</code> or <code>--limit</code>.</p>",
            points.len(),
            all.len(),
            left.len(),
            esc(&oldest.run.started_at),
            esc(&newest.run.started_at)
        );
    }
    h.push_str("</header>\n");
    let limits: Vec<LimitLine> = [Side::Low, Side::High]
        .into_iter()
        .filter_map(|side| limit_line(points, side))
        .collect();
    let marks = marks(points, &units);
    let svg = trend_svg(&TrendPlot {
        marks: &marks,
        units: units.len(),
        value_title: &value_title(points),
        limits: &limits,
        label: &format!("{title} per run over time"),
    });
    let _ = writeln!(
        h,
        "<section>\n<h2>Plot</h2>\n<figure>{svg}<figcaption>{} per run: {} marker(s), a square for a failed run, a diamond for a marginal one; runs that measured nothing (a comparison without history) have none. {}Dashed: the limits each run had.{}</figcaption></figure>\n</section>",
        esc(&title),
        marks.len(),
        if units.len() > UNIT_COLOURS.len() {
            format!("{} units in one colour, without lines. ", units.len())
        } else {
            "A thin line joins each unit's runs. ".into()
        },
        legend(&units)
    );
    h.push_str("<section>\n<h2>Values</h2>\n<table id=\"values\">\n<thead><tr><th>Started (UTC)</th><th>Unit</th><th>Measured</th><th>Limits</th><th>Result</th><th>Run</th></tr></thead>\n<tbody>\n");
    for p in points {
        let (row, mark) = match (p.check.passed, p.check.marginal) {
            (true, false) => ("", "ok"),
            (true, true) => (" class=\"marginal\"", "warn"),
            (false, _) => (" class=\"fail\"", "fail"),
        };
        let _ = writeln!(
            h,
            "<tr{row}><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"{mark}\">{}</td><td>{}</td></tr>",
            esc(&p.run.started_at),
            p.run.unit.serial
                .as_deref()
                .map_or(String::new(), |s| links.unit(s, &esc(s))),
            esc(&p.measured_text()),
            esc(&p.limits_text().unwrap_or_else(|| "—".into())),
            p.result_text(),
            links.run(&p.run.id, &format!("<code>{}</code>", esc(&p.run.id)))
        );
    }
    let _ = write!(
        h,
        "</tbody>\n</table>\n</section>\n<footer>Written by drivescript {} from its results store.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}

/// ` Units: ● SP-1 ● SP-2` in their colours, when there are several and each has one.
fn legend(units: &[&str]) -> String {
    if units.len() < 2 || units.len() > UNIT_COLOURS.len() {
        return String::new();
    }
    let mut s = String::from(" Units:");
    for (i, u) in units.iter().enumerate() {
        let _ = write!(
            s,
            " <span class=\"unit-key\" style=\"color:{}\">●</span>&#8239;{}",
            unit_colour(i, units.len()),
            esc(u)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{CheckRow, RunRow};
    use crate::session::UnitIdentity;

    fn point(started_at: &str, serial: &str, measured: Option<f64>, passed: bool) -> TrendPoint {
        TrendPoint {
            check: CheckRow {
                run: format!("run-{started_at}"),
                name: "bearing temperature compared with last pass".into(),
                key: Some("bearing temperature compared with last pass".into()),
                measured,
                unit: Some("K".into()),
                limits: Limits::new(None, Some(3.0)),
                passed,
                step: "2".into(),
                ..CheckRow::default()
            },
            run: RunRow {
                id: format!("run-{started_at}"),
                started_at: started_at.into(),
                unit: UnitIdentity {
                    serial: Some(serial.into()),
                    ..UnitIdentity::default()
                },
                recipe: "Bearing acceptance".into(),
                ..RunRow::default()
            },
        }
    }

    /// `p` with its check changed by `change`.
    fn with_check(p: &TrendPoint, change: impl FnOnce(CheckRow) -> CheckRow) -> TrendPoint {
        TrendPoint {
            check: change(p.check.clone()),
            ..p.clone()
        }
    }

    #[test]
    fn a_comparison_reads_as_a_signed_change_with_limits_in_its_unit() {
        let p = point("2026-11-25T05:02:55.544Z", "SP-1", Some(7.3), false);
        assert_eq!(p.measured_text(), "+7.3 K");
        assert_eq!(p.limits_text().as_deref(), Some("≤ 3 K"));
        assert_eq!(p.verdict(), "FAIL");
        let fell = with_check(&p, |c| CheckRow {
            measured: Some(-0.25),
            limits: Limits::new(Some(-10.0), Some(10.0)),
            unit: Some("%".into()),
            ..c
        });
        assert_eq!(fell.measured_text(), "-0.25 %");
        assert_eq!(fell.limits_text().as_deref(), Some("-10 .. 10 %"));
        let plain = with_check(&p, |c| CheckRow {
            name: "motor_temperature below 80 °C".into(),
            measured: Some(31.4),
            unit: Some("°C".into()),
            ..c
        });
        assert_eq!(plain.measured_text(), "31.4 °C");
        let none = with_check(&p, |c| CheckRow { measured: None, ..c });
        assert_eq!(none.measured_text(), "—");
        assert_eq!(value_title(std::slice::from_ref(&none)), "change");
        assert_eq!(value_title(&[fell, none]), "change [%]");
        assert_eq!(value_title(&[plain]), "[°C]");
    }

    #[test]
    fn the_page_draws_a_marker_per_measured_run_and_keeps_the_newest_when_bounded() {
        let points = [
            point("2026-01-05T08:00:00.000Z", "SP-1", None, true),
            point("2026-02-05T08:00:00.000Z", "SP-1", Some(1.0), true),
            point("2026-03-05T08:00:00.000Z", "SP-2", Some(7.3), false),
        ];
        let page = trend_page(
            "bearing temperature compared with last pass",
            &points,
            PageLinks::None,
        );
        assert_eq!(
            page.matches("class=\"mark ").count(),
            2,
            "no marker without a value"
        );
        assert_eq!(
            page.matches("class=\"run-limit\"").count(),
            2,
            "each measured run's own limit across its marker"
        );
        assert!(page.contains("<td class=\"num\">+7.3 K</td><td class=\"num\">≤ 3 K</td>"));
        assert!(
            page.contains(">change [K]</text>") && page.contains(">2026-02-16</text>"),
            "{page}"
        );
        assert!(page.contains("Units:") && page.contains("SP-2"));
        assert!(!page.contains("left out"));
        let many: Vec<TrendPoint> = (0..MAX_PLOT_POINTS + 5)
            .map(|k| {
                point(
                    &format!("2026-01-01T{:02}:{:02}:{:02}.000Z", k / 3600, k / 60 % 60, k % 60),
                    "SP-1",
                    Some(1.0),
                    true,
                )
            })
            .collect();
        let page = trend_page("x", &many, PageLinks::None);
        assert_eq!(page.matches("class=\"mark ").count(), MAX_PLOT_POINTS);
        assert!(page.contains(&format!(
            "Only the newest {MAX_PLOT_POINTS} of {} values are shown: the 5 from 2026-01-01T00:00:00.000Z to 2026-01-01T00:00:04.000Z are left out.",
            MAX_PLOT_POINTS + 5
        )), "{}", &page[..3000]);
        assert!(!page.contains("<script") && !page.contains("src=") && !page.contains("href="));
    }
}
