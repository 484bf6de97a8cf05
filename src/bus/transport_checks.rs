//! Assertions the tests of every byte transport share. Test support only: never part of
//! the program, and it checks what a transport promises, not how one is built.

use super::Transport;
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
