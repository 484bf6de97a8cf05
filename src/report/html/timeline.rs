//! The "Whole run" section of the HTML page: per sampled object one compact SVG of its
//! values over the entire run (every window and wait, each its own line so gaps stay
//! gaps), the speed setpoints written as a step profile on the plot of the same unit, and
//! the stage boundaries (top-level repeats and includes, the safe stop) as labelled
//! vertical lines. Every plot draws at most [`MAX_PLOT_POINTS`] points however long the
//! run, so a day draws as fast as a minute. Reads the run report; draws nothing else.

use super::html_text::esc;
use super::plot_axes::{axes, axis_title, grid, padded_range, Area, Scale};
use super::svg_plot::{downsample_to, finite, MAX_PLOT_POINTS};
use super::time_axis::TimeAxis;
use crate::session::{RunReport, Series};
use std::fmt::Write as _;

/// The timeline's width and side margins (SVG user units), which a trend's plot shares.
pub(super) const W: f64 = 760.0;
const H: f64 = 200.0;
pub(super) const LEFT: f64 = 80.0;
pub(super) const RIGHT: f64 = 24.0;
const TOP: f64 = 26.0;
const BOTTOM: f64 = 40.0;

/// Where the run changes stage: (seconds since the start, label).
fn boundaries(r: &RunReport) -> Vec<(f64, String)> {
    let mut out: Vec<(f64, String)> = r
        .steps
        .iter()
        .filter(|s| s.phase == "steps" && !s.number.contains('.'))
        .filter(|s| s.label.starts_with("repeat") || s.label.starts_with("include"))
        .map(|s| (s.started.as_secs_f64(), s.label.clone()))
        .collect();
    if let Some(stop) = r.steps.iter().find(|s| s.phase != "steps") {
        out.push((stop.started.as_secs_f64(), "safe stop".into()));
    }
    out
}

pub fn timeline(h: &mut String, r: &RunReport) {
    let mut objects: Vec<(&str, Option<&str>)> = Vec::new();
    for s in &r.series {
        if !objects.iter().any(|(o, _)| *o == s.object) {
            objects.push((&s.object, s.unit.as_deref()));
        }
    }
    if objects.is_empty() {
        return;
    }
    h.push_str("<section id=\"timeline\">\n<h2>Whole run</h2>\n");
    let stages = boundaries(r);
    let span = r.duration.as_secs_f64().max(1e-3);
    for (i, (object, unit)) in objects.iter().enumerate() {
        let windows: Vec<&Series> = r.series.iter().filter(|s| s.object == *object).collect();
        let setpoints = r
            .setpoints
            .as_ref()
            .filter(|t| t.unit.as_deref() == *unit && unit.is_some());
        h.push_str("<figure>\n");
        h.push_str(&timeline_svg(
            object,
            *unit,
            &windows,
            setpoints.map(|t| &t.points[..]),
            &stages,
            span,
            i,
        ));
        let _ = writeln!(
            h,
            "<figcaption>{} over the whole run: {} sampled stretch(es){}{}</figcaption>\n</figure>",
            esc(&axis_title(object, *unit)),
            windows.len(),
            match setpoints {
                Some(t) => format!(", with the {} written (dashed)", esc(&t.object)),
                None => String::new(),
            },
            if stages.is_empty() {
                ""
            } else {
                "; vertical lines mark the stages"
            }
        );
    }
    h.push_str("</section>\n");
}

