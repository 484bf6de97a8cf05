//! Settings of the Control Techniques link: how long to wait, how often to retry, and the
//! pause the drive needs between its reply and the next message.

use super::codec::Parameter;
use std::time::Duration;

/// After a write that changes the drive's baud rate, its reply still comes at the old rate
/// and the drive needs at least 20 ms before it talks at the new one (the notes).
pub const BAUD_CHANGE_WAIT: Duration = Duration::from_millis(20);

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CtLinkConfig {
    /// How long to wait for a reply. The drive answers about 1 ms after a message, later
    /// when a menu-11 parameter adds a delay; 1 s covers that and any line speed.
    pub reply_timeout: Duration,
    /// Further attempts after a timeout or a corrupt or mismatched reply. Writes to a
    /// group or every drive (no reply) are never repeated.
    pub retries: u32,
    /// Quiet time before every message: the drive holds its transmitter up to 1 ms after
    /// its reply, and a drive that acted on a group write gets the same pause.
    pub turnaround: Duration,
    /// Before a retry, the line is listened to for this long and what arrives is thrown
    /// away: a late answer to the failed attempt must not pass for the retry's.
    pub settle: Duration,
    /// On a line not yet known to echo, how long after a message has left a lone `EOT` must
    /// stand alone to count as the drive's answer (a missing parameter) rather than the
    /// start of the adapter's echo of the message. The echo is on the line while the
    /// message is; this covers the latency of USB serial adapters, which hand received
    /// bytes on in batches (commonly every 16 ms).
    pub echo_wait: Duration,
    /// The parameter that sets the drive's serial baud rate (`--link-option
    /// baud-parameter=#M.PP`): the notes do not say which one it is, so the user names it.
    /// An accepted write to it makes the link wait [`BAUD_CHANGE_WAIT`] and then stop.
    pub baud_parameter: Option<Parameter>,
}

impl Default for CtLinkConfig {
    fn default() -> Self {
        CtLinkConfig {
            reply_timeout: Duration::from_secs(1),
            retries: 2,
            turnaround: Duration::from_millis(2),
            settle: Duration::from_millis(20),
            echo_wait: Duration::from_millis(50),
            baud_parameter: None,
        }
    }
}
