//! How a value, a check's measurement and limits, a place and a duration are written on
//! the HTML page, and the escaping of every text put into it. Pure text; builds no markup.

use crate::session::{number, CheckResult, RunReport};
use std::time::Duration;

/// A check's name without its limits (they have their own column).
pub fn check_title(c: &CheckResult) -> String {
    c.key.clone()
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
pub fn value_text(r: &RunReport, object: Option<&str>, v: f64, unit: Option<&str>) -> String {
    let text = match object.and_then(|o| r.resolution(o)) {
        Some(res) => format!("{v:.*}", decimals(res)),
        None => number((v * 1000.0).round() / 1000.0),
    };
    match unit {
        Some(u) => format!("{text} {u}"),
        None => text,
    }
}

pub fn measured_cell(r: &RunReport, c: &CheckResult) -> String {
    match (c.measured, &c.measured_text) {
        (Some(v), _) => value_text(r, c.object.as_deref(), v, c.unit.as_deref()),
        (None, Some(t)) => t.clone(),
        (None, None) => "—".into(),
    }
}

/// `speed-stage.yaml:15:5` for `/long/path/includes/speed-stage.yaml:15:5`: the page is
/// read beside the recipe; the full place is in the cell's title.
pub fn short_origin(origin: &str) -> String {
    origin.rsplit('/').next().unwrap_or(origin).to_string()
}

/// Limits as the recipe wrote them (no padding to the resolution).
pub fn limits_cell(_r: &RunReport, c: &CheckResult) -> String {
    c.limits_text().unwrap_or_else(|| "—".into())
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
    fn values_and_durations() {
        assert_eq!(
            (decimals(0.001), decimals(0.1), decimals(1.0), decimals(10.0)),
            (3, 1, 0, 0)
        );
        assert_eq!(duration_text(Duration::from_millis(250)), "0:00:00.250");
        assert_eq!(duration_text(Duration::from_millis(8_465_007)), "2:21:05.007");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(
            esc("<a href='x'>&\"</a>"),
            "&lt;a href=&#39;x&#39;&gt;&amp;&quot;&lt;/a&gt;"
        );
    }
}
