//! The test-only text family's simulated drive: answers request lines from the
//! family-neutral drive model, as any family's simulator front does.

use drivescript::bus::{Peer, PeerReply};
use drivescript::drive::DeviceState;
use drivescript::sim::{DriveModel, FaultInjection, SimConfig, SimulatedDrive};
use std::time::Duration;

pub struct TextSimulator {
    model: DriveModel,
    faults: FaultInjection,
    control_words: Vec<u16>,
    pending: Vec<u8>,
}

impl TextSimulator {
    pub fn new(config: SimConfig) -> Self {
        TextSimulator {
            model: DriveModel::new(config),
            faults: FaultInjection::default(),
            control_words: Vec::new(),
            pending: Vec::new(),
        }
    }

    fn answer(&mut self, line: &str) -> String {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["R", "2"] => format!("= {}", self.model.status_word()),
            ["R", "1"] => format!("= {}", self.model.control_word()),
            ["R", "3"] => format!("= {}", self.model.setpoint_rpm().round()),
            ["R", "4"] => format!("= {}", self.model.measured_speed_rpm().round()),
            ["W", "1", v] => match v.parse::<u16>() {
                Ok(cw) => {
                    self.control_words.push(cw);
                    self.model.write_control_word(cw, false);
                    "ok".into()
                }
                Err(_) => "! 2 not a number".into(),
            },
            ["W", "3", v] => match v.parse::<f64>().map(|rpm| self.model.set_setpoint_rpm(rpm)) {
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
        self.model.advance_to(now);
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

impl SimulatedDrive for TextSimulator {
    fn faults(&mut self) -> &mut FaultInjection {
        &mut self.faults
    }
    fn control_words_written(&self) -> Vec<u16> {
        self.control_words.clone()
    }
    fn state(&self) -> DeviceState {
        self.model.state()
    }
    fn speed_rpm(&self, _now: Duration) -> f64 {
        self.model.speed_rpm()
    }
    fn set_logging(&mut self, _on: bool) {}
    fn describe(&self) -> String {
        "simulated text drive".into()
    }
    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}
