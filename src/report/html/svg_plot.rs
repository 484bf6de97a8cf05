//! One SVG line plot of a sampled series with the limits of its checks, drawn in data
//! coordinates, and the reduction of long series to the points it draws. Knows nothing of
//! the page around it; the axes' ranges and ticks come from [`super::plot_axes`].

use super::html_text::esc;
use super::plot_axes::{axes, axis_title, grid, padded_range, Area, Scale};
use super::time_axis::TimeAxis;
use crate::session::with_unit;
use crate::session::{number, CheckResult, Series};
use std::fmt::Write as _;

/// Most points a plot's polyline holds; longer series keep the min and max of each bucket.
pub const MAX_PLOT_POINTS: usize = 2000;
// Plot geometry (SVG user units).
const W: f64 = 760.0;
const H: f64 = 320.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 165.0;
const TOP: f64 = 16.0;
const BOTTOM: f64 = 52.0;

/// A limit drawn on a plot, labelled at the right edge with its last value.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitLine {
    /// From each time on (s, as the series' times), the limit's value then (`None`: none
    /// from then on); one step at `-∞`: the same limit across the whole plot.
    pub steps: Vec<(f64, Option<f64>)>,
    pub label: String,
}

impl LimitLine {
    fn values(&self) -> impl Iterator<Item = f64> + '_ {
        self.steps.iter().filter_map(|s| s.1).filter(|v| v.is_finite())
    }

    /// The value at the right edge, which the label names.
    fn last(&self) -> Option<f64> {
        self.steps.last().and_then(|s| s.1).filter(|v| v.is_finite())
    }
}

/// The value range a plot shows: the data decides it; a limit close to it widens it, one
/// far off is marked at the edge, so ±0.5 % of data never shrinks to a flat line under a
/// distant limit.
pub fn value_range(values: impl Iterator<Item = f64> + Clone, limits: &[LimitLine]) -> (f64, f64) {
    let (d0, d1) = padded_range(values.clone(), 0.05);
    let reach = (d1 - d0) * 0.5;
    let near: Vec<f64> = limits
        .iter()
        .flat_map(LimitLine::values)
        .filter(|v| *v >= d0 - reach && *v <= d1 + reach)
        .collect();
    if near.is_empty() {
        (d0, d1)
    } else {
        padded_range(values.chain(near.iter().copied()), 0.05)
    }
}

/// An SVG line plot of a series with the limits of `checks`. The polyline's `points` hold
/// the data itself (time in s, value); a transform maps them onto the plot area.
pub fn plot_svg(series: &Series, checks: &[&CheckResult], id: usize) -> String {
    // Limits of the checks on this object: each value once, across the plot.
    let mut limits: Vec<LimitLine> = Vec::new();
    for c in checks {
        let stat = c.statistic.clone().map(|s| format!("{s} ")).unwrap_or_default();
        let u = c.unit.as_deref().or(series.unit.as_deref());
        let marks: Vec<(f64, String)> = match (c.limits.low, c.limits.high) {
            (Some(lo), Some(hi)) if lo == hi => vec![(lo, format!("{stat}= {}", with_unit(lo, u)))],
            (lo, hi) => lo
                .map(|v| (v, format!("{stat}≥ {}", with_unit(v, u))))
                .into_iter()
                .chain(hi.map(|v| (v, format!("{stat}≤ {}", with_unit(v, u)))))
                .collect(),
        };
        for (v, label) in marks {
            if v.is_finite() && !limits.iter().any(|l| l.last() == Some(v)) {
                limits.push(LimitLine {
                    steps: vec![(f64::NEG_INFINITY, Some(v))],
                    label,
                });
            }
        }
    }
    plot_svg_with_limits(series, &limits, id)
}

