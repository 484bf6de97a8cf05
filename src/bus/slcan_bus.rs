//! A CAN bus through an SLCAN (Lawicel) adapter on any byte transport: a USB-serial
//! adapter, or a pseudo-terminal with the simulated adapter behind it. Opening closes the
//! channel (in case a previous program left it open), sets the bit rate and opens it;
//! frames go out as `t…` lines and come back as events of [`SlcanReader`], with the
//! adapter's acknowledgements passed over and its refusals (BELL) reported. Knows nothing
//! about what the frames mean.

use super::slcan_codec::{bitrate_command, encode_frame, SlcanEvent, SlcanReader, BITRATES};
use super::{CanFrame, FrameBus, Transport, TransportError};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// How long the adapter may take to acknowledge a setup command.
const SETUP_TIMEOUT: Duration = Duration::from_secs(1);
/// Quiet time before the set-up is tried again.
const SETTLE: Duration = Duration::from_millis(50);
/// Frames kept while the link is not reading (a busy bus between two transfers); the
/// oldest go first.
const QUEUE_MAX: usize = 1024;

pub struct SlcanBus {
    transport: Box<dyn Transport>,
    reader: SlcanReader,
    name: String,
    bitrate: u32,
    frames: VecDeque<CanFrame>,
    /// The adapter refused something since the last frame was sent.
    refused: bool,
    buf: [u8; 256],
}

impl SlcanBus {
    /// Opens the CAN channel on `transport` at `bitrate` bit/s.
    pub fn open(transport: Box<dyn Transport>, bitrate: u32) -> Result<SlcanBus, TransportError> {
        let name = format!("{}, SLCAN at {} kbit/s", transport.name(), bitrate / 1000);
        let mut bus = SlcanBus {
            transport,
            reader: SlcanReader::new(),
            name,
            bitrate,
            frames: VecDeque::new(),
            refused: false,
            buf: [0; 256],
        };
        bus.start()?;
        Ok(bus)
    }

    /// `C`, `Sn`, `O`: closing may be refused (the channel was closed), the others not.
    /// A refusal is tried once more after the line settled: an acknowledgement still on
    /// its way from the previous program's last command would otherwise be taken as the
    /// answer to `C`, and the answer to `C` as a refusal of `Sn`.
    fn start(&mut self) -> Result<(), TransportError> {
        let rate = bitrate_command(self.bitrate).ok_or_else(|| TransportError::Open {
            port: self.name.clone(),
            detail: format!(
                "SLCAN adapters know the bit rates {BITRATES}, not {} bit/s",
                self.bitrate
            ),
        })?;
        let mut attempt = 0;
        loop {
            attempt += 1;
            self.transport.discard_input()?;
            self.reader.clear();
            self.frames.clear();
            let result = self
                .command("C", true)
                .and_then(|()| self.command(rate, false))
                .and_then(|()| self.command("O", false));
            match result {
                Err(TransportError::Open { .. }) if attempt < 2 => std::thread::sleep(SETTLE),
                other => return other,
            }
        }
    }

    /// Sends a setup command and waits for its acknowledgement. Frames arriving meanwhile
    /// are kept. `may_refuse`: a BELL is an answer too.
    fn command(&mut self, command: &str, may_refuse: bool) -> Result<(), TransportError> {
        self.transport.write_all(format!("{command}\r").as_bytes())?;
        let deadline = Instant::now() + SETUP_TIMEOUT;
        loop {
            let now = Instant::now();
            if now >= deadline {
                return Err(TransportError::Open {
                    port: self.name.clone(),
                    detail: format!(
                        "the adapter did not acknowledge `{command}` within {} ms; is it an SLCAN (Lawicel) adapter, and is nothing else using it?",
                        SETUP_TIMEOUT.as_millis()
                    ),
                });
            }
            let n = match self.transport.read(&mut self.buf, deadline - now) {
                Ok(n) => n,
                Err(TransportError::Timeout { .. }) => continue,
                Err(e) => return Err(e),
            };
            let bytes = self.buf[..n].to_vec();
            // Frames that came with the answer are kept; the first answer counts.
            let mut answer = None;
            for event in self.reader.push(&bytes) {
                match event {
                    SlcanEvent::Ack => {
                        answer.get_or_insert(true);
                    }
                    SlcanEvent::Refused => {
                        answer.get_or_insert(false);
                    }
                    SlcanEvent::Frame(f) => self.keep(f),
                    SlcanEvent::Remote | SlcanEvent::Other(_) => {}
                }
            }
            match answer {
                Some(true) => return Ok(()),
                Some(false) if may_refuse => return Ok(()),
                Some(false) => {
                    return Err(TransportError::Open {
                        port: self.name.clone(),
                        detail: format!("the adapter refused `{command}` (it answered BELL)"),
                    })
                }
                None => {}
            }
        }
    }

    fn keep(&mut self, frame: CanFrame) {
        if self.frames.len() >= QUEUE_MAX {
            self.frames.pop_front();
        }
        self.frames.push_back(frame);
    }

    fn refusal(&self) -> TransportError {
        TransportError::Io {
            port: self.name.clone(),
            detail: "the adapter refused to transmit (it answered BELL); check the bit rate, the termination and whether the adapter is bus-off".into(),
        }
    }
}

