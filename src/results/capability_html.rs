//! `results capability CHECK --html FILE`: the capability of one check as a page — n,
//! mean, σ, Cp, Cpk with the spec limits — and a histogram of the values (an SVG, the
//! spec limits and the mean drawn over it). The run report's style; self-contained, no
//! script. Knows no store.

use super::capability::Capability;
use super::PageLinks;
use crate::report::{esc, REPORT_CSS};
use crate::session::with_unit;
use std::fmt::Write as _;

/// `v` to `digits` significant digits, for statistics (never more digits than they mean).
pub fn significant(v: f64, digits: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let scale = 10f64.powi(digits - 1 - v.abs().log10().floor() as i32);
    (v * scale).round() / scale
}

/// A statistic with its unit, to `digits` significant digits; `—` without one.
pub fn stat_text(v: Option<f64>, digits: i32, unit: Option<&str>) -> String {
    v.map_or_else(|| "—".into(), |v| with_unit(significant(v, digits), unit))
}

/// Cp or Cpk to two decimals; `—` without one.
pub fn index_text(v: Option<f64>) -> String {
    v.map_or_else(|| "—".into(), |v| format!("{v:.2}"))
}

/// The page.
pub fn capability_page(c: &Capability, links: PageLinks) -> String {
    let title = c.key.clone().unwrap_or_else(|| c.check.clone());
    let unit = c.unit.as_deref();
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"generator\" content=\"drivescript {v}\">\n<title>Capability of {t}</title>\n\
         <style>{REPORT_CSS}</style>\n</head>\n<body>\n{nav}<header>\n<h1>Capability of {t}</h1>\n</header>\n",
        v = env!("CARGO_PKG_VERSION"),
        nav = links.nav(),
        t = esc(&title)
    );
    h.push_str("<section>\n<h2>Summary</h2>\n<table id=\"capability\">\n<tbody>\n");
    let limit = |v: Option<f64>| v.map_or_else(|| "none".into(), |v| with_unit(v, unit));
    for (name, value) in [
        ("n", c.n.to_string()),
        ("Mean", stat_text(c.mean, 6, unit)),
        ("σ (n − 1)", stat_text(c.sigma, 3, unit)),
        (
            "Min … max",
            format!("{} … {}", stat_text(c.min, 6, unit), stat_text(c.max, 6, unit)),
        ),
        ("Lower spec limit", limit(c.limits.low)),
        ("Upper spec limit", limit(c.limits.high)),
        ("Cp", index_text(c.cp)),
        (
            "Cpk",
            match c.why_no_cpk() {
                Some(why) => format!("— ({why})"),
                None => index_text(c.cpk),
            },
        ),
    ] {
        let _ = writeln!(
            h,
            "<tr><th scope=\"row\">{}</th><td class=\"num\">{}</td></tr>",
            esc(name),
            esc(&value)
        );
    }
    h.push_str("</tbody>\n</table>\n");
    if !c.other_limits.is_empty() {
        let _ = writeln!(
            h,
            "<p class=\"why\">Older runs had other limits ({}): computed against the newest run's.</p>",
            esc(&c
                .other_limits
                .iter()
                .map(|l| format!("{} .. {}", limit(l.low), limit(l.high)))
                .collect::<Vec<_>>()
                .join("; "))
        );
    }
    let _ = writeln!(
        h,
        "</section>\n<section>\n<h2>Histogram</h2>\n<figure>{}<figcaption>{} value(s) per interval; dashed: the spec limits, solid: the mean.</figcaption></figure>\n</section>",
        histogram_svg(c),
        c.n
    );
    let _ = write!(
        h,
        "<footer>Written by drivescript {} from its results store.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}

/// Bars of the histogram, the spec limits dashed and the mean solid, with the value axis'
/// ends labelled.
fn histogram_svg(c: &Capability) -> String {
    let (w, hgt, left, bottom) = (640.0, 240.0, 40.0, 30.0);
    let hist = c.histogram();
    let most = hist.counts.iter().copied().max().unwrap_or(0).max(1) as f64;
    let span = hist.width * hist.counts.len() as f64;
    let x = |v: f64| left + (v - hist.start) / span * (w - left - 10.0);
    let y = |n: f64| (hgt - bottom) - n / most * (hgt - bottom - 10.0);
    let mut s = format!(
        "<svg class=\"histogram\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {w} {hgt}\" role=\"img\" aria-label=\"histogram\">"
    );
    for (i, n) in hist.counts.iter().enumerate() {
        let x0 = x(hist.start + i as f64 * hist.width);
        let x1 = x(hist.start + (i + 1) as f64 * hist.width);
        let _ = write!(
            s,
            "<rect class=\"bar\" x=\"{x0:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#4a7ab5\"><title>{n}</title></rect>",
            y(*n as f64),
            (x1 - x0 - 1.0).max(0.5),
            (hgt - bottom) - y(*n as f64)
        );
    }
    for (class, v, dash) in [
        ("spec", c.limits.low, " stroke-dasharray=\"6 4\""),
        ("spec", c.limits.high, " stroke-dasharray=\"6 4\""),
        ("mean", c.mean, ""),
    ] {
        if let Some(v) = v {
            let _ = write!(
                s,
                "<line class=\"{class}\" x1=\"{0:.1}\" x2=\"{0:.1}\" y1=\"5\" y2=\"{1:.1}\" stroke=\"#b03030\"{dash}/>",
                x(v),
                hgt - bottom
            );
        }
    }
    let unit = c.unit.as_deref();
    let _ = write!(
        s,
        "<text x=\"{left}\" y=\"{:.1}\" font-size=\"11\">{}</text><text x=\"{:.1}\" y=\"{:.1}\" font-size=\"11\" text-anchor=\"end\">{}</text></svg>",
        hgt - 10.0,
        esc(&stat_text(Some(hist.start), 6, unit)),
        w - 10.0,
        hgt - 10.0,
        esc(&stat_text(Some(hist.start + span), 6, unit))
    );
    s
}
