//! `--report`: the run report as one HTML page, read back with an HTML5 parser.

use super::markup::{elements, html, inside, rows, select, text, texts};
use super::sample_reports::{error_report, origin, passed_report, step};
use crate::support::{assert_has, succeeded};
use drivescript::report::{html_report, write_html};
use drivescript::session::{CheckResult, Limits, Series};
use scraper::{ElementRef, Html};

const SVG_NAMESPACE: &str = "http://www.w3.org/2000/svg";

fn parse(page: &str) -> Html {
    html(page).unwrap_or_else(|e| panic!("{e}\n{page}"))
}

fn attr(e: &ElementRef, name: &str) -> f64 {
    let value = e
        .attr(name)
        .unwrap_or_else(|| panic!("{} lacks {name}", e.html()));
    value.parse().unwrap_or_else(|_| panic!("{name}={value}"))
}

#[test]
fn the_page_says_what_ran_and_how_it_ended() {
    let r = passed_report();
    let page = html_report(&r);
    let doc = parse(&page);
    assert_eq!(texts(&doc, "h1"), vec!["Spindle <run-in> & \"test\""]);
    assert!(!page.contains("<run-in>"), "the recipe name is escaped");
    assert_eq!(
        texts(&doc, "head > title"),
        vec!["Spindle <run-in> & \"test\" — PASSED"],
        "the page title"
    );
    let verdict = select(&doc, "#verdict")[0];
    assert_eq!(verdict.attr("class"), Some("verdict passed"));
    assert_eq!(text(&verdict), "✔ PASSED");
    let facts = texts(&doc, "td");
    for want in [
        "recipes/run-in.yaml",
        "sd2 at /dev/ttyUSB0, address 2",
        "SD2S 0362150C",
        "speed = 6000 rpm",
        "2024-06-10 06:13:20 UTC",
        "0:01:06.250",
        "PASSED (exit code 0)",
        "switched on",
    ] {
        assert!(facts.iter().any(|f| f == want), "{want} not in {facts:?}");
    }

    let steps = rows(&doc, "steps");
    assert_eq!(steps.len(), r.steps.len());
    assert_eq!(
        steps[2],
        vec![
            "3",
            "steps",
            "sample speed_actual every 100 ms for 60 s",
            "ok",
            "mean 6000.1 rpm",
            "0:00:05.000",
            "0:00:00.250"
        ]
    );
    assert_eq!(steps[4][1], "finally");
    for (row, step) in steps.iter().zip(&r.steps) {
        assert_eq!(row[2], step.label);
    }

    let checks = rows(&doc, "checks");
    assert_eq!(checks.len(), r.checks.len());
    assert_eq!(
        checks[0],
        vec![
            "speed_actual mean near",
            "6000.1 rpm",
            "5970 .. 6030 rpm",
            "PASS",
            "mean 6000.1 rpm",
            "run-in.yaml:20:5"
        ]
    );
    assert_eq!(checks[1][0], "wait until state operation_enabled");
    assert_eq!(checks[1][1], "operation enabled");
    assert_eq!(checks[1][2], "—");

    assert_eq!(texts(&doc, "li"), vec!["finally: disable_operation ran"]);
}

#[test]
fn failures_and_errors_stand_out_and_text_is_escaped() {
    let page = html_report(&error_report());
    let doc = parse(&page);
    let verdict = select(&doc, "#verdict")[0];
    assert_eq!(verdict.attr("class"), Some("verdict error"));
    assert_eq!(text(&verdict), "✘ ERROR");
    assert!(page
        .contains("Communication failure or drive fault: no reply within 100 ms from drive 2 &lt;port&gt;"));
    assert_eq!(
        texts(&doc, "p.why"),
        vec!["Communication failure or drive fault: no reply within 100 ms from drive 2 <port>"]
    );
    assert!(page.contains("speed &amp; &lt;mean&gt;"));
    assert!(!page.contains("<port>") && !page.contains("<mean>"));
    let checks = rows(&doc, "checks");
    assert_eq!(checks[0][0], "speed & <mean>");
    assert_eq!(checks[0][3], "FAIL");
    let steps = rows(&doc, "steps");
    assert_eq!(steps[1][3], "FAIL");
    assert_eq!(steps[1][4], "no reply within 100 ms from drive 2 <port>");
    assert!(page.contains("<tr class=\"fail\">"));
    assert!(!select(&doc, "section#checks tbody > tr.fail").is_empty());
    assert!(page.contains("an unknown state (it could not be read back)"));
    assert!(page.contains("CHECK THE DRIVE BY HAND"));
    // No plot section without series.
    assert!(!page.contains("<svg"));
    assert!(elements(&doc, "svg").is_empty());
}

