//! The test-only text family's simulated drive: answers request lines from the
//! family-neutral drive model, as any family's simulator front does.

use drivescript::bus::{Peer, PeerReply};
use drivescript::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

pub struct TextSimulator {
    core: SimCore<()>,
    pending: Vec<u8>,
}

impl TextSimulator {
    pub fn new(config: SimConfig) -> Self {
        TextSimulator {
            core: SimCore::new(config),
            pending: Vec::new(),
        }
    }

    fn answer(&mut self, line: &str) -> String {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["R", "2"] => format!("= {}", self.core.model.status_word()),
            ["R", "1"] => format!("= {}", self.core.model.control_word()),
            ["R", "3"] => format!("= {}", self.core.model.setpoint_rpm().round()),
            ["R", "4"] => format!("= {}", self.core.model.measured_speed_rpm().round()),
            ["W", "1", v] => match v.parse::<u16>() {
                Ok(cw) => {
                    self.core.log_control_word(cw);
                    self.core.model.write_control_word(cw, false);
                    "ok".into()
                }
                Err(_) => "! 2 not a number".into(),
            },
            ["W", "3", v] => match v.parse::<f64>().map(|rpm| self.core.model.set_setpoint_rpm(rpm)) {
                Ok(Ok(())) => "ok".into(),
                Ok(Err(_)) => "! 3 out of range".into(),
                Err(_) => "! 2 not a number".into(),
            },
            _ => "! 1 unknown request".into(),
        }
    }
}

impl Peer for TextSimulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.core.model.advance_to(now);
        self.pending.extend_from_slice(bytes);
        let mut replies = Vec::new();
        while let Some(end) = self.pending.iter().position(|&b| b == b'\r') {
            let line: Vec<u8> = self.pending.drain(..=end).collect();
            let answer = self.answer(String::from_utf8_lossy(&line).trim());
            replies.push(PeerReply {
                at: now + Duration::from_micros(500),
                bytes: format!("{answer}\r").into_bytes(),
            });
        }
        replies
    }
}

impl SimFront for TextSimulator {
    drivescript::sim_front_core!(());
    fn describe_drive(&self) -> String {
        "simulated text drive".into()
    }
}
