//! The simulated CiA 402 node's objects, served from its EDS: every object the EDS lists
//! with its type, access, limits and default; the live ones (statusword, velocity, DC link
//! voltage, error code, error register, mode display) read from the drive model, and the
//! controlword, target velocity and mode written to it. Like many CiA 402 drives it enables
//! operation only in NMT operational. Values in and out as SDO value bytes; no frames here.

use super::sdo_server::{ObjectStore, Place, SdoLogged};
use crate::diag::{Diagnostics, Source};
use crate::dictionary::eds::{EdsEntry, EdsFile, EdsNumber};
use crate::dictionary::{Access, DataType, Real, MAX_BLOCK_LEN};
use crate::family::canopen::codec::AbortCode;
use crate::family::canopen::nmt_master::enables_operation;
use crate::sim::{ModelRefusal, SimCore};
use std::collections::BTreeMap;

/// The EDS the simulated node is served from.
pub const NODE_EDS: &str = include_str!("cia402_node.eds");

pub const ERROR_REGISTER: Place = (0x1001, 0);
pub const HEARTBEAT_TIME: Place = (0x1017, 0);
pub const ERROR_CODE: Place = (0x603F, 0);
pub const CONTROLWORD: Place = (0x6040, 0);
pub const STATUSWORD: Place = (0x6041, 0);
pub const MODES: Place = (0x6060, 0);
pub const MODES_DISPLAY: Place = (0x6061, 0);
pub const VELOCITY_ACTUAL: Place = (0x606C, 0);
pub const DC_LINK_VOLTAGE: Place = (0x6079, 0);
pub const TARGET_VELOCITY: Place = (0x60FF, 0);
/// A DOMAIN bigger than any transfer drivescript takes: the client must refuse it without
/// keeping it.
pub const TRACE_BUFFER: Place = (0x2F01, 0);
const TRACE_BUFFER_LEN: usize = 4096;

/// The velocity modes in which the node follows 0x60FF: 2 velocity, 3 profile velocity.
const VELOCITY_MODES: [i64; 2] = [2, 3];

#[derive(Debug, Clone)]
struct Slot {
    data_type: DataType,
    access: Access,
    /// Limits as numbers (a float's as given, an integer's exact up to 2^53).
    low: Option<f64>,
    high: Option<f64>,
    value: Vec<u8>,
}

/// The node's object table and stored values.
#[derive(Debug, Clone)]
pub struct Cia402Objects {
    slots: BTreeMap<Place, Slot>,
    /// Whether the node is in NMT operational (its node says).
    operational: bool,
}

impl Cia402Objects {
    /// The objects of [`NODE_EDS`] for node `node` (which `$NODEID` means).
    pub fn from_node_eds(node: u8) -> Cia402Objects {
        let mut problems = Diagnostics::new();
        let file = EdsFile::parse(&Source::new("cia402_node.eds", NODE_EDS), &mut problems);
        debug_assert!(problems.is_empty(), "{}", problems.render(false));
        let slots = file
            .entries
            .iter()
            .filter_map(|e| slot(e, node).map(|s| ((e.index, e.subindex), s)))
            .collect();
        Cia402Objects {
            slots,
            operational: false,
        }
    }

    /// The node's NMT state changed: operation can be enabled in operational only.
    pub fn set_operational(&mut self, operational: bool) {
        self.operational = operational;
    }

    /// The stored value of `place` as an integer (0 when absent).
    pub fn int(&self, place: Place) -> i64 {
        self.slots
            .get(&place)
            .map_or(0, |s| s.data_type.from_le_bytes(&s.value))
    }

    /// The model follows the target velocity only in a velocity mode.
    fn apply_setpoint(&self, core: &mut SimCore<SdoLogged>) -> Result<(), AbortCode> {
        let rpm = if VELOCITY_MODES.contains(&self.int(MODES)) {
            self.int(TARGET_VELOCITY) as f64
        } else {
            0.0
        };
        core.model.set_setpoint_rpm(rpm).map_err(|r| match r {
            ModelRefusal::TooHigh => AbortCode::VALUE_TOO_HIGH,
            ModelRefusal::TooLow => AbortCode::VALUE_TOO_LOW,
            ModelRefusal::OutOfRange => AbortCode::VALUE_RANGE_EXCEEDED,
            ModelRefusal::NotInThisState => AbortCode::DEVICE_STATE,
        })
    }
}

