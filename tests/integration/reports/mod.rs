//! The report writers fed with sample run reports, their files read back with real
//! parsers.

mod junit_report;
mod markup;
mod sample_reports;
