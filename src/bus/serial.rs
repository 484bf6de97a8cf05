//! Serial port backend (RS232, or RS485 through an adapter) on the `serialport` crate.
//!
//! Opens the port exclusively, applies the line settings, and turns the crate's errors into
//! [`TransportError`]s that name the port and say what to try. It must not interpret,
//! frame or retry telegrams; that is the link's job.

use super::read_within::read_within;
use super::{Transport, TransportError};
use serialport::{ClearBuffer, SerialPort};
use std::fmt;
use std::io::{self, Read, Write};
use std::time::Duration;

/// Bits of data per character.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DataBits {
    Seven,
    Eight,
}

/// Parity bit per character.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Parity {
    None,
    Even,
    Odd,
}

/// Stop bits per character.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StopBits {
    One,
    Two,
}

impl DataBits {
    fn count(self) -> u32 {
        match self {
            DataBits::Seven => 7,
            DataBits::Eight => 8,
        }
    }
}

impl From<DataBits> for serialport::DataBits {
    fn from(d: DataBits) -> Self {
        match d {
            DataBits::Seven => serialport::DataBits::Seven,
            DataBits::Eight => serialport::DataBits::Eight,
        }
    }
}

impl From<Parity> for serialport::Parity {
    fn from(p: Parity) -> Self {
        match p {
            Parity::None => serialport::Parity::None,
            Parity::Even => serialport::Parity::Even,
            Parity::Odd => serialport::Parity::Odd,
        }
    }
}

impl From<StopBits> for serialport::StopBits {
    fn from(s: StopBits) -> Self {
        match s {
            StopBits::One => serialport::StopBits::One,
            StopBits::Two => serialport::StopBits::Two,
        }
    }
}

/// Line settings of a serial port.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SerialSettings {
    pub baud: u32,
    pub data_bits: DataBits,
    pub parity: Parity,
    pub stop_bits: StopBits,
}

impl Default for SerialSettings {
    /// 57600 8N1, a common drive default (each family states its own).
    fn default() -> Self {
        SerialSettings {
            baud: 57_600,
            data_bits: DataBits::Eight,
            parity: Parity::None,
            stop_bits: StopBits::One,
        }
    }
}

impl SerialSettings {
    /// 8N1 at `baud`.
    pub fn with_baud(baud: u32) -> Self {
        SerialSettings {
            baud,
            ..Self::default()
        }
    }

    /// Bits on the wire per character, start and stop bits included: 10 for 8N1.
    pub fn bits_per_byte(&self) -> u32 {
        let parity = u32::from(self.parity != Parity::None);
        let stop = match self.stop_bits {
            StopBits::One => 1,
            StopBits::Two => 2,
        };
        1 + self.data_bits.count() + parity + stop
    }

    /// Time that `n` bytes occupy the line.
    fn wire_time(&self, n: usize) -> Duration {
        if self.baud == 0 {
            return Duration::ZERO;
        }
        let bits = n as u128 * u128::from(self.bits_per_byte());
        Duration::from_nanos(u64::try_from(bits * 1_000_000_000 / u128::from(self.baud)).unwrap_or(u64::MAX))
    }
}

impl fmt::Display for SerialSettings {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parity = match self.parity {
            Parity::None => 'N',
            Parity::Even => 'E',
            Parity::Odd => 'O',
        };
        let stop = match self.stop_bits {
            StopBits::One => 1,
            StopBits::Two => 2,
        };
        write!(f, "{} {}{}{}", self.baud, self.data_bits.count(), parity, stop)
    }
}

/// Headroom on top of the pure wire time for a write to get out: a USB adapter's buffer, a
/// busy scheduler. Only a stuck adapter or hardware flow control holding us off exceeds it.
const WRITE_MARGIN: Duration = Duration::from_secs(1);

/// A drive (or bus) on a local serial port.
pub struct SerialTransport {
    /// `None` only between closing and reopening the device.
    port: Option<Box<dyn SerialPort>>,
    /// What was opened, for [`Transport::reopen`].
    path: String,
    name: String,
    settings: SerialSettings,
    /// Set by [`Transport::exchange_complete`], used up by the next `discard_input`.
    input_clean: bool,
    /// The line time of the last write, which `write_all` does not wait for.
    last_write: Duration,
    /// The open device's descriptor, non-blocking, for writes that skip the crate's poll
    /// for writability (the line's output buffer almost always has room for a telegram).
    #[cfg(unix)]
    fd: Option<std::os::fd::RawFd>,
}

