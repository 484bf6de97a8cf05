//! Drive families: one folder per protocol family (codec, link, object access, simulator
//! front, telegram explainer) and the registry that the command line picks them from.
//! Nothing outside this folder names a family.

pub mod sd2;
