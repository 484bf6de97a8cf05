//! The Control Techniques family as the registry sees it: the Unidrive SP dictionary,
//! addresses as group.unit (`1.2`; `G.0` a group, `0.0` every drive), parameters as
//! menu.parameter (`#1.21`), 7E1 serial, and how to open a [`CtAccess`] over a shared byte
//! bus, simulate a drive and explain messages.

use super::codec::{NodeAddress, Parameter};
use super::{CtAccess, CtExplainer, CtLink, CtLinkConfig, CtSimulator};
use crate::bus::{Bus, DataBits, Parity, SerialSettings, StopBits};
use crate::dictionary::{Access, Address, AddressError, DataType, DecimalPlaces, Dictionary, ObjectDef};
use crate::family::{
    serial_line, DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened,
    SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

/// The classic Unidrive's default; the sources do not give the Unidrive SP's, so it is
/// only where drivescript starts (`--baud` sets the drive's).
const DEFAULT_BAUD: u32 = 4800;

/// drivescript's default drive address when `--address` is not given (the sources give no
/// factory setting).
const DEFAULT_ADDRESS: &str = "1.1";

pub struct CtFamily;

const ADDRESS_HELP: &str = "the drive's serial address as group.unit, e.g. `1.2` (or `12`); `G.0` writes to every drive of group G and `0.0` to every drive, without a reply (writes only)";

/// An object's `address:` in a Control Techniques dictionary: `#1.21` → index 1, subindex 21.
fn parse_object_address(text: &str) -> Result<Address, AddressError> {
    Parameter::parse(text).map(|p| Address::indexed(u16::from(p.menu), u32::from(p.param)))
}

/// `--link-option baud-parameter=#M.PP`: the parameter that sets the drive's serial baud
/// rate. The notes say a drive answers a baud-rate change at the old rate and needs 20 ms,
/// but not which parameter it is, so the user names it (the dictionary has no such object).
fn baud_parameter(extra: &[(String, String)]) -> Result<Option<Parameter>, FamilyError> {
    let mut found = None;
    for (name, value) in extra {
        match name.replace('_', "-").as_str() {
            "baud-parameter" => {
                found = Some(Parameter::parse(value).map_err(|e| FamilyError::LinkOption(format!("--link-option {name}: {e}")))?)
            }
            _ => {
                return Err(FamilyError::LinkOption(format!(
                    "--link-option {name}: the ct-ansi family knows only `baud-parameter=#M.PP` (the parameter that sets the drive's baud rate); the line is set with --baud, --data-bits, --parity, --stop-bits, --timeout, --retries"
                )))
            }
        }
    }
    Ok(found)
}

impl Family for CtFamily {
    fn info(&self) -> FamilyInfo {
        let title = "Control Techniques (Unidrive SP and others) over the ANSI x3.28 serial protocol";
        // 7 data bits, even parity, 1 stop bit (the UD70 frame).
        let line = SerialSettings {
            baud: DEFAULT_BAUD,
            data_bits: DataBits::Seven,
            parity: Parity::Even,
            stop_bits: StopBits::One,
        };
        FamilyInfo::new("ct-ansi", title, parse_object_address)
            .dictionaries(&[crate::builtin_dictionary!("ct-unidrive-sp")])
            .serial(line)
            .address_help(ADDRESS_HELP)
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        let node = NodeAddress::parse(text.unwrap_or(DEFAULT_ADDRESS))
            .map_err(|e| FamilyError::DriveAddress(format!("--address {e}")))?;
        Ok(DriveAddress {
            number: node.number(),
            shown: node.describe(),
        })
    }

    fn no_reply_advice(&self) -> &'static str {
        super::ct_link::NO_REPLY_HINT
    }

    fn check_link_options(&self, extra: &[(String, String)]) -> Result<(), FamilyError> {
        baud_parameter(extra).map(|_| ())
    }

    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        let transport = serial_line(bus, self.id())?;
        let node = NodeAddress::from_number(drive.number).ok_or_else(|| {
            FamilyError::DriveAddress(format!("drive address {} is not group.unit", drive.number))
        })?;
        let config = CtLinkConfig {
            reply_timeout: options.reply_timeout,
            retries: options.retries,
            baud_parameter: baud_parameter(&options.extra)?,
            ..CtLinkConfig::default()
        };
        let link = context.link(|clock| CtLink::new(transport, clock, config));
        Ok(Box::new(CtAccess::new(link, node)))
    }

    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        let node = NodeAddress::from_number(drive.number)
            .filter(|n| !n.is_broadcast())
            .unwrap_or(NodeAddress { group: 1, unit: 1 });
        SimulatedDevice::bytes(CtSimulator::new(node, config))
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(CtExplainer::new(dictionary))
    }

    /// STX data ETX BCC: the BCC checks what follows STX up to ETX.
    fn reseal(&self, telegram: &mut [u8]) {
        const STX: u8 = 0x02;
        const ETX: u8 = 0x03;
        let etx = telegram.len().checked_sub(2).filter(|&i| telegram[i] == ETX);
        let stx = telegram.iter().position(|&b| b == STX);
        if let (Some(stx), Some(etx)) = (stx, etx) {
            if stx < etx {
                telegram[etx + 1] = super::codec::bcc(&telegram[stx + 1..=etx]);
            }
        }
    }

    /// `#1.21`: menu.parameter, from index = menu and subindex = parameter.
    fn show_address(&self, address: &Address) -> String {
        let Address::Indexed { index, subindex } = *address;
        match (u8::try_from(index), u8::try_from(subindex)) {
            (Ok(m), Ok(p)) if m <= 99 && p <= 99 => Parameter { menu: m, param: p }.to_string(),
            _ => address.to_string(),
        }
    }

    /// `#5.04` or `5.04`. The data field is decimal text with its sign and decimal point,
    /// so no `--type` is needed to read it: the value is shown exactly as the drive sends
    /// it, and a write sends the number exactly as typed (`1500.5` as `1500.5`). The range
    /// is that of i32 unless `--type` narrows it; the drive refuses (NAK) what does not fit
    /// the parameter.
    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let t = text.trim();
        if !(t.starts_with('#') || t.starts_with(|c: char| c.is_ascii_digit())) {
            return None;
        }
        Some(parse_object_address(t).map_err(FamilyError::from).and_then(|address| {
            let data_type = data_type.unwrap_or(DataType::I32);
            if !data_type.is_integer() {
                return Err(FamilyError::Object(format!(
                    "a Control Techniques parameter holds a number, not {data_type}; leave out --type, or give an integer type (u8 … i32) for its range"
                )));
            }
            let mut object = ObjectDef::new(t, address, data_type, Access::ReadWrite);
            object.decimal_places = Some(DecimalPlaces::AsGiven);
            Ok(object)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reply whose data changed gets the BCC the codec's worked example gives.
    #[test]
    fn reseal_recomputes_the_bcc_after_a_changed_reply() {
        let mut reply = b"\x020121-99.9\x03?".to_vec();
        CtFamily.reseal(&mut reply);
        let mut expected = b"\x020121-47.6\x03?".to_vec();
        CtFamily.reseal(&mut expected);
        assert_eq!(expected.last(), Some(&b'7'));
        assert_eq!(reply.last(), Some(&super::super::codec::bcc(b"0121-99.9\x03")));
        let mut request = b"\x041111".to_vec();
        CtFamily.reseal(&mut request);
        assert_eq!(request, b"\x041111");
    }

    #[test]
    fn drive_addresses_in_group_unit_notation() {
        let f = CtFamily;
        let a = |t: Option<&str>| f.parse_drive_address(t).map(|a| (a.number, a.shown));
        assert_eq!(a(Some("1.2")), Ok((12, "drive 1.2".into())));
        assert_eq!(a(Some("12")), Ok((12, "drive 1.2".into())));
        assert_eq!(a(None), Ok((11, "drive 1.1".into())));
        assert!(a(Some("1.0")).unwrap().1.contains("group 1"));
        assert!(a(Some("0.0")).unwrap().1.contains("every drive"));
        assert!(a(Some("1.23")).unwrap_err().to_string().contains("group.unit"));
        assert_eq!(f.serial_settings().to_string(), "4800 7E1");
    }

    #[test]
    fn object_addresses_and_raw_parameters() {
        assert_eq!(parse_object_address("#1.21"), Ok(Address::indexed(1, 21)));
        assert_eq!(parse_object_address("10.40"), Ok(Address::indexed(10, 40)));
        assert!(parse_object_address("1021").is_err());
        let f = CtFamily;
        assert!(f.raw_object("speed_actual", None).is_none());
        let o = f.raw_object("#5.04", None).unwrap().unwrap();
        assert_eq!((o.address, o.data_type), (Address::indexed(5, 4), DataType::I32));
        assert_eq!(o.name, "#5.04");
        let o = f.raw_object("5.04", Some(DataType::U16)).unwrap().unwrap();
        assert_eq!(o.data_type, DataType::U16);
        assert!(f
            .raw_object("#5.04", Some(DataType::String { max: 8 }))
            .unwrap()
            .unwrap_err()
            .to_string()
            .contains("holds a number"));
        assert!(f.raw_object("#5.400", None).unwrap().is_err());
        assert_eq!(f.show_address(&Address::indexed(5, 4)), "#5.04");
    }

    #[test]
    fn the_only_link_option_names_the_baud_rate_parameter() {
        let o = |name: &str, value: &str| vec![(name.to_string(), value.to_string())];
        let e = CtFamily
            .check_link_options(&o("write-length", "captured"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("knows only `baud-parameter=#M.PP`"), "{e}");
        assert!(CtFamily.check_link_options(&[]).is_ok());
        assert_eq!(
            baud_parameter(&o("baud-parameter", "#11.25")),
            Ok(Parameter::new(11, 25))
        );
        assert_eq!(
            baud_parameter(&o("baud_parameter", "11.25")),
            Ok(Parameter::new(11, 25))
        );
        let e = CtFamily
            .check_link_options(&o("baud-parameter", "1125"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("--link-option baud-parameter: `1125` is not a parameter"),
            "{e}"
        );
    }
}
