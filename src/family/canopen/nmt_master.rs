//! When drivescript changes a CiA 402 node's NMT state, and back. SDO works in
//! pre-operational, but many CiA 402 drives accept "enable operation" only in operational
//! (their device control follows the NMT state), so before the first controlword that
//! enables operation a node not seen operational gets NMT start, addressed to it alone.
//! Nothing else sends NMT: no broadcast, nothing on the safe stop's path (the stop writes
//! controlwords that never enable, and comes first). After the run's verified safe stop a
//! node drivescript started goes back to pre-operational, the state it was found in (or,
//! when no heartbeat showed it, the state a node boots into), so that a left-running
//! bench does not go on exchanging process data; a drive the run leaves enabled on
//! purpose keeps operational.

use super::codec::{NmtCommand, NmtState};
use super::sdo_link::SdoLink;
use crate::drive::AccessError;
use crate::link::CoreLink;

/// The CiA 402 controlword, 0x6040 subindex 0.
const CONTROLWORD: (u16, u8) = (0x6040, 0);

/// How the node was found when drivescript started it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    /// Its heartbeat or boot-up message said so.
    PreOperational,
    /// No heartbeat seen (its producer time 0x1017 may be 0).
    Unknown,
}

#[derive(Debug, Default)]
pub struct NmtMaster {
    /// Whether the node was looked at before an enable; once is enough.
    checked: bool,
    /// Set while drivescript holds the node in operational.
    started: Option<Found>,
    /// What is worth a console line, until taken.
    notices: Vec<String>,
}

/// Whether writing `data` to `place` commands "enable operation" (bits 0–3 set, no fault
/// reset): the CiA 402 transition that many drives refuse outside NMT operational.
pub fn enables_operation(place: (u16, u8), data: &[u8]) -> bool {
    match (place == CONTROLWORD, data) {
        (true, [lo, ..]) => lo & 0x8F == 0x0F,
        _ => false,
    }
}

impl NmtMaster {
    /// Before a write of `data` to `place`: the node is started first when the write
    /// enables operation and the node was not seen operational.
    pub fn before_write(
        &mut self,
        link: &mut SdoLink,
        place: (u16, u8),
        data: &[u8],
    ) -> Result<(), AccessError> {
        if self.checked || !enables_operation(place, data) {
            return Ok(());
        }
        let node = link.node();
        let (found, seen) = match link.nmt_state()? {
            Some(NmtState::Operational) => {
                self.checked = true;
                return Ok(());
            }
            Some(NmtState::PreOperational) => (Found::PreOperational, "is pre-operational (heartbeat)"),
            Some(NmtState::BootUp) => (Found::PreOperational, "is pre-operational (it booted)"),
            // A stopped node is a lost link: `nmt_state` said so already.
            Some(NmtState::Stopped) | None => (Found::Unknown, "showed no NMT state (no heartbeat seen)"),
        };
        link.send_nmt(NmtCommand::Start)?;
        self.checked = true;
        self.started = Some(found);
        let text = format!(
            "node {node} {seen}: sent NMT start (`000#01{node:02X}`) so that it is operational, which CiA 402 drives may need to enable operation"
        );
        // The trace and `-v` say it too, for one-off commands that print no notices.
        link.core().event(&text);
        self.notices.push(text);
        Ok(())
    }

    /// After the run's verified safe stop: a node drivescript started goes back to
    /// pre-operational. Says what it did; `None` when it started nothing.
    pub fn release(&mut self, link: &mut SdoLink) -> Option<String> {
        let found = self.started.take()?;
        self.checked = false;
        let node = link.node();
        let why = match found {
            Found::PreOperational => "the state it was found in",
            Found::Unknown => "the state a node boots into; its state before was not seen",
        };
        let text = match link.send_nmt(NmtCommand::EnterPreOperational) {
            Ok(()) => format!(
                "node {node} back to pre-operational (NMT enter pre-operational, `000#80{node:02X}`): {why}"
            ),
            Err(e) => {
                format!("node {node} was left operational: NMT enter pre-operational could not be sent ({e})")
            }
        };
        link.core().event(&text);
        Some(text)
    }

    /// After a safe stop that could not be verified: a node drivescript started is left
    /// operational — no NMT command goes to a node whose drive may still turn — and this
    /// says so. `None` when it started nothing.
    pub fn withhold(&mut self, link: &mut SdoLink) -> Option<String> {
        self.started.take()?;
        self.checked = false;
        let node = link.node();
        let text = format!(
            "node {node} is left operational: NMT enter pre-operational (`000#80{node:02X}`) is not sent, since the drive's stop was not verified"
        );
        link.core().event(&text);
        Some(text)
    }