/// [`plot_svg`] with its limits as lines: a limit the same throughout is a dashed line
/// across, one that changes a dashed step line.
fn plot_svg_with_limits(series: &Series, limits: &[LimitLine], id: usize) -> String {
    let mut s = String::new();
    let title = axis_title(&series.object, series.unit.as_deref());
    let _ = writeln!(
        s,
        "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {W} {H}\" \
         font-family=\"Helvetica, Arial, sans-serif\" font-size=\"11\" \
         width=\"{W}\" height=\"{H}\" role=\"img\" aria-label=\"{}\">",
        esc(&format!("{title} over time"))
    );
    let _ = writeln!(s, "<title>{}</title>", esc(&format!("{title} over time")));
    let points = finite(&series.points);
    if points.is_empty() {
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no samples</text>\n</svg>",
            W / 2.0,
            H / 2.0
        );
        return s;
    }

    let (t0, t1) = padded_range(points.iter().map(|p| p.0), 0.0);
    let (v0, v1) = value_range(points.iter().map(|p| p.1), limits);
    let area = Area::inside((W, H), (LEFT, RIGHT, TOP, BOTTOM));
    let (x_left, x_right, y_top, y_bottom) = (area.left, area.right, area.top, area.bottom);
    let scale = Scale::new(area, (t0, t1), (v0, v1));
    let (sx, sy) = (scale.sx, scale.sy);
    let x = |t: f64| scale.x(t);
    let y = |v: f64| scale.y(v);

    // Grid and tick labels.
    let time = TimeAxis::elapsed(t0, t1);
    grid(&mut s, area, (&x, &y), &time, (v0, v1), 16.0);
    axes(&mut s, area, &time.title, H - 12.0, &title);

    // The data, clipped to the plot area, in data coordinates.
    let _ = writeln!(
        s,
        "<clipPath id=\"plot-area-{id}\"><rect x=\"{x_left}\" y=\"{y_top}\" width=\"{:.2}\" height=\"{:.2}\"/></clipPath>",
        x_right - x_left,
        y_bottom - y_top
    );
    let _ = write!(
        s,
        "<g clip-path=\"url(#plot-area-{id})\">\n<polyline class=\"data\" fill=\"none\" stroke=\"#1f4fa0\" stroke-width=\"1.5\" \
         vector-effect=\"non-scaling-stroke\" \
         transform=\"matrix({sx} 0 0 {} {} {})\" points=\"",
        -sy,
        x_left - t0 * sx,
        y_bottom + v0 * sy
    );
    for (k, (t, v)) in downsample(&points).iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{},{}", number(*t), number(*v));
    }
    s.push_str("\"/>\n");
    // Limits: dashed lines across inside the range, labelled on the right; a limit outside
    // the range is a label at the edge it lies beyond, with an arrow.
    for l in limits {
        match l.steps.as_slice() {
            [(_, Some(v))] => {
                if (v0..=v1).contains(v) {
                    let py = y(*v);
                    let _ = writeln!(
                        s,
                        "<line class=\"limit\" stroke=\"#b00000\" stroke-dasharray=\"6 4\" x1=\"{x_left}\" y1=\"{py:.2}\" x2=\"{x_right}\" y2=\"{py:.2}\"/>"
                    );
                }
            }
            steps => step_line(&mut s, steps, &x, &y, (x_left, x_right)),
        }
    }
    response_marks(&mut s, series, &x, &y, (y_top, y_bottom));
    s.push_str("</g>\n");
    let mut labels: Vec<(f64, String)> = limits
        .iter()
        .filter_map(|l| l.last().map(|v| (v, &l.label)))
        .map(|(v, label)| {
            if v > v1 {
                (y_top + 4.0, format!("↑ {label}"))
            } else if v < v0 {
                (y_bottom, format!("↓ {label}"))
            } else {
                (y(v) + 4.0, label.clone())
            }
        })
        .collect();
    spread_labels(&mut labels, 13.0, y_top + 4.0, y_bottom);
    for (py, label) in &labels {
        let _ = writeln!(
            s,
            "<text class=\"limit-label\" fill=\"#b00000\" x=\"{:.2}\" y=\"{py:.2}\">{}</text>",
            x_right + 4.0,
            esc(label)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// A limit that changes along the plot as a dashed step line (clipped to the plot area):
/// each value from its time to the next one's, nothing where there is none.
pub(super) fn step_line(
    s: &mut String,
    steps: &[(f64, Option<f64>)],
    x: &dyn Fn(f64) -> f64,
    y: &dyn Fn(f64) -> f64,
    (left, right): (f64, f64),
) {
    let mut d = String::new();
    for (k, (t, v)) in steps.iter().enumerate() {
        let Some(v) = v.filter(|v| v.is_finite()) else {
            continue;
        };
        let from = x(*t).max(left);
        let to = steps.get(k + 1).map_or(right, |next| x(next.0).min(right));
        // Down or up from the value before, else a line of its own.
        let _ = match k > 0 && steps[k - 1].1.is_some_and(f64::is_finite) {
            true => write!(d, "V{:.2} H{to:.2} ", y(v)),
            false => write!(d, "M{from:.2} {:.2} H{to:.2} ", y(v)),
        };
    }
    if !d.is_empty() {
        let _ = writeln!(
            s,
            "<path class=\"limit\" fill=\"none\" stroke=\"#b00000\" stroke-dasharray=\"6 4\" d=\"{}\"/>",
            d.trim_end()
        );
    }
}

/// Where a window's step response was measured: a vertical line where it crossed 10 % and
/// 90 % of the step and where it settled, a ring on the peak, each labelled.
fn response_marks(
    s: &mut String,
    series: &Series,
    x: &dyn Fn(f64) -> f64,
    y: &dyn Fn(f64) -> f64,
    (top, bottom): (f64, f64),
) {
    let Some(m) = series.marks else {
        return;
    };
    let lines = [
        (m.rise_start, "10 %"),
        (m.rise_end, "90 %"),
        (m.settled, "settled"),
    ];
    for (k, (t, label)) in lines.iter().enumerate() {
        let Some(t) = t.filter(|t| t.is_finite()) else {
            continue;
        };
        let px = x(t);
        let _ = writeln!(
            s,
            "<line class=\"marker\" stroke=\"#2a7a2a\" stroke-dasharray=\"3 2\" x1=\"{px:.2}\" y1=\"{top}\" x2=\"{px:.2}\" y2=\"{bottom}\"/>\
             <text class=\"marker-label\" fill=\"#2a7a2a\" x=\"{:.2}\" y=\"{:.2}\" font-size=\"10\">{label}</text>",
            px + 3.0,
            top + 12.0 + 12.0 * k as f64
        );
    }
    if let Some((t, v)) = m.peak.filter(|(t, v)| t.is_finite() && v.is_finite()) {
        let (px, py) = (x(t), y(v));
        let _ = writeln!(
            s,
            "<circle class=\"marker\" fill=\"none\" stroke=\"#2a7a2a\" stroke-width=\"1.5\" cx=\"{px:.2}\" cy=\"{py:.2}\" r=\"5\"/>\
             <text class=\"marker-label\" fill=\"#2a7a2a\" x=\"{:.2}\" y=\"{:.2}\" font-size=\"10\">peak</text>",
            px + 7.0,
            py - 6.0
        );
    }
}

/// Moves label baselines apart so that no two are closer than `gap`, keeping them between
/// `top` and `bottom` where there is room; the order of the labels is kept.
pub fn spread_labels(labels: &mut [(f64, String)], gap: f64, top: f64, bottom: f64) {
    labels.sort_by(|a, b| a.0.total_cmp(&b.0));
    for i in 1..labels.len() {
        if labels[i].0 < labels[i - 1].0 + gap {
            labels[i].0 = labels[i - 1].0 + gap;
        }
    }
    // Pushed past the bottom: shift the whole stack up as far as the top allows.
    if let Some(last) = labels.last().map(|l| l.0) {
        let over = (last - bottom).max(0.0);
        let room = labels.first().map_or(0.0, |l| (l.0 - top).max(0.0));
        let shift = over.min(room);
        for l in labels.iter_mut() {
            l.0 -= shift;
        }
        for i in (0..labels.len().saturating_sub(1)).rev() {
            if labels[i].0 > labels[i + 1].0 - gap {
                labels[i].0 = labels[i + 1].0 - gap;
            }
        }
    }
}

pub fn finite(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(t, v)| t.is_finite() && v.is_finite())
        .collect()
}

/// At most [`MAX_PLOT_POINTS`] points: all of them, or per bucket of consecutive points
/// its minimum and maximum in time order, so peaks stay visible.
pub fn downsample(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    downsample_to(points, MAX_PLOT_POINTS)
}

/// [`downsample`] to at most `cap` points (at least 2).
pub fn downsample_to(points: &[(f64, f64)], cap: usize) -> Vec<(f64, f64)> {
    let cap = cap.max(2);
    if points.len() <= cap {
        return points.to_vec();
    }
    let buckets = cap / 2;
    let mut out = Vec::with_capacity(cap);
    for b in 0..buckets {
        let start = b * points.len() / buckets;
        let end = ((b + 1) * points.len() / buckets).min(points.len());
        let chunk = &points[start..end];
        if chunk.is_empty() {
            continue;
        }
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[lo].1 {
                lo = i;
            }
            if p.1 > chunk[hi].1 {
                hi = i;
            }
        }
        let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(chunk[a]);
        if b != a {
            out.push(chunk[b]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_series_are_downsampled_keeping_peaks() {
        let mut points: Vec<(f64, f64)> = (0..100_000).map(|i| (f64::from(i) * 0.01, 1.0)).collect();
        points[54_321].1 = 99.0;
        points[77_777].1 = -42.0;
        let d = downsample(&points);
        assert!(
            d.len() <= MAX_PLOT_POINTS && d.len() > MAX_PLOT_POINTS / 2,
            "{}",
            d.len()
        );
        assert!(d.contains(&points[54_321]) && d.contains(&points[77_777]));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0), "in time order");
    }

    #[test]
    fn labels_are_spread() {
        let mut labels: Vec<(f64, String)> = [(100.0, "a"), (101.0, "b"), (99.0, "c"), (300.0, "d")]
            .map(|(y, l)| (y, l.to_string()))
            .into();
        spread_labels(&mut labels, 13.0, 20.0, 300.0);
        let ys: Vec<f64> = labels.iter().map(|l| l.0).collect();
        assert!(ys.windows(2).all(|w| w[1] - w[0] >= 13.0 - 1e-9), "{ys:?}");
        assert!(ys.iter().all(|y| (20.0..=300.0).contains(y)), "{ys:?}");
        assert_eq!(labels[0].1, "c", "order kept");
    }
}
