//! The Lenze 9400 family as the registry sees it: its dictionary, code addressing
//! (`C00099`, `C00002/16`), node addresses 1..=127 on a CAN frame bus, and how to open an
//! SDO link, simulate a node and explain frames.

use super::codec::Code;
use super::sim::Lenze9400Simulator;
use crate::bus::Bus;
use crate::dictionary::{Address, AddressError, DataType, Dictionary, ObjectDef};
use crate::family::canopen::sdo_family::{
    open_sdo, parse_node, raw_sdo_object, sdo_family_info, sdo_frame_direction, sim_node,
};
use crate::family::canopen::{ExplainNotation, SdoExplainer, SdoNotation};
use crate::family::{
    DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened, SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

pub struct Lenze9400Family;

/// The 9400's words in the SDO link's messages: objects as codes, the node address as C00350.
pub const LENZE_NOTATION: SdoNotation = SdoNotation {
    object_text: code_text,
    no_reply_hint: "check the node address (C00350), the bit rate, the CAN wiring and termination, and that the adapter is open on the right bus",
};

/// The 9400's words in explanations: objects as codes, whose index is 0x5FFF − code.
pub const LENZE_EXPLAIN: ExplainNotation = ExplainNotation {
    code: |index, subindex| Code::at(index, subindex).map(|c| c.to_string()),
    index_rule: " = 0x5FFF − code",
};

/// `C00099 (index 0x5F9C, subindex 0)`, or the index alone outside the codes' range.
fn code_text(index: u16, subindex: u8) -> String {
    match Code::at(index, subindex) {
        Some(code) => format!("{code} (index 0x{index:04X}, subindex {subindex})"),
        None => crate::family::canopen::index_text(index, subindex),
    }
}

/// A dictionary's `address:` (and `read`/`write` raw notation): a Lenze code.
fn parse_code_address(text: &str) -> Result<Address, AddressError> {
    let code = Code::parse(text)?;
    Ok(Address::indexed(code.index(), u32::from(code.subcode)))
}

impl Family for Lenze9400Family {
    fn info(&self) -> FamilyInfo {
        let title = "Lenze 9400 over CANopen SDO (SLCAN adapter or SocketCAN)";
        sdo_family_info("lenze-9400", title, parse_code_address)
            .dictionaries(&[crate::builtin_dictionary!("lenze-9400")])
            .address_help("the drive's CANopen node address 1..127 (code C00350; default 1)")
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        parse_node(text, self.address_help())
    }

    fn no_reply_advice(&self) -> &'static str {
        LENZE_NOTATION.no_reply_hint
    }

    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        open_sdo(
            bus,
            drive,
            options,
            context,
            LENZE_NOTATION,
            None,
            "the Lenze 9400",
        )
    }

    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        SimulatedDevice::frames(Lenze9400Simulator::new(sim_node(drive), config))
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(SdoExplainer::new(dictionary, LENZE_EXPLAIN))
    }

    /// SDO requests go to 0x600 + node, responses come from 0x580 + node.
    fn frame_direction(&self, frame: &crate::bus::CanFrame) -> Option<crate::link::Direction> {
        sdo_frame_direction(frame)
    }

    /// `C00061`, `C00002/16` (see `raw_sdo_object`: without `--type`, read-only).
    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let t = text.trim();
        // Dictionary names are lower case, so `C` and a digit can only be a code.
        if !(t.starts_with('C') && t[1..].starts_with(|c: char| c.is_ascii_digit())) {
            return None;
        }
        let description = format!("Lenze code {t} (not in the dictionary)");
        Some(raw_sdo_object(t, parse_code_address, data_type, description))
    }

    /// `C00099`, `C00002/16`: what the vendor's EDS lists gains the code as an alias.
    fn object_alias(&self, address: &Address) -> Option<String> {
        let Address::Indexed { index, subindex } = *address;
        Code::at(index, u8::try_from(subindex).ok()?).map(|c| c.to_string())
    }

    /// `C00099 (index 0x5F9C)`, `C00002/16 (index 0x5FFD/16)`.
    fn show_address(&self, address: &Address) -> String {
        let Address::Indexed { index, subindex } = *address;
        let code = u8::try_from(subindex).ok().and_then(|s| Code::at(index, s));
        match (code, subindex) {
            (Some(code), 0) => format!("{code} (index 0x{index:04X})"),
            (Some(code), sub) => format!("{code} (index 0x{index:04X}/{sub})"),
            (None, _) => address.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_addresses() {
        let f = Lenze9400Family;
        let a = |t: Option<&str>| f.parse_drive_address(t).map(|a| (a.number, a.shown));
        assert_eq!(a(None), Ok((1, "CAN node 1".into())));
        assert_eq!(a(Some("12")), Ok((12, "CAN node 12".into())));
        assert!(a(Some("0")).unwrap_err().to_string().contains("1..127"));
        assert!(a(Some("128")).is_err());
        assert!(a(Some("x")).is_err());
    }

    #[test]
    fn raw_codes_need_a_type_to_be_written() {
        let f = Lenze9400Family;
        assert!(f.raw_object("speed", None).is_none());
        assert!(f.raw_object("c99", None).is_none());
        let read = f.raw_object("C00061", None).unwrap().unwrap();
        assert_eq!(read.address, Address::indexed(0x5FC2, 0));
        assert!(!read.writable());
        assert!(read.unconfirmed.unwrap().contains("--type"));
        let write = f.raw_object("C11", Some(DataType::I32)).unwrap().unwrap();
        assert_eq!(
            (write.address, write.writable()),
            (Address::indexed(0x5FF4, 0), true)
        );
        assert!(f.raw_object("C2/999", None).unwrap().is_err());
        assert_eq!(
            f.show_address(&Address::indexed(0x5F9C, 0)),
            "C00099 (index 0x5F9C)"
        );
        assert_eq!(
            f.show_address(&Address::indexed(0x5FFD, 16)),
            "C00002/16 (index 0x5FFD/16)"
        );
    }
}
