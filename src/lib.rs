//! drivescript: a recipe engine for commissioning and testing servo and spindle drives.
//!
//! Data flows one way: `cli` → `recipe`/`script` → `drive` → `link` → `transport`.
//! The codecs in [`protocol`] are pure; only `transport` touches I/O.
//! Every file drivescript reads (recipes, dictionaries, limits) is read through [`diag`]: one
//! diagnostic type and one YAML field reader.

// Errors here carry structured context (port, telegram, object, expected vs. actual) and
// travel on cold paths of a tool that waits milliseconds per telegram; boxing them would
// cost readability and buy nothing measurable.
#![allow(clippy::result_large_err)]
// Files are named after their one main type, so `drive/drive.rs` holds `Drive`.
#![allow(clippy::module_inception)]

pub mod bus;
pub mod cli;
pub mod clock;
pub mod csv_file;
pub mod diag;
pub mod dictionary;
pub mod drive;
pub mod family;
pub mod hex;
pub mod link;
pub mod parameters;
pub mod recipe;
pub mod report;
pub mod run;
pub mod script;
pub mod session;
pub mod sim;
pub mod sim_server;
pub mod stop_request;
