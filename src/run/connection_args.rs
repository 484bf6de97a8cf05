//! How to reach the drive, as command-line options shared by every command that talks to
//! one: serial port, TCP serial server, or the built-in simulated drive; the drive's
//! address in its family's notation; reply timeout, retries and family link options.
//! Opens the bus; must not send anything itself.

use super::address_key_flags::DNC_ADDRESS;
use super::{BadValue, RunError};
use crate::bus::{
    Bus, BusKind, DataBits, MemoryFrameBus, MemoryTransport, Parity, SerialSettings, SerialTransport,
    SharedFrameBus, SharedTransport, SlcanBus, StopBits, TcpTransport, TransportError,
};
use crate::clock::{RealClock, SharedClock, VirtualClock};
use crate::dictionary::is_pole_pairs_setting;
use crate::family::{DriveAddress, Family, LinkOptions, Registry, SimPeer};
use crate::sim::{SimConfig, SimSetting, SimulatedDrive};
use clap::Args;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How long to wait for a TCP serial server to accept the connection.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

#[derive(Debug, Clone, Args)]
#[command(next_help_heading = "Connection (without --port, --tcp or --can: the built-in simulated drive)")]
pub struct ConnectionArgs {
    /// Serial port the drive is on (/dev/ttyUSB0, /dev/serial/by-id/…, COM3).
    #[arg(long, value_name = "PATH", conflicts_with = "tcp")]
    pub port: Option<String>,
    /// Baud rate of the serial port [default: the drive family's, e.g. 57600 for SD2, 4800
    /// for Control Techniques].
    #[arg(long, value_name = "N")]
    pub baud: Option<u32>,
    /// Data bits per character, 7 or 8 [default: the drive family's, e.g. 8 for SD2, 7 for
    /// Control Techniques].
    #[arg(hide_short_help = true, long = "data-bits", value_name = "7|8", value_parser = parse_data_bits)]
    pub data_bits: Option<DataBits>,
    /// Parity bit [default: the drive family's, e.g. none for SD2, even for Control
    /// Techniques].
    #[arg(hide_short_help = true, long, value_name = "none|even|odd", value_parser = parse_parity)]
    pub parity: Option<Parity>,
    /// Stop bits, 1 or 2 [default: the drive family's, 1].
    #[arg(hide_short_help = true, long = "stop-bits", value_name = "1|2", value_parser = parse_stop_bits)]
    pub stop_bits: Option<StopBits>,
    /// A serial device server or ser2net in raw TCP mode.
    #[arg(long, value_name = "HOST:PORT")]
    pub tcp: Option<String>,
    /// A CAN bus, for drive families on CAN (lenze-9400): `slcan:PATH` for a USB-serial
    /// SLCAN (Lawicel) adapter or a pseudo-terminal, `socketcan:IF` for a Linux CAN
    /// interface (can0, vcan0).
    #[arg(long, value_name = "slcan:PATH|socketcan:IF", value_parser = parse_can, conflicts_with_all = ["port", "tcp"])]
    pub can: Option<CanSpec>,
    /// CAN bit rate for an SLCAN adapter: 10k, 20k, 50k, 100k, 125k, 250k, 500k, 800k or
    /// 1M (SocketCAN interfaces keep the rate `ip link` gave them).
    #[arg(long, value_name = "RATE", default_value = "500k", value_parser = parse_bitrate)]
    pub bitrate: u32,
    /// The drive's address in its family's notation. SD2: the address switch position
    /// (`0`, the default), `3B` for drive B of a double-axis device, or `dnc:N` for a raw
    /// DNC address. Control Techniques: group.unit (`1.2`, default `1.1`); `G.0` writes to
    /// a whole group and `0.0` to every drive, with no reply. Lenze 931: none (one drive
    /// per RS232 line). Lenze 9400: the CANopen node address 1..127 (C00350; default 1).
    /// Modbus RTU: the slave id 1..247 (default 1; 0 broadcasts writes); Modbus TCP: the
    /// unit id.
    #[arg(long, value_name = "ADDRESS")]
    pub address: Option<String>,
    /// The drive's raw DNC address, for families whose drives have one (SD2): the same as
    /// `--address dnc:N`, and a recipe's `dnc_address: N`.
    #[arg(
        hide_short_help = true,
        long = "dnc-address",
        value_name = "N",
        conflicts_with = "address"
    )]
    pub dnc_address: Option<String>,
    /// How long to wait for each reply (the SD2 vendor's PC tool uses 1 s).
    #[arg(long, value_name = "DURATION", default_value = "1s", value_parser = parse_duration)]
    pub timeout: Duration,
    /// Further attempts after a reply is lost, corrupt or mismatched.
    #[arg(hide_short_help = true, long, value_name = "N", default_value_t = 2)]
    pub retries: u32,
    /// A setting of the family's link, NAME=VALUE; may be repeated. SD2:
    /// `write-length=captured` (0x0B in Write Wide Object, as every capture from real drives
    /// sends; the default) or `write-length=formula` (10 + count, the manual's formula).
    /// Control Techniques: `baud-parameter=#M.PP`, the parameter that sets the drive's baud
    /// rate (an accepted write to it waits 20 ms, then ends the session). Any inverter
    /// dictionary: `pole-pairs=N`, the motor's pole pairs (rpm = Hz × 60 / N).
    #[arg(hide_short_help = true, long = "link-option", value_name = "NAME=VALUE", value_parser = parse_link_option)]
    pub link_options: Vec<(String, String)>,
    /// Which channel carries commands and values, where the family has several. SD2:
    /// `object` (Read/Write Wide Object, the default) or `cyclic` (the DNC 8-byte telegram;
    /// needs --velocity-scaling). Same as `--link-option channel=…`.
    #[arg(hide_short_help = true, long, value_name = "CHANNEL")]
    pub channel: Option<String>,
    /// The speed the cyclic telegram's +100 % stands for (the drive's velocity scaling
    /// parameter), e.g. 24000rpm.
    #[arg(hide_short_help = true, long, value_name = "SPEED")]
    pub velocity_scaling: Option<String>,
    /// Toggle the cyclic telegram's heartbeat bit (when the drive's heartbeat is on).
    #[arg(hide_short_help = true, long)]
    pub heartbeat: bool,
    /// Longest interval between cyclic telegrams [default: 20ms].
    #[arg(hide_short_help = true, long, value_name = "DURATION")]
    pub cycle: Option<String>,
    /// Replay a capture instead of a drive: a `--trace` file of an earlier run, or a
    /// candump log (`candump -l`) of the CAN bus. Each request gets what the drive answered
    /// then, in virtual time following the capture's clock; nothing is sent to any port.
    #[arg(long, value_name = "CAPTURE", conflicts_with_all = ["port", "tcp", "can"])]
    pub replay: Option<std::path::PathBuf>,
    /// A setting of the built-in simulated drive's physics, NAME=VALUE; may be repeated:
    /// `response-time=200ms` and `overshoot=10%` (the speed follows a setpoint step in
    /// first or second order instead of ramping), `coast-rate=300rpm/s` (friction while
    /// coasting), `ambient=25°C`, `heating=25K/A`, `thermal-time=10min` (motor temperature),
    /// `emergency-at=20s:0x2310` (a CANopen node sends an EMCY with this code, nothing trips),
    /// `trip-at=20s:0x1234` (the drive trips), `silent=20s..25s` (the drive answers nothing
    /// and sends no heartbeat while the line stays up),
    /// `reply-latency=1500ms` (every reply leaves that long after its request).
    #[arg(long = "sim", value_name = "NAME=VALUE", value_parser = parse_sim_setting)]
    pub sim: Vec<SimSetting>,
}

