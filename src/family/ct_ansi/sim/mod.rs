//! The simulated Control Techniques drive: a byte-level front that speaks ANSI x3.28 in
//! front of the family-neutral drive model (`crate::sim`), with the Unidrive SP parameters
//! of the built-in dictionary mapped onto it.
//!
//! Choices the sources leave open, made here and nowhere else:
//! - The drive follows the speed reference #1.21 whatever #1.14 says (#1.14 reads 3, Pr).
//! - The control word #6.42 acts when #6.43 = 1 and its AUTO bit 7 is set: ENABLE off
//!   disables (the CiA model's disable voltage), ENABLE without a run bit (RUN FWD, RUN REV,
//!   RUN) stops into "enabled, not running" (switched on), ENABLE with a run bit runs
//!   (operation enabled). A tripped drive ignores it until a reset; after the reset it waits
//!   for the next control word rather than restarting.
//! - #10.38 = 100 resets a trip; other values than 0 and 100 are refused (NAK).
//! - Zero speed (#10.03) within 5 rpm; at speed (#10.06) within 1 rpm of the reference while
//!   active. Software version #11.29 reads 1.10.
//! - Replies 1 ms after a message (the earliest the sources give). A read of a group or
//!   global address gets no answer (it would collide on a shared line).

mod ct_parameters;
mod ct_simulator;

pub use ct_simulator::CtSimulator;
