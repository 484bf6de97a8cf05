//! Simulated drives that speak the real protocol bytes: the stand-in for hardware in every
//! test and in `drivescript run` without a port. They must behave like a drive at byte level
//! (decode every request, encode every reply, stay silent on corrupt blocks), be
//! deterministic (same bytes at the same times give the same replies; noise is a seeded
//! xorshift) and cheap (time advances lazily, in closed form, only when a block arrives).
//!
//! [`Sd2Simulator`] is a Sieb & Meyer SD2 at one DNC address: CiA 402 device control,
//! a speed ramp, current, bus voltage and power-stage load, the objects of the project's
//! SD2 dictionary, the DNC 8-byte cyclic telegram with its service channel, and
//! [`FaultInjection`] for the link's error paths.
//!
//! Time: the simulator has no clock. Each `receive(bytes, now)` first advances the model to
//! `now` (splitting the interval at scheduled trips), then answers every complete request at
//! `now + response_latency`. Speed ramps are straight lines toward the state's target:
//! the clamped setpoint at `ramp_rpm_per_s` in operation enabled, 0 at the quick-stop ramp
//! in quick stop active and fault reaction active, 0 at `coast_rpm_per_s` otherwise.
//!
//! Choices the sources leave open, made here and nowhere else:
//! - Status word: b5 (quick stop off) only where the state table requires 1, so switch on
//!   disabled is 0x0240; b4 voltage enabled in ready, switched on, operation enabled and
//!   quick stop active; b9 remote always; b10 target reached in operation enabled when the
//!   speed is within 1 rpm of the setpoint clamped to ±max speed.
//! - Quick stop active and fault reaction active end as soon as the motor is at rest, so a
//!   quick stop or a trip at standstill goes straight through to switch on disabled / fault.
//!   A trip while already in fault (reaction) only replaces the drive error.
//! - Object access: checks run subindex (0x94), access (0x8A / 0x89), length (0x92 longer,
//!   0x93 shorter; 0x91 is never sent), then range. Parameter set: range (0x95) before
//!   state (0x9B). Store parameters (402) accepts only 1, other values 0x95. The ident
//!   string accepts subindex 0..=32 and always returns the whole string.
//! - The cyclic telegram applies its control word, then its speed reference, then the
//!   service channel; the reply shows the result of all three. Its current is signed with
//!   the direction of rotation, like object 400.
//! - Service channel state byte, array index and failures: see `service_channel.rs`.
//! - Injected reply faults are independent, each counting down once per reply the drive
//!   produces; the request behind a lost or damaged reply is still executed.
//! - Requests are logged until [`Sd2Simulator::clear_log`]; [`Sd2Simulator::set_logging`]
//!   turns the log off for long unattended runs.

mod device_state_machine;
mod drive_model;
mod fault_injection;
mod motor;
mod noise;
mod sd2_simulator;
mod service_channel;
mod sim_config;
mod sim_objects;

pub use fault_injection::FaultInjection;
pub use sd2_simulator::Sd2Simulator;
pub use sim_config::SimConfig;