pub fn parse_duration(text: &str) -> Result<Duration, BadValue> {
    humantime::parse_duration(text.trim()).map_err(|e| BadValue(format!("{e} (write e.g. 500ms, 1s, 2min)")))
}

fn parse_data_bits(text: &str) -> Result<DataBits, BadValue> {
    match text.trim() {
        "7" => Ok(DataBits::Seven),
        "8" => Ok(DataBits::Eight),
        other => Err(BadValue(format!("`{other}`: give 7 or 8"))),
    }
}

fn parse_parity(text: &str) -> Result<Parity, BadValue> {
    match text.trim().to_ascii_lowercase().as_str() {
        "none" | "n" => Ok(Parity::None),
        "even" | "e" => Ok(Parity::Even),
        "odd" | "o" => Ok(Parity::Odd),
        other => Err(BadValue(format!("`{other}`: give none, even or odd"))),
    }
}

fn parse_stop_bits(text: &str) -> Result<StopBits, BadValue> {
    match text.trim() {
        "1" => Ok(StopBits::One),
        "2" => Ok(StopBits::Two),
        other => Err(BadValue(format!("`{other}`: give 1 or 2"))),
    }
}

/// Where the CAN bus is: an SLCAN adapter's serial port or a SocketCAN interface.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CanSpec {
    Slcan(String),
    SocketCan(String),
}

