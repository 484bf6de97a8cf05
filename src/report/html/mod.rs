//! The HTML run report, split by concern: the page and its sections ([`html_page`]), the
//! index page of a command with several files ([`html_index`]), how
//! values are written on it ([`html_text`]), the plots section ([`plot_section`]) with its
//! SVG plots ([`svg_plot`]) and their axes ([`plot_axes`], the time axis in [`time_axis`]),
//! the whole-run timeline ([`timeline`]), the plot of a check across runs
//! ([`trend_plot`]), and the styles
//! (`html_report.css`, included at compile time). Reads the run report; talks to nothing.

mod html_index;
mod html_page;
mod html_text;
mod plot_axes;
mod plot_section;
mod svg_plot;
mod time_axis;
mod timeline;
mod trend_plot;

pub use html_index::{html_index, IndexEntry};
pub use html_page::{html_report, write_html, CSS as REPORT_CSS, IDENTITY_NOT_READ};
pub use html_text::esc;
pub use svg_plot::{plot_svg, LimitLine, MAX_PLOT_POINTS};
pub use trend_plot::{trend_svg, unit_colour, Outcome, TrendMark, TrendPlot, UNIT_COLOURS};
