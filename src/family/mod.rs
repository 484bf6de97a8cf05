//! Drive families: one folder per protocol family (codec, link, object access, simulator
//! front, telegram explainer) and the registry that the command line picks them from.
//! Nothing outside this folder names a family.

pub mod canopen;
pub mod ct_ansi;
mod documented_code;
mod family;
mod family_error;
mod family_info;
mod integer_value;
pub(crate) mod le_integer;
pub mod lenze_931;
pub mod lenze_9400;
pub mod modbus;
mod registry;
pub mod sd2;

pub use family::{
    serial_line, BuiltinDictionary, DriveAddress, Family, LinkContext, LinkOptions, LinkRange, Opened,
    SimPeer, SimulatedDevice,
};
pub use family_error::FamilyError;
pub use family_info::FamilyInfo;
pub use registry::{Registry, DEFAULT_DICTIONARY};
