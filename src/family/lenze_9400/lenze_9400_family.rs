//! The Lenze 9400 family as the registry sees it: its dictionary, code addressing
//! (`C00099`, `C00002/16`), node addresses 1..=127 on a CAN frame bus, its simulated node
//! and its words in messages and explanations.

use super::codec::Code;
use super::sim::Lenze9400Simulator;
use crate::dictionary::{Address, AddressError};
use crate::family::canopen::sdo_family::{sdo_family_info, SdoFamily};
use crate::family::canopen::{ExplainNotation, SdoNotation};
use crate::family::SimulatedDevice;

pub const LENZE_9400_FAMILY: SdoFamily = SdoFamily {
    info: || {
        let title = "Lenze 9400 over CANopen SDO (SLCAN adapter or SocketCAN)";
        sdo_family_info("lenze-9400", title, parse_code_address)
            .dictionaries(&[crate::builtin_dictionary!("lenze-9400")])
            .address_help("the drive's CANopen node address 1..127 (code C00350; default 1)")
    },
    notation: LENZE_NOTATION,
    explain: LENZE_EXPLAIN,
    nmt: false,
    what: "the Lenze 9400",
    simulator: |node, config| SimulatedDevice::frames(Lenze9400Simulator::new(node, config)),
    // `C00061`, `C00002/16`. Dictionary names are lower case, so `C` and a digit can only
    // be a code.
    raw_description: |t| {
        let code = t.starts_with('C') && t[1..].starts_with(|c: char| c.is_ascii_digit());
        code.then(|| format!("Lenze code {t} (not in the dictionary)"))
    },
    show_address,
    // What the vendor's EDS lists gains the code as an alias.
    object_alias: |address| {
        let Address::Indexed { index, subindex } = *address;
        Code::at(index, u8::try_from(subindex).ok()?).map(|c| c.to_string())
    },
};

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

/// `C00099 (index 0x5F9C)`, `C00002/16 (index 0x5FFD/16)`.
fn show_address(address: &Address) -> String {
    let Address::Indexed { index, subindex } = *address;
    let code = u8::try_from(subindex).ok().and_then(|s| Code::at(index, s));
    match (code, subindex) {
        (Some(code), 0) => format!("{code} (index 0x{index:04X})"),
        (Some(code), sub) => format!("{code} (index 0x{index:04X}/{sub})"),
        (None, _) => address.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::DataType;
    use crate::family::Family;

    #[test]
    fn node_addresses() {
        let f = LENZE_9400_FAMILY;
        let a = |t: Option<&str>| f.parse_drive_address(t).map(|a| (a.number, a.shown));
        assert_eq!(a(None), Ok((1, "CAN node 1".into())));
        assert_eq!(a(Some("12")), Ok((12, "CAN node 12".into())));
        assert!(a(Some("0")).unwrap_err().to_string().contains("1..127"));
        assert!(a(Some("128")).is_err());
        assert!(a(Some("x")).is_err());
    }

    #[test]
    fn raw_codes_need_a_type_to_be_written() {
        let f = LENZE_9400_FAMILY;
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