fn parse_can(text: &str) -> Result<CanSpec, BadValue> {
    match text.trim().split_once(':') {
        Some(("slcan", path)) if !path.is_empty() => Ok(CanSpec::Slcan(path.to_string())),
        Some(("socketcan", interface)) if !interface.is_empty() => Ok(CanSpec::SocketCan(interface.to_string())),
        _ => Err(BadValue(format!(
            "`{text}`: write slcan:PATH (an SLCAN adapter, e.g. slcan:/dev/ttyACM0) or socketcan:IF (e.g. socketcan:can0)"
        ))),
    }
}

/// `500k`, `1M`, `125000`.
pub fn parse_bitrate(text: &str) -> Result<u32, BadValue> {
    let t = text.trim();
    let (digits, factor) = if let Some(d) = t.strip_suffix(['k', 'K']) {
        (d, 1_000)
    } else if let Some(d) = t.strip_suffix('M') {
        (d, 1_000_000)
    } else {
        (t, 1)
    };
    digits
        .parse::<u32>()
        .ok()
        .and_then(|n| n.checked_mul(factor))
        .filter(|&n| n > 0)
        .ok_or_else(|| {
            BadValue(format!(
                "`{text}` is not a bit rate; write e.g. 500k, 1M or 125000"
            ))
        })
}

fn parse_sim_setting(text: &str) -> Result<SimSetting, BadValue> {
    SimSetting::parse(text).map_err(|e| BadValue(e.to_string()))
}

fn parse_link_option(text: &str) -> Result<(String, String), BadValue> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(BadValue(format!(
            "`{text}`: write NAME=VALUE, e.g. write-length=formula"
        ))),
    }
}

/// An open bus to one drive, real or simulated.
pub struct Connection {
    pub bus: Bus,
    pub address: DriveAddress,
    pub clock: SharedClock,
    /// The in-process simulated drive, when no port was given (tests look into it).
    pub simulator: Option<Arc<Mutex<dyn SimulatedDrive>>>,
    /// For the first line of output: what we are talking to.
    pub description: String,
}

impl ConnectionArgs {
    /// The built-in simulated drive at the family's default address, default link settings.
    pub fn simulated() -> Self {
        ConnectionArgs {
            port: None,
            baud: None,
            data_bits: None,
            parity: None,
            stop_bits: None,
            tcp: None,
            can: None,
            bitrate: 500_000,
            address: None,
            dnc_address: None,
            timeout: Duration::from_secs(1),
            retries: 2,
            link_options: Vec::new(),
            channel: None,
            velocity_scaling: None,
            heartbeat: false,
            cycle: None,
            replay: None,
            sim: Vec::new(),
        }
    }

    /// These arguments with `defaults` (a recipe's `link:`) put before the command line's
    /// own link options, so the command line wins.
    pub fn with_defaults(&self, defaults: &[(String, String)]) -> ConnectionArgs {
        let mut merged = self.clone();
        let mut options = defaults.to_vec();
        options.extend(self.link_options.iter().cloned());
        merged.link_options = options;
        merged
    }

    /// The motor's pole pairs a `--link-option pole-pairs=N` (or a recipe's `link:`) gives,
    /// the last one given: a setting of the dictionary, not of the family's link.
    pub fn pole_pairs(&self) -> Option<String> {
        self.link_options
            .iter()
            .rev()
            .find(|(name, _)| is_pole_pairs_setting(name))
            .map(|(_, value)| value.clone())
    }

    /// `--link-option`s and the options that stand for one (`--channel cyclic` is
    /// `channel=cyclic`), without the pole pairs, which the dictionary takes.
    fn all_link_options(&self) -> Vec<(String, String)> {
        let mut all: Vec<(String, String)> = self
            .link_options
            .iter()
            .filter(|(name, _)| !is_pole_pairs_setting(name))
            .cloned()
            .collect();
        let named = [
            ("channel", self.channel.clone()),
            ("velocity-scaling", self.velocity_scaling.clone()),
            ("heartbeat", self.heartbeat.then(|| "on".to_string())),
            ("cycle", self.cycle.clone()),
        ];
        all.extend(named.into_iter().filter_map(|(k, v)| Some((k.to_string(), v?))));
        all
    }

    /// The built-in simulated drive's settings: the defaults with every `--sim` applied.
    pub fn sim_config(&self) -> SimConfig {
        let mut config = SimConfig::default();
        self.sim.iter().for_each(|s| s.apply(&mut config));
        config
    }

    pub fn is_simulated(&self) -> bool {
        self.port.is_none() && self.tcp.is_none() && self.can.is_none()
    }

    pub fn link_options(&self) -> LinkOptions {
        LinkOptions {
            reply_timeout: self.timeout,
            retries: self.retries,
            extra: self.all_link_options(),
        }
    }

