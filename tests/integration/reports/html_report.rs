//! `--report`: the run report as one HTML page, read back with an HTML5 parser.

use super::markup::{elements, html, inside, rows, select, text, texts};
use super::sample_reports::{error_report, passed_report};
use drivescript::report::{html_report, write_html};
use drivescript::session::Series;
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
        "1m 6s 250ms",
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
            "5.000 s",
            "0.250 s"
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
            "speed_actual mean near 6000 rpm ± 0.5 %",
            "6000.1 rpm",
            "5970 .. 6030 rpm",
            "PASS",
            "mean 6000.1 rpm",
            "recipes/run-in.yaml:20:5"
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
    let r = passed_report();
    let page = html_report(&r);
    let doc = parse(&page);
    assert_eq!(elements(&doc, "svg").len(), 1);
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
    for tick in ["10", "20", "30", "40", "50", "60", "5970", "6000", "6030"] {
        assert!(
            svg_texts.contains(&tick.to_string()),
            "tick {tick} in {svg_texts:?}"
        );
    }
    // The check's limits: dashed lines at 5970 and 6030, labelled.
    let limits: Vec<ElementRef> = elements(&doc, "line")
        .into_iter()
        .filter(|e| e.attr("class") == Some("limit"))
        .collect();
    assert_eq!(limits.len(), 2);
    assert!(
        svg_texts.contains(&"mean ≥ 5970 rpm".to_string()),
        "{svg_texts:?}"
    );
    assert!(svg_texts.contains(&"mean ≤ 6030 rpm".to_string()));
    // The lines sit where the polyline's transform puts those values.
    let m: Vec<f64> = transform["matrix(".len()..]
        .trim_end_matches(')')
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    let y_of = |v: f64| m[3] * v + m[5];
    let ys: Vec<f64> = limits.iter().map(|l| attr(l, "y1")).collect();
    assert!((ys[0] - y_of(5970.0)).abs() < 0.01, "{ys:?}");
    assert!((ys[1] - y_of(6030.0)).abs() < 0.01, "{ys:?}");
    // Within the plot area, which the data's clip path declares.
    let area = select(&doc, "clipPath > rect")[0];
    let (top, bottom) = (attr(&area, "y"), attr(&area, "y") + attr(&area, "height"));
    assert_eq!((top, bottom), (16.0, 268.0));
    assert!(ys.iter().all(|y| (top..=bottom).contains(y)), "{ys:?}");
    assert!(page.contains("speed_actual [rpm] sampled by step 3: 601 points"));
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
    });
    let page = html_report(&r);
    let doc = parse(&page);
    let svgs = elements(&doc, "svg");
    assert_eq!(svgs.len(), 2);
    assert!(page.contains("points=\"1,5\""));
    assert!(page.contains(">no samples</text>"));
    assert!(page.contains("a&lt;b [°C]"));
    assert_eq!(svgs[1].attr("aria-label"), Some("a<b [°C] over time"));
    let ids: Vec<&str> = elements(&doc, "clipPath")
        .iter()
        .map(|e| e.attr("id").unwrap())
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
