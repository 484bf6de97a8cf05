//! Settings of the SD2 link: how long to wait, how often to retry, how to frame writes.

use crate::family::sd2::codec::{WriteLength, MASTER_ADDRESS};
use std::time::Duration;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkConfig {
    /// How long to wait for a reply. The vendor's PC tool uses 1 s; drives answer within
    /// 250 µs, so anything longer is a lost telegram rather than a slow drive.
    pub reply_timeout: Duration,
    /// Further attempts after a timeout or a corrupt or mismatched reply.
    pub retries: u32,
    /// Before a retry, the line is listened to for this long and whatever arrives is
    /// thrown away: the protocol has no sequence numbers, so a late answer to the failed
    /// attempt would otherwise be taken for the answer to the retry.
    pub settle: Duration,
    /// The length field sent in Write Wide Object commands.
    pub write_length: WriteLength,
    /// The PC's own DNC address.
    pub master_address: u8,
}

impl Default for LinkConfig {
    fn default() -> Self {
        LinkConfig {
            reply_timeout: Duration::from_secs(1),
            retries: 2,
            settle: Duration::from_millis(20),
            write_length: WriteLength::Captured,
            master_address: MASTER_ADDRESS,
        }
    }
}
