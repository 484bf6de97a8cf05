//! Control Techniques drives (Unidrive SP, Commander SK, Mentor, Unidrive classic) over the
//! ANSI x3.28 serial protocol: the pure codec, the link (one message, one checked reply;
//! group and global writes get none), object access for the drive layer, the simulated
//! drive's byte-level front, and the message explainer for `decode` and traces.

pub mod codec;
mod ct_access;
mod ct_link;
mod echo;
mod link_config;

pub use ct_access::CtAccess;
pub use ct_link::CtLink;
pub use link_config::CtLinkConfig;
mod ct_explainer;
mod ct_family;
pub mod sim;

pub use ct_explainer::CtExplainer;
pub use ct_family::CtFamily;
pub use sim::CtSimulator;

#[cfg(test)]
mod dictionary_tests;