    /// The drive's address and the family's link options, checked before anything opens.
    pub fn check(&self, registry: &Registry, family: &dyn Family) -> Result<DriveAddress, RunError> {
        family.check_link_options(&self.all_link_options())?;
        if let Some(capture) = &self.replay {
            super::replay_connection::captured_drive(registry, family, capture)?;
        }
        Ok(family.parse_drive_address(self.address_for(registry, family)?.as_deref())?)
    }

    /// The address in `family`'s notation: `--address` as given, or `--dnc-address N` as
    /// the family writes it (`dnc:N`); `None`: the family's default.
    pub fn address_for(&self, registry: &Registry, family: &dyn Family) -> Result<Option<String>, RunError> {
        match &self.dnc_address {
            Some(n) => DNC_ADDRESS.address(registry, family, n).map(Some),
            None => Ok(self.address.clone()),
        }
    }

    /// The address as a parameter backup records it: `--address` as given, or the address
    /// key a flag stands for with its value (`dnc_address 2`).
    pub fn address_recorded(&self) -> Option<String> {
        self.address.clone().or_else(|| {
            self.dnc_address
                .as_ref()
                .map(|n| format!("{} {n}", DNC_ADDRESS.key))
        })
    }

    /// The address option as the user typed it, for messages: `--address 3B`,
    /// `--dnc-address 2`.
    pub fn address_given(&self) -> Option<String> {
        match (&self.address, &self.dnc_address) {
            (Some(a), _) => Some(format!("--address {a}")),
            (None, Some(n)) => Some(format!("{} {n}", DNC_ADDRESS.flag)),
            (None, None) => None,
        }
    }

    /// The family's serial settings with the ones given here over them.
    pub fn serial_settings(&self, family: &dyn Family) -> SerialSettings {
        let mut settings = family.serial_settings();
        if let Some(baud) = self.baud {
            settings.baud = baud;
        }
        if let Some(bits) = self.data_bits {
            settings.data_bits = bits;
        }
        if let Some(parity) = self.parity {
            settings.parity = parity;
        }
        if let Some(stop) = self.stop_bits {
            settings.stop_bits = stop;
        }
        settings
    }

    /// The line these arguments open for `family`, in words (a trace's header).
    pub fn line_text(&self, family: &dyn Family) -> String {
        let bus = match (&self.port, &self.tcp, &self.can) {
            (Some(path), _, _) => format!("serial {path}, {}", self.serial_settings(family)),
            (None, Some(addr), _) => format!("TCP serial server {addr}"),
            (None, None, Some(CanSpec::Slcan(path))) => {
                format!("CAN via SLCAN adapter {path} at {} bit/s", self.bitrate)
            }
            (None, None, Some(CanSpec::SocketCan(interface))) => format!("CAN via SocketCAN {interface}"),
            (None, None, None) => match &self.replay {
                Some(capture) => format!("a replay of {}", capture.display()),
                None => "the built-in simulated drive".to_string(),
            },
        };
        let mut text = format!(
            "{bus}; reply timeout {:?}, {} retries",
            self.timeout, self.retries
        );
        for (name, value) in self.all_link_options() {
            text.push_str(&format!("; {name}={value}"));
        }
        text
    }

