//! Rhai scripts: the same drive operations as recipes, with logic, in a sandbox. A script
//! is checked before it runs (syntax, and the names, units, states and durations it
//! writes as literals, against the dictionary), then runs on a thread of its own while the
//! session performs its drive calls, so reports, fault watching and the safe stop are
//! those of recipes. Knows the drive API and Rhai; never bytes, ports or families.

mod bridge;
mod drive_api;
mod drive_in_condition;
mod dynamics_api;
mod exchange;
mod last_pass_api;
mod literal_calls;
mod operator_api;
mod param_api;
mod param_value;
mod resolve;
mod sample_tap;
mod sample_window;
mod sandbox;
mod script;
mod script_error;
mod script_header;
mod script_runner;
mod static_check;
mod unknown_calls;
mod watch_api;

pub use sandbox::{
    MAX_ARRAY_SIZE, MAX_CALL_LEVELS, MAX_CSV_FILES, MAX_EXPR_DEPTH, MAX_MAP_SIZE,
    MAX_OPERATIONS_BETWEEN_CALLS, MAX_STRING_SIZE,
};
pub use script::{
    declared_script_drives, declared_script_params, is_script, load_script, load_script_for,
    load_script_text, Script,
};
/// A script that did not pass its check.
pub type ScriptInvalid = crate::diag::FileInvalid;
pub use script_runner::ScriptRunner;
