//! Counters of what a link did, for reports and the benchmark.

/// Totals since the link was opened.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LinkStats {
    pub requests: u64,
    pub replies: u64,
    pub retries: u64,
    pub timeouts: u64,
    pub corrupt_replies: u64,
    pub mismatched_replies: u64,
    /// Our own messages handed back by a half-duplex RS485 adapter and skipped.
    pub echoes: u64,
}
