//! The SD2 family as the registry sees it: its dictionary, its address notation (the
//! address switch, drive A or B, or a raw DNC address), 57600 8N1, and how to open an
//! [`Sd2Access`] over a shared byte bus, simulate a drive and explain telegrams.

use super::codec::{dnc_address, WriteLength};
use super::cyclic_settings::{self, Channel};
use super::{LinkConfig, Sd2Access, Sd2CyclicAccess, Sd2Explainer, Sd2Link, Sd2Simulator};
use crate::bus::{Bus, SerialSettings};
use crate::dictionary::{Access, Address, AddressError, DataType, Dictionary, ObjectDef};
use crate::drive::AddressKeys;
use crate::family::{
    serial_line, DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, LinkRange, Opened,
    SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

pub struct Sd2Family;

const ADDRESS_HELP: &str = "the drive's address switch position (0..126), with `B` for drive B of a double-axis device (`3B`), or `dnc:N` for a raw DNC address";

/// An object's address as the SD2 manual writes it: the index, decimal or `0x` hex, and an
/// optional `/subindex`: `395`, `0x18B`, `22/3`.
fn parse_object_address(text: &str) -> Result<Address, AddressError> {
    let (index, subindex) = text.trim().split_once('/').unwrap_or((text.trim(), "0"));
    let number = |t: &str| match t
        .trim()
        .strip_prefix("0x")
        .or_else(|| t.trim().strip_prefix("0X"))
    {
        Some(hex) => u32::from_str_radix(hex, 16).ok(),
        None => t.trim().parse::<u32>().ok(),
    };
    let help = "write the index and an optional subindex, e.g. `395`, `0x18B` or `22/3`";
    let index = number(index)
        .and_then(|i| u16::try_from(i).ok())
        .ok_or_else(|| format!("not an SD2 object index (0..=65535); {help}"))?;
    let subindex = number(subindex).ok_or_else(|| format!("not a subindex; {help}"))?;
    Ok(Address::indexed(index, subindex))
}

impl Sd2Family {
    fn write_length(extra: &[(String, String)]) -> Result<WriteLength, FamilyError> {
        let mut choice = WriteLength::Captured;
        for (name, value) in extra {
            match (name.as_str(), value.as_str()) {
                ("write-length", "captured") => choice = WriteLength::Captured,
                ("write-length", "formula") => choice = WriteLength::Formula,
                ("write-length", other) => {
                    return Err(FamilyError::LinkOption(format!(
                        "--link-option write-length={other}: give `captured` (0x0B, what every capture from real drives sends) or `formula` (10 + count, the manual's formula)"
                    )))
                }
                (other, _) if cyclic_settings::OPTIONS.contains(&other.replace('_', "-").as_str()) => {}
                (other, _) => {
                    return Err(FamilyError::LinkOption(format!(
                        "--link-option {other}: the sd2 family knows `write-length=captured|formula`, `channel=object|cyclic`, and for the cyclic channel `velocity-scaling=RPM`, `heartbeat=on|off`, `cycle=DURATION`, `current-scaling=AMPERES_PER_COUNT`"
                    )))
                }
            }
        }
        Ok(choice)
    }
}

impl Family for Sd2Family {
    fn info(&self) -> FamilyInfo {
        FamilyInfo::new(
            "sd2",
            "Sieb & Meyer SD2 / SD2S over the DNC serial protocol",
            parse_object_address,
        )
        .dictionaries(&[crate::builtin_dictionary!("sd2")])
        .serial(SerialSettings::with_baud(57_600))
        .address_help(ADDRESS_HELP)
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        let text = text.map(str::trim).unwrap_or("0");
        let dnc = if let Some(raw) = text.strip_prefix("dnc:") {
            match raw.trim().parse::<u8>() {
                Ok(n) if n >= 2 => n,
                _ => {
                    return Err(FamilyError::DriveAddress(format!(
                        "--address {text}: addresses 0 and 1 belong to the master; a drive's DNC address is 2..=255"
                    )))
                }
            }
        } else {
            let (digits, drive_b) = match text.chars().last() {
                Some('b' | 'B') => (&text[..text.len() - 1], true),
                Some('a' | 'A') => (&text[..text.len() - 1], false),
                _ => (text, false),
            };
            let switch: u8 = digits.parse().map_err(|_| {
                FamilyError::DriveAddress(format!("--address {text}: {}", self.address_help()))
            })?;
            dnc_address(switch, drive_b).ok_or_else(|| {
                FamilyError::DriveAddress(format!(
                    "--address {text}: switch × 2 + {} exceeds 255; the highest switch position is 126",
                    2 + u8::from(drive_b)
                ))
            })?
        };
        Ok(DriveAddress {
            number: u32::from(dnc),
            shown: format!("DNC address {dnc}"),
        })
    }

    fn no_reply_advice(&self) -> &'static str {
        super::sd2_link::NO_REPLY_HINT
    }

    fn address_keys(&self) -> AddressKeys {
        super::SD2_ADDRESS_KEYS
    }

    fn check_link_options(&self, extra: &[(String, String)]) -> Result<(), FamilyError> {
        Self::write_length(extra)?;
        Channel::from_options(extra).map(|_| ())
    }

    fn link_range(&self, object: &ObjectDef, extra: &[(String, String)]) -> Option<LinkRange> {
        match Channel::from_options(extra) {
            Ok(Channel::Cyclic(settings)) => settings.carried_range(object),
            _ => None,
        }
    }

    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        let transport = serial_line(bus, self.id())?;
        let dest = u8::try_from(drive.number).map_err(|_| {
            FamilyError::DriveAddress(format!("DNC address {} is more than 255", drive.number))
        })?;
        let config = LinkConfig {
            reply_timeout: options.reply_timeout,
            retries: options.retries,
            write_length: Self::write_length(&options.extra)?,
            ..LinkConfig::default()
        };
        let link = context.link(|clock| Sd2Link::new(transport, clock, config));
        let access = Sd2Access::new(link, dest);
        Ok(match Channel::from_options(&options.extra)? {
            Channel::Object => Box::new(access),
            Channel::Cyclic(settings) => Box::new(Sd2CyclicAccess::new(access, settings)),
        })
    }

    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        let address = u8::try_from(drive.number).unwrap_or(config.address);
        SimulatedDevice::bytes(Sd2Simulator::new(SimConfig { address, ..config }))
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(Sd2Explainer::new(dictionary))
    }

    /// The last byte checks every byte but the first.
    fn reseal(&self, telegram: &mut [u8]) {
        if let Some(last) = telegram.len().checked_sub(1).filter(|&l| l > 1) {
            telegram[last] = super::codec::checksum(&telegram[1..last]);
        }
    }

    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        // Dictionary names start with a letter, so a leading digit can only mean an index.
        if !text.trim().starts_with(|c: char| c.is_ascii_digit()) {
            return None;
        }
        Some(parse_object_address(text).map_err(FamilyError::from).and_then(|address| {
            let data_type = data_type.ok_or_else(|| {
                FamilyError::Object(
                    "an SD2 reply gives a value's length but not whether it is signed or text; give the type with --type \
                     (u8, i8, u16, i16, u32, i32 or string(N))"
                        .to_string(),
                )
            })?;
            Ok(ObjectDef::new(text.trim(), address, data_type, Access::ReadWrite))
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_say_which_input_was_wrong() {
        let f = Sd2Family;
        assert!(matches!(
            f.parse_drive_address(Some("dnc:1")),
            Err(FamilyError::DriveAddress(_))
        ));
        let option = [("write-length".to_string(), "long".to_string())];
        assert!(matches!(
            f.check_link_options(&option),
            Err(FamilyError::LinkOption(_))
        ));
        assert!(matches!(
            f.raw_object("395", None),
            Some(Err(FamilyError::Object(_)))
        ));
        assert!(matches!(
            f.raw_object("99999", Some(DataType::U8)),
            Some(Err(FamilyError::Object(_)))
        ));
    }

    #[test]
    fn addresses_in_sd2_notation() {
        let f = Sd2Family;
        let a = |t: Option<&str>| f.parse_drive_address(t).map(|a| (a.number, a.shown));
        assert_eq!(a(None), Ok((2, "DNC address 2".into())));
        assert_eq!(a(Some("5")).unwrap().0, 12);
        assert_eq!(a(Some("0B")).unwrap().0, 3);
        assert_eq!(a(Some("dnc:17")).unwrap().0, 17);
        assert!(a(Some("dnc:1"))
            .unwrap_err()
            .to_string()
            .contains("belong to the master"));
        assert!(a(Some("127B"))
            .unwrap_err()
            .to_string()
            .contains("highest switch position is 126"));
        assert!(a(Some("x")).unwrap_err().to_string().contains("address switch"));
    }

    #[test]
    fn object_addresses_in_sd2_notation() {
        assert_eq!(parse_object_address("395"), Ok(Address::indexed(395, 0)));
        assert_eq!(parse_object_address("0x18B"), Ok(Address::indexed(395, 0)));
        assert_eq!(parse_object_address(" 22/3 "), Ok(Address::indexed(22, 3)));
        assert!(parse_object_address("70000")
            .unwrap_err()
            .to_string()
            .contains("0..=65535"));
        assert!(parse_object_address("22/x")
            .unwrap_err()
            .to_string()
            .contains("subindex"));
    }

    #[test]
    fn link_options() {
        let f = Sd2Family;
        let o = |n: &str, v: &str| vec![(n.to_string(), v.to_string())];
        assert!(f.check_link_options(&o("write-length", "formula")).is_ok());
        assert!(f.check_link_options(&o("write-length", "x")).is_err());
        assert!(f.check_link_options(&o("parity", "even")).is_err());
    }
}