impl FrameBus for SlcanBus {
    fn name(&self) -> &str {
        &self.name
    }

    fn send(&mut self, frame: &CanFrame) -> Result<(), TransportError> {
        self.refused = false;
        self.transport.write_all(&encode_frame(frame))
    }

    fn receive(&mut self, timeout: Duration) -> Result<CanFrame, TransportError> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(f) = self.frames.pop_front() {
                return Ok(f);
            }
            let now = Instant::now();
            if now >= deadline && !timeout.is_zero() {
                if self.refused {
                    return Err(self.refusal());
                }
                return Err(TransportError::Timeout {
                    port: self.name.clone(),
                    waited: timeout,
                });
            }
            // A zero timeout only takes what is already there.
            let wait = deadline
                .saturating_duration_since(now)
                .max(Duration::from_micros(1));
            let n = match self.transport.read(&mut self.buf, wait) {
                Ok(n) => n,
                Err(TransportError::Timeout { .. }) if timeout.is_zero() => {
                    return Err(TransportError::Timeout {
                        port: self.name.clone(),
                        waited: timeout,
                    })
                }
                Err(TransportError::Timeout { .. }) => continue,
                Err(e) => return Err(e),
            };
            let bytes = self.buf[..n].to_vec();
            for event in self.reader.push(&bytes) {
                match event {
                    SlcanEvent::Frame(f) => self.keep(f),
                    SlcanEvent::Refused => self.refused = true,
                    SlcanEvent::Ack | SlcanEvent::Remote | SlcanEvent::Other(_) => {}
                }
            }
        }
    }

    fn reopen(&mut self) -> Result<(), TransportError> {
        self.transport.reopen()?;
        self.start()
    }
}

impl Drop for SlcanBus {
    /// Closes the channel so the adapter is left as it was found.
    fn drop(&mut self) {
        let _ = self.transport.write_all(b"C\r");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::{MemoryTransport, Peer, PeerReply};
    use crate::clock::RealClock;
    use std::sync::{Arc, Mutex};

    /// An adapter that acknowledges setup commands and answers every transmit as told.
    struct Adapter {
        transmit_answer: &'static [u8],
        lines: Vec<String>,
        stale_ack: bool,
    }

    impl Peer for Adapter {
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            let text = String::from_utf8_lossy(bytes).into_owned();
            self.lines.push(text.clone());
            let answers: Vec<&[u8]> = if text.starts_with('t') {
                vec![self.transmit_answer]
            } else if text == "C\r" && self.lines.len() == 1 && self.stale_ack {
                // The previous program's close is answered just now, then this one's.
                vec![b"\r", b"\x07"]
            } else {
                vec![b"\r"]
            };
            answers
                .into_iter()
                .map(|bytes| PeerReply {
                    at: now,
                    bytes: bytes.to_vec(),
                })
                .collect()
        }
    }

    fn bus(transmit_answer: &'static [u8]) -> (SlcanBus, Arc<Mutex<Adapter>>) {
        with_adapter(Adapter {
            transmit_answer,
            lines: Vec::new(),
            stale_ack: false,
        })
    }

    fn with_adapter(adapter: Adapter) -> (SlcanBus, Arc<Mutex<Adapter>>) {
        let adapter = Arc::new(Mutex::new(adapter));
        let t = MemoryTransport::new("/dev/ttyACM0", adapter.clone(), RealClock::shared());
        (SlcanBus::open(Box::new(t), 250_000).unwrap(), adapter)
    }

    #[test]
    fn setup_then_frames_with_acknowledgements_and_timestamps_passed_over() {
        let (mut b, adapter) = bus(b"z\rt58C8419C5F000B0000000F3A\r");
        assert_eq!(adapter.lock().unwrap().lines, ["C\r", "S5\r", "O\r"]);
        b.send(&CanFrame::new(0x60C, &[0x40, 0x9C, 0x5F, 0, 0, 0, 0, 0]).unwrap())
            .unwrap();
        let f = b.receive(Duration::from_millis(200)).unwrap();
        assert_eq!(f.to_candump(), "58C#419C5F000B000000");
        assert!(b.receive(Duration::ZERO).unwrap_err().is_timeout());
    }

    #[test]
    fn a_late_acknowledgement_of_the_previous_program_does_not_fail_the_setup() {
        let (_, adapter) = with_adapter(Adapter {
            transmit_answer: b"z\r",
            lines: Vec::new(),
            stale_ack: true,
        });
        assert_eq!(
            adapter.lock().unwrap().lines,
            ["C\r", "S5\r", "C\r", "S5\r", "O\r", "C\r"],
            "the set-up again after the refusal, then the close on drop"
        );
    }

    #[test]
    fn a_refused_transmit_is_an_adapter_error_not_a_silent_timeout() {
        let (mut b, _) = bus(b"\x07");
        b.send(&CanFrame::new(0x60C, &[0x40]).unwrap()).unwrap();
        let e = b.receive(Duration::from_millis(30)).unwrap_err();
        assert!(!e.is_timeout());
        assert!(
            e.to_string().contains("refused to transmit (it answered BELL)"),
            "{e}"
        );
    }
}