impl SerialTransport {
    /// Opens `path` (`/dev/ttyUSB0`, `COM3`) exclusively with `settings`.
    pub fn open(path: &str, settings: SerialSettings) -> Result<Self, TransportError> {
        let builder = serialport::new(path, settings.baud)
            .data_bits(settings.data_bits.into())
            .parity(settings.parity.into())
            .stop_bits(settings.stop_bits.into())
            .flow_control(serialport::FlowControl::None);

        #[cfg(unix)]
        let fd;
        #[cfg(unix)]
        let port: Box<dyn SerialPort> = {
            let mut port = builder.open_native().map_err(|e| open_error(path, &e))?;
            fd = nonblocking_fd(&port);
            // The builder already asks for exclusivity, but saying it here keeps the
            // guarantee if the crate's default ever changes: two programs talking on one
            // drive line interleave telegrams and corrupt both conversations.
            port.set_exclusive(true).map_err(|_| TransportError::PortBusy {
                port: path.to_string(),
            })?;
            Box::new(port)
        };
        #[cfg(not(unix))]
        let port: Box<dyn SerialPort> = builder.open().map_err(|e| open_error(path, &e))?;

        let mut t = SerialTransport {
            port: Some(port),
            path: path.to_string(),
            name: format!("{path} at {settings}"),
            settings,
            input_clean: false,
            last_write: Duration::ZERO,
            #[cfg(unix)]
            fd,
        };
        // Opening can catch the tail of an earlier conversation or garbage from the line
        // settling at the new baud rate; none of it can be an answer to us.
        t.discard_input()?;
        Ok(t)
    }

    /// Wraps a port that is already open (a pseudo-terminal, for tests and the simulator).
    /// `name` is used as given in messages.
    #[cfg(unix)]
    pub fn from_port(port: serialport::TTYPort, name: String) -> Self {
        SerialTransport {
            fd: nonblocking_fd(&port),
            port: Some(Box::new(port)),
            path: name.clone(),
            name,
            settings: SerialSettings::default(),
            input_clean: false,
            last_write: Duration::ZERO,
        }
    }

    /// Writes what the device takes without waiting and returns how many bytes that was;
    /// the rest (a full output buffer, an error to report) goes the crate's way.
    #[cfg(unix)]
    fn write_at_once(&mut self, bytes: &[u8]) -> usize {
        let (Some(fd), Some(_)) = (self.fd, self.port.as_ref()) else {
            return 0;
        };
        let mut done = 0;
        while done < bytes.len() {
            let rest = &bytes[done..];
            // SAFETY: `fd` belongs to the open port (checked above; it is cleared whenever
            // the port is closed) and `rest` is a valid buffer of `rest.len()` bytes.
            let n = unsafe { libc::write(fd, rest.as_ptr().cast(), rest.len()) };
            match usize::try_from(n) {
                Ok(n) if n > 0 => done += n,
                _ => break,
            }
        }
        done
    }

    /// The line settings this transport was opened with.
    pub fn settings(&self) -> SerialSettings {
        self.settings
    }

    fn io_error(&self, e: &io::Error) -> TransportError {
        let detail = match e.kind() {
            // poll() reports a hang-up this way.
            io::ErrorKind::BrokenPipe => {
                "the device hung up (USB adapter unplugged, or the other end closed)".to_string()
            }
            _ => e.to_string(),
        };
        TransportError::Io {
            port: self.name.clone(),
            detail,
        }
    }

    /// The open device; an error when an earlier reopen closed it and could not open it
    /// again.
    fn device(&mut self) -> Result<&mut Box<dyn SerialPort>, TransportError> {
        let name = &self.name;
        self.port.as_mut().ok_or_else(|| TransportError::Io {
            port: name.clone(),
            detail: "the port is closed: the device went away and could not be opened again".into(),
        })
    }

    fn port_error(&self, e: &serialport::Error) -> TransportError {
        TransportError::Io {
            port: self.name.clone(),
            detail: e.to_string(),
        }
    }
}

