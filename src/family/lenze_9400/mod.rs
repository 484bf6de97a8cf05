//! The Lenze 9400 family: parameter access over CANopen SDO on the "CAN on board" system
//! bus. The pure codec, the link (one transfer at a time over a shared frame bus), object
//! access for the drive layer, the simulated node's frame-level front, and the explainer
//! for `decode` and traces.

pub mod codec;
mod lenze_9400_access;
mod lenze_9400_explainer;
mod lenze_9400_family;
mod sdo_link;
pub mod sdo_value;
pub mod sim;

pub use lenze_9400_access::Lenze9400Access;
pub use lenze_9400_explainer::Lenze9400Explainer;
pub use lenze_9400_family::Lenze9400Family;
pub use sdo_link::{object_text, SdoLink, SdoLinkConfig};