fn slot(entry: &EdsEntry, node: u8) -> Option<Slot> {
    let (data_type, _) = entry.data_type.carried().ok()?;
    let default = entry.default.as_deref().unwrap_or("");
    let value = match data_type {
        DataType::String { .. } => default.as_bytes().to_vec(),
        DataType::Unicode => default.encode_utf16().flat_map(u16::to_le_bytes).collect(),
        // CiA 306 writes byte values as hex digits.
        DataType::Octets | DataType::Domain => crate::hex::parse_hex(default).unwrap_or_default(),
        DataType::F32 | DataType::F64 => {
            let single = data_type == DataType::F32;
            Real::parse(default, single)
                .unwrap_or(Real::of(0.0, single))
                .to_le_bytes()
        }
        _ => {
            let n = EdsNumber::parse(default)
                .ok()
                .and_then(|n| n.resolve(Some(node)))
                .unwrap_or(0);
            data_type
                .to_le_bytes(n as i64)
                .unwrap_or_else(|| vec![0; data_type.size()])
        }
    };
    Some(Slot {
        data_type,
        access: entry.access,
        low: entry.low.and_then(|n| n.resolve(Some(node))),
        high: entry.high.and_then(|n| n.resolve(Some(node))),
        value,
    })
}

/// The slot at `place`, or the abort CiA 301 gives: no such object or subindex, or
/// `refused` when the slot's access is `barred` (write-only for a read, read-only for a write).
fn slot_for(
    slots: &BTreeMap<Place, Slot>,
    place: Place,
    barred: Access,
    refused: AbortCode,
) -> Result<&Slot, AbortCode> {
    let Some(slot) = slots.get(&place) else {
        return Err(if slots.keys().any(|(i, _)| *i == place.0) {
            AbortCode::SUBINDEX_DOES_NOT_EXIST
        } else {
            AbortCode::OBJECT_DOES_NOT_EXIST
        });
    };
    if slot.access == barred {
        return Err(refused);
    }
    Ok(slot)
}

impl ObjectStore for Cia402Objects {
    fn read(&mut self, core: &mut SimCore<SdoLogged>, place: Place) -> Result<Vec<u8>, AbortCode> {
        let slot = slot_for(&self.slots, place, Access::WriteOnly, AbortCode::WRITE_ONLY)?;
        let m = &mut core.model;
        let live = match place {
            STATUSWORD => i64::from(m.status_word()),
            CONTROLWORD => i64::from(m.control_word()),
            ERROR_CODE => i64::from(m.drive_error()),
            // Bit 0, generic error, while the drive has a fault.
            ERROR_REGISTER => i64::from(m.drive_error() != 0),
            MODES_DISPLAY => self.int(MODES),
            VELOCITY_ACTUAL => m.measured_speed_rpm().round() as i64,
            DC_LINK_VOLTAGE => (m.measured_bus_voltage_v() * 1000.0).round() as i64,
            TRACE_BUFFER => return Ok((0..TRACE_BUFFER_LEN).map(|i| i as u8).collect()),
            _ => return Ok(slot.value.clone()),
        };
        slot.data_type.to_le_bytes(live).ok_or(AbortCode::GENERAL_ERROR)
    }

    fn write(&mut self, core: &mut SimCore<SdoLogged>, place: Place, bytes: &[u8]) -> Result<(), AbortCode> {
        let slot = slot_for(&self.slots, place, Access::ReadOnly, AbortCode::READ_ONLY)?;
        let fits = match slot.data_type {
            DataType::String { max } => bytes.len() <= usize::from(max),
            DataType::Octets | DataType::Unicode | DataType::Domain => bytes.len() <= MAX_BLOCK_LEN,
            other => bytes.len() == other.size(),
        };
        if !fits {
            return Err(AbortCode::LENGTH_MISMATCH);
        }
        let number = match slot.data_type.float_single() {
            Some(single) => Real::from_le_bytes(bytes, single).map(Real::value),
            None if slot.data_type.is_integer() => Some(slot.data_type.from_le_bytes(bytes) as f64),
            None => None,
        };
        if let Some(value) = number {
            // A NaN is within no limits: a node with limits refuses it.
            let limited = slot.low.is_some() || slot.high.is_some();
            if slot.low.is_some_and(|low| value < low) || (limited && value.is_nan()) {
                return Err(AbortCode::VALUE_TOO_LOW);
            }
            if slot.high.is_some_and(|high| value > high) {
                return Err(AbortCode::VALUE_TOO_HIGH);
            }
        }
        let value = slot.data_type.from_le_bytes(bytes);
        if place == CONTROLWORD {
            let control_word = value as u16;
            core.log_control_word(control_word);
            if !self.operational && enables_operation(CONTROLWORD, bytes) {
                return Err(AbortCode::DEVICE_STATE);
            }
            if !core.disobeys_word(control_word) {
                let blocked = core.faults.is_fault_reset_blocked();
                core.model.write_control_word(control_word, blocked);
            }
            return Ok(());
        }
        let before = self.slots.get(&place).map(|s| s.value.clone());
        if let Some(s) = self.slots.get_mut(&place) {
            s.value = bytes.to_vec();
        }
        if place == TARGET_VELOCITY || place == MODES {
            if let Err(code) = self.apply_setpoint(core) {
                if let (Some(s), Some(b)) = (self.slots.get_mut(&place), before) {
                    s.value = b;
                }
                return Err(code);
            }
        }
        Ok(())
    }
}
