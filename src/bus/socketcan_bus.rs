//! A CAN bus through a Linux SocketCAN interface (`can0`, `vcan0`) with the `socketcan`
//! crate. The interface's bit rate is the system's business (`ip link set can0 type can
//! bitrate 500000`); this only opens a raw CAN socket on it. Error and remote frames are
//! passed over. Knows nothing about what the frames mean.

use super::{CanFrame, FrameBus, TransportError};
use socketcan::{CanSocket, EmbeddedFrame, ExtendedId, Id, Socket, StandardId};
use std::io::ErrorKind;
use std::time::{Duration, Instant};

pub struct SocketCanBus {
    socket: CanSocket,
    interface: String,
    name: String,
}

impl SocketCanBus {
    pub fn open(interface: &str) -> Result<SocketCanBus, TransportError> {
        let socket = Self::socket(interface)?;
        Ok(SocketCanBus {
            socket,
            interface: interface.to_string(),
            name: format!("socketcan {interface}"),
        })
    }

    fn socket(interface: &str) -> Result<CanSocket, TransportError> {
        CanSocket::open(interface).map_err(|e| match e.kind() {
            ErrorKind::NotFound => TransportError::Open {
                port: interface.to_string(),
                detail: "no such CAN interface; `ip link show` lists the interfaces (bring it up with `ip link set can0 up type can bitrate 500000`)".into(),
            },
            ErrorKind::PermissionDenied => TransportError::PermissionDenied {
                port: interface.to_string(),
            },
            _ => TransportError::Open {
                port: interface.to_string(),
                detail: format!(
                    "{e}; `ip link show` lists the CAN interfaces (bring one up with `ip link set can0 up type can bitrate 500000`)"
                ),
            },
        })
    }

    fn io(&self, e: std::io::Error) -> TransportError {
        TransportError::Io {
            port: self.name.clone(),
            detail: e.to_string(),
        }
    }
}

impl FrameBus for SocketCanBus {
    fn name(&self) -> &str {
        &self.name
    }

    fn send(&mut self, frame: &CanFrame) -> Result<(), TransportError> {
        let id: Id = if frame.extended {
            ExtendedId::new(frame.id).map(Id::Extended)
        } else {
            u16::try_from(frame.id)
                .ok()
                .and_then(StandardId::new)
                .map(Id::Standard)
        }
        .ok_or_else(|| TransportError::Io {
            port: self.name.clone(),
            detail: format!("identifier 0x{:X} does not fit its frame format", frame.id),
        })?;
        let out = socketcan::CanFrame::new(id, frame.data()).ok_or_else(|| TransportError::Io {
            port: self.name.clone(),
            detail: "more than 8 data bytes".into(),
        })?;
        self.socket.write_frame_insist(&out).map_err(|e| self.io(e))
    }

    fn receive(&mut self, timeout: Duration) -> Result<CanFrame, TransportError> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let frame = match self.socket.read_frame_timeout(left) {
                Ok(f) => f,
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => {
                    return Err(TransportError::Timeout {
                        port: self.name.clone(),
                        waited: timeout,
                    })
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(e) => return Err(self.io(e)),
            };
            let socketcan::CanFrame::Data(data) = frame else {
                continue;
            };
            let converted = match data.id() {
                Id::Standard(id) => CanFrame::new(u32::from(id.as_raw()), data.data()),
                Id::Extended(id) => CanFrame::extended(id.as_raw(), data.data()),
            };
            if let Some(f) = converted {
                return Ok(f);
            }
        }
    }

    fn reopen(&mut self) -> Result<(), TransportError> {
        self.socket = Self::socket(&self.interface)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_interface_is_named_with_what_to_do() {
        let e = SocketCanBus::open("nosuchcan7")
            .err()
            .expect("no such interface here");
        let text = e.to_string();
        assert!(text.contains("nosuchcan7"), "{text}");
        assert!(text.contains("ip link"), "{text}");
    }
}