#[test]
fn one_plot_per_series_with_data_axes_and_limits() {
    let mut r = passed_report();
    // Limits close to the data: drawn as levels inside the range.
    r.checks[0].limits.low = Some(5999.0);
    r.checks[0].limits.high = Some(6001.0);
    let page = html_report(&r);
    let doc = parse(&page);
    assert_eq!(select(&doc, "section#plots svg").len(), 1);
    let polyline = elements(&doc, "polyline")[0];
    assert!(inside(&polyline, "svg"));
    assert_eq!(&*polyline.value().name.ns, SVG_NAMESPACE);
    let points: Vec<(f64, f64)> = polyline
        .attr("points")
        .unwrap()
        .split(' ')
        .map(|p| {
            let (t, v) = p.split_once(',').unwrap();
            (t.parse().unwrap(), v.parse().unwrap())
        })
        .collect();
    // All 601 points, as data (to the 6 decimals written).
    assert_eq!(points.len(), r.series[0].points.len());
    for (got, want) in points.iter().zip(&r.series[0].points) {
        assert!(
            (got.0 - want.0).abs() < 1e-6 && got.1 == want.1,
            "{got:?} vs {want:?}"
        );
    }
    assert_eq!(points[1], (5.1, 5998.75));
    let transform = polyline.attr("transform").unwrap();
    assert!(transform.starts_with("matrix("));

    // Axis titles with units, tick labels.
    let svg_texts: Vec<String> = elements(&doc, "text")
        .iter()
        .filter(|e| inside(e, "svg"))
        .map(text)
        .collect();
    assert!(svg_texts.contains(&"time [s]".to_string()), "{svg_texts:?}");
    assert!(svg_texts.contains(&"speed_actual [rpm]".to_string()));
    for tick in ["10", "20", "30", "40", "50", "60", "5999", "6000", "6001"] {
        assert!(
            svg_texts.contains(&tick.to_string()),
            "tick {tick} in {svg_texts:?}"
        );
    }
    // The check's limits: dashed lines at 5999 and 6001, labelled.
    let limits: Vec<ElementRef> = elements(&doc, "line")
        .into_iter()
        .filter(|e| e.attr("class") == Some("limit"))
        .collect();
    assert_eq!(limits.len(), 2);
    assert!(
        svg_texts.contains(&"mean ≥ 5999 rpm".to_string()),
        "{svg_texts:?}"
    );
    assert!(svg_texts.contains(&"mean ≤ 6001 rpm".to_string()));
    // The lines sit where the polyline's transform puts those values.
    let m: Vec<f64> = transform["matrix(".len()..]
        .trim_end_matches(')')
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    let y_of = |v: f64| m[3] * v + m[5];
    let ys: Vec<f64> = limits.iter().map(|l| attr(l, "y1")).collect();
    assert!((ys[0] - y_of(5999.0)).abs() < 0.01, "{ys:?}");
    assert!((ys[1] - y_of(6001.0)).abs() < 0.01, "{ys:?}");
    // Within the plot area, which the data's clip path declares.
    let area = select(&doc, "clipPath > rect")[0];
    let (top, bottom) = (attr(&area, "y"), attr(&area, "y") + attr(&area, "height"));
    assert_eq!((top, bottom), (16.0, 268.0));
    assert!(ys.iter().all(|y| (top..=bottom).contains(y)), "{ys:?}");
    assert!(page.contains("speed_actual [rpm] sampled by step 3: 601 points"));
}