    /// Opens the bus for `family`. `virtual_time` applies to the simulated drive only:
    /// waiting then costs no real time.
    pub fn open(
        &self,
        registry: &Registry,
        family: &dyn Family,
        virtual_time: bool,
    ) -> Result<Connection, TransportError> {
        let address = self
            .check(registry, family)
            .map_err(|detail| TransportError::Open {
                port: "the drive".into(),
                detail: detail.to_string(),
            })?;
        let real =
            || -> (SharedClock, Option<Arc<Mutex<dyn SimulatedDrive>>>) { (RealClock::shared(), None) };
        if family.bus_kind() == BusKind::Frames && !self.is_simulated() && self.can.is_none() {
            return Err(TransportError::Open {
                port: self.port.clone().or_else(|| self.tcp.clone()).unwrap_or_default(),
                detail: format!(
                    "the {} family talks CAN frames, not a byte stream; give --can slcan:PATH (an SLCAN adapter) or --can socketcan:IF",
                    family.id()
                ),
            });
        }
        if let Some(can) = &self.can {
            let bus = self.open_can(family, can)?;
            let description = format!("{} on {}", address.shown, bus.name());
            return Ok(Connection {
                bus,
                address,
                clock: RealClock::shared(),
                simulator: None,
                description,
            });
        }
        let (bus, (clock, simulator), description) = match (&self.port, &self.tcp, &self.replay) {
            (Some(path), _, _) => {
                let t = SerialTransport::open(path, self.serial_settings(family))?;
                let d = format!("drive {} on {}", address.number, crate::bus::Transport::name(&t));
                (Bus::Bytes(SharedTransport::new(Box::new(t))), real(), d)
            }
            (None, Some(addr), _) => {
                let t = TcpTransport::connect(addr, CONNECT_TIMEOUT)?;
                let d = format!("drive {} on {}", address.number, crate::bus::Transport::name(&t));
                (Bus::Bytes(SharedTransport::new(Box::new(t))), real(), d)
            }
            (None, None, Some(capture)) => {
                let drive =
                    super::replay_connection::captured_drive(registry, family, capture).map_err(|e| {
                        TransportError::Open {
                            port: capture.display().to_string(),
                            detail: e.to_string().trim_start_matches("error: ").to_string(),
                        }
                    })?;
                // The capture's clock, not the wall's: a replay runs in virtual time.
                let clock: SharedClock = Arc::new(VirtualClock::new());
                let bus = super::replay_connection::replay_bus(drive, family, capture, clock.clone());
                let d = format!(
                    "a replay of {} ({}, virtual time; nothing is sent to any drive)",
                    capture.display(),
                    address.shown
                );
                (bus, (clock, None), d)
            }
            (None, None, None) => {
                let clock: SharedClock = if virtual_time {
                    Arc::new(VirtualClock::new())
                } else {
                    RealClock::shared()
                };
                let device = family.simulator(&address, self.sim_config());
                let name = crate::drive::SIMULATED_PORT;
                let bus = match (device.peer, family.bus_kind()) {
                    (SimPeer::Bytes(peer), _) => Bus::Bytes(SharedTransport::new(Box::new(
                        MemoryTransport::new(name, peer, clock.clone()),
                    ))),
                    (SimPeer::Frames(peer), _) => Bus::Frames(SharedFrameBus::new(Box::new(
                        MemoryFrameBus::new(name, peer, clock.clone()),
                    ))),
                };
                let time = if virtual_time { "virtual time" } else { "real time" };
                let d = format!(
                    "the built-in simulated {} drive ({}, {time}; no hardware is moved)",
                    family.id().to_uppercase(),
                    address.shown
                );
                (bus, (clock, Some(device.drive)), d)
            }
        };
        if family.bus_kind() == BusKind::Frames && bus.kind() != BusKind::Frames {
            return Err(TransportError::Open {
                port: bus.name().to_string(),
                detail: format!(
                    "the {} family talks CAN frames, not a byte stream; give --can slcan:PATH or --can socketcan:IF",
                    family.id()
                ),
            });
        }
        Ok(Connection {
            bus,
            address,
            clock,
            simulator,
            description,
        })
    }

    /// The CAN bus `--can` names, for a family that talks CAN frames.
    fn open_can(&self, family: &dyn Family, can: &CanSpec) -> Result<Bus, TransportError> {
        let name = match can {
            CanSpec::Slcan(path) => path.clone(),
            CanSpec::SocketCan(interface) => interface.clone(),
        };
        if family.bus_kind() != BusKind::Frames {
            return Err(TransportError::Open {
                port: name,
                detail: format!(
                    "the {} family talks over a serial line, not CAN; give --port or --tcp",
                    family.id()
                ),
            });
        }
        let bus: Box<dyn crate::bus::FrameBus> = match can {
            CanSpec::Slcan(path) => {
                let mut settings = family.serial_settings();
                if let Some(baud) = self.baud {
                    settings.baud = baud;
                }
                let port = SerialTransport::open(path, settings)?;
                Box::new(SlcanBus::open(Box::new(port), self.bitrate)?)
            }
            CanSpec::SocketCan(interface) => crate::bus::open_socketcan(interface)?,
        };
        Ok(Bus::Frames(SharedFrameBus::new(bus)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serial_frame_overrides() {
        assert_eq!(parse_data_bits("7"), Ok(DataBits::Seven));
        assert_eq!(parse_data_bits("8"), Ok(DataBits::Eight));
        assert!(parse_data_bits("9").unwrap_err().0.contains("7 or 8"));
        assert_eq!(parse_parity("even"), Ok(Parity::Even));
        assert_eq!(parse_parity("O"), Ok(Parity::Odd));
        assert_eq!(parse_parity("none"), Ok(Parity::None));
        assert!(parse_parity("mark").unwrap_err().0.contains("none, even or odd"));
        assert_eq!(parse_stop_bits("2"), Ok(StopBits::Two));
        assert!(parse_stop_bits("1.5").is_err());
    }
}