/// Turns an open failure into the error that tells the user what to do.
///
/// `serialport` reports "busy" as `NoDevice` on unix (EBUSY from TIOCEXCL, or the flock
/// held by another program), so the description is checked before the kind.
fn open_error(path: &str, e: &serialport::Error) -> TransportError {
    let port = path.to_string();
    let description = e.description.to_ascii_lowercase();
    if description.contains("busy") || description.contains("lock") {
        return TransportError::PortBusy { port };
    }
    // Windows answers ACCESS_DENIED (as `NoDevice`) when another program holds the port.
    if cfg!(windows) && description.contains("access is denied") {
        return TransportError::PortBusy { port };
    }
    match e.kind {
        serialport::ErrorKind::NoDevice | serialport::ErrorKind::Io(io::ErrorKind::NotFound) => {
            TransportError::PortNotFound { port }
        }
        serialport::ErrorKind::Io(io::ErrorKind::PermissionDenied) => {
            TransportError::PermissionDenied { port }
        }
        // ENODEV/ENXIO: the node exists but the hardware behind it is gone (an unplugged
        // adapter whose node is still around), which to the user is a missing port.
        _ if description.contains("no such device") => TransportError::PortNotFound { port },
        // ENOTTY ("Not a typewriter", "Inappropriate ioctl for device"): a file, a pipe or
        // /dev/null given as the port; the system's word for it means nothing to a user.
        _ if description.contains("typewriter") || description.contains("inappropriate ioctl") => {
            TransportError::Open {
                port,
                detail: "it is not a serial port (it takes no baud rate or line settings); give the serial device, e.g. /dev/ttyUSB0 or /dev/serial/by-id/…; `drivescript ports` lists this machine's ports".into(),
            }
        }
        _ => TransportError::Open {
            port,
            detail: e.description.clone(),
        },
    }
}

/// `op` on `port` with the port's one timeout (it serves both directions) set to `timeout`.
fn within<T>(
    port: &mut Box<dyn SerialPort>,
    timeout: Duration,
    op: impl FnOnce(&mut Box<dyn SerialPort>) -> io::Result<T>,
) -> io::Result<T> {
    port.set_timeout(timeout).map_err(io::Error::from)?;
    op(port)
}

impl Transport for SerialTransport {
    fn name(&self) -> &str {
        &self.name
    }

    fn serial_settings(&self) -> Option<SerialSettings> {
        Some(self.settings())
    }

    fn write_all(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        // The port has one timeout for both directions and the last read may have left it
        // at a few milliseconds, too short for a long telegram at a low baud rate.
        self.last_write = self.settings.wire_time(bytes.len());
        let allowed = self.last_write + WRITE_MARGIN;
        #[cfg(unix)]
        let bytes = &bytes[self.write_at_once(bytes)..];
        if bytes.is_empty() {
            return Ok(());
        }
        let port = self.device()?;
        // No drain (tcdrain) after the write: the reply timeout starts after the line time
        // of the request instead (`still_sending`), which spares a system call per telegram.
        let sent = within(port, allowed, |port| port.write_all(bytes));
        match sent {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == io::ErrorKind::TimedOut => Err(TransportError::Io {
                port: self.name.clone(),
                detail: format!(
                    "could not send {} bytes within {} ms (adapter stuck, or flow control holding the line)",
                    bytes.len(),
                    allowed.as_millis()
                ),
            }),
            Err(e) => Err(self.io_error(&e)),
        }
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        let read = read_within(buf, timeout, |buf, left| {
            let port = self.device()?;
            let read = within(port, left, |port| port.read(buf));
            match read {
                Ok(n) if n > 0 => Ok(Some(n)),
                // A signal or a zero-length read is not an answer; keep waiting while the
                // caller's time lasts.
                Ok(_) => Ok(None),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => Ok(None),
                Err(e) if e.kind() == io::ErrorKind::TimedOut || e.kind() == io::ErrorKind::WouldBlock => {
                    Ok(None)
                }
                Err(e) => Err(self.io_error(&e)),
            }
        })?;
        read.ok_or_else(|| TransportError::Timeout {
            port: self.name.clone(),
            waited: timeout,
        })
    }

