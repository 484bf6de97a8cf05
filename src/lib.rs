//! drivescript: a recipe engine for commissioning and testing servo and spindle drives.
//!
//! Data flows one way: `cli` → `recipe`/`script` → `drive` → `link` → `transport`.
//! The codecs in [`protocol`] are pure; only `transport` touches I/O.

pub mod cli;
pub mod clock;
pub mod hex;
pub mod protocol;
pub mod transport;
