//! The one error type of the link layer: which port, which telegram, what went wrong, and
//! what to try.

use crate::bus::TransportError;
use crate::family::sd2::codec::{DecodeError, EncodeError, ErrorCode};

#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    #[error(transparent)]
    Transport(#[from] TransportError),

    #[error("no reply from drive {dest} on {port} to {request} ({attempts} attempt(s), {timeout_ms} ms each); check the cable, the baud rate, the drive's DNC address (address switch), and that its control channel is set to the serial interface")]
    NoReply {
        port: String,
        dest: u8,
        /// The request in hex with a short description.
        request: String,
        attempts: u32,
        timeout_ms: u128,
    },

    #[error("no valid reply from drive {dest} on {port} to {request} after {attempts} attempt(s): last reply {reply} was refused: {problem}; check for noise on the line (shielding, RS485 termination) or another master on the bus")]
    BadReply {
        port: String,
        dest: u8,
        request: String,
        reply: String,
        problem: DecodeError,
        attempts: u32,
    },

    #[error("drive {dest} on {port} refused to {operation} object {index} (subindex {subindex}): {code}")]
    DriveRefused {
        port: String,
        dest: u8,
        operation: &'static str,
        index: u16,
        subindex: u32,
        code: ErrorCode,
    },

    #[error("drive {dest} on {port} answered {request} with a reply of the wrong kind: {detail}")]
    UnexpectedReply {
        port: String,
        dest: u8,
        request: String,
        detail: String,
    },

    #[error("cannot build the telegram: {0}")]
    Encode(#[from] EncodeError),

    #[error("stopped waiting for drive {dest} on {port} to answer {request}: a stop was requested")]
    Interrupted { port: String, dest: u8, request: String },
}

impl LinkError {
    /// The drive's error code, when the drive itself refused.
    pub fn drive_code(&self) -> Option<ErrorCode> {
        match self {
            LinkError::DriveRefused { code, .. } => Some(*code),
            _ => None,
        }
    }

    /// True when the port itself failed (device gone, connection closed): only reopening
    /// it can help.
    pub fn is_transport(&self) -> bool {
        matches!(self, LinkError::Transport(_))
    }

    /// True when a stop request ended the wait for a reply.
    pub fn is_interrupted(&self) -> bool {
        matches!(self, LinkError::Interrupted { .. })
    }

    /// True when nothing usable came back at all (line down, drive off).
    pub fn is_no_reply(&self) -> bool {
        matches!(self, LinkError::NoReply { .. })
    }
}
