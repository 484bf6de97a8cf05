//! One protocol-independent drive API: read and write objects by name with units, issue
//! device-control commands, read the state, walk the state machine. Each protocol family
//! implements the small [`ObjectAccess`] trait underneath. Knows names and units, not bytes.

mod access_error;
mod address_keys;
pub mod device_control;
mod drive;
mod drive_error;
mod maintenance;
mod object_access;
pub mod state_path;
pub mod stop_direction;

pub use access_error::AccessError;

/// The port name of the built-in simulated drive: every report marks a run on it as
/// simulated beside its verdict.
pub const SIMULATED_PORT: &str = "built-in simulated drive";
pub use address_keys::{
    AddressKey, AddressKeyTable, AddressKeys, FamilyAddressKeys, KeyProblem, KeyUse, KeyValues, ToAddress,
};
pub use device_control::{DeviceCommand, DeviceState};
pub use drive::{Drive, ReadSet, Transition, ValueLimits};
pub use drive_error::DriveError;
pub use maintenance::{MaintenanceAction, MaintenanceClearance, MaintenanceOutcome};
pub use object_access::{DriveLimits, ObjectAccess, WriteOutcome, WriteResult};
pub use state_path::{next_step, NextStep};
