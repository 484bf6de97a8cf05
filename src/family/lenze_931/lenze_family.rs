//! The Lenze 931 family as the registry sees it: its dictionary, its object notation
//! (`0x0011`, `TYPE?`, `sdo:0x6041/0`), 9600 8N1 point to point (no drive address), and
//! how to open a [`LenzeAccess`], simulate a drive and explain lines.

use super::codec::{Reply, Request};
use super::lenze_link::LinkConfig;
use super::object_address::{self, LenzeObject};
use super::{LenzeAccess, LenzeExplainer, LenzeLink, LenzeSimulator};
use crate::bus::{Bus, SerialSettings};
use crate::dictionary::{Access, DataType, Dictionary, Format, ObjectDef};
use crate::family::{
    serial_line, DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened,
    SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

pub struct Lenze931Family;

impl Family for Lenze931Family {
    fn info(&self) -> FamilyInfo {
        let title = "Lenze 931E/K servo positioning controllers over the serial ASCII object protocol";
        FamilyInfo::new("lenze-931", title, object_address::parse_address)
            .dictionaries(&[crate::builtin_dictionary!("lenze-931")])
            .serial(SerialSettings::with_baud(9600))
            .address_help("the 931's serial interface is RS232 point to point and has no drive address; leave --address out")
    }

    fn maintenance_actions(&self) -> &'static [crate::drive::MaintenanceAction] {
        super::maintenance::ACTIONS
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        match text.map(str::trim) {
            None | Some("") | Some("rs232") | Some("RS232") => Ok(DriveAddress {
                number: 0,
                shown: "RS232 (point to point)".into(),
            }),
            Some(other) => Err(FamilyError::DriveAddress(format!(
                "--address {other}: {}",
                self.address_help()
            ))),
        }
    }

    fn no_reply_advice(&self) -> &'static str {
        super::lenze_link::NO_REPLY_HINT
    }

    fn open(&self, bus: &Bus, _drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        let transport = serial_line(bus, self.id())?;
        self.check_link_options(&options.extra)?;
        let config = LinkConfig {
            reply_timeout: options.reply_timeout,
            retries: options.retries,
            ..LinkConfig::default()
        };
        let link = context.link(|clock| LenzeLink::new(transport, clock, config));
        Ok(Box::new(LenzeAccess::new(link)))
    }

    fn simulator(&self, _drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        SimulatedDevice::bytes(LenzeSimulator::new(config))
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(LenzeExplainer::new(dictionary))
    }

    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let t = text.trim();
        // Dictionary names are `[a-z][a-z0-9_]*`: a digit, `sdo:` or a `?` cannot be one.
        let ours = t.starts_with(|c: char| c.is_ascii_digit()) || t.starts_with("sdo:") || t.ends_with('?');
        if !ours {
            return None;
        }
        Some(object_address::parse(t).map_err(FamilyError::from).map(|object| {
            let (default_type, access) = match object {
                LenzeObject::Ident(_) => (DataType::String { max: 32 }, Access::ReadOnly),
                _ => (DataType::I32, Access::ReadWrite),
            };
            let mut def = ObjectDef::new(t, object.address(), data_type.unwrap_or(default_type), access);
            // Without a dictionary nobody knows what the number means: the signed value
            // and its 32 bits in hex are both shown (`read` prints the raw value too).
            if data_type.is_none() && default_type.is_integer() {
                def.format = Format::Hex;
            }
            def
        }))
    }

    fn show_address(&self, address: &crate::dictionary::Address) -> String {
        LenzeObject::of(address).map_or_else(|| address.to_string(), LenzeObject::notation)
    }

    fn line_telegram(&self, text: &str) -> Option<Vec<u8>> {
        let t = text.trim();
        // A line of the protocol, or text that is no hex either: the explainer says why
        // it is no 931 line. Hex (a serial monitor's dump of the bytes) is read as hex.
        let line = Request::parse(t).is_ok() || Reply::parse(t).is_ok() || crate::hex::parse_hex(t).is_err();
        line.then(|| {
            let mut bytes = t.as_bytes().to_vec();
            bytes.push(super::codec::CR);
            bytes
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::Address;

    #[test]
    fn no_drive_address_and_no_link_options() {
        let f = Lenze931Family;
        assert_eq!(
            f.parse_drive_address(None).unwrap().shown,
            "RS232 (point to point)"
        );
        assert!(f
            .parse_drive_address(Some("3"))
            .unwrap_err()
            .to_string()
            .contains("point to point"));
        assert!(f.check_link_options(&[("x".into(), "y".into())]).is_err());
        assert_eq!(f.serial_settings(), SerialSettings::with_baud(9600));
    }

    #[test]
    fn raw_objects_in_the_manuals_notation() {
        let f = Lenze931Family;
        let def = f.raw_object("0x0011", None).unwrap().unwrap();
        assert_eq!(
            (def.address, def.data_type, def.format),
            (Address::indexed(0x11, 0), DataType::I32, Format::Hex)
        );
        let def = f.raw_object("0x0011", Some(DataType::U16)).unwrap().unwrap();
        assert_eq!((def.data_type, def.format), (DataType::U16, Format::Decimal));
        assert!(f
            .raw_object("17", None)
            .unwrap()
            .unwrap_err()
            .to_string()
            .contains("`0x0017`"));
        let def = f.raw_object("TYPE?", None).unwrap().unwrap();
        assert_eq!(
            (def.data_type, def.access),
            (DataType::String { max: 32 }, Access::ReadOnly)
        );
        assert!(f.raw_object("speed_setpoint", None).is_none());
    }

    #[test]
    fn captured_lines_are_telegrams() {
        let f = Lenze931Family;
        assert_eq!(f.line_telegram("OR:0011"), Some(b"OR:0011\r".to_vec()));
        assert_eq!(f.line_telegram("OW:FFFF FFFF"), Some(b"OW:FFFF FFFF\r".to_vec()));
        assert_eq!(f.line_telegram("4f 52 3a"), None);
        assert_eq!(f.line_telegram("garbage"), Some(b"garbage\r".to_vec()));
    }
}
