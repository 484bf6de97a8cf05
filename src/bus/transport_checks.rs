//! What the tests of byte transports and CAN peers share. Test support only: never part
//! of the program, and it checks what a transport or peer promises, not how one is built.

use super::{CanFrame, FramePeer, Transport};
use std::time::Duration;

/// Nothing is waiting on `t`: a short read times out instead of returning stale bytes
/// (what [`Transport::discard_input`] must leave behind).
pub fn assert_nothing_to_read(t: &mut dyn Transport) {
    let mut buf = [0u8; 8];
    assert!(t
        .read(&mut buf, Duration::from_millis(20))
        .unwrap_err()
        .is_timeout());
}

/// The frames `peer` sends back to `frame` at clock time `now`, as candump text.
pub fn candump_replies(peer: &mut dyn FramePeer, frame: &CanFrame, now: Duration) -> Vec<String> {
    peer.receive(frame, now)
        .into_iter()
        .map(|(_, f)| f.to_candump())
        .collect()
}
