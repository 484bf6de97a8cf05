//! Pure protocol codecs: bytes in, typed telegrams out, and back. No I/O, no clocks;
//! every decode error says what was expected and what arrived.

pub mod sd2;
