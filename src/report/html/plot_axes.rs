//! The axes of a plot: the value range with its margins, round tick values, an axis'
//! title, and the grid with its tick labels and the axes with their titles as SVG text
//! (the time axis' ticks from [`super::time_axis`]). Pure arithmetic and text.

use super::html_text::esc;
use super::time_axis::TimeAxis;
use crate::session::number;
use std::fmt::Write as _;

/// The plot area of an SVG, in its user units.
#[derive(Debug, Clone, Copy)]
pub struct Area {
    pub left: f64,
    pub right: f64,
    pub top: f64,
    pub bottom: f64,
}

impl Area {
    /// The plot area of a `width` × `height` SVG within its margins.
    pub fn inside((width, height): (f64, f64), (left, right, top, bottom): (f64, f64, f64, f64)) -> Area {
        Area {
            left,
            right: width - right,
            top,
            bottom: height - bottom,
        }
    }
}

/// Where a plot draws: times `t0..t1` across its area, values `v0..v1` up it.
#[derive(Debug, Clone, Copy)]
pub struct Scale {
    area: Area,
    t0: f64,
    v0: f64,
    /// Units across per second, and up per unit of value.
    pub sx: f64,
    pub sy: f64,
}

impl Scale {
    pub fn new(area: Area, (t0, t1): (f64, f64), (v0, v1): (f64, f64)) -> Scale {
        Scale {
            area,
            t0,
            v0,
            sx: (area.right - area.left) / (t1 - t0),
            sy: (area.bottom - area.top) / (v1 - v0),
        }
    }

    /// Where time `t` is drawn across.
    pub fn x(&self, t: f64) -> f64 {
        self.area.left + (t - self.t0) * self.sx
    }

    /// Where value `v` is drawn up.
    pub fn y(&self, v: f64) -> f64 {
        self.area.bottom - (v - self.v0) * self.sy
    }
}

/// The grid lines of `time`'s ticks and of round values across `area`, each labelled:
/// times `gap` below the area, values left of it.
pub fn grid(
    s: &mut String,
    area: Area,
    (x, y): (&dyn Fn(f64) -> f64, &dyn Fn(f64) -> f64),
    time: &TimeAxis,
    (v0, v1): (f64, f64),
    gap: f64,
) {
    let Area {
        left,
        right,
        top,
        bottom,
    } = area;
    for (t, label) in &time.ticks {
        let px = x(*t);
        let _ = writeln!(
            s,
            "<line class=\"grid\" stroke=\"#ddd\" x1=\"{px:.2}\" y1=\"{top}\" x2=\"{px:.2}\" y2=\"{bottom}\"/>\
             <text x=\"{px:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            bottom + gap,
            esc(label)
        );
    }
    for tick in ticks(v0, v1) {
        let py = y(tick);
        let _ = writeln!(
            s,
            "<line class=\"grid\" stroke=\"#ddd\" x1=\"{left}\" y1=\"{py:.2}\" x2=\"{right}\" y2=\"{py:.2}\"/>\
             <text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
            left - 6.0,
            py + 4.0,
            number(round_to(tick, 9))
        );
    }
}

/// The axes along the left and the bottom of `area`, the time axis' title centred at
/// height `time_title_y`, and `title` turned along the value axis.
pub fn axes(s: &mut String, area: Area, time_title: &str, time_title_y: f64, title: &str) {
    let (left, right, top, bottom) = (area.left, area.right, area.top, area.bottom);
    let _ = writeln!(
        s,
        "<line class=\"axis\" stroke=\"#111\" x1=\"{left}\" y1=\"{bottom}\" x2=\"{right}\" y2=\"{bottom}\"/>\
         <line class=\"axis\" stroke=\"#111\" x1=\"{left}\" y1=\"{top}\" x2=\"{left}\" y2=\"{bottom}\"/>"
    );
    let _ = writeln!(
        s,
        "<text class=\"axis-title\" x=\"{:.2}\" y=\"{time_title_y:.2}\" text-anchor=\"middle\">{}</text>",
        (left + right) / 2.0,
        esc(time_title)
    );
    let (tx, ty) = (16.0, (top + bottom) / 2.0);
    let _ = writeln!(
        s,
        "<text class=\"axis-title\" x=\"{tx}\" y=\"{ty:.2}\" text-anchor=\"middle\" transform=\"rotate(-90 {tx} {ty:.2})\">{}</text>",
        esc(title)
    );
}

/// The range of `values`, widened by `pad` of its width on each side; never empty.
pub fn padded_range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() || !hi.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo <= f64::EPSILON * hi.abs().max(1.0) {
        let half = (lo.abs() * 0.01).max(0.5);
        return (lo - half, hi + half);
    }
    let margin = (hi - lo) * pad;
    (lo - margin, hi + margin)
}

/// Four to nine round tick values (1, 2 or 5 × 10^n apart) inside `lo..=hi`.
pub fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let raw = (hi - lo) / 8.0;
    if raw <= 0.0 || !raw.is_finite() {
        return vec![lo];
    }
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// `v` rounded to `decimals` places, so that a tick reads 0.3 rather than 0.30000000000000004.
pub fn round_to(v: f64, decimals: i32) -> f64 {
    let f = 10f64.powi(decimals);
    (v * f).round() / f
}

/// `speed_actual [rpm]`: the object with its unit, as axes and captions name a series.
pub fn axis_title(object: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{object} [{u}]"),
        None => object.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round() {
        assert_eq!(ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(
            ticks(5967.0, 6033.0),
            vec![5970.0, 5980.0, 5990.0, 6000.0, 6010.0, 6020.0, 6030.0]
        );
    }
}
