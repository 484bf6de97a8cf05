//! The family-neutral simulated drive: the stand-in for hardware in every test and in
//! `drivescript run` without a port. A device-control state machine (the CiA 402 states and
//! transitions), a spindle with a speed ramp, current, bus voltage and power-stage load,
//! deterministic noise (seeded xorshift), and [`FaultInjection`] for the error paths. Each
//! family's simulator front (under `family/<id>/sim/`) speaks the real bytes of its
//! protocol and maps its objects onto this model; nothing here knows bytes or objects.
//!
//! Time: the model has no clock. It is advanced lazily to the time of each request it is
//! given, in closed form (a two-hour run-in is one subtraction per poll). Speed ramps are
//! straight lines toward the state's target: the clamped setpoint at `ramp_rpm_per_s` in
//! operation enabled, 0 at the quick-stop ramp in quick stop active and fault reaction
//! active, 0 at `coast_rpm_per_s` otherwise (friction: a coast-down from v₁ to v₂ takes
//! (v₁ − v₂) / `coast_rpm_per_s`). With a `response` configured (`--sim response-time=…`,
//! `--sim overshoot=…`), operation enabled follows a setpoint step as a speed controller
//! does instead of ramping: first order, or second order with the given overshoot (see
//! [`Response`]). The motor temperature follows the load in first order: toward ambient +
//! `heating_k_per_a` × the current at the target speed, with `thermal_time_constant`; each
//! change of target or state restarts it from the temperature reached (the heat of the
//! seconds-long transients is left out, as it is small against a thermal time constant of
//! minutes).
//!
//! Choices the sources leave open, made here and nowhere else:
//! - Status word: b5 (quick stop off) only where the state table requires 1, so switch on
//!   disabled is 0x0240; b4 voltage enabled in ready, switched on, operation enabled and
//!   quick stop active; b9 remote always; b10 target reached in operation enabled when the
//!   speed is within 1 rpm of the setpoint clamped to ±max speed.
//! - Quick stop active and fault reaction active end as soon as the motor is at rest, so a
//!   quick stop or a trip at standstill goes straight through to switch on disabled / fault.
//!   A trip while already in fault (reaction) only replaces the drive error.
//! - Injected reply faults are independent, each counting down once per reply the drive
//!   produces; the request behind a lost or damaged reply is still executed.

mod device_state_machine;
mod drive_model;
mod fault_injection;
mod motor;
mod noise;
pub mod replay;
mod request_log;
mod sim_config;
mod sim_core;
mod sim_setting;
mod simulated_drive;
mod thermal;

pub use drive_model::{DriveModel, ModelRefusal};
pub use fault_injection::FaultInjection;
pub use motor::Response;
pub use request_log::{keep_recent, LOG_KEEPS};
pub use sim_config::SimConfig;
pub use sim_core::{SimCore, SimFront};
pub use sim_setting::{SimSetting, SimSettingError};
pub use simulated_drive::SimulatedDrive;