/// The y range fits the data (±1.5 rpm around 6000), not limits 30 rpm away: those are
/// labels at the edge, with an arrow, and no line.
#[test]
fn far_limits_are_marked_at_the_edge_and_the_data_keeps_the_range() {
    let page = html_report(&passed_report());
    let doc = parse(&page);
    let svg_texts: Vec<String> = elements(&doc, "text")
        .iter()
        .filter(|e| inside(e, "svg"))
        .map(text)
        .collect();
    assert!(
        svg_texts.contains(&"↑ mean ≤ 6030 rpm".to_string()),
        "{svg_texts:?}"
    );
    assert!(
        svg_texts.contains(&"↓ mean ≥ 5970 rpm".to_string()),
        "{svg_texts:?}"
    );
    assert!(!svg_texts.contains(&"5970".to_string()), "{svg_texts:?}");
    assert!(svg_texts.contains(&"6000".to_string()), "{svg_texts:?}");
    assert!(!elements(&doc, "line")
        .iter()
        .any(|e| e.attr("class") == Some("limit")));
}

/// Each plot shows only the checks computed over its own window; a spread statistic
/// (ripple, std) is text under it, never a level; labels never overlap.
#[test]
fn plots_show_their_own_window_checks_and_statistics_as_text() {
    let mut r = passed_report();
    let mut second = r.series[0].clone();
    second.step = "5[2].3".into();
    r.series.push(second);
    let ripple = CheckResult {
        statistic: Some("ripple".into()),
        measured: Some(2.75),
        limits: Limits::new(None, Some(5.0)),
        name: "speed_actual ripple below 5 rpm".into(),
        key: "speed_actual ripple below".into(),
        window: Some("5[2].3".into()),
        ..r.checks[0].clone()
    };
    let base = r.checks[0].clone();
    let near = |lo: f64, hi: f64| CheckResult {
        limits: Limits::new(Some(lo), Some(hi)),
        window: Some("5[2].3".into()),
        ..base.clone()
    };
    r.checks.push(ripple);
    r.checks.push(near(5999.0, 6001.0));
    r.checks.push(near(5999.1, 6000.9));
    let page = html_report(&r);
    let doc = parse(&page);
    let figures = select(&doc, "section#plots figure");
    assert_eq!(figures.len(), 2);
    let label_texts = |f: &ElementRef| -> Vec<(String, f64)> {
        f.select(&scraper::Selector::parse("text.limit-label").unwrap())
            .map(|t| (text(&t), attr(&t, "y")))
            .collect()
    };
    // The first window has only its own check (the far 5970/6030 limits).
    let first: Vec<String> = label_texts(&figures[0]).into_iter().map(|l| l.0).collect();
    assert_eq!(first, vec!["↑ mean ≤ 6030 rpm", "↓ mean ≥ 5970 rpm"]);
    // The second: its two level checks, no ripple level, labels at least 13 px apart.
    let mut second = label_texts(&figures[1]);
    assert_eq!(second.len(), 4, "{second:?}");
    assert!(second.iter().all(|l| !l.0.contains("ripple")), "{second:?}");
    second.sort_by(|a, b| a.1.total_cmp(&b.1));
    assert!(
        second.windows(2).all(|w| w[1].1 - w[0].1 >= 13.0 - 1e-9),
        "{second:?}"
    );
    let caption = text(
        &figures[1]
            .select(&scraper::Selector::parse("figcaption").unwrap())
            .next()
            .unwrap(),
    );
    assert_has(
        &caption,
        &["PASS speed_actual ripple below: 2.75 rpm (limits < 5 rpm)"],
    );
}

