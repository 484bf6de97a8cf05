//! One SVG plot of a check's value across runs: a marker per run that measured a value (a
//! failed run's a square in the fail colour, a marginal one an amber diamond, each with
//! its tooltip), a thin line joining each unit's runs, each unit in a colour of its own
//! when there are few, and the limits each run had, over a time axis of dates or of the
//! time since the first run ([`super::time_axis`]), as wide as the whole-run timeline.
//! Knows nothing of the store; the caller bounds the marks.

use super::html_text::esc;
use super::plot_axes::{axes, grid, Area, Scale};
use super::svg_plot::{spread_labels, step_line, value_range, LimitLine};
use super::time_axis::TimeAxis;
use super::timeline::{LEFT, RIGHT, W};
use std::fmt::Write as _;

const H: f64 = 320.0;
/// Room above the plot for a limit beyond the values' range.
const TOP: f64 = 24.0;
const BOTTOM: f64 = 44.0;
/// The run report's colours of a failed and a marginal check.
const FAIL: &str = "#8b0000";
const AMBER: &str = "#d98e04";
const AMBER_EDGE: &str = "#8a5300";

/// The colours units are told apart by, when there are no more units than colours; none
/// is the fail colour or amber.
pub const UNIT_COLOURS: [&str; 8] = [
    "#1f4fa0", "#2a7a2a", "#6a3d9a", "#00838f", "#222222", "#5e9bd6", "#b0409a", "#7f7f7f",
];

/// The colour of unit `unit` of `units`: its own among few, else the data colour for all.
pub fn unit_colour(unit: usize, units: usize) -> &'static str {
    if units <= UNIT_COLOURS.len() {
        UNIT_COLOURS[unit % UNIT_COLOURS.len()]
    } else {
        UNIT_COLOURS[0]
    }
}

/// How a run's check ended, as its marker shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Passed,
    /// Passed outside its warning band.
    Marginal,
    Failed,
}

/// One run's value.
#[derive(Debug, Clone, PartialEq)]
pub struct TrendMark {
    /// When the run started, in seconds since 1970 UTC.
    pub at: f64,
    pub value: f64,
    pub outcome: Outcome,
    /// Which unit's, as an index into the plot's units: its colour and line.
    pub unit: usize,
    /// The tooltip: when, which unit, the value, the verdict.
    pub tip: String,
    /// The limits this run had (low, high): a short tick at each across its marker, so
    /// every run is judged against its own limits on the plot, not only the step line.
    pub limits: (Option<f64>, Option<f64>),
}

/// What a trend's plot draws.
#[derive(Debug, Clone, Copy)]
pub struct TrendPlot<'a> {
    /// In the order the runs started.
    pub marks: &'a [TrendMark],
    /// How many units the marks' `unit` counts.
    pub units: usize,
    /// The value axis' title: `[K]`, `change [%]`.
    pub value_title: &'a str,
    /// Each a step line over the runs' times (seconds since 1970 UTC).
    pub limits: &'a [LimitLine],
    /// What the plot shows, for those who cannot see it.
    pub label: &'a str,
}

