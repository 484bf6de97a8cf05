//! The simulated Lenze 9400 node as a frame-level peer: the shared CANopen SDO server
//! (`canopen::sim::SdoServer`, with its injected faults) in front of the 9400's codes, and
//! the EMCY frames injected without a trip (`--sim emergency-at`). A lost line is a lost
//! adapter.

use super::sim_codes::SimCodes;
use crate::bus::{CanFrame, FramePeer};
use crate::family::canopen::codec::SdoRequest;
use crate::family::canopen::sim::{injected_emcy, SdoLogged, SdoServer};
use crate::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

pub use super::sim_codes::FIRMWARE_VERSION;

#[derive(Debug)]
pub struct Lenze9400Simulator {
    /// The model, the faults and the log of decoded requests (no control words: the 9400
    /// is not commanded through a control word here, it has no profile).
    core: SimCore<SdoLogged>,
    node: u8,
    codes: SimCodes,
    server: SdoServer,
}

impl Lenze9400Simulator {
    /// A node just powered up at `node` (1..=127).
    pub fn new(node: u8, config: SimConfig) -> Self {
        Lenze9400Simulator {
            core: SimCore::new(config),
            node,
            codes: SimCodes::default(),
            server: SdoServer::default(),
        }
    }

    pub fn node(&self) -> u8 {
        self.node
    }

    /// The requests decoded, with the time each arrived (the latest ones, bounded).
    pub fn received(&self) -> &[(Duration, SdoRequest)] {
        self.core.requests()
    }

    /// The stored codes (rated current, reference speed, enable).
    pub fn codes(&self) -> &SimCodes {
        &self.codes
    }
}

impl FramePeer for Lenze9400Simulator {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        self.core.panic_if_due(now);
        let mut out = injected_emcy(&mut self.core, self.node, now);
        out.extend(
            self.server
                .receive(frame, now, self.node, &mut self.core, &mut self.codes),
        );
        out.sort_by_key(|(at, _)| *at);
        out
    }

    crate::sim_frame_line_core!();

    /// An injected EMCY goes out when it is due, without a request to answer.
    fn poll(&mut self, until: Duration) -> Vec<(Duration, CanFrame)> {
        match self.core.faults.line_up(until) {
            true => injected_emcy(&mut self.core, self.node, until),
            false => Vec::new(),
        }
    }
}

impl SimFront for Lenze9400Simulator {
    crate::sim_front_core!(SdoLogged);
    fn describe_drive(&self) -> String {
        format!(
            "simulated Lenze 9400 at CAN node {} (firmware {FIRMWARE_VERSION})",
            self.node
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hex::{parse_hex, to_hex};

    fn ask(sim: &mut Lenze9400Simulator, node_id: u32, hex: &str) -> Vec<String> {
        let data: [u8; 8] = parse_hex(hex).unwrap().try_into().unwrap();
        crate::bus::candump_replies(sim, &CanFrame::standard8(node_id, data), Duration::ZERO)
    }

    #[test]
    fn the_worked_examples_answered_by_the_simulated_node() {
        let mut sim = Lenze9400Simulator::new(12, SimConfig::default());
        assert_eq!(
            ask(&mut sim, 0x60C, "40 9c 5f 00 00 00 00 00"),
            ["58C#419C5F000B000000"]
        );
        assert_eq!(
            ask(&mut sim, 0x60C, "60 00 00 00 00 00 00 00"),
            ["58C#0030352E30302E31"]
        );
        assert_eq!(
            ask(&mut sim, 0x60C, "70 00 00 00 00 00 00 00"),
            ["58C#17322E3037000000"]
        );
        let mut node5 = Lenze9400Simulator::new(5, SimConfig::default());
        assert_eq!(
            ask(&mut node5, 0x605, "40 c2 5f 00 00 00 00 00"),
            ["585#43C25F002B000000"]
        );
        let mut node2 = Lenze9400Simulator::new(2, SimConfig::default());
        assert_eq!(
            ask(&mut node2, 0x602, "23 a7 5f 00 66 00 00 00"),
            ["582#60A75F0000000000"]
        );
        assert_eq!(node2.codes().rated_current, 102);
    }

    /// An injected EMCY goes out once, when due: on its own (poll) or before the answer
    /// to the next request, stamped with the time it was due.
    #[test]
    fn an_injected_emcy_goes_out_when_due() {
        let config = SimConfig {
            emergencies: vec![(Duration::from_secs(2), 0x4310), (Duration::from_secs(5), 0x2310)],
            ..SimConfig::default()
        };
        let mut sim = Lenze9400Simulator::new(12, config);
        let shown = |frames: Vec<(Duration, CanFrame)>| -> Vec<(u64, String)> {
            frames
                .into_iter()
                .map(|(at, f)| (at.as_secs(), f.to_candump()))
                .collect()
        };
        assert!(sim.poll(Duration::from_secs(1)).is_empty());
        assert_eq!(
            shown(sim.poll(Duration::from_secs(3))),
            [(2, "08C#1043010000000000".to_string())]
        );
        assert!(sim.poll(Duration::from_secs(4)).is_empty(), "sent once");
        let read = CanFrame::standard8(0x60C, [0x40, 0xc2, 0x5f, 0, 0, 0, 0, 0]);
        let out = shown(sim.receive(&read, Duration::from_secs(6)));
        assert_eq!(out[0], (5, "08C#1023010000000000".to_string()), "{out:?}");
        assert!(out[1].1.starts_with("58C#43C25F00"), "{out:?}");
    }

    #[test]
    fn other_nodes_frames_are_not_answered_and_errors_are_aborts() {
        let mut sim = Lenze9400Simulator::new(12, SimConfig::default());
        assert!(ask(&mut sim, 0x60D, "40 9c 5f 00 00 00 00 00").is_empty());
        // C00999 does not exist.
        assert_eq!(
            ask(&mut sim, 0x60C, "40 18 5c 00 00 00 00 00"),
            ["58C#80185C0000000206"]
        );
        // A segment with the wrong toggle bit.
        ask(&mut sim, 0x60C, "40 9c 5f 00 00 00 00 00");
        assert_eq!(
            ask(&mut sim, 0x60C, "70 00 00 00 00 00 00 00"),
            ["58C#809C5F0000000305"]
        );
        // The heatsink temperature is read-only.
        let abort = ask(&mut sim, 0x60C, "23 c2 5f 00 01 00 00 00");
        assert_eq!(abort, ["58C#80C25F0002000106"]);
        let _ = to_hex(&[]);
    }
}