    fn still_sending(&self) -> Duration {
        self.last_write
    }

    fn discard_input(&mut self) -> Result<usize, TransportError> {
        if std::mem::take(&mut self.input_clean) {
            return Ok(0);
        }
        let port = self.device()?;
        // Clearing only when something is there saves a system call per telegram.
        let cleared = port.bytes_to_read().and_then(|pending| match pending {
            0 => Ok(0),
            n => port.clear(ClearBuffer::Input).map(|()| n),
        });
        let pending = cleared.map_err(|e| self.port_error(&e))?;
        Ok(usize::try_from(pending).unwrap_or(usize::MAX))
    }

    fn discard_output(&mut self) -> Result<bool, TransportError> {
        let port = self.device()?;
        let cleared = port.clear(ClearBuffer::Output);
        cleared.map_err(|e| self.port_error(&e))?;
        Ok(true)
    }

    fn reopen(&mut self) -> Result<(), TransportError> {
        // The old descriptor holds the exclusive lock on a device that may have come back
        // under the same path (a udev by-id link); it must be closed before the new open.
        drop(self.port.take());
        self.input_clean = false;
        #[cfg(unix)]
        {
            self.fd = None;
        }
        let mut fresh = SerialTransport::open(&self.path, self.settings)?;
        self.port = fresh.port.take();
        #[cfg(unix)]
        {
            self.fd = fresh.fd;
        }
        Ok(())
    }

    fn exchange_complete(&mut self) {
        self.input_clean = true;
    }
}

/// The port's descriptor switched to non-blocking, or `None` when that fails (then every
/// write goes through the crate's poll).
#[cfg(unix)]
fn nonblocking_fd(port: &serialport::TTYPort) -> Option<std::os::fd::RawFd> {
    use std::os::fd::AsRawFd;
    let fd = port.as_raw_fd();
    // SAFETY: `fd` is the open descriptor `port` owns; F_GETFL/F_SETFL only change its
    // status flags. The crate's own reads and writes poll first, so they are unaffected.
    let set = unsafe {
        let flags = libc::fcntl(fd, libc::F_GETFL);
        flags >= 0 && libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK) == 0
    };
    set.then_some(fd)
}

/// How a port is attached, for `drivescript ports`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsbInfo {
    pub vid: u16,
    pub pid: u16,
    pub serial_number: Option<String>,
    pub manufacturer: Option<String>,
    pub product: Option<String>,
}

/// One serial port this machine has.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInfo {
    /// What to pass to `--port`: `/dev/ttyUSB0`, `COM3`.
    pub name: String,
    /// `usb`, `pci`, `bluetooth` or `unknown`.
    pub kind: String,
    /// Present for USB adapters: the IDs and strings that tell two adapters apart.
    pub usb: Option<UsbInfo>,
    /// A USB-serial adapter's latency timer in ms, where the system exposes it.
    pub latency_timer_ms: Option<u32>,
}

