//! The one error type of object access, the same for every family: no reply, a bad reply,
//! a refusal by the drive (its code and text), the transport, or a stop request — each with
//! the port, the drive's address and the telegram, and what to try.

use crate::bus::TransportError;

#[derive(Debug, thiserror::Error)]
pub enum AccessError {
    #[error(transparent)]
    Transport(#[from] TransportError),

    #[error("no reply from drive {address} on {port} to {request} ({attempts} attempt(s), {timeout_ms} ms each); {hint}")]
    NoReply {
        port: String,
        address: String,
        /// The request in hex with a short description.
        request: String,
        attempts: u32,
        timeout_ms: u128,
        /// What to check, in the family's words (cable, baud rate, address setting).
        hint: String,
    },

    #[error("no valid reply from drive {address} on {port} to {request} after {attempts} attempt(s): last reply {reply} was refused: {problem}; check for noise on the line (shielding, RS485 termination) or another master on the bus")]
    BadReply {
        port: String,
        address: String,
        request: String,
        reply: String,
        problem: String,
        attempts: u32,
    },

    #[error("drive {address} on {port} refused to {operation} object {object}: {text}")]
    Refused {
        port: String,
        address: String,
        operation: &'static str,
        /// The object in the family's notation.
        object: String,
        /// The drive's own error code, and its meaning.
        code: u32,
        text: String,
    },

    #[error("drive {address} on {port} answered {request} with a reply of the wrong kind: {detail}")]
    UnexpectedReply {
        port: String,
        address: String,
        request: String,
        detail: String,
    },

    #[error("cannot build the telegram: {0}")]
    Encode(String),

    /// The drive no longer talks the way the port was opened (a write changed its baud
    /// rate): nothing more is sent to it.
    #[error("drive {address} on {port}: {text}")]
    LineChanged {
        port: String,
        address: String,
        text: String,
    },

    #[error("stopped waiting for drive {address} on {port} to answer {request}: a stop was requested")]
    Interrupted {
        port: String,
        address: String,
        request: String,
    },
}

impl AccessError {
    /// True when the port itself failed (device gone, connection closed): only reopening
    /// it can help.
    pub fn is_transport(&self) -> bool {
        matches!(self, AccessError::Transport(_))
    }

    /// True when a stop request ended the wait for a reply.
    pub fn is_interrupted(&self) -> bool {
        matches!(self, AccessError::Interrupted { .. })
    }

    /// True when the request was refused before anything was sent: it cannot be written
    /// as a telegram (a read to a group address, a parameter the protocol cannot name).
    pub fn is_unsent(&self) -> bool {
        matches!(self, AccessError::Encode(_))
    }

    /// True when nothing usable came back at all (line down, drive off).
    pub fn is_no_reply(&self) -> bool {
        matches!(self, AccessError::NoReply { .. })
    }
}
