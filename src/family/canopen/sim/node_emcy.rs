//! The EMCY frames every simulated CANopen node sends alike (CiA 301: 0x80 + node, 8
//! bytes): the frame of an error code, and the ones injected without a trip
//! (`FaultInjection::emergency_at`) that are due. Frames only; when a node may send is
//! the node's business.

use crate::bus::CanFrame;
use crate::family::canopen::codec::emcy_id;
use crate::sim::SimCore;
use std::time::Duration;

/// `node`'s EMCY frame for `code`: the error code, the error register (bit 0, generic
/// error, set for any code but the error reset 0x0000) and five manufacturer bytes (0 here).
pub fn emcy_frame(node: u8, code: u16) -> CanFrame {
    let [lo, hi] = code.to_le_bytes();
    let register = u8::from(code != 0);
    CanFrame::standard8(emcy_id(node), [lo, hi, register, 0, 0, 0, 0, 0])
}

/// The injected EMCY frames of `node` due by `now`, each at the time it was due; they
/// are taken, so each goes out once.
pub fn injected_emcy<L>(core: &mut SimCore<L>, node: u8, now: Duration) -> Vec<(Duration, CanFrame)> {
    std::iter::from_fn(|| core.faults.take_emergency_due(now))
        .map(|(at, code)| (at, emcy_frame(node, code)))
        .collect()
}