/// The serial ports this machine has, sorted by name.
pub fn list_ports() -> Result<Vec<PortInfo>, TransportError> {
    let ports = serialport::available_ports().map_err(|e| TransportError::Io {
        port: "the list of serial ports".to_string(),
        detail: e.to_string(),
    })?;
    let mut list: Vec<PortInfo> = ports
        .into_iter()
        .map(|p| {
            let (kind, usb) = match p.port_type {
                serialport::SerialPortType::UsbPort(u) => (
                    "usb",
                    Some(UsbInfo {
                        vid: u.vid,
                        pid: u.pid,
                        serial_number: u.serial_number,
                        manufacturer: u.manufacturer,
                        product: u.product,
                    }),
                ),
                serialport::SerialPortType::PciPort => ("pci", None),
                serialport::SerialPortType::BluetoothPort => ("bluetooth", None),
                serialport::SerialPortType::Unknown => ("unknown", None),
            };
            PortInfo {
                name: p.port_name,
                kind: kind.to_string(),
                usb,
                latency_timer_ms: None,
            }
        })
        .collect();
    // The kernel's own list of USB-serial ports, for those the enumeration missed (Linux's
    // sysfs; elsewhere there is none).
    let root = super::usb_latency::sysfs_root();
    let sysfs = cfg!(target_os = "linux");
    for name in super::usb_latency::usb_serial_ports(&root)
        .into_iter()
        .filter(|_| sysfs)
    {
        if !list.iter().any(|p| p.name == name) {
            list.push(PortInfo {
                name,
                kind: "usb".to_string(),
                usb: None,
                latency_timer_ms: None,
            });
        }
    }
    for p in &mut list {
        p.latency_timer_ms = super::usb_latency::latency_timer_ms(&root, &p.name);
    }
    list.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(list)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(unix)]
    use std::time::Instant;

    #[test]
    fn default_settings_display_as_8n1() {
        assert_eq!(SerialSettings::default().to_string(), "57600 8N1");
        let s = SerialSettings {
            baud: 9600,
            data_bits: DataBits::Seven,
            parity: Parity::Even,
            stop_bits: StopBits::Two,
        };
        assert_eq!(s.to_string(), "9600 7E2");
        assert_eq!(s.bits_per_byte(), 11);
        assert_eq!(SerialSettings::with_baud(115_200).to_string(), "115200 8N1");
        assert_eq!(SerialSettings::default().bits_per_byte(), 10);
    }

    #[test]
    fn missing_port_is_port_not_found_and_named() {
        let err = SerialTransport::open("/dev/does-not-exist-xyz", SerialSettings::default())
            .err()
            .unwrap();
        assert!(matches!(err, TransportError::PortNotFound { .. }), "{err:?}");
        assert!(err.to_string().contains("/dev/does-not-exist-xyz"));
    }

    #[test]
    fn open_errors_are_classified() {
        use serialport::{Error, ErrorKind};
        let busy = Error::new(ErrorKind::NoDevice, "Device or resource busy");
        assert!(matches!(open_error("p", &busy), TransportError::PortBusy { .. }));
        let locked = Error::new(
            ErrorKind::NoDevice,
            "Unable to acquire exclusive lock on serial port",
        );
        assert!(matches!(
            open_error("p", &locked),
            TransportError::PortBusy { .. }
        ));
        let denied = Error::new(
            ErrorKind::Io(io::ErrorKind::PermissionDenied),
            "Permission denied",
        );
        assert!(matches!(
            open_error("p", &denied),
            TransportError::PermissionDenied { .. }
        ));
        let gone = Error::new(ErrorKind::Unknown, "No such device or address");
        assert!(matches!(
            open_error("p", &gone),
            TransportError::PortNotFound { .. }
        ));
        let odd = Error::new(ErrorKind::InvalidInput, "bad baud rate");
        match open_error("p", &odd) {
            TransportError::Open { port, detail } => {
                assert_eq!(port, "p");
                assert_eq!(detail, "bad baud rate");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn port_list_is_sorted_by_name() {
        // A machine may have no ports at all; the list must still come back, in order.
        let ports = list_ports().unwrap();
        assert!(ports.windows(2).all(|w| w[0].name <= w[1].name));
        for p in &ports {
            assert!(["usb", "pci", "bluetooth", "unknown"].contains(&p.kind.as_str()));
            assert_eq!(p.usb.is_some(), p.kind == "usb");
        }
    }

    #[cfg(unix)]
    mod pty {
        use super::*;
        use serialport::TTYPort;

        /// The transport on the pty's device side, and the other end to play the drive.
        fn pair() -> (SerialTransport, TTYPort) {
            let (master, slave) = TTYPort::pair().unwrap();
            (SerialTransport::from_port(slave, "pty".to_string()), master)
        }

        /// The first `n` bytes the drive's end reads, each read waiting at most `timeout`.
        fn drive_reads(drive: &mut TTYPort, n: usize, timeout: Duration) -> Vec<u8> {
            drive.set_timeout(timeout).unwrap();
            let mut got = Vec::new();
            let mut buf = [0u8; 4096];
            while got.len() < n {
                let read = drive.read(&mut buf).unwrap();
                got.extend_from_slice(&buf[..read]);
            }
            got
        }

        fn wait_until_pending(t: &mut SerialTransport, n: u32) {
            let deadline = Instant::now() + Duration::from_millis(500);
            while t.device().unwrap().bytes_to_read().unwrap() < n {
                assert!(Instant::now() < deadline, "bytes never arrived");
                std::thread::yield_now();
            }
        }

        #[test]
        fn bytes_written_by_the_drive_are_read() {
            let (mut t, mut drive) = pair();
            drive.write_all(&[0x02, 0x10, 0x20, 0x03]).unwrap();
            let mut got = Vec::new();
            let mut buf = [0u8; 16];
            while got.len() < 4 {
                let n = t.read(&mut buf, Duration::from_millis(200)).unwrap();
                assert!(n > 0);
                got.extend_from_slice(&buf[..n]);
            }
            assert_eq!(got, [0x02, 0x10, 0x20, 0x03]);
            assert_eq!(t.name(), "pty");
        }

        #[test]
        fn bytes_written_by_the_transport_reach_the_drive() {
            let (mut t, mut drive) = pair();
            assert_eq!(t.still_sending(), Duration::ZERO);
            t.write_all(b"hello").unwrap();
            // Not drained: the reply timeout starts after the bytes' time on the line.
            assert_eq!(t.still_sending(), t.settings.wire_time(5));
            assert!(t.still_sending() > Duration::ZERO);
            assert_eq!(drive_reads(&mut drive, 5, Duration::from_millis(200)), b"hello");
        }

        #[test]
        fn silence_is_a_timeout_not_zero_bytes() {
            let (mut t, _drive) = pair();
            let mut buf = [0u8; 8];
            let started = Instant::now();
            let err = t.read(&mut buf, Duration::from_millis(50)).unwrap_err();
            assert!(started.elapsed() >= Duration::from_millis(50));
            match err {
                TransportError::Timeout { port, waited } => {
                    assert_eq!(port, "pty");
                    assert_eq!(waited, Duration::from_millis(50));
                }
                other => panic!("{other:?}"),
            }
        }

        #[test]
        fn a_complete_exchange_spares_one_discard_and_only_one() {
            let (mut t, mut drive) = pair();
            drive.write_all(&[1, 2, 3]).unwrap();
            wait_until_pending(&mut t, 3);
            t.exchange_complete();
            // The link vouched that nothing stale is waiting: the device is not asked.
            assert_eq!(t.discard_input().unwrap(), 0);
            // The next exchange gets no such promise, so the bytes are found and dropped.
            assert_eq!(t.discard_input().unwrap(), 3);
        }

        #[test]
        fn a_telegram_larger_than_one_write_still_arrives_whole() {
            let (mut t, mut drive) = pair();
            let telegram: Vec<u8> = (0..=255u8).cycle().take(200_000).collect();
            let reader = std::thread::spawn(move || {
                let got = drive_reads(&mut drive, 200_000, Duration::from_secs(2));
                // The drive's end stays open until the writer's drain is over: closing it
                // earlier is a hang-up, which the drain rightly reports.
                (got, drive)
            });
            t.write_all(&telegram).unwrap();
            let (got, _drive) = reader.join().unwrap();
            assert_eq!(got, telegram);
        }

        #[test]
        fn discard_drops_pending_bytes() {
            let (mut t, mut drive) = pair();
            drive.write_all(&[1, 2, 3]).unwrap();
            wait_until_pending(&mut t, 3);
            assert_eq!(t.discard_input().unwrap(), 3);
            crate::bus::transport_checks::assert_nothing_to_read(&mut t);
            drive.write_all(&[4]).unwrap();
            let mut buf = [0u8; 8];
            assert_eq!(t.read(&mut buf, Duration::from_millis(200)).unwrap(), 1);
            assert_eq!(buf[0], 4);
        }

        #[test]
        fn a_port_held_by_another_transport_is_busy() {
            let (_master, slave) = TTYPort::pair().unwrap();
            let path = slave.name().unwrap();
            let first = SerialTransport::open(&path, SerialSettings::default()).unwrap();
            assert!(first.name().starts_with(&path));
            assert!(first.name().ends_with(" at 57600 8N1"));
            let err = SerialTransport::open(&path, SerialSettings::default())
                .err()
                .unwrap();
            assert!(matches!(err, TransportError::PortBusy { .. }), "{err:?}");
            assert!(err.to_string().contains(&path));
        }
    }
}
