//! The report writers (JUnit, HTML, live progress) fed with sample run reports, their files
//! read back with real XML and HTML parsers.

mod html_report;
mod junit_report;
pub mod markup;
mod progress_reporter;
mod sample_reports;
mod unfinished_report;
