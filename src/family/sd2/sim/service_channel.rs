//! The acyclic service channel inside the cyclic telegram, as the simulator implements it:
//! toggle tracking, the stored array index and the layout of the reply. It decides what a
//! request asks for and shapes the answer; it must not touch objects itself.
//!
//! The sources define the request's ctrl byte but not the reply's state byte, so these are
//! the simulator's own choices:
//! - A new service starts only when ctrl bit 0 differs from the previous service request's
//!   (the first service request always starts one). The same toggle again re-sends the
//!   previous reply without executing anything.
//! - Reply: reserved byte 0; state byte = the request's ctrl, with bit 7 set when the
//!   access failed; the request's index echoed; sdata = the value read (little-endian,
//!   zero-padded), the written data echoed, or on failure sdata0 = the SD2 error code.
//! - Write: the object's own size is taken from sdata; fewer valid bytes (ctrl bits 3–4
//!   plus one) than that is "too short". More valid bytes than the size are accepted.
//! - Set array index (function 1) stores sdata's valid bytes and acknowledges; the stored
//!   index is the subindex of later service reads and writes.
//! - Read of an object wider than 4 bytes (the ident string) fails with 0x88.
//! - Function 3 (invalid) trips the drive to fault with drive error 0x0003 and fails
//!   with 0x88.

use crate::family::sd2::codec::{ErrorCode, ServiceChannel, ServiceFunction};

/// Failure bit in the reply's state byte.
const FAILED: u8 = 0x80;
/// "Unsupported access to an object".
pub(crate) const UNSUPPORTED_ACCESS: ErrorCode = ErrorCode(0x88);
/// Drive error shown after an invalid service function.
pub(crate) const INVALID_SERVICE_DRIVE_ERROR: u16 = 0x0003;

/// What a service request asks the drive to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ServiceAction {
    /// Same toggle as before: send this reply again, execute nothing.
    Resend(ServiceChannel),
    Read {
        index: u16,
        subindex: u32,
    },
    Write {
        index: u16,
        subindex: u32,
        data: [u8; 4],
        valid: usize,
    },
    /// The array index has been stored; acknowledge.
    Acknowledge,
    Invalid,
}

#[derive(Debug, Clone, Default)]
pub(crate) struct ServiceSession {
    previous: Option<(bool, ServiceChannel)>,
    array_index: u32,
}

impl ServiceSession {
    pub(crate) fn begin(&mut self, request: &ServiceChannel) -> ServiceAction {
        if let Some((toggle, reply)) = self.previous {
            if toggle == request.toggle() {
                return ServiceAction::Resend(reply);
            }
        }
        match request.function() {
            ServiceFunction::Read => ServiceAction::Read {
                index: request.index,
                subindex: self.array_index,
            },
            ServiceFunction::Write => ServiceAction::Write {
                index: request.index,
                subindex: self.array_index,
                data: request.data,
                valid: request.valid_bytes(),
            },
            ServiceFunction::SetArrayIndex => {
                let mut bytes = [0u8; 4];
                let n = request.valid_bytes();
                bytes[..n].copy_from_slice(&request.data[..n]);
                self.array_index = u32::from_le_bytes(bytes);
                ServiceAction::Acknowledge
            }
            ServiceFunction::Invalid => ServiceAction::Invalid,
        }
    }

    /// Builds the reply for an executed request from its outcome (the sdata to send, or
    /// the error) and remembers it for a repeated toggle.
    pub(crate) fn finish(
        &mut self,
        request: &ServiceChannel,
        outcome: Result<[u8; 4], ErrorCode>,
    ) -> ServiceChannel {
        let (state, data) = match outcome {
            Ok(data) => (request.ctrl & !FAILED, data),
            Err(e) => (request.ctrl | FAILED, [e.0, 0, 0, 0]),
        };
        let reply = ServiceChannel {
            reserved: 0,
            ctrl: state,
            index: request.index,
            data,
        };
        self.previous = Some((request.toggle(), reply));
        reply
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(toggle: bool, f: ServiceFunction, valid: u8, index: u16, data: [u8; 4]) -> ServiceChannel {
        ServiceChannel::request(toggle, f, valid, index, data)
    }

    #[test]
    fn toggle_decides_between_new_service_and_resend() {
        let mut s = ServiceSession::default();
        let r = req(false, ServiceFunction::Read, 2, 39, [0; 4]);
        assert_eq!(
            s.begin(&r),
            ServiceAction::Read {
                index: 39,
                subindex: 0
            }
        );
        let reply = s.finish(&r, Ok([7, 0, 0, 0]));
        assert_eq!(reply.ctrl, 0x08);
        assert_eq!(reply.data, [7, 0, 0, 0]);
        // Same toggle, even with a different request: the old reply again.
        let w = req(false, ServiceFunction::Write, 2, 352, [1, 0, 0, 0]);
        assert_eq!(s.begin(&w), ServiceAction::Resend(reply));
        let w = req(true, ServiceFunction::Write, 2, 352, [1, 0, 0, 0]);
        assert!(matches!(
            s.begin(&w),
            ServiceAction::Write {
                index: 352,
                valid: 2,
                ..
            }
        ));
        let failed = s.finish(&w, Err(ErrorCode::STATE_OF_CONTROL));
        assert_eq!(failed.ctrl, 0x8D);
        assert_eq!(failed.data, [0x9B, 0, 0, 0]);
        assert_eq!(failed.index, 352);
    }

    #[test]
    fn array_index_is_stored_and_used() {
        let mut s = ServiceSession::default();
        let set = req(true, ServiceFunction::SetArrayIndex, 1, 22, [5, 9, 9, 9]);
        assert_eq!(s.begin(&set), ServiceAction::Acknowledge);
        s.finish(&set, Ok(set.data));
        let r = req(false, ServiceFunction::Read, 4, 22, [0; 4]);
        assert_eq!(
            s.begin(&r),
            ServiceAction::Read {
                index: 22,
                subindex: 5
            }
        );
        let bad = req(true, ServiceFunction::Invalid, 1, 0, [0; 4]);
        s.finish(&r, Ok([0; 4]));
        assert_eq!(s.begin(&bad), ServiceAction::Invalid);
    }
}
