//! The Lenze 931E/K servo positioning controllers over their serial ASCII object
//! protocol: the pure codec, the link (one request line, one checked reply line), object
//! access for the drive layer (with the drive's own limits from `ON`/`OX`), the simulated
//! drive's byte-level front, and the explainer for `decode` and traces.

pub mod codec;
