//! Raw TCP backend for serial device servers (RS232/RS485 to Ethernet) and ser2net.
//!
//! The server forwards bytes to and from the drive's serial line unchanged, so this is a
//! byte pipe like the serial port. It must not speak Telnet/RFC 2217 or interpret, frame or
//! retry telegrams; that is the link's job.

use super::read_within::read_within;
use super::{Transport, TransportError};
use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::Duration;

/// `set_read_timeout` rejects a zero duration (it would mean "block forever").
const MIN_READ_TIMEOUT: Duration = Duration::from_millis(1);

/// How long a write may wait for room in the socket buffer. A server that stops taking bytes
/// for this long has lost its serial side; better a clear error than a hang.
const WRITE_TIMEOUT: Duration = Duration::from_secs(5);

/// A drive (or bus) behind a serial device server, over raw TCP.
pub struct TcpTransport {
    stream: TcpStream,
    name: String,
    /// Where [`TcpTransport::connect`] connected, and how long it may take, for
    /// [`Transport::reopen`]; `None` for a wrapped stream.
    dialled: Option<(String, Duration)>,
}

impl TcpTransport {
    /// Connects to `addr` (`HOST:PORT`), trying every address the host name resolves to,
    /// each for at most `connect_timeout`.
    pub fn connect(addr: &str, connect_timeout: Duration) -> Result<Self, TransportError> {
        let fail = |detail: String| TransportError::Connect {
            addr: addr.to_string(),
            waited: connect_timeout,
            detail,
        };
        let candidates: Vec<SocketAddr> = addr
            .to_socket_addrs()
            .map_err(|e| {
                if e.kind() == io::ErrorKind::InvalidInput {
                    fail(format!("not a HOST:PORT address such as 192.0.2.7:4001 ({e})"))
                } else {
                    fail(format!("cannot resolve the host name ({e})"))
                }
            })?
            .collect();
        if candidates.is_empty() {
            return Err(fail("the host name resolved to no address".to_string()));
        }

        // connect_timeout also rejects a zero duration.
        let per_try = connect_timeout.max(MIN_READ_TIMEOUT);
        let mut failures = Vec::new();
        let mut connected = None;
        for candidate in &candidates {
            match TcpStream::connect_timeout(candidate, per_try) {
                Ok(s) => {
                    connected = Some(s);
                    break;
                }
                Err(e) => failures.push((candidate, e)),
            }
        }
        let Some(stream) = connected else {
            let detail = match failures.as_slice() {
                [(_, e)] => e.to_string(),
                many => many
                    .iter()
                    .map(|(a, e)| format!("{a}: {e}"))
                    .collect::<Vec<_>>()
                    .join("; "),
            };
            return Err(fail(detail));
        };

        let mut t = Self::from_stream(stream, format!("tcp {addr}"))?;
        t.dialled = Some((addr.to_string(), connect_timeout));
        Ok(t)
    }

    /// Wraps a connected stream (the simulator's side of `drivescript simulate --tcp`).
    pub fn from_stream(stream: TcpStream, name: String) -> Result<Self, TransportError> {
        let setup = |e: io::Error| TransportError::Io {
            port: name.clone(),
            detail: e.to_string(),
        };
        // Telegrams are a few bytes and every one waits for its answer; Nagle's algorithm
        // would hold each request back for up to a delayed-ACK period.
        stream.set_nodelay(true).map_err(setup)?;
        stream.set_write_timeout(Some(WRITE_TIMEOUT)).map_err(setup)?;
        Ok(TcpTransport {
            stream,
            name,
            dialled: None,
        })
    }

    fn closed(&self) -> TransportError {
        TransportError::Closed {
            port: self.name.clone(),
        }
    }

    fn io_error(&self, e: &io::Error) -> TransportError {
        TransportError::Io {
            port: self.name.clone(),
            detail: e.to_string(),
        }
    }

    fn is_disconnect(e: &io::Error) -> bool {
        matches!(
            e.kind(),
            io::ErrorKind::ConnectionReset
                | io::ErrorKind::ConnectionAborted
                | io::ErrorKind::BrokenPipe
                | io::ErrorKind::NotConnected
                | io::ErrorKind::UnexpectedEof
        )
    }

