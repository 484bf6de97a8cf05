//! What every family on CANopen SDO does alike (the generic `canopen` family and the
//! Lenze 9400): one [`Family`] for both, with their bus and serial settings, node ids
//! 1..=127 as `--address`, SDO object access on a CAN frame bus in the family's notation,
//! and an object named on the command line in the family's notation. The families keep
//! what differs in an [`SdoFamily`] of their own: their notation, dictionary and simulator.

use super::nmt_master::NmtMaster;
use super::{ExplainNotation, SdoAccess, SdoExplainer, SdoLink, SdoLinkConfig, SdoNotation};
use crate::bus::{Bus, SerialSettings};
use crate::dictionary::{Access, Address, AddressParser, DataType, Dictionary, ObjectDef};
use crate::family::{
    DriveAddress, Family, FamilyError, FamilyInfo, LinkContext, LinkOptions, Opened, SimulatedDevice,
};
use crate::link::TelegramExplainer;
use crate::sim::SimConfig;
use std::sync::Arc;

/// A family on CANopen SDO: what it differs in from the other SDO families.
pub struct SdoFamily {
    /// Its id, title, address notation, dictionaries and address help.
    pub info: fn() -> FamilyInfo,
    /// Its words in the SDO link's messages.
    pub notation: SdoNotation,
    /// Its words in explanations.
    pub explain: ExplainNotation,
    /// Whether drivescript puts the node in NMT operational before it enables operation,
    /// and back after the run ([`NmtMaster`]): a CiA 402 node.
    pub nmt: bool,
    /// The drive in the wrong-bus message (`a CANopen node`, `the Lenze 9400`).
    pub what: &'static str,
    /// Its simulated node with the given node id.
    pub simulator: fn(u8, SimConfig) -> SimulatedDevice,
    /// The description of an object named on the command line in the family's notation
    /// (`CANopen object 0x6041 (not in the dictionary)`), `None` for a text in another.
    pub raw_description: fn(&str) -> Option<String>,
    /// An address as the family writes it.
    pub show_address: fn(&Address) -> String,
    /// The vendor's name of an object an EDS lists by index, if it has one.
    pub object_alias: fn(&Address) -> Option<String>,
}

impl Family for SdoFamily {
    fn info(&self) -> FamilyInfo {
        (self.info)()
    }

    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError> {
        parse_node(text, self.address_help())
    }

    fn no_reply_advice(&self) -> &'static str {
        self.notation.no_reply_hint
    }

    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened {
        let nmt = self.nmt.then(NmtMaster::default);
        open_sdo(bus, drive, options, context, self.notation, nmt, self.what)
    }

    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice {
        (self.simulator)(sim_node(drive), config)
    }

    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer> {
        Box::new(SdoExplainer::new(dictionary, self.explain))
    }

    /// SDO requests go to 0x600 + node, responses come from 0x580 + node.
    fn frame_direction(&self, frame: &crate::bus::CanFrame) -> Option<crate::link::Direction> {
        sdo_frame_direction(frame)
    }

    /// See [`raw_sdo_object`].
    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let t = text.trim();
        let description = (self.raw_description)(t)?;
        Some(raw_sdo_object(t, self.address_parser(), data_type, description))
    }

    fn object_alias(&self, address: &Address) -> Option<String> {
        (self.object_alias)(address)
    }

    fn show_address(&self, address: &Address) -> String {
        (self.show_address)(address)
    }
}

/// The node `--address` means when it is not given: CANopen's lowest node id.
pub const DEFAULT_NODE: u8 = 1;

/// The facts of an SDO family with objects in the notation `address_parser` reads: it talks
/// over a CAN frame bus, and SLCAN adapters on USB ignore the serial rate, while 115200 8N1
/// suits those on a real UART; its simulated node sends an injected EMCY (the frames every
/// simulated node shares, `sim::injected_emcy`). The family adds its dictionaries and
/// address help.
pub fn sdo_family_info(id: &'static str, title: &'static str, address_parser: AddressParser) -> FamilyInfo {
    FamilyInfo::new(id, title, address_parser)
        .frames()
        .serial(SerialSettings::with_baud(115_200))
        .sim_emergencies()
}

