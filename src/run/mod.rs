//! The application layer: everything a command does with a drive above the session, one
//! way each. A run (recipe or script) is one [`RunPlan`] taken through one pipeline,
//! [`run`]; [`run_many`] runs several files. Also what every command shares to reach a
//! drive: the dictionary choice with bench limits ([`DictionaryArgs`]), the connection
//! ([`ConnectionArgs`]), opening it ([`open_drive`]), the drive-limit comparison and the
//! exit codes. Must not parse a command line or print to the process's own streams
//! except through the writers it is given.

mod address_key_flags;
mod connection_args;
mod drive_args;
pub mod drive_limits;
mod drive_set;
mod exit_code;
mod maintain;
mod not_run;
mod output_args;
mod pipeline;
mod run_error;
mod run_many;
mod run_plan;
mod run_request;
mod run_setup;
mod safe_stop_args;

pub use address_key_flags::{AddressKeyFlag, DNC_ADDRESS};
pub use connection_args::{parse_bitrate, parse_duration, CanSpec, Connection, ConnectionArgs};
pub use drive_args::{open_drive, DictionaryArgs, OpenDrive};
pub use drive_set::drive_dictionaries;
pub use exit_code::*;
pub use maintain::{run_maintain, MaintainRequest, MaintainResult, PrepareMaintained};
pub use output_args::{ColorWhen, OutputArgs};
pub use pipeline::run;
pub use run_error::{BadValue, RunError};
pub use run_many::{outputs_for, run_many, worse};
pub use run_plan::{LoadedPlan, RunPlan};
pub use run_request::{PrepareSimulator, RunRequest, RunResult, SharedObserver};
pub use safe_stop_args::SafeStopArgs;