/// Failed checks are summed up at the top; checks are grouped by stage; steps are in the
/// order they ran with each group before its steps, failed when one inside failed.
#[test]
fn failures_at_the_top_stages_grouped_and_steps_in_order() {
    let mut r = error_report();
    r.checks[0].stage = "Stage 1, 6000 rpm".into();
    r.steps = vec![
        step("2.1", "expect speed_actual", false, "mean 5800 rpm", 0, "steps"),
        step("2", "Stage 1, 6000 rpm", true, "1 steps", 0, "steps"),
        step("3", "dwell 10 s", false, "no reply", 2_000, "steps"),
    ];
    // Step 2.1 is where the failed check is written: its failure is the check's.
    r.steps[0].origin = origin(11);
    let page = html_report(&r);
    let doc = parse(&page);
    let summary = texts(&doc, "section#failures li");
    assert_eq!(summary.len(), 2, "{summary:?}");
    assert!(
        summary[0].starts_with("FAIL Stage 1, 6000 rpm / speed & <mean>: measured 5800 rpm"),
        "{summary:?}"
    );
    assert!(summary[1].contains("step 3 dwell 10 s: no reply"), "{summary:?}");
    assert!(page.find("id=\"failures\"").unwrap() < page.find("id=\"checks\"").unwrap());
    assert_eq!(
        texts(&doc, "section#checks tr.group th"),
        vec!["Stage 1, 6000 rpm — 1 FAILED"]
    );
    let steps = rows(&doc, "steps");
    let order: Vec<(&str, &str)> = steps.iter().map(|s| (s[0].as_str(), s[3].as_str())).collect();
    assert_eq!(
        order,
        vec![("2", "FAIL (inside)"), ("2.1", "FAIL"), ("3", "FAIL")]
    );
}

#[test]
fn long_series_are_plotted_downsampled_keeping_peaks() {
    let mut points: Vec<(f64, f64)> = (0..100_000).map(|i| (f64::from(i) * 0.01, 1.0)).collect();
    points[54_321].1 = 99.0;
    points[77_777].1 = -42.0;
    let mut r = passed_report();
    r.series[0].points = points;
    r.series[0].unit = None;
    r.checks.clear();
    let page = html_report(&r);
    let doc = parse(&page);
    assert!(page.contains("points=\""));
    assert!(page.contains(",99 ") && page.contains(",-42 "));
    assert!(page.contains("of 100000 points shown (min and max of each interval)"));
    assert!(page.contains(">time [min]</text>"), "1000 s is shown in minutes");
    assert!(!page.contains("class=\"limit\""));
    let shown = elements(&doc, "polyline")[0]
        .attr("points")
        .unwrap()
        .split(' ')
        .count();
    assert!(shown <= drivescript::report::MAX_PLOT_POINTS, "{shown}");
    assert!(elements(&doc, "text").iter().any(|t| text(t) == "time [min]"));
}

#[test]
fn degenerate_series_still_plot() {
    let mut r = passed_report();
    r.series[0].points = vec![(1.0, 5.0)];
    r.series.push(Series {
        object: "a<b".into(),
        unit: Some("°C".into()),
        step: "9".into(),
        points: vec![(f64::NAN, 1.0)],
        samples: None,
        marks: None,
    });
    let page = html_report(&r);
    let doc = parse(&page);
    let svgs = select(&doc, "section#plots svg");
    assert_eq!(svgs.len(), 2);
    assert!(page.contains("points=\"1,5\""));
    assert!(page.contains(">no samples</text>"));
    assert!(page.contains("a&lt;b [°C]"));
    assert_eq!(svgs[1].attr("aria-label"), Some("a<b [°C] over time"));
    // The plots' own clip paths (the timeline's are `timeline-area-N`).
    let ids: Vec<&str> = elements(&doc, "clipPath")
        .iter()
        .map(|e| e.attr("id").unwrap())
        .filter(|id| !id.starts_with("timeline-area"))
        .collect();
    assert_eq!(ids, vec!["plot-area-0"]);
}

#[test]
fn self_contained_and_print_friendly() {
    let page = html_report(&passed_report());
    let doc = parse(&page);
    for external in [
        "<link",
        "<script",
        "<img",
        "src=",
        "@import",
        "url(http",
        "href=\"http",
    ] {
        assert!(!page.contains(external), "{external}");
    }
    for e in doc.root_element().descendent_elements() {
        assert!(
            e.attr("src").is_none() && e.attr("href").is_none(),
            "{}",
            e.html()
        );
    }
    // The only URL is the SVG namespace, which browsers never fetch.
    assert_eq!(
        page.matches("http").count(),
        page.matches("http://www.w3.org/2000/svg").count()
    );
    assert!(page.contains("@media print"));
    assert!(
        page.contains("@page { size: A4;"),
        "printed pages with margins and numbers"
    );
    assert!(page.contains("break-inside: avoid"));
    assert!(page.contains("background: none !important"));
}

