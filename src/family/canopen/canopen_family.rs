//! The generic CANopen family as the registry sees it: the built-in CiA 402 dictionary,
//! objects addressed by index (`0x6041`, `0x1018/2`), node ids 1..=127 on a CAN frame bus,
//! and how to open an SDO link, simulate a CiA 402 node and explain frames. The node is
//! put in NMT operational before it enables operation, and back after the run
//! ([`NmtMaster`]).

use super::nmt_master::NmtMaster;
use super::sdo_family::{
    open_sdo, parse_node, raw_sdo_object, sdo_family_info, sdo_frame_direction, sim_node,
};
use super::sim::Cia402Node;
use super::{SdoExplainer, CIA_301_NOTATION, INDEX_NOTATION};
use crate::bus::Bus;
use crate::dictionary::{Address, AddressError, DataType, Dictionary, ObjectDef};
use crate::family::{
    DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened, SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

pub struct CanopenFamily;

/// `0x6041` (subindex 0) or `0x1018/2`: a CANopen index in hex and a decimal subindex.
pub fn parse_index_address(text: &str) -> Result<Address, AddressError> {
    let t = text.trim();
    let wrong = || {
        AddressError::from(format!(
            "`{t}` is not a CANopen object address; write the index in hex and the subindex after `/`, e.g. `0x6041` or `0x1018/2`"
        ))
    };
    let hex = t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .ok_or_else(wrong)?;
    let (index, sub) = match hex.split_once('/') {
        Some((i, s)) => (i, Some(s)),
        None => (hex, None),
    };
    if index.is_empty() || index.len() > 4 || !index.chars().all(|c| c.is_ascii_hexdigit()) {
        return Err(wrong());
    }
    let index = u16::from_str_radix(index, 16).map_err(|_| wrong())?;
    let subindex = match sub {
        None => 0,
        Some(s) => s
            .trim()
            .parse::<u8>()
            .map_err(|_| AddressError::from(format!("`{t}`: the subindex after `/` is 0..255")))?,
    };
    Ok(Address::indexed(index, u32::from(subindex)))
}

impl Family for CanopenFamily {
    fn info(&self) -> FamilyInfo {
        let title = "CANopen CiA 402 drives over SDO (SLCAN adapter or SocketCAN), objects from their EDS";
        sdo_family_info("canopen", title, parse_index_address)
            .dictionaries(&[crate::builtin_dictionary!("canopen")])
            .address_help("the drive's CANopen node id 1..127 (default 1)")
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        parse_node(text, self.address_help())
    }

    fn no_reply_advice(&self) -> &'static str {
        CIA_301_NOTATION.no_reply_hint
    }

    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        open_sdo(
            bus,
            drive,
            options,
            context,
            CIA_301_NOTATION,
            Some(NmtMaster::default()),
            "a CANopen node",
        )
    }

    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        SimulatedDevice::frames(Cia402Node::new(sim_node(drive), config))
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(SdoExplainer::new(dictionary, INDEX_NOTATION))
    }

    /// SDO requests go to 0x600 + node, responses come from 0x580 + node.
    fn frame_direction(&self, frame: &crate::bus::CanFrame) -> Option<crate::link::Direction> {
        sdo_frame_direction(frame)
    }

    /// `0x6041`, `0x1018/2` (see `raw_sdo_object`).
    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let t = text.trim();
        if !(t.starts_with("0x") || t.starts_with("0X")) {
            return None;
        }
        let description = format!("CANopen object {t} (not in the dictionary)");
        Some(raw_sdo_object(t, parse_index_address, data_type, description))
    }

    /// `0x6041`, `0x1018/2`.
    fn show_address(&self, address: &Address) -> String {
        let Address::Indexed { index, subindex } = *address;
        match subindex {
            0 => format!("0x{index:04X}"),
            sub => format!("0x{index:04X}/{sub}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_addresses() {
        assert_eq!(parse_index_address("0x6041"), Ok(Address::indexed(0x6041, 0)));
        assert_eq!(parse_index_address(" 0x1018/2 "), Ok(Address::indexed(0x1018, 2)));
        assert!(parse_index_address("6041")
            .unwrap_err()
            .reason
            .contains("0x1018/2"));
        assert!(parse_index_address("0x16041").is_err());
        assert!(parse_index_address("0x1018/256")
            .unwrap_err()
            .reason
            .contains("0..255"));
        let f = CanopenFamily;
        assert_eq!(f.show_address(&Address::indexed(0x1018, 2)), "0x1018/2");
        assert_eq!(f.show_address(&Address::indexed(0x6041, 0)), "0x6041");
    }

    #[test]
    fn node_ids_and_raw_objects() {
        let f = CanopenFamily;
        assert_eq!(f.parse_drive_address(Some("5")).unwrap().shown, "CAN node 5");
        assert!(f.parse_drive_address(Some("128")).is_err());
        assert!(f.raw_object("speed", None).is_none());
        let read = f.raw_object("0x6041", None).unwrap().unwrap();
        assert!(!read.writable() && read.unconfirmed.unwrap().contains("--type"));
        let write = f.raw_object("0x6060", Some(DataType::I8)).unwrap().unwrap();
        assert!(write.writable());
    }
}