/// The plot as an SVG element.
pub fn trend_svg(p: &TrendPlot) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg class=\"plot trend\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {W} {H}\" \
         font-family=\"Helvetica, Arial, sans-serif\" font-size=\"11\" width=\"{W}\" height=\"{H}\" \
         role=\"img\" aria-label=\"{0}\"><title>{0}</title>",
        esc(p.label)
    );
    let (Some(first), Some(last)) = (p.marks.first(), p.marks.last()) else {
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no run measured a value</text>\n</svg>",
            W / 2.0,
            H / 2.0
        );
        return s;
    };
    let time = TimeAxis::calendar(first.at, last.at);
    let (t0, t1) = time.range;
    let (v0, v1) = value_range(p.marks.iter().map(|m| m.value), p.limits);
    let area = Area::inside((W, H), (LEFT, RIGHT, TOP, BOTTOM));
    let scale = Scale::new(area, (t0, t1), (v0, v1));
    let x = |t: f64| scale.x(t);
    let y = |v: f64| scale.y(v);
    grid(&mut s, area, (&x, &y), &time, (v0, v1), 16.0);
    axes(&mut s, area, &time.title, H - 8.0, p.value_title);
    let _ = writeln!(
        s,
        "<clipPath id=\"trend-area\"><rect x=\"{}\" y=\"{}\" width=\"{:.2}\" height=\"{:.2}\"/></clipPath>\n\
         <g clip-path=\"url(#trend-area)\">",
        area.left,
        area.top,
        area.right - area.left,
        area.bottom - area.top
    );
    for l in p.limits {
        step_line(&mut s, &l.steps, &x, &y, (area.left, area.right));
    }
    // A line means one unit's runs after another; among many units they could not be told
    // apart, so only the markers are drawn then.
    if p.units <= UNIT_COLOURS.len() {
        for unit in 0..p.units {
            let mut pts = String::new();
            for m in p.marks.iter().filter(|m| m.unit == unit) {
                let _ = write!(pts, "{:.2},{:.2} ", x(m.at), y(m.value));
            }
            if pts.matches(' ').count() > 1 {
                let _ = writeln!(
                    s,
                    "<polyline class=\"trend-line\" fill=\"none\" stroke=\"{}\" stroke-width=\"1\" points=\"{}\"/>",
                    unit_colour(unit, p.units),
                    pts.trim_end()
                );
            }
        }
    }
    for m in p.marks {
        for limit in [m.limits.0, m.limits.1]
            .into_iter()
            .flatten()
            .filter(|v| v.is_finite())
        {
            let _ = writeln!(
                s,
                "<line class=\"run-limit\" x1=\"{:.2}\" x2=\"{:.2}\" y1=\"{2:.2}\" y2=\"{2:.2}\" stroke=\"#b00000\" stroke-width=\"2\"/>",
                x(m.at) - 6.0,
                x(m.at) + 6.0,
                y(limit)
            );
        }
    }
    s.push_str("</g>\n");
    // The labels first: where one meets the newest run, the run's marker stays on top.
    limit_labels(&mut s, p.limits, area, (v0, v1), &y);
    for m in p.marks {
        marker(&mut s, m, (x(m.at), y(m.value)), p.units);
    }
    s.push_str("</svg>\n");
    s
}

/// A run's marker with its tooltip: a circle in its unit's colour, an amber diamond when
/// marginal, a square in the fail colour when failed (shapes that tell them apart on
/// paper too).
fn marker(s: &mut String, m: &TrendMark, (px, py): (f64, f64), units: usize) {
    let tip = esc(&m.tip);
    let _ = match m.outcome {
        Outcome::Passed => writeln!(
            s,
            "<circle class=\"mark passed\" cx=\"{px:.2}\" cy=\"{py:.2}\" r=\"3.5\" fill=\"{}\" stroke=\"#fff\" stroke-width=\"0.8\"><title>{tip}</title></circle>",
            unit_colour(m.unit, units)
        ),
        Outcome::Marginal => writeln!(
            s,
            "<path class=\"mark marginal\" d=\"M{px:.2} {:.2}L{:.2} {py:.2}L{px:.2} {:.2}L{:.2} {py:.2}Z\" fill=\"{AMBER}\" stroke=\"{AMBER_EDGE}\" stroke-width=\"1\"><title>{tip}</title></path>",
            py - 5.0,
            px + 5.0,
            py + 5.0,
            px - 5.0
        ),
        Outcome::Failed => writeln!(
            s,
            "<rect class=\"mark failed\" x=\"{:.2}\" y=\"{:.2}\" width=\"8\" height=\"8\" fill=\"{FAIL}\" stroke=\"#fff\" stroke-width=\"0.8\"><title>{tip}</title></rect>",
            px - 4.0,
            py - 4.0
        ),
    };
}

