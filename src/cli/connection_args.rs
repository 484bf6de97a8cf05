//! How to reach the drive, as command-line options shared by every command that talks to
//! one: serial port, TCP serial server, or the built-in simulated drive. Opens the link;
//! must not send anything itself.

use crate::bus::{
    MemoryTransport, Peer, SerialSettings, SerialTransport, TcpTransport, Transport, TransportError,
};
use crate::clock::{RealClock, SharedClock, VirtualClock};
use crate::family::sd2::codec::{dnc_address, WriteLength};
use crate::family::sd2::Sd2Link;
use crate::family::sd2::{Sd2Simulator, SimConfig};
use crate::link::LinkConfig;
use clap::{Args, ValueEnum};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How long to wait for a TCP serial server to accept the connection.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

#[derive(Debug, Clone, Args)]
#[command(next_help_heading = "Connection (without --port or --tcp: the built-in simulated drive)")]
pub struct ConnectionArgs {
    /// Serial port the drive is on (/dev/ttyUSB0, COM3).
    #[arg(long, value_name = "PATH", conflicts_with = "tcp")]
    pub port: Option<String>,
    /// Baud rate of the serial port (SD2: 57600, 8N1).
    #[arg(long, value_name = "N", default_value_t = 57_600)]
    pub baud: u32,
    /// A serial device server or ser2net in raw TCP mode.
    #[arg(long, value_name = "HOST:PORT")]
    pub tcp: Option<String>,
    /// The position of the drive's address switch. The DNC address is then
    /// switch × 2 + 2 (drive A) or switch × 2 + 3 (drive B, with --drive-b).
    #[arg(long, value_name = "SWITCH", default_value_t = 0)]
    pub address: u8,
    /// Address drive B of a double-axis device.
    #[arg(long)]
    pub drive_b: bool,
    /// The raw DNC address (2..=255) instead of the address switch position.
    #[arg(long, value_name = "N", conflicts_with_all = ["drive_b"])]
    pub dnc_address: Option<u8>,
    /// How long to wait for each reply (the vendor's PC tool uses 1 s).
    #[arg(long, value_name = "DURATION", default_value = "1s", value_parser = parse_duration)]
    pub timeout: Duration,
    /// Further attempts after a lost, corrupt or mismatched reply.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub retries: u32,
    /// Length field of Write Wide Object commands: `captured` sends 0x0B as every capture
    /// from real drives does; `formula` sends 10 + count as the manual's formula says.
    #[arg(long, value_enum, default_value_t = WriteLengthArg::Captured)]
    pub write_length: WriteLengthArg,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum WriteLengthArg {
    Captured,
    Formula,
}

pub fn parse_duration(text: &str) -> Result<Duration, String> {
    humantime::parse_duration(text.trim()).map_err(|e| format!("{e} (write e.g. 500ms, 1s, 2min)"))
}

/// An open link to one drive, real or simulated.
pub struct Connection {
    pub link: Sd2Link,
    /// The drive's DNC address.
    pub dest: u8,
    /// The in-process simulated drive, when no port was given (tests look into it).
    pub simulator: Option<Arc<Mutex<Sd2Simulator>>>,
    /// For the first line of output: what we are talking to.
    pub description: String,
}

impl ConnectionArgs {
    /// The built-in simulated drive at address switch 0, with the default link settings.
    pub fn simulated() -> Self {
        ConnectionArgs {
            port: None,
            baud: 57_600,
            tcp: None,
            address: 0,
            drive_b: false,
            dnc_address: None,
            timeout: Duration::from_secs(1),
            retries: 2,
            write_length: WriteLengthArg::Captured,
        }
    }

    /// The DNC address the options select.
    pub fn dnc_address(&self) -> Result<u8, String> {
        if let Some(raw) = self.dnc_address {
            if raw < 2 {
                return Err(format!(
                    "--dnc-address {raw}: addresses 0 and 1 belong to the master; a drive has 2..=255"
                ));
            }
            return Ok(raw);
        }
        dnc_address(self.address, self.drive_b).ok_or_else(|| {
            format!(
                "--address {}: switch × 2 + {} exceeds 255; the highest switch position is 126",
                self.address,
                2 + u8::from(self.drive_b),
            )
        })
    }

    pub fn is_simulated(&self) -> bool {
        self.port.is_none() && self.tcp.is_none()
    }

    fn link_config(&self) -> LinkConfig {
        LinkConfig {
            reply_timeout: self.timeout,
            retries: self.retries,
            write_length: match self.write_length {
                WriteLengthArg::Captured => WriteLength::Captured,
                WriteLengthArg::Formula => WriteLength::Formula,
            },
            ..LinkConfig::default()
        }
    }

    /// Opens the link. `virtual_time` applies to the simulated drive only: waiting then
    /// costs no real time.
    pub fn open(&self, virtual_time: bool) -> Result<Connection, TransportError> {
        let dest = self.dnc_address().map_err(|detail| TransportError::Open {
            port: "the drive".into(),
            detail,
        })?;
        let (transport, clock, simulator, description): (Box<dyn Transport>, SharedClock, _, String) =
            match (&self.port, &self.tcp) {
                (Some(path), _) => {
                    let t = SerialTransport::open(path, SerialSettings::with_baud(self.baud))?;
                    let d = format!("drive {dest} on {}", t.name());
                    (Box::new(t), RealClock::shared(), None, d)
                }
                (None, Some(addr)) => {
                    let t = TcpTransport::connect(addr, CONNECT_TIMEOUT)?;
                    let d = format!("drive {dest} on {}", t.name());
                    (Box::new(t), RealClock::shared(), None, d)
                }
                (None, None) => {
                    let clock: SharedClock = if virtual_time {
                        Arc::new(VirtualClock::new())
                    } else {
                        RealClock::shared()
                    };
                    let sim = Arc::new(Mutex::new(Sd2Simulator::new(SimConfig {
                        address: dest,
                        ..SimConfig::default()
                    })));
                    let peer: Arc<Mutex<dyn Peer>> = sim.clone();
                    let time = if virtual_time { "virtual time" } else { "real time" };
                    let d = format!(
                        "the built-in simulated SD2 drive (DNC address {dest}, {time}; no hardware is moved)"
                    );
                    let t = MemoryTransport::new("built-in simulated drive", peer, clock.clone());
                    (Box::new(t), clock, Some(sim), d)
                }
            };
        Ok(Connection {
            link: Sd2Link::new(transport, clock, self.link_config()),
            dest,
            simulator,
            description,
        })
    }
}
