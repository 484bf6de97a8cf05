//! The Sieb & Meyer SD2 / SD2S family over the DNC serial protocol: the pure codec, the
//! link (one request, one checked reply), object access for the drive layer, the simulated
//! drive's byte-level front, and the telegram explainer for `decode` and traces.

mod address_keys;
pub mod codec;
mod cyclic_access;
mod cyclic_settings;
mod link_config;
mod object_names;
mod sd2_access;
mod sd2_explainer;
mod sd2_family;
mod sd2_link;
pub mod sim;
pub mod wire_value;

pub use address_keys::SD2_ADDRESS_KEYS;
pub use cyclic_access::Sd2CyclicAccess;
pub use cyclic_settings::{Channel, CyclicSettings};
pub use link_config::LinkConfig;
pub use object_names::ObjectNames;
pub use sd2_access::Sd2Access;
pub use sd2_explainer::{explain, Sd2Explainer};
pub use sd2_family::Sd2Family;
pub use sd2_link::Sd2Link;
pub use sim::{Sd2Simulator, SimConfig};

#[cfg(test)]
mod dictionary_tests;