/// Each limit's label inside the plot's right edge, above its last value; one beyond the
/// value range with an arrow: above the plot, or inside its bottom edge.
fn limit_labels(
    s: &mut String,
    limits: &[LimitLine],
    area: Area,
    (v0, v1): (f64, f64),
    y: &dyn Fn(f64) -> f64,
) {
    let mut labels: Vec<(f64, String)> = limits
        .iter()
        .filter_map(|l| {
            let v = l.steps.last().and_then(|s| s.1).filter(|v| v.is_finite())?;
            Some(if v > v1 {
                (area.top - 6.0, format!("↑ {}", l.label))
            } else if v < v0 {
                (area.bottom - 4.0, format!("↓ {}", l.label))
            } else {
                (y(v) - 4.0, l.label.clone())
            })
        })
        .collect();
    spread_labels(&mut labels, 13.0, area.top - 6.0, area.bottom - 4.0);
    for (py, label) in &labels {
        let _ = writeln!(
            s,
            "<text class=\"limit-label\" fill=\"#b00000\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\" \
             x=\"{:.2}\" y=\"{py:.2}\" text-anchor=\"end\">{}</text>",
            area.right - 4.0,
            esc(label)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mark(at: f64, value: f64, outcome: Outcome, unit: usize) -> TrendMark {
        TrendMark {
            at,
            value,
            outcome,
            unit,
            tip: format!("SP-{unit} <{value}>"),
            limits: (None, Some(3.0)),
        }
    }

    fn plot(marks: &[TrendMark], units: usize) -> String {
        let limits = [LimitLine {
            steps: vec![(f64::NEG_INFINITY, Some(3.0))],
            label: "≤ 3 K".into(),
        }];
        trend_svg(&TrendPlot {
            marks,
            units,
            value_title: "change [K]",
            limits: &limits,
            label: "a trend",
        })
    }

    #[test]
    fn each_run_is_a_marker_shaped_and_coloured_by_its_outcome_and_unit() {
        let t = 1_795_582_975.0;
        let marks = [
            mark(t, 1.0, Outcome::Passed, 0),
            mark(t + 86_400.0, 2.0, Outcome::Marginal, 1),
            mark(t + 3.0 * 86_400.0, 4.0, Outcome::Failed, 0),
            mark(t + 9.0 * 86_400.0, 1.5, Outcome::Passed, 1),
        ];
        let svg = plot(&marks, 2);
        assert_eq!(svg.matches("class=\"mark ").count(), 4);
        assert!(svg.contains(&format!("fill=\"{FAIL}\"")), "{svg}");
        assert!(svg.contains("class=\"mark marginal\""));
        assert!(svg.contains(&format!("fill=\"{}\"", UNIT_COLOURS[0])));
        assert!(svg.contains("<circle class=\"mark passed\" cx=\""));
        assert!(svg.contains(&format!("fill=\"{}\" stroke=\"#fff\"", UNIT_COLOURS[1])));
        assert!(
            svg.contains("<title>SP-1 &lt;2&gt;</title>"),
            "tooltips are escaped"
        );
        // A thin line per unit, the limit dashed with its label, dates along the time axis.
        assert_eq!(svg.matches("class=\"trend-line\"").count(), 2);
        assert!(svg.contains("stroke-width=\"1\" points="));
        assert!(svg.contains("class=\"limit\"") && svg.contains(">≤ 3 K</text>"));
        assert!(
            svg.contains(">date (UTC)</text>") && svg.contains(">2026-11-27</text>"),
            "{svg}"
        );
        assert!(svg.contains(">change [K]</text>"));
    }

    #[test]
    fn many_units_share_one_colour_and_draw_no_lines() {
        let marks: Vec<TrendMark> = (0..20)
            .map(|k| mark(f64::from(k) * 60.0, f64::from(k % 3), Outcome::Passed, k as usize))
            .collect();
        let svg = plot(&marks, 20);
        assert_eq!(svg.matches("class=\"mark passed\"").count(), 20);
        assert!(!svg.contains("trend-line"));
        assert!(!svg.contains(UNIT_COLOURS[1]));
        assert!(
            svg.contains(">time since 1970-01-01 00:00:00 UTC [min]</text>"),
            "{svg}"
        );
    }

    #[test]
    fn nothing_measured_says_so() {
        assert!(plot(&[], 0).contains("no run measured a value"));
    }
}
