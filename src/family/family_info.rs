//! What a family is, as data: its id, title, built-in dictionaries, bus, line settings and
//! address notations. A family states these once, in `Family::info`, and the seam's
//! accessors (`id`, `title`, `bus_kind`, …) read them from here; no behaviour lives here.

use super::BuiltinDictionary;
use crate::bus::{BusKind, SerialSettings};
use crate::dictionary::AddressParser;

/// A family's facts. Built with [`FamilyInfo::new`] and the setters below; what a family
/// does not set is a byte line at 57600 8N1.
#[derive(Debug, Clone, Copy)]
pub struct FamilyInfo {
    /// What a dictionary's `family:` names (`sd2`, `ct_ansi`, `lenze-931`, `lenze_9400`).
    pub id: &'static str,
    /// One line for listings.
    pub title: &'static str,
    pub dictionaries: &'static [BuiltinDictionary],
    pub bus_kind: BusKind,
    /// The line settings a drive of the family ships with.
    pub serial_settings: SerialSettings,
    /// Reads an object's `address:` text in the family's dictionaries.
    pub address_parser: AddressParser,
    /// How `--address` is written, for help and messages.
    pub address_help: &'static str,
    /// The family's simulated drive sends emergency messages on its own (a CANopen node's
    /// EMCY), so `--sim emergency-at` reaches it.
    pub sim_emergencies: bool,
}

impl FamilyInfo {
    /// A family on a byte line, its objects written the way `address_parser` reads.
    pub fn new(id: &'static str, title: &'static str, address_parser: AddressParser) -> Self {
        FamilyInfo {
            id,
            title,
            dictionaries: &[],
            bus_kind: BusKind::Bytes,
            serial_settings: SerialSettings::default(),
            address_parser,
            address_help: "",
            sim_emergencies: false,
        }
    }

    pub fn dictionaries(self, dictionaries: &'static [BuiltinDictionary]) -> Self {
        FamilyInfo { dictionaries, ..self }
    }

    pub fn serial(self, serial_settings: SerialSettings) -> Self {
        FamilyInfo {
            serial_settings,
            ..self
        }
    }

    /// The family's link needs a CAN frame bus rather than a byte line.
    pub fn frames(self) -> Self {
        FamilyInfo {
            bus_kind: BusKind::Frames,
            ..self
        }
    }

    /// The family's simulated drive sends an injected emergency message (`--sim emergency-at`).
    pub fn sim_emergencies(self) -> Self {
        FamilyInfo {
            sim_emergencies: true,
            ..self
        }
    }

    pub fn address_help(self, address_help: &'static str) -> Self {
        FamilyInfo { address_help, ..self }
    }
}
