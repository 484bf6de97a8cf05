//! drivescript: a recipe engine for commissioning and testing servo and spindle drives.
//!
//! Data flows one way: `main` (builds the [`family::Registry`] once) → [`cli`] (parses,
//! prints, exit codes) → [`run`] (the application layer: one pipeline for a recipe or a
//! script, the policies around it) → [`recipe`]/[`script`] (turn a file into session
//! operations) → [`session`] (operations, the verified safe stop, the run report) →
//! [`drive`] (names, units, limits, device control, the maintenance interlock) →
//! `family/<id>` (codec, link on the shared [`link`] core, object access, simulator front)
//! → [`bus`] (byte transports and CAN frame buses). The codecs are pure; only `bus`
//! touches I/O. [`report`] turns session events and telegrams into console lines, CSV,
//! traces, JUnit and HTML. Every file drivescript reads (recipes, dictionaries, limits) is
//! read through [`diag`]: one diagnostic type and one YAML field reader.

// Errors here carry structured context (port, telegram, object, expected vs. actual) and
// travel on cold paths of a tool that waits milliseconds per telegram; boxing them would
// cost readability and buy nothing measurable.
#![allow(clippy::result_large_err)]
// Files are named after their one main type, so `drive/drive.rs` holds `Drive`.
#![allow(clippy::module_inception)]

pub mod bus;
pub mod calendar;
pub mod cli;
pub mod clock;
pub mod csv_file;
pub mod diag;
pub mod dictionary;
pub mod drive;
pub mod family;
pub mod hex;
pub mod link;
pub mod output_file_error;
pub mod parameters;
pub mod recipe;
pub mod report;
pub mod results;
pub mod run;
#[cfg(test)]
pub(crate) mod scratch_dir;
pub mod script;
pub mod session;
pub mod sim;
pub mod sim_server;
pub mod station;
pub mod stop_request;
pub mod store_site;
pub mod web;
