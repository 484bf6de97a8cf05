//! The HTML run report, split by concern: the page and its sections ([`html_page`]), how
//! values are written on it ([`html_text`]), the plots section ([`plot_section`]) with its
//! SVG plots ([`svg_plot`]) and their axes ([`plot_axes`]), and the styles
//! (`html_report.css`, included at compile time). Reads the run report; talks to nothing.

mod html_page;
mod html_text;
mod plot_axes;
mod plot_section;
mod svg_plot;

pub use html_page::{html_report, write_html};
pub use html_text::esc;
pub use svg_plot::MAX_PLOT_POINTS;