/// `--address` as a node id 1..=127; `help` says how it is written.
pub fn parse_node(text: Option<&str>, help: &str) -> Result<DriveAddress, FamilyError> {
    let node = match text.map(str::trim) {
        None => DEFAULT_NODE,
        Some(t) => match t.parse::<u8>() {
            Ok(n) if (1..=127).contains(&n) => n,
            _ => return Err(FamilyError::DriveAddress(format!("--address {t}: {help}"))),
        },
    };
    Ok(DriveAddress {
        number: u32::from(node),
        shown: format!("CAN node {node}"),
    })
}

/// Whether a frame of a capture that does not say (a candump log) is a request to a node
/// (an SDO request to 0x600 + node, an NMT command) or a node's response (from 0x580 +
/// node); `None` for anything else (heartbeats, EMCY, process data).
pub fn sdo_frame_direction(frame: &crate::bus::CanFrame) -> Option<crate::link::Direction> {
    match frame.id {
        _ if frame.extended => None,
        // An NMT command is drivescript's too (it starts a node before enabling it): a
        // request that gets no answer (CiA 301: NMT is unconfirmed), which a replay of the
        // capture must accept as the capture did.
        super::codec::NMT_ID => Some(crate::link::Direction::Sent),
        0x601..=0x67F => Some(crate::link::Direction::Sent),
        0x581..=0x5FF => Some(crate::link::Direction::Received),
        _ => None,
    }
}

/// The node id of a parsed address, for a simulator (the default when out of range).
fn sim_node(drive: &DriveAddress) -> u8 {
    u8::try_from(drive.number).unwrap_or(DEFAULT_NODE)
}

/// SDO object access to `drive` on `bus`; `nmt` for a CiA 402 node drivescript starts
/// before it enables operation; `what` names the drive for the wrong-bus message (`a
/// CANopen node`, `the Lenze 9400`).
fn open_sdo(
    bus: &Bus,
    drive: &DriveAddress,
    options: &LinkOptions,
    context: LinkContext,
    notation: SdoNotation,
    nmt: Option<NmtMaster>,
    what: &str,
) -> Opened {
    let Bus::Frames(frames) = bus else {
        return Err(FamilyError::WrongBus(format!(
            "{what} is reached over CAN, not over the byte stream {}; give --can slcan:PATH or --can socketcan:IF",
            bus.name()
        )));
    };
    let node = u8::try_from(drive.number)
        .ok()
        .filter(|n| (1..=127).contains(n))
        .ok_or_else(|| FamilyError::DriveAddress(format!("CAN node {} is outside 1..127", drive.number)))?;
    let config = SdoLinkConfig {
        reply_timeout: options.reply_timeout,
        retries: options.retries,
        notation,
    };
    let link = context.link(|clock| SdoLink::new(frames.clone(), clock, node, config));
    Ok(Box::new(SdoAccess::new(link, nmt)))
}

/// An object named `text` on the command line, at the address `parse` reads from it (its
/// error the family's refusal). Without `--type` it is read-only and typed `i32`: the node
/// indicates each value's size, and the access reads narrower values widened as signed
/// (see `sdo_value`); a write needs `--type`, because a wrong width is refused by the node
/// at best and misread at worst.
pub fn raw_sdo_object(
    text: &str,
    parse: AddressParser,
    data_type: Option<DataType>,
    description: String,
) -> Result<ObjectDef, FamilyError> {
    let address = parse(text)?;
    let mut def = match data_type {
        Some(dt) => ObjectDef::new(text, address, dt, Access::ReadWrite),
        None => {
            let mut d = ObjectDef::new(text, address, DataType::I32, Access::ReadOnly);
            d.unconfirmed = Some(
                "no --type given: read with the size the drive indicates (signed); give --type (u8, i8, u16, i16, u32, i32 or string(N)) to write it"
                    .into(),
            );
            d
        }
    };
    def.description = description;
    Ok(def)
}
