//! The simulated 931 as a byte-level peer: it cuts request lines with the codec's line
//! extractor, answers each with the reply line a drive sends, and maps its objects onto
//! the family-neutral drive model in `crate::sim`.
//!
//! The sources give no object numbers beyond the command syntax, so the simulator's
//! object table (`sim_objects.rs`) is its own choice, documented there and used by the
//! tests' completed dictionary; a real drive's numbers come from the user's dictionary.
//! Other choices made here and nowhere else:
//! - A write beyond the speed setpoint's limits is stored limited (codes 4/5); a write
//!   beyond the operating mode's range is refused (codes 2/3), and while enabled refused
//!   with code 9; a control-word value that is no known command is refused with code 8.
//! - Garbage and over-long lines are answered `ERROR!`, like any unknown command.
//! - `INIT!` and `RESET!` both restart the drive model with its defaults (switch on
//!   disabled, setpoint 0, operating mode 0) and answer a switch-on message of the
//!   simulator's own (`931 SIMULATED: …`; a real drive's text is not in the sources).
//!   `SAVE!` keeps the operating mode as the flash's; `SEP!` loads it back. `BAUDbbbb`
//!   is answered `OK!` and remembered ([`LenzeSimulator::line_rate`]); the simulated line
//!   keeps working at any rate.
//! - Injected faults: a dropped reply is not sent; a "corrupt" reply has one character
//!   replaced by `#` (ASCII lines have no checksum); a "wrong address" value reply names
//!   the next object number. [`LenzeSimulator::set_echo`] and
//!   [`LenzeSimulator::set_crlf`] make it echo requests and end replies with CR LF.

mod lenze_simulator;
mod sim_objects;

pub use lenze_simulator::LenzeSimulator;
pub use sim_objects::SimObject;
