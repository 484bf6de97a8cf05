//! The two Modbus families as the registry sees them: `modbus-rtu` (RS485, or a raw
//! serial server over --tcp) and `modbus-tcp` (MBAP over --tcp), with their dictionaries,
//! the register notation (`40001`, `holding 0x1001`), the slave id as `--address`, the
//! serial default 19 200 8E1 (Serial Line V1.02, 2.5.1: even parity is the default), and
//! how to open a [`ModbusAccess`], simulate an inverter and explain frames.

use super::codec::rtu;
use super::modbus_link::{LinkConfig, NO_REPLY_HINT, NO_REPLY_HINT_TCP};
use super::register_address::{self, Register};
use super::{Framing, ModbusAccess, ModbusExplainer, ModbusLink, ModbusSimulator};
use crate::bus::{Bus, Parity, SerialSettings};
use crate::dictionary::{Access, Address, DataType, Dictionary, ObjectDef};
use crate::family::{
    serial_line, DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened,
    SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

pub struct ModbusFamily {
    framing: Framing,
}

impl ModbusFamily {
    pub const RTU: ModbusFamily = ModbusFamily {
        framing: Framing::Rtu,
    };
    pub const TCP: ModbusFamily = ModbusFamily {
        framing: Framing::Tcp,
    };
}

/// 19 200 bit/s, 8 data bits, even parity, 1 stop bit.
fn serial_default() -> SerialSettings {
    SerialSettings {
        parity: Parity::Even,
        ..SerialSettings::with_baud(19_200)
    }
}

impl Family for ModbusFamily {
    fn info(&self) -> FamilyInfo {
        match self.framing {
            Framing::Rtu => FamilyInfo::new(
                "modbus-rtu",
                "Frequency inverters over Modbus RTU (RS485)",
                register_address::parse_address,
            )
            .dictionaries(&[
                crate::builtin_dictionary!("sunfar-e500"),
                crate::builtin_dictionary!("modbus-inverter"),
            ])
            .serial(serial_default())
            .address_help("the slave id 1..247 set on the inverter (default 1); 0 broadcasts writes to every slave, which no slave answers"),
            Framing::Tcp => FamilyInfo::new(
                "modbus-tcp",
                "Frequency inverters over Modbus TCP (MBAP, --tcp HOST:502)",
                register_address::parse_address,
            )
            .dictionaries(&[crate::builtin_dictionary!("modbus-tcp-inverter")])
            .serial(serial_default())
            .address_help("the unit id 0..255 (default 1); a gateway to RS485 passes it on as the slave id"),
        }
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        let Some(text) = text.map(str::trim) else {
            return Ok(self.address(1));
        };
        let max = match self.framing {
            Framing::Rtu => rtu::MAX_SLAVE,
            Framing::Tcp => u8::MAX,
        };
        match text.parse::<u8>() {
            Ok(n) if n <= max => Ok(self.address(n)),
            _ => Err(FamilyError::DriveAddress(format!(
                "--address {text}: {}",
                self.address_help()
            ))),
        }
    }

    fn no_reply_advice(&self) -> &'static str {
        match self.framing {
            Framing::Rtu => NO_REPLY_HINT,
            Framing::Tcp => NO_REPLY_HINT_TCP,
        }
    }

    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        let transport = serial_line(bus, self.id())?;
        self.check_link_options(&options.extra)?;
        let config = LinkConfig {
            framing: self.framing,
            reply_timeout: options.reply_timeout,
            retries: options.retries,
            ..LinkConfig::default()
        };
        let line = transport.lock().serial_settings();
        let config = match line {
            Some(s) => LinkConfig {
                silence: rtu::frame_silence(s.baud, s.bits_per_byte()),
                ..config
            },
            None => config,
        };
        let unit = u8::try_from(drive.number).unwrap_or(1);
        let link = context.link(|clock| ModbusLink::new(transport, clock, unit, config));
        Ok(Box::new(ModbusAccess::new(link)))
    }

    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        let unit = u8::try_from(drive.number).unwrap_or(1);
        SimulatedDevice::bytes(ModbusSimulator::new(unit, self.framing, config))
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(ModbusExplainer::new(dictionary, self.framing))
    }

    fn show_address(&self, address: &Address) -> String {
        Register::of(address).map_or_else(|| address.to_string(), Register::notation)
    }

    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let t = text.trim();
        let ours = t.starts_with(|c: char| c.is_ascii_digit())
            || t.starts_with("holding ")
            || t.starts_with("input ");
        if !ours {
            return None;
        }
        Some(
            Register::parse(t)
                .map_err(|e| FamilyError::DriveAddress(e.to_string()))
                .map(|register| {
                    let access = match register.table {
                        register_address::Table::Holding => Access::ReadWrite,
                        register_address::Table::Input => Access::ReadOnly,
                    };
                    ObjectDef::new(t, register.address(), data_type.unwrap_or(DataType::U16), access)
                }),
        )
    }
}

impl ModbusFamily {
    fn address(&self, n: u8) -> DriveAddress {
        let shown = match (self.framing, n) {
            (Framing::Rtu, rtu::BROADCAST) => "broadcast (slave 0: every slave, no reply)".to_string(),
            (Framing::Rtu, n) => format!("Modbus slave {n}"),
            (Framing::Tcp, n) => format!("Modbus unit {n}"),
        };
        DriveAddress {
            number: n.into(),
            shown,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slave_id_is_the_address_and_the_line_defaults_to_19200_8e1() {
        let f = ModbusFamily::RTU;
        assert_eq!(f.parse_drive_address(None).unwrap().number, 1);
        assert_eq!(
            f.parse_drive_address(Some("247")).unwrap().shown,
            "Modbus slave 247"
        );
        assert!(f
            .parse_drive_address(Some("0"))
            .unwrap()
            .shown
            .starts_with("broadcast"));
        for bad in ["248", "-1", "x"] {
            assert!(
                f.parse_drive_address(Some(bad))
                    .unwrap_err()
                    .to_string()
                    .contains("1..247"),
                "{bad}"
            );
        }
        assert_eq!(f.serial_settings().to_string(), "19200 8E1");
        assert_eq!(
            ModbusFamily::TCP.parse_drive_address(Some("255")).unwrap().number,
            255
        );
    }

    #[test]
    fn raw_registers_in_the_manuals_notations() {
        let f = ModbusFamily::RTU;
        let def = f.raw_object("404098", None).unwrap().unwrap();
        assert_eq!(f.show_address(&def.address), "holding 0x1001 (44098)");
        assert_eq!(def.data_type, DataType::U16);
        let def = f.raw_object("input 8", Some(DataType::I16)).unwrap().unwrap();
        assert_eq!((def.access, def.data_type), (Access::ReadOnly, DataType::I16));
        assert!(f.raw_object("50001", None).unwrap().is_err());
        assert!(f.raw_object("speed_setpoint", None).is_none());
    }
}
