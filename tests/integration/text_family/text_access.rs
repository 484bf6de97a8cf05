//! Object access for the test-only text family: one request line, one reply line, over a
//! shared byte line, within the reply timeout.

use drivescript::bus::{SharedTransport, Transport};
use drivescript::clock::SharedClock;
use drivescript::dictionary::{Address, DataType, RawValue};
use drivescript::drive::{AccessError, ObjectAccess, WriteOutcome, WriteResult};
use drivescript::family::LinkContext;
use drivescript::link::{AttemptFailure, CoreLink, Direction, ExchangeText, LinkCore, RetryPlan};
use std::convert::Infallible;
use std::time::Duration;

pub struct TextAccess {
    line: SharedTransport,
    node: u32,
    plan: RetryPlan,
    core: LinkCore,
}

impl CoreLink for TextAccess {
    drivescript::core_link_field!();
}

impl TextAccess {
    pub fn new(line: SharedTransport, node: u32, timeout: Duration, context: LinkContext) -> Self {
        context.link(|clock| TextAccess {
            line,
            node,
            plan: RetryPlan::new(0, Duration::ZERO, timeout),
            core: LinkCore::new(clock, Duration::ZERO),
        })
    }

    fn exchange(&mut self, request: String) -> Result<String, AccessError> {
        let bytes = format!("{request}\r").into_bytes();
        let shared = self.line.clone();
        let mut line = shared.lock();
        let t: &mut dyn Transport = line.as_mut();
        let plan = self.plan;
        let reply = plan
            .run(self, t, |link, t, _| {
                t.discard_input().map_err(AttemptFailure::Transport)?;
                t.write_all(&bytes).map_err(AttemptFailure::Transport)?;
                link.core.notify(Direction::Sent, &bytes);
                let sent = link.core.clock.now();
                let mut reply = Vec::new();
                while !reply.ends_with(b"\r") {
                    reply.extend_from_slice(link.core.read_reply(t, sent, sent + plan.reply_timeout)?);
                }
                link.core.notify(Direction::Received, &reply);
                Ok::<_, AttemptFailure<Infallible>>(reply)
            })
            .map_err(|unanswered| {
                let text = ExchangeText {
                    port: self.line.name().to_string(),
                    address: self.node.to_string(),
                    request: request.clone(),
                    hint: "check the test".into(),
                };
                unanswered.into_error(text, plan.reply_timeout, |never| match never {})
            })?;
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

    fn write(&mut self, address: &Address, value: &RawValue, _data_type: DataType) -> WriteResult {
        self.exchange(format!("W {} {value}", Self::index(address)))?;
        Ok(WriteOutcome::Stored)
    }

    fn port(&self) -> String {
        format!("node {} on {}", self.node, self.line.name())
    }

    fn clock(&self) -> SharedClock {
        self.core.clock.clone()
    }

    fn reopen(&mut self) -> Result<(), AccessError> {
        Ok(self.line.reopen()?)
    }
}
