//! The generic CANopen family: any CiA 301 node reached by SDO over a CAN frame bus, its
//! objects from the built-in CiA 402 dictionary and the node's own EDS/DCF, device control
//! by the CiA 402 profile. The pure codec, the SDO link and object access (which the Lenze
//! 9400 family speaks too), the simulated CiA 402 node and the explainer.

mod canopen_family;
pub mod codec;
mod nmt_master;
mod node_watch;
mod sdo_access;
mod sdo_explainer;
#[cfg(test)]
mod sdo_explainer_tests;
pub mod sdo_family;
mod sdo_link;
pub mod sdo_value;
pub mod sim;
mod transfer_bytes;

pub use canopen_family::{parse_index_address, CANOPEN_FAMILY};
pub use sdo_access::SdoAccess;
pub use sdo_explainer::{ExplainNotation, SdoExplainer, INDEX_NOTATION};
pub use sdo_link::{index_text, SdoLink, SdoLinkConfig, SdoNotation, CIA_301_NOTATION};
