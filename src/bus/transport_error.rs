//! The one error type of the transport layer: which port, what went wrong, what to try.

use std::time::Duration;

#[derive(Debug, thiserror::Error)]
pub enum TransportError {
    #[error("no reply on {port} within {} ms", waited.as_millis())]
    Timeout { port: String, waited: Duration },

    #[error("serial port {port} does not exist; run `drivescript ports` to list the ports this machine has")]
    PortNotFound { port: String },

    #[error("serial port {port} is in use by another program; close it (a terminal, another drivescript) and try again")]
    PortBusy { port: String },

    #[error("permission denied opening {port}; add your user to the `dialout` group (then log in again) or run with access to the device")]
    PermissionDenied { port: String },

    #[error("cannot open {port}: {detail}")]
    Open { port: String, detail: String },

    #[error("cannot connect to {addr} within {} ms: {detail}; check the address, the port number and that the serial server is reachable", waited.as_millis())]
    Connect {
        addr: String,
        waited: Duration,
        detail: String,
    },

    #[error("{port} was closed by the other side")]
    Closed { port: String },

    #[error("I/O error on {port}: {detail}")]
    Io { port: String, detail: String },

    /// A replayed capture has no answer for what was sent: `detail` names the telegram and
    /// what the capture had at that point.
    #[error("{detail}")]
    NotInCapture { detail: String },
}

impl TransportError {
    pub fn is_timeout(&self) -> bool {
        matches!(self, TransportError::Timeout { .. })
    }
}
