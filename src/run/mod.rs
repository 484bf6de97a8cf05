//! The application layer, between the command line and the session. One run of a recipe
//! or a script is one [`RunPlan`] taken through one pipeline, [`run`]: load and check the
//! file against each drive's dictionary, open the output files (with placeholders that
//! replace an earlier run's reports at once), open the drives (one, or each named one; the
//! ones on one line share one bus), say early when one never answers, compare every value
//! the file is known to write with the limits the drive itself reports, run with the safe
//! stop at every ending, and write the console, CSV, trace, JUnit and HTML reports; a run
//! that never starts writes its not-run JUnit and HTML. [`run_many`] runs several files,
//! each with its own outputs (one JUnit file and an index page for all), to the worst
//! exit code. [`check`] loads a file the way a run does and, given a port, compares what
//! it writes with the drive's own limits, for `check` to say. Features that follow a run
//! plug in as [`RunRequest::observers`]. Also what every command shares to reach a drive: the
//! dictionary with its bench limits ([`DictionaryArgs`]), the connection
//! ([`ConnectionArgs`], address-key flags such as `--dnc-address`), [`open_drive`], the
//! maintenance flow over the drive layer's interlock ([`run_maintain`]), typed errors
//! ([`RunError`]) and the exit codes.
//!
//! Must not parse a command line (the option structs derive clap's `Args` so that `cli`
//! can flatten them, nothing more), must not name a family, and writes only to the
//! writers it is given (except the `-v` telegram lines and the live progress bar, which
//! belong to the process's standard error and terminal).

mod address_key_flags;
mod anonymise;
mod answers_check;
mod check;
mod connection_args;
mod drive_args;
pub mod drive_limits;
mod drive_set;
mod exit_code;
mod latency_note;
mod line_exchange;
mod link_range_check;
mod locked_observer;
mod maintain;
mod not_run;
mod operator_args;
mod output_args;
mod output_names;
mod pipeline;
mod record_args;
mod replay_connection;
mod run_error;
mod run_many;
mod run_operator;
mod run_options;
mod run_plan;
mod run_request;
mod run_setup;
mod safe_stop_args;
mod several_reports;
mod several_sets;
mod sim_settings_check;
mod terminal_input;
mod verdict_rule;
mod watch_line_check;

pub use address_key_flags::{AddressKeyFlag, DNC_ADDRESS};
pub use anonymise::{anonymise_capture, AnonymiseError};
pub use check::{check, CheckRequest, Checked};
pub use connection_args::{parse_bitrate, parse_duration, CanSpec, Connection, ConnectionArgs};
pub use drive_args::{open_drive, DictionaryArgs, OpenDrive};
pub use drive_set::drive_dictionaries;
pub use exit_code::*;
pub use link_range_check::{quantised_values, within_link_range};
pub use maintain::{run_maintain, MaintainRequest, MaintainResult, PrepareMaintained};
pub use not_run::{another_family, silent_drive};
pub use operator_args::OperatorArgs;
pub use output_args::{ColorWhen, OutputArgs};
pub use output_names::{outputs_named, unit_before_start};
pub use pipeline::run;
pub use record_args::RecordArgs;
pub use replay_connection::{captured_drive, recorded_drive};
pub use run_error::{BadValue, RunError};
pub use run_many::{outputs_for, run_many, worse};
pub use run_operator::RunOperator;
pub use run_options::{parse_set, RunOptions};
pub use run_plan::{LoadedPlan, RunPlan};
pub use run_request::{PrepareSimulator, RunRequest, RunResult, SharedObserver};
pub use safe_stop_args::SafeStopArgs;
pub use sim_settings_check::{check_sim_settings, sim_checked};
pub use terminal_input::TerminalInput;
pub use verdict_rule::settle;
pub use watch_line_check::watches_fit_the_line;
