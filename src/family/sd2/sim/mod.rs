//! The simulated SD2 drive's byte-level front: the SD2 object table, Read/Write Wide Object,
//! the cyclic telegram and its service channel over the family-neutral drive model in
//! `crate::sim` (see there for the model and the choices it makes). It decodes every
//! request and encodes every reply with the codec, and stays silent on corrupt blocks.
//!
//! Choices the sources leave open, made here and nowhere else:
//! - Object access: checks run subindex (0x94), access (0x8A / 0x89), length (0x92 longer,
//!   0x93 shorter; 0x91 is never sent), then range. Parameter set: range (0x95) before
//!   state (0x9B). Store parameters (402) accepts only 1, other values 0x95. The ident
//!   string accepts subindex 0..=32 and always returns the whole string.
//! - The cyclic telegram applies its control word, then its speed reference, then the
//!   service channel; the reply shows the result of all three. Its current is signed with
//!   the direction of rotation, like object 400.
//! - Service channel state byte, array index and failures: see `service_channel.rs`.
//! - Requests are logged until [`Sd2Simulator::clear_log`]; [`Sd2Simulator::set_logging`]
//!   turns the log off for long unattended runs.

mod sd2_objects;
mod sd2_simulator;
mod service_channel;
mod sim_objects;

pub use crate::sim::SimConfig;
pub use sd2_simulator::Sd2Simulator;
