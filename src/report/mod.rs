//! Showing what happened: console lines as the run goes, and (from the run report) the
//! files handed over afterwards. Reads the run's events and report; never talks to a drive.

mod atomic_write;
pub(crate) mod case_names;
mod console_color;
mod console_reporter;
mod csv_recorder;
mod html;
mod junit_report;
mod junit_xml_writer;
mod open_attempts;
mod progress_reporter;
mod telegram_fan_out;
mod trace_header;
mod trace_writer;
mod unfinished_report;
mod visible_text;

pub use atomic_write::{replace, tmp_path, write_atomically, ReportWriteError};
pub use console_color::{color_wanted, paint};
pub use console_reporter::{
    check_line, container_line, header_lines, message_line, step_line, summary_lines, ConsoleReporter,
};
pub use csv_recorder::{CsvRecorder, CSV_HEADER};
pub use html::{
    esc, html_index, html_report, plot_svg, trend_svg, unit_colour, write_html, IndexEntry, LimitLine,
    Outcome, TrendMark, TrendPlot, IDENTITY_NOT_READ, MAX_PLOT_POINTS, REPORT_CSS, UNIT_COLOURS,
};
pub use junit_report::{junit_document, junit_suite, junit_xml, write_junit, JunitSuite};
pub use junit_xml_writer::XmlWriter;
pub use open_attempts::OpenAttempts;
pub use progress_reporter::{progress_text, ProgressReporter};
pub use telegram_fan_out::TelegramFanOut;
pub use trace_header::{trace_notes_path, TraceHeader};
pub use trace_writer::{hex_of_trace_line, is_trace_line, TraceWriter};
pub use unfinished_report::{
    html_not_run, html_unfinished, junit_not_run, junit_not_run_suite, junit_skipped_suite, junit_unfinished,
    junit_unfinished_suite, write_unfinished,
};
pub use visible_text::{visible, visible_inline};
