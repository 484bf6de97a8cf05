//! The "Sampled values" section of the HTML page: per series a figure with its plot and a
//! caption holding the window's statistics and its spread checks as text. Leaves the
//! drawing to [`super::svg_plot`].

use super::html_text::{check_title, esc, limits_cell, measured_cell, value_text};
use super::plot_axes::axis_title;
use super::svg_plot::{downsample, finite, plot_svg};
use crate::session::{CheckResult, RunReport, Series};
use std::fmt::Write as _;

/// Whether a check's limits are levels of the plotted value (the value itself, its mean,
/// min or max) rather than of a statistic about its spread (ripple, std), which is shown
/// as text under the plot.
fn is_level(c: &CheckResult) -> bool {
    matches!(c.statistic.as_deref(), None | Some("mean" | "min" | "max"))
}

pub fn plots(h: &mut String, r: &RunReport) {
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
        let all = s.samples.map_or(s.points.len(), |w| w.count);
        let how = if shown < all {
            format!("{shown} of {all} points shown (min and max of each interval)")
        } else {
            format!("{all} points")
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
                let mark = match (c.passed, c.marginal, c.retried) {
                    (false, _, true) => "<span class=\"retried\">FAIL, RETRIED</span>",
                    (true, false, _) => "<span class=\"ok\">PASS</span>",
                    (true, true, _) => "<span class=\"warn\">MARGINAL</span>",
                    (false, _, false) => "<span class=\"fail\">FAIL</span>",
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

/// The window's min, mean and max: of every sample when the run kept them, else of the
/// points.
fn stats_text(r: &RunReport, s: &Series) -> String {
    let (min, mean, max) = match s.samples {
        Some(w) if w.count > 0 => (w.min, w.mean, w.max),
        _ => {
            let values: Vec<f64> = finite(&s.points).iter().map(|p| p.1).collect();
            if values.is_empty() {
                return String::new();
            }
            let min = values.iter().copied().fold(f64::INFINITY, f64::min);
            let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (min, values.iter().sum::<f64>() / values.len() as f64, max)
        }
    };
    let u = s.unit.as_deref();
    let v = |x: f64| value_text(r, Some(&s.object), x, u);
    format!("; min {}, mean {}, max {}", v(min), v(mean), v(max))
}
