//! Why bytes are no valid Modbus PDU, RTU frame or MBAP frame, or why a request cannot be
//! built: what was expected and what came.

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CodecError {
    #[error("{what} is {len} byte(s); expected {expected}")]
    Length {
        what: &'static str,
        len: usize,
        expected: String,
    },
    #[error(
        "function code {0:#04x} is not one drivescript speaks (03, 04, 06, 16, 23 and their exceptions)"
    )]
    Function(u8),
    #[error("{what} is {value}; the specification allows {allowed}")]
    Quantity {
        what: &'static str,
        value: usize,
        allowed: &'static str,
    },
    #[error("the byte count is {count} but {actual} data byte(s) follow")]
    ByteCount { count: usize, actual: usize },
    #[error("bad CRC: the frame ends {:02X} {:02X}, its bytes give {:02X} {:02X}", *carried as u8, carried >> 8, *computed as u8, computed >> 8)]
    Crc { carried: u16, computed: u16 },
    #[error("the MBAP protocol identifier is {0}; Modbus is 0")]
    Protocol(u16),
    #[error("the MBAP length field says {field}, but {actual} byte(s) follow it")]
    MbapLength { field: usize, actual: usize },
    /// A well-formed response that does not answer the request it came for.
    #[error("a reply to {function} ({expected})")]
    NotTheAnswer {
        function: &'static str,
        expected: String,
    },
}
