//! The Lenze 931E/K servo positioning controllers over their serial ASCII object
//! protocol: the pure codec, the link (one request line, one checked reply line), object
//! access for the drive layer (with the drive's own limits from `ON`/`OX`), the simulated
//! drive's byte-level front, and the explainer for `decode` and traces.

pub mod codec;
mod lenze_access;
mod lenze_explainer;
mod lenze_family;
mod lenze_link;
mod maintenance;
pub mod object_address;
pub mod sim;
pub mod wire_value;

pub use lenze_access::LenzeAccess;
pub use lenze_explainer::{status_bits, LenzeExplainer};
pub use lenze_family::Lenze931Family;
pub use lenze_link::{LenzeLink, LinkConfig};
pub use sim::LenzeSimulator;
