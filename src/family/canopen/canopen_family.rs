//! The generic CANopen family as the registry sees it: the built-in CiA 402 dictionary,
//! objects addressed by index (`0x6041`, `0x1018/2`), node ids 1..=127 on a CAN frame bus,
//! a simulated CiA 402 node. The node is put in NMT operational before it enables
//! operation, and back after the run ([`super::nmt_master::NmtMaster`]).

use super::sdo_family::{sdo_family_info, SdoFamily};
use super::sim::Cia402Node;
use super::{CIA_301_NOTATION, INDEX_NOTATION};
use crate::dictionary::{Address, AddressError};
use crate::family::SimulatedDevice;

pub const CANOPEN_FAMILY: SdoFamily = SdoFamily {
    info: || {
        let title = "CANopen CiA 402 drives over SDO (SLCAN adapter or SocketCAN), objects from their EDS";
        sdo_family_info("canopen", title, parse_index_address)
            .dictionaries(&[crate::builtin_dictionary!("canopen")])
            .address_help("the drive's CANopen node id 1..127 (default 1)")
    },
    notation: CIA_301_NOTATION,
    explain: INDEX_NOTATION,
    nmt: true,
    what: "a CANopen node",
    simulator: |node, config| SimulatedDevice::frames(Cia402Node::new(node, config)),
    raw_description: |t| {
        let hex = t.starts_with("0x") || t.starts_with("0X");
        hex.then(|| format!("CANopen object {t} (not in the dictionary)"))
    },
    show_address,
    object_alias: |_| None,
};

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

/// `0x6041`, `0x1018/2`.
fn show_address(address: &Address) -> String {
    let Address::Indexed { index, subindex } = *address;
    match subindex {
        0 => format!("0x{index:04X}"),
        sub => format!("0x{index:04X}/{sub}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::DataType;
    use crate::family::Family;

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
        let f = CANOPEN_FAMILY;
        assert_eq!(f.show_address(&Address::indexed(0x1018, 2)), "0x1018/2");
        assert_eq!(f.show_address(&Address::indexed(0x6041, 0)), "0x6041");
    }

    #[test]
    fn node_ids_and_raw_objects() {
        let f = CANOPEN_FAMILY;
        assert_eq!(f.parse_drive_address(Some("5")).unwrap().shown, "CAN node 5");
        assert!(f.parse_drive_address(Some("128")).is_err());
        assert!(f.raw_object("speed", None).is_none());
        let read = f.raw_object("0x6041", None).unwrap().unwrap();
        assert!(!read.writable() && read.unconfirmed.unwrap().contains("--type"));
        let write = f.raw_object("0x6060", Some(DataType::I8)).unwrap().unwrap();
        assert!(write.writable());
    }
}