fn timeline_svg(
    object: &str,
    unit: Option<&str>,
    windows: &[&Series],
    setpoints: Option<&[(f64, f64)]>,
    stages: &[(f64, String)],
    span: f64,
    id: usize,
) -> String {
    let title = axis_title(object, unit);
    let cap = (MAX_PLOT_POINTS / windows.len().max(1)).max(16);
    let lines: Vec<Vec<(f64, f64)>> = windows
        .iter()
        .map(|w| downsample_to(&finite(&w.points), cap))
        .collect();
    let profile: Vec<(f64, f64)> = setpoints
        .map(|p| downsample_to(&finite(p), MAX_PLOT_POINTS))
        .unwrap_or_default();
    let values = lines.iter().flatten().chain(profile.iter()).map(|p| p.1);
    let (v0, v1) = padded_range(values, 0.05);
    let (t0, t1) = (0.0, span);
    let area = Area::inside((W, H), (LEFT, RIGHT, TOP, BOTTOM));
    let (xl, xr, yt, yb) = (area.left, area.right, area.top, area.bottom);
    let scale = Scale::new(area, (t0, t1), (v0, v1));
    let x = |t: f64| scale.x(t);
    let y = |v: f64| scale.y(v);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg class=\"plot timeline\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {W} {H}\" \
         font-family=\"Helvetica, Arial, sans-serif\" font-size=\"11\" width=\"{W}\" height=\"{H}\" \
         role=\"img\" aria-label=\"{0}\"><title>{0}</title>",
        esc(&format!("{title} over the whole run"))
    );
    let time = TimeAxis::elapsed(t0, t1);
    grid(&mut s, area, (&x, &y), &time, (v0, v1), 14.0);
    axes(&mut s, area, &time.title, H - 6.0, &title);
    for (k, (t, label)) in stages.iter().enumerate() {
        let px = x(*t);
        // Labels alternate between two rows so neighbouring stages stay readable.
        let ly = if k % 2 == 0 { yt - 14.0 } else { yt - 3.0 };
        // Near the right edge a label ends at its line instead of starting there.
        let anchor = if px > xr - 120.0 { "end" } else { "start" };
        let _ = writeln!(
            s,
            "<line class=\"stage\" stroke=\"#666\" stroke-dasharray=\"2 3\" x1=\"{px:.2}\" y1=\"{yt}\" x2=\"{px:.2}\" y2=\"{yb}\"/>\
             <text class=\"stage-label\" x=\"{px:.2}\" y=\"{ly:.2}\" font-size=\"9\" text-anchor=\"{anchor}\">{}</text>",
            esc(&short(label))
        );
    }
    let _ = writeln!(
        s,
        "<clipPath id=\"timeline-area-{id}\"><rect x=\"{xl}\" y=\"{yt}\" width=\"{:.2}\" height=\"{:.2}\"/></clipPath>\
         <g clip-path=\"url(#timeline-area-{id})\">",
        xr - xl,
        yb - yt
    );
    if !profile.is_empty() {
        // A step profile: each setpoint holds until the next one.
        let mut pts = String::new();
        let mut last = None;
        for (t, v) in &profile {
            if let Some(held) = last {
                let _ = write!(pts, "{:.2},{:.2} ", x(*t), y(held));
            }
            let _ = write!(pts, "{:.2},{:.2} ", x(*t), y(*v));
            last = Some(*v);
        }
        if let Some(held) = last {
            let _ = write!(pts, "{:.2},{:.2}", x(t1), y(held));
        }
        let _ = writeln!(
            s,
            "<polyline class=\"setpoint\" fill=\"none\" stroke=\"#b06000\" stroke-width=\"1.2\" stroke-dasharray=\"5 3\" points=\"{}\"/>",
            pts.trim_end()
        );
    }
    for line in &lines {
        let mut pts = String::new();
        for (k, (t, v)) in line.iter().enumerate() {
            if k > 0 {
                pts.push(' ');
            }
            let _ = write!(pts, "{:.2},{:.2}", x(*t), y(*v));
        }
        let _ = writeln!(
            s,
            "<polyline class=\"data\" fill=\"none\" stroke=\"#1f4fa0\" stroke-width=\"1.5\" points=\"{pts}\"/>"
        );
    }
    s.push_str("</g>\n</svg>\n");
    s
}

/// A stage label short enough for the top of a timeline.
fn short(label: &str) -> String {
    let mut out: String = label.chars().take(28).collect();
    if label.chars().count() > 28 {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::{RunReport, Series, StepOrigin, StepRecord, Track};
    use std::time::{Duration, SystemTime};

    fn report(hours: u32, every_s: u32) -> RunReport {
        let mut r = RunReport::started(
            "r".into(),
            "r.yaml".into(),
            "d".into(),
            Vec::new(),
            SystemTime::UNIX_EPOCH,
        );
        r.duration = Duration::from_secs(u64::from(hours) * 3600);
        let mut series = crate::session::BucketSeries::new(0.0, 1.0);
        let n = hours * 3600 / every_s;
        for k in 0..n {
            series.push(f64::from(k * every_s), 6000.0 + f64::from(k % 7));
        }
        r.series.push(Series {
            object: "speed_actual".into(),
            unit: Some("rpm".into()),
            step: "3".into(),
            points: series.points(),
            samples: None,
            marks: None,
        });
        r.setpoints = Some(Track {
            object: "speed_setpoint".into(),
            unit: Some("rpm".into()),
            points: vec![(0.0, 0.0), (1.0, 6000.0)],
        });
        r.steps.push(StepRecord {
            number: "2".into(),
            id: "2".into(),
            label: "repeat 2 times".into(),
            origin: StepOrigin {
                path: "r.yaml".into(),
                line: 3,
                column: 3,
            },
            ok: true,
            detail: String::new(),
            started: Duration::from_secs(60),
            duration: Duration::from_secs(60),
            phase: "steps",
        });
        r
    }

    #[test]
    fn a_day_draws_no_more_points_than_a_minute_would_allow() {
        let mut day = String::new();
        timeline(&mut day, &report(24, 1));
        let points = day.matches(',').count();
        assert!(points <= MAX_PLOT_POINTS + 10, "{points} points");
        assert!(day.contains("class=\"setpoint\""));
        assert!(day.contains(">repeat 2 times</text>"), "{day}");
        let mut hour = String::new();
        timeline(&mut hour, &report(1, 1));
        assert!(hour.contains("<h2>Whole run</h2>"));
    }

    #[test]
    fn nothing_sampled_draws_no_timeline() {
        let mut h = String::new();
        let mut r = report(1, 1);
        r.series.clear();
        timeline(&mut h, &r);
        assert!(h.is_empty());
    }
}
