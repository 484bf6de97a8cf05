//! Object access for the test-only text family: one request line, one reply line, over a
//! shared byte line, within the reply timeout.

use drivescript::bus::{SharedTransport, TransportError};
use drivescript::clock::SharedClock;
use drivescript::dictionary::{Address, DataType, RawValue};
use drivescript::drive::{AccessError, ObjectAccess, WriteOutcome};
use drivescript::family::LinkContext;
use drivescript::link::{Direction, TelegramObserver};
use std::time::Duration;

pub struct TextAccess {
    line: SharedTransport,
    node: u32,
    timeout: Duration,
    clock: SharedClock,
    observer: Option<Box<dyn TelegramObserver>>,
}

impl TextAccess {
    pub fn new(line: SharedTransport, node: u32, timeout: Duration, context: LinkContext) -> Self {
        TextAccess {
            line,
            node,
            timeout,
            clock: context.clock,
            observer: context.observer,
        }
    }

    fn exchange(&mut self, request: String) -> Result<String, AccessError> {
        let bytes = format!("{request}\r").into_bytes();
        let mut reply = Vec::new();
        {
            let mut t = self.line.lock();
            t.discard_input()?;
            t.write_all(&bytes)?;
            let deadline = self.clock.now() + self.timeout;
            let mut buf = [0u8; 64];
            while !reply.ends_with(b"\r") {
                let left = deadline.saturating_sub(self.clock.now());
                match t.read(&mut buf, left) {
                    Ok(n) => reply.extend_from_slice(&buf[..n]),
                    Err(TransportError::Timeout { .. }) => {
                        return Err(AccessError::NoReply {
                            port: self.line.name().to_string(),
                            address: self.node.to_string(),
                            request,
                            attempts: 1,
                            timeout_ms: self.timeout.as_millis(),
                            hint: "check the test".into(),
                        })
                    }
                    Err(e) => return Err(e.into()),
                }
            }
        }
        let now = self.clock.now();
        if let Some(o) = self.observer.as_mut() {
            o.telegram(now, Direction::Sent, &bytes);
            o.telegram(now, Direction::Received, &reply);
        }
        let text = String::from_utf8_lossy(&reply).trim().to_string();
        match text.strip_prefix("! ") {
            Some(refusal) => {
                let (code, why) = refusal.split_once(' ').unwrap_or((refusal, ""));
                Err(AccessError::Refused {
                    port: self.line.name().to_string(),
                    address: self.node.to_string(),
                    operation: if request.starts_with('W') { "write" } else { "read" },
                    object: request.clone(),
                    code: code.parse().unwrap_or(0),
                    text: why.to_string(),
                })
            }
            None => Ok(text),
        }
    }

    fn index(address: &Address) -> u16 {
        let Address::Indexed { index, .. } = *address;
        index
    }
}

impl ObjectAccess for TextAccess {
    fn read(&mut self, address: &Address, _data_type: DataType) -> Result<RawValue, AccessError> {
        let reply = self.exchange(format!("R {}", Self::index(address)))?;
        let value = reply.strip_prefix("= ").unwrap_or(&reply);
        value
            .parse()
            .map(RawValue::Int)
            .map_err(|_| AccessError::UnexpectedReply {
                port: self.line.name().to_string(),
                address: self.node.to_string(),
                request: format!("R {}", Self::index(address)),
                detail: format!("`{reply}` is not a number"),
            })
    }

    fn write(
        &mut self,
        address: &Address,
        value: &RawValue,
        _data_type: DataType,
    ) -> Result<WriteOutcome, AccessError> {
        self.exchange(format!("W {} {value}", Self::index(address)))?;
        Ok(WriteOutcome::Stored)
    }

    fn port(&self) -> String {
        format!("node {} on {}", self.node, self.line.name())
    }

    fn clock(&self) -> SharedClock {
        self.clock.clone()
    }

    fn reopen(&mut self) -> Result<(), AccessError> {
        Ok(self.line.reopen()?)
    }
}
