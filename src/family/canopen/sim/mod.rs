//! Simulated CANopen nodes: the SDO server and the EMCY frames they share (the Lenze
//! 9400's simulated node uses both too) and the CiA 402 drive served from an EDS.

mod cia402_node;
mod cia402_objects;
mod node_emcy;
mod sdo_server;

pub use cia402_node::Cia402Node;
pub use cia402_objects::{Cia402Objects, NODE_EDS};
pub use node_emcy::{emcy_frame, injected_emcy};
pub use sdo_server::{ObjectStore, Place, SdoLogged, SdoServer};
