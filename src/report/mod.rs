//! Showing what happened: console lines as the run goes, and (from the run report) the
//! files handed over afterwards. Reads the run's events and report; never talks to a drive.

mod console_reporter;

pub use console_reporter::ConsoleReporter;