#[test]
fn written_atomically() {
    let dir = std::env::temp_dir().join(format!("drivescript-html-{}", std::process::id()));
    let path = dir.join("out/report.html");
    write_html(&passed_report(), &path).unwrap();
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        html_report(&passed_report())
    );
    assert!(!dir.join("out/report.html.tmp").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The checks above would notice a broken page: each of these edits of a good one is
/// refused, saying why.
#[test]
fn a_broken_page_is_refused() {
    let page = html_report(&error_report());
    parse(&page);
    for (broken, why) in [
        // Text that was not escaped.
        (page.replacen("&lt;port&gt;", "<port>", 1), "parse errors"),
        (
            page.replacen("speed &amp; &lt;mean&gt;", "speed & <mean>", 1),
            "parse errors",
        ),
        (
            page.replacen("</h1>", "<b>bold</b></h1>", 1),
            "unexpected element <b>",
        ),
        (
            page.replacen("CHECK THE DRIVE BY HAND", "1 < 2", 1),
            "parse errors",
        ),
        // Markup that does not nest or close.
        (page.replacen("</span>", "", 1), "parse errors"),
        (page.replacen("</table>", "", 1), "parse errors"),
        (
            page.replacen("class=\"verdict error\"", "class=\"verdict\" error\"", 1),
            "parse errors",
        ),
        (page.replacen("<!DOCTYPE html>", "", 1), "DOCTYPE"),
    ] {
        assert_ne!(broken, page, "the edit for {why:?} changed nothing");
        let refused = html(&broken).map(|_| ()).unwrap_err();
        assert!(refused.contains(why), "{why:?}: {refused}");
    }
}

/// Printed by headless Chromium (where installed), the acceptance test's report is a PDF
/// of a few A4 pages; `tests/render_reports.sh` renders every example report to look at.
#[test]
fn chromium_prints_the_report_to_pdf() {
    let dir = std::env::temp_dir().join(format!("drivescript-pdf-{}", std::process::id()));
    let Some(mut chromium) = crate::support::headless_chromium(&dir.join("profile")) else {
        return;
    };
    let html = dir.join("report.html");
    write_html(&passed_report(), &html).unwrap();
    let pdf = dir.join("report.pdf");
    succeeded(
        chromium
            .arg(format!("--print-to-pdf={}", pdf.display()))
            .arg(&html),
        "chromium",
    );
    let bytes = std::fs::read(&pdf).expect("a PDF");
    assert!(bytes.starts_with(b"%PDF"));
    let text = String::from_utf8_lossy(&bytes);
    // A4 pages (595 × 842 points), each with its media box: the @page rule took effect.
    let pages = text.matches("/MediaBox [0 0 594.9").count();
    assert!((1..=6).contains(&pages), "{pages} A4 pages");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A check after a repeat is not listed under the repeat's last pass: once a group heading
/// stands before them, checks outside any repeat or include get a heading of their own.
#[test]
fn checks_after_a_repeat_are_not_under_its_last_pass() {
    let mut r = passed_report();
    let base = r.checks[0].clone();
    r.checks = ["repeat 2 times (2 steps) #1", "repeat 2 times (2 steps) #2", ""]
        .iter()
        .map(|stage| CheckResult {
            stage: stage.to_string(),
            ..base.clone()
        })
        .collect();
    let doc = parse(&html_report(&r));
    assert_eq!(
        texts(&doc, "section#checks tr.group th"),
        vec![
            "repeat 2 times (2 steps) #1",
            "repeat 2 times (2 steps) #2",
            "not in a repeat or include"
        ]
    );
    let last_two: Vec<String> = select(&doc, "section#checks tbody > tr")
        .iter()
        .rev()
        .take(2)
        .map(|row| row.value().attr("class").unwrap_or_default().to_string())
        .collect();
    assert_eq!(last_two, ["pass", "group"]);
}

/// A marginal pass is its own row class (amber on screen) and mark, and the summary
/// counts it.
#[test]
fn a_marginal_pass_is_amber_and_counted() {
    let mut r = passed_report();
    r.checks[0].marginal = true;
    let page = html_report(&r);
    let doc = parse(&page);
    let marginal = select(&doc, "tr.marginal");
    assert_eq!(marginal.len(), 1, "{page}");
    assert!(text(&marginal[0]).contains("MARGINAL"));
    assert!(page.contains("(1 marginal)"));
    assert!(
        page.contains("tr.marginal td { background: #fff4d6; }"),
        "amber on screen"
    );
    r.checks[0].marginal = false;
    assert!(select(&parse(&html_report(&r)), "tr.marginal").is_empty());
}

/// The shipped dynamics recipe's report: markers where the step response was measured, a
/// marginal pass in amber, and the whole-run timeline with the setpoints written and the
/// stages; headless Chromium renders it on screen (PNG) and prints it on A4 (PDF).
#[test]
fn the_dynamics_report_marks_the_response_and_draws_the_whole_run() {
    let dir = crate::support::scratch("dynamics-report");
    let html = dir.join("dynamics.html");
    let out = crate::support::cli(
        &[
            "run",
            "recipes/spindle-dynamics.yaml",
            "--fast",
            "--sim",
            "response-time=150ms",
            "--sim",
            "overshoot=8%",
            "--report",
            html.to_str().unwrap(),
        ],
        0,
    );
    assert_has(
        &out.stdout,
        &["MARGINAL  speed_actual overshoot below 15 %", "(1 marginal)"],
    );
    let page = std::fs::read_to_string(&html).unwrap();
    let doc = parse(&page);
    let step_plot = select(&doc, "section#plots svg.plot")[0];
    let labels: Vec<String> = step_plot
        .select(&scraper::Selector::parse("text.marker-label").unwrap())
        .map(|t| text(&t))
        .collect();
    assert_eq!(labels, ["10 %", "90 %", "settled", "peak"]);
    assert_eq!(select(&doc, "section#checks tr.marginal").len(), 1);
    let timelines = select(&doc, "section#timeline svg.timeline");
    assert_eq!(timelines.len(), 2, "speed_actual and motor_temperature");
    assert!(
        timelines[0].html().contains("class=\"setpoint\""),
        "the setpoints on the speed"
    );
    assert!(
        !timelines[1].html().contains("class=\"setpoint\""),
        "not on the temperature"
    );
    assert!(timelines[0].html().contains(">safe stop</text>"));
    let Some(mut screen) = crate::support::headless_chromium(&dir.join("profile-screen")) else {
        return;
    };
    let png = dir.join("dynamics.png");
    succeeded(
        screen
            .arg("--window-size=1100,2600")
            .arg(format!("--screenshot={}", png.display()))
            .arg(&html),
        "chromium",
    );
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let Some(mut print) = crate::support::headless_chromium(&dir.join("profile-print")) else {
        return;
    };
    let pdf = dir.join("dynamics.pdf");
    succeeded(
        print.arg(format!("--print-to-pdf={}", pdf.display())).arg(&html),
        "chromium",
    );
    let bytes = std::fs::read(&pdf).unwrap();
    let pages = String::from_utf8_lossy(&bytes)
        .matches("/MediaBox [0 0 594.9")
        .count();
    assert!((1..=8).contains(&pages), "{pages} A4 pages");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A failure of an attempt that was tried again is a grey row that says so, and is not
/// among what failed.
#[test]
fn a_retried_failure_is_kept_but_not_among_what_failed() {
    let mut r = passed_report();
    r.checks[0].passed = false;
    r.checks[0].retried = true;
    let doc = parse(&html_report(&r));
    let rows = select(&doc, "section#checks tr.retried");
    assert_eq!(rows.len(), 1);
    assert!(text(&rows[0]).contains("FAIL, RETRIED"));
    assert!(select(&doc, "section#failures").is_empty());
    r.checks[0].retried = false;
    assert_eq!(select(&parse(&html_report(&r)), "section#failures").len(), 1);
}