    /// Reads and drops whatever has arrived, without waiting for more.
    fn drain(&mut self) -> io::Result<usize> {
        let mut dropped = 0;
        let mut scratch = [0u8; 512];
        loop {
            match self.stream.read(&mut scratch) {
                // The peer has closed; the next read reports that.
                Ok(0) => return Ok(dropped),
                Ok(n) => dropped += n,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => return Ok(dropped),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

impl Transport for TcpTransport {
    fn name(&self) -> &str {
        &self.name
    }

    fn write_all(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        match self.stream.write_all(bytes).and_then(|()| self.stream.flush()) {
            Ok(()) => Ok(()),
            Err(e) if Self::is_disconnect(&e) => Err(self.closed()),
            Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {
                Err(TransportError::Io {
                    port: self.name.clone(),
                    detail: format!("the server took no data for {} s", WRITE_TIMEOUT.as_secs()),
                })
            }
            Err(e) => Err(self.io_error(&e)),
        }
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        let read = read_within(buf, timeout, |buf, left| {
            self.stream
                .set_read_timeout(Some(left.max(MIN_READ_TIMEOUT)))
                .map_err(|e| self.io_error(&e))?;
            match self.stream.read(buf) {
                Ok(0) => Err(self.closed()),
                Ok(n) => Ok(Some(n)),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => Ok(None),
                Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => Ok(None),
                Err(e) if Self::is_disconnect(&e) => Err(self.closed()),
                Err(e) => Err(self.io_error(&e)),
            }
        })?;
        read.ok_or_else(|| TransportError::Timeout {
            port: self.name.clone(),
            waited: timeout,
        })
    }

    fn discard_input(&mut self) -> Result<usize, TransportError> {
        self.stream.set_nonblocking(true).map_err(|e| self.io_error(&e))?;
        let drained = self.drain();
        // Switch back even when draining failed, or every later read would return at once.
        let restored = self.stream.set_nonblocking(false);
        let dropped = match drained {
            Ok(n) => n,
            Err(e) if Self::is_disconnect(&e) => return Err(self.closed()),
            Err(e) => return Err(self.io_error(&e)),
        };
        restored.map_err(|e| self.io_error(&e))?;
        Ok(dropped)
    }

    fn reopen(&mut self) -> Result<(), TransportError> {
        let Some((addr, timeout)) = self.dialled.clone() else {
            return Err(TransportError::Open {
                port: self.name.clone(),
                detail: "a connection accepted from a peer cannot be dialled again".into(),
            });
        };
        let _ = self.stream.shutdown(std::net::Shutdown::Both);
        *self = TcpTransport::connect(&addr, timeout)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;
    use std::thread;
    use std::time::Instant;

    const LOOPBACK: &str = "127.0.0.1:0";

    /// A connected transport and the server's side of the connection.
    fn connected() -> (TcpTransport, TcpStream) {
        let listener = TcpListener::bind(LOOPBACK).unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        let t = TcpTransport::connect(&addr, Duration::from_millis(500)).unwrap();
        let (server, _) = listener.accept().unwrap();
        (t, server)
    }

    fn read_exactly(t: &mut TcpTransport, n: usize) -> Vec<u8> {
        let mut got = Vec::new();
        let mut buf = [0u8; 64];
        while got.len() < n {
            let k = t.read(&mut buf, Duration::from_millis(500)).unwrap();
            assert!(k > 0);
            got.extend_from_slice(&buf[..k]);
        }
        got
    }

    #[test]
    fn echoes_through_a_server() {
        let listener = TcpListener::bind(LOOPBACK).unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        let echo = thread::spawn(move || {
            let (mut s, _) = listener.accept().unwrap();
            let mut buf = [0u8; 64];
            let n = s.read(&mut buf).unwrap();
            s.write_all(&buf[..n]).unwrap();
        });
        let mut t = TcpTransport::connect(&addr, Duration::from_millis(500)).unwrap();
        assert_eq!(t.name(), format!("tcp {addr}"));
        assert!(t.stream.nodelay().unwrap());
        t.write_all(&[0x02, 0x41, 0x03]).unwrap();
        assert_eq!(read_exactly(&mut t, 3), [0x02, 0x41, 0x03]);
        echo.join().unwrap();
    }

    #[test]
    fn silence_is_a_timeout() {
        let (mut t, _server) = connected();
        let mut buf = [0u8; 8];
        let started = Instant::now();
        match t.read(&mut buf, Duration::from_millis(50)).unwrap_err() {
            TransportError::Timeout { port, waited } => {
                assert!(port.starts_with("tcp 127.0.0.1:"));
                assert_eq!(waited, Duration::from_millis(50));
            }
            other => panic!("{other:?}"),
        }
        assert!(started.elapsed() >= Duration::from_millis(50));
        // A zero timeout must not be passed to set_read_timeout as zero.
        assert!(t.read(&mut buf, Duration::ZERO).unwrap_err().is_timeout());
    }

    #[test]
    fn peer_closing_is_closed() {
        let (mut t, server) = connected();
        drop(server);
        let mut buf = [0u8; 8];
        let err = t.read(&mut buf, Duration::from_millis(500)).unwrap_err();
        assert!(matches!(err, TransportError::Closed { .. }), "{err:?}");
    }

    #[test]
    fn closed_port_is_a_connect_error_naming_the_address() {
        // Bind then drop: the port was free a moment ago and nothing listens on it now.
        let addr = TcpListener::bind(LOOPBACK)
            .unwrap()
            .local_addr()
            .unwrap()
            .to_string();
        let err = TcpTransport::connect(&addr, Duration::from_millis(200))
            .err()
            .unwrap();
        assert!(matches!(err, TransportError::Connect { .. }), "{err:?}");
        assert!(err.to_string().contains(&addr), "{err}");
    }

    #[test]
    fn an_address_without_port_says_so() {
        let err = TcpTransport::connect("127.0.0.1", Duration::from_millis(50))
            .err()
            .unwrap();
        assert!(err.to_string().contains("HOST:PORT"), "{err}");
    }

    #[test]
    fn discard_drops_what_has_arrived_and_reads_block_again() {
        let (mut t, mut server) = connected();
        server.write_all(&[1, 2, 3, 4, 5]).unwrap();
        // Wait until all five are in our socket buffer, without consuming them.
        let deadline = Instant::now() + Duration::from_millis(500);
        t.stream
            .set_read_timeout(Some(Duration::from_millis(500)))
            .unwrap();
        let mut peek = [0u8; 8];
        while t.stream.peek(&mut peek).unwrap() < 5 {
            assert!(Instant::now() < deadline, "bytes never arrived");
            thread::yield_now();
        }
        assert_eq!(t.discard_input().unwrap(), 5);
        assert_eq!(t.discard_input().unwrap(), 0);
        crate::bus::transport_checks::assert_nothing_to_read(&mut t);
        server.write_all(&[9]).unwrap();
        assert_eq!(read_exactly(&mut t, 1), [9]);
    }
}