    /// What is worth a console line since the last call.
    pub fn take_notices(&mut self) -> Vec<String> {
        std::mem::take(&mut self.notices)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::{MemoryFrameBus, SharedFrameBus};
    use crate::clock::{Clock, VirtualClock};
    use crate::dictionary::{Address, DataType, RawValue};
    use crate::drive::ObjectAccess;
    use crate::family::canopen::sim::Cia402Node;
    use crate::family::canopen::{SdoAccess, SdoLinkConfig};
    use crate::sim::SimConfig;
    use std::sync::{Arc, Mutex};
    use std::time::Duration;

    fn node() -> (SdoAccess, Arc<Mutex<Cia402Node>>, Arc<VirtualClock>) {
        node_with(Some(NmtMaster::default()))
    }

    fn node_with(nmt: Option<NmtMaster>) -> (SdoAccess, Arc<Mutex<Cia402Node>>, Arc<VirtualClock>) {
        let clock = Arc::new(VirtualClock::new());
        let sim = Arc::new(Mutex::new(Cia402Node::new(1, SimConfig::default())));
        let bus = MemoryFrameBus::new("memory", sim.clone(), clock.clone());
        let link = SdoLink::new(
            SharedFrameBus::new(Box::new(bus)),
            clock.clone(),
            1,
            SdoLinkConfig::default(),
        );
        (SdoAccess::new(link, nmt), sim, clock)
    }

    fn control(access: &mut SdoAccess, word: i64) -> Result<(), AccessError> {
        let address = Address::indexed(0x6040, 0);
        access
            .write(&address, &RawValue::Int(word), DataType::U16)
            .map(|_| ())
    }

    #[test]
    fn a_pre_operational_node_is_started_before_it_enables_operation_and_put_back_after() {
        let (mut access, sim, _) = node();
        control(&mut access, 6).unwrap();
        control(&mut access, 7).unwrap();
        assert_eq!(sim.lock().unwrap().nmt_state(), NmtState::PreOperational);
        assert!(access.notices().is_empty(), "nothing sent before the enable");
        control(&mut access, 15).unwrap();
        assert_eq!(sim.lock().unwrap().nmt_state(), NmtState::Operational);
        let said = access.notices();
        assert_eq!(said.len(), 1);
        assert!(
            said[0].starts_with("node 1 is pre-operational (")
                && said[0].contains("sent NMT start (`000#0101`)"),
            "{said:?}"
        );
        // Once: the next enable sends nothing more.
        control(&mut access, 7).unwrap();
        control(&mut access, 15).unwrap();
        assert!(access.notices().is_empty());
        let back = access.release().unwrap();
        assert!(back.contains("node 1 back to pre-operational"), "{back}");
        assert_eq!(sim.lock().unwrap().nmt_state(), NmtState::PreOperational);
        assert_eq!(access.release(), None, "once");
    }

    #[test]
    fn the_simulated_node_refuses_to_enable_operation_in_pre_operational() {
        let (mut bare, _, _) = node_with(None);
        control(&mut bare, 6).unwrap();
        control(&mut bare, 7).unwrap();
        let e = control(&mut bare, 15).unwrap_err().to_string();
        assert!(e.contains("0x08000022"), "{e}");
        assert_eq!(bare.release(), None, "without NMT, nothing to hand back");
    }

    /// A node whose heartbeat and boot-up message never reach the bus (0x1017 = 0).
    struct Silent(Cia402Node);
    impl crate::bus::FramePeer for Silent {
        fn receive(
            &mut self,
            frame: &crate::bus::CanFrame,
            now: Duration,
        ) -> Vec<(Duration, crate::bus::CanFrame)> {
            let mut out = self.0.receive(frame, now);
            out.retain(|(_, f)| f.id & 0x780 != 0x700);
            out
        }
    }

    #[test]
    fn a_node_of_unknown_state_is_started_and_put_back_to_the_state_nodes_boot_into() {
        let clock = Arc::new(VirtualClock::new());
        let sim = Arc::new(Mutex::new(Silent(Cia402Node::new(1, SimConfig::default()))));
        let bus = MemoryFrameBus::new("memory", sim.clone(), clock.clone());
        let link = SdoLink::new(
            SharedFrameBus::new(Box::new(bus)),
            clock,
            1,
            SdoLinkConfig::default(),
        );
        let mut access = SdoAccess::new(link, Some(NmtMaster::default()));
        for word in [6, 7, 15] {
            control(&mut access, word).unwrap();
        }
        let said = access.notices();
        assert!(
            said[0].contains("node 1 showed no NMT state (no heartbeat seen): sent NMT start"),
            "{said:?}"
        );
        assert_eq!(sim.lock().unwrap().0.nmt_state(), NmtState::Operational);
        let back = access.release().unwrap();
        assert!(
            back.ends_with("the state a node boots into; its state before was not seen"),
            "{back}"
        );
        assert_eq!(sim.lock().unwrap().0.nmt_state(), NmtState::PreOperational);
    }

    #[test]
    fn a_node_seen_operational_is_left_as_it_is() {
        let (mut access, sim, clock) = node();
        // Started by another master; its heartbeat says so.
        let start = crate::bus::CanFrame::new(0x000, &[0x01, 0x01]).unwrap();
        crate::bus::FramePeer::receive(&mut *sim.lock().unwrap(), &start, clock.now());
        clock.advance(Duration::from_millis(250));
        control(&mut access, 6).unwrap();
        control(&mut access, 7).unwrap();
        control(&mut access, 15).unwrap();
        assert!(access.notices().is_empty());
        assert_eq!(access.release(), None);
        assert_eq!(sim.lock().unwrap().nmt_state(), NmtState::Operational);
    }

    #[test]
    fn only_an_enable_operation_controlword_needs_operational() {
        for word in [0x0Fu16, 0x1F, 0x4F, 0x10F] {
            assert!(enables_operation(CONTROLWORD, &word.to_le_bytes()), "{word:#x}");
        }
        // The safe stop's words, a fault reset and other objects never.
        for word in [0x00u16, 0x02, 0x06, 0x07, 0x0B, 0x80, 0x8F] {
            assert!(!enables_operation(CONTROLWORD, &word.to_le_bytes()), "{word:#x}");
        }
        assert!(!enables_operation((0x60FF, 0), &[0x0F, 0, 0, 0]));
        assert!(!enables_operation((0x6040, 1), &[0x0F, 0]));
        assert!(!enables_operation(CONTROLWORD, &[]));
    }
}
