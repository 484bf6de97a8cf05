//! The seam a drive family plugs in through: its id and built-in dictionaries, how it
//! writes drive addresses, which bus it needs, how it opens object access on that bus, its
//! simulated drive, and its telegram explainer. A new family is one folder implementing
//! this, one dictionary file and one line in the registry.

use super::{FamilyError, FamilyInfo};
use crate::bus::{Bus, BusKind, FramePeer, Peer, SerialSettings, SharedTransport};
use crate::clock::SharedClock;
use crate::dictionary::{Address, AddressParser, DataType, Dictionary, ObjectDef};
use crate::drive::{AddressKeys, ObjectAccess};
use crate::link::{CoreLink, TelegramExplainer, TelegramObserver};
use crate::sim::{SimConfig, SimulatedDrive};
use crate::stop_request::StopRequests;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The values an object can be written with over a link with given options, where the
/// link carries less than the object holds, in the object's engineering unit.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkRange {
    pub min: f64,
    pub max: f64,
    /// Why, for the message: `the cyclic channel carries at most ±100 % of the velocity
    /// scaling, 24000 rpm`.
    pub why: String,
}

/// A dictionary compiled into the binary.
#[derive(Debug, Clone, Copy)]
pub struct BuiltinDictionary {
    /// The dictionary's name, what `--drive` and a recipe's `drive:` name: the file's stem,
    /// kebab-case (`sd2`, `ct-unidrive-sp`, `lenze-931`). Not a family id: the dictionary
    /// names its family inside, with `family:`.
    pub name: &'static str,
    /// Shown in messages: `dictionary/sd2.yaml`.
    pub path: &'static str,
    pub text: &'static str,
}

/// A dictionary file compiled in: `builtin_dictionary!("sd2")` is `dictionary/sd2.yaml`;
/// a second argument gives another path below the crate (a test family's own file).
#[macro_export]
macro_rules! builtin_dictionary {
    ($name:literal) => {
        $crate::builtin_dictionary!($name, concat!("dictionary/", $name, ".yaml"))
    };
    ($name:literal, $path:expr) => {
        $crate::family::BuiltinDictionary {
            name: $name,
            path: $path,
            text: include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/", $path)),
        }
    };
}

/// What `Family::open` gives: object access to one drive, or why there is none.
pub type Opened = Result<Box<dyn ObjectAccess>, FamilyError>;

/// One drive's address on its bus, as the family parsed it from `--address`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DriveAddress {
    /// The number on the wire (SD2: the DNC address).
    pub number: u32,
    /// For messages: `DNC address 2 (switch 0, drive A)`.
    pub shown: String,
}

/// How the link waits and retries; `extra` holds the NAME=VALUE settings only this family
/// knows (`--link-option`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinkOptions {
    pub reply_timeout: Duration,
    pub retries: u32,
    pub extra: Vec<(String, String)>,
}

/// What a link is given besides its bus: the clock, a telegram observer (trace, `-v`) and
/// the stop requests that end its waits early.
pub struct LinkContext {
    pub clock: SharedClock,
    pub observer: Option<Box<dyn TelegramObserver>>,
    pub stop: Option<Arc<StopRequests>>,
}

impl LinkContext {
    /// Builds a link on this context's clock and hands it the observer and the stop
    /// requests: what every family's `open` does, done once.
    pub fn link<L: CoreLink>(self, make: impl FnOnce(SharedClock) -> L) -> L {
        let mut link = make(self.clock);
        let core = link.core();
        if let Some(o) = self.observer {
            core.set_observer(o);
        }
        if let Some(s) = self.stop {
            core.set_stop_requests(s);
        }
        link
    }
}

/// The byte line of `bus` for a family (`family` its id) that talks over a serial line.
pub fn serial_line(bus: &Bus, family: &str) -> Result<SharedTransport, FamilyError> {
    match bus {
        Bus::Bytes(transport) => Ok(transport.clone()),
        Bus::Frames(_) => Err(FamilyError::WrongBus(format!(
            "the {family} family talks over a serial line, not over {}",
            bus.name()
        ))),
    }
}

/// A simulated drive: its family-neutral handle and the peer that speaks its bytes.
pub struct SimulatedDevice {
    pub drive: Arc<Mutex<dyn SimulatedDrive>>,
    pub peer: SimPeer,
}

impl SimulatedDevice {
    /// A simulated drive on a byte line.
    pub fn bytes<S: SimulatedDrive + Peer + 'static>(sim: S) -> Self {
        let sim = Arc::new(Mutex::new(sim));
        SimulatedDevice {
            drive: sim.clone(),
            peer: SimPeer::Bytes(sim),
        }
    }

    /// A simulated node on a CAN bus.
    pub fn frames<S: SimulatedDrive + FramePeer + 'static>(sim: S) -> Self {
        let sim = Arc::new(Mutex::new(sim));
        SimulatedDevice {
            drive: sim.clone(),
            peer: SimPeer::Frames(sim),
        }
    }
}

pub enum SimPeer {
    Bytes(Arc<Mutex<dyn Peer>>),
    Frames(Arc<Mutex<dyn FramePeer>>),
}

pub trait Family: Send + Sync {
    /// The family's facts: id, title, dictionaries, bus, line settings, address notations.
    fn info(&self) -> FamilyInfo;
    /// The family id: what a dictionary's `family:` names, in kebab-case like dictionary
    /// names (`sd2`, `ct-ansi`, `lenze-931`, `lenze-9400`). Users name dictionaries
    /// (`--drive ct-unidrive-sp`), and each dictionary names its family.
    fn id(&self) -> &'static str {
        self.info().id
    }
    /// One line for listings: `Sieb & Meyer SD2 / SD2S over the DNC serial protocol`.
    fn title(&self) -> &'static str {
        self.info().title
    }
    /// The dictionaries compiled in for this family.
    fn dictionaries(&self) -> &'static [BuiltinDictionary] {
        self.info().dictionaries
    }
    /// Which kind of bus the family's link needs.
    fn bus_kind(&self) -> BusKind {
        self.info().bus_kind
    }
    /// The line settings a drive of this family ships with (serial families).
    fn serial_settings(&self) -> SerialSettings {
        self.info().serial_settings
    }
    /// Reads an object's `address:` text in this family's dictionaries.
    fn address_parser(&self) -> AddressParser {
        self.info().address_parser
    }
    /// `--address` in this family's notation; `None` is the family's default drive.
    fn parse_drive_address(&self, text: Option<&str>) -> Result<DriveAddress, FamilyError>;
    /// How `--address` is written, for help and messages.
    fn address_help(&self) -> &'static str {
        self.info().address_help
    }
    /// What to check when a drive of this family does not answer, in its own terms (how
    /// its address is set, its line settings); the link says the same in its no-reply
    /// error. The default names only what every family has.
    fn no_reply_advice(&self) -> &'static str {
        "check the cable, the baud rate (--baud) and the drive's address (--address)"
    }
    /// Keys besides `address:` a `drives:` entry may give for this family's drives
    /// (`dnc_address: 2`), and how their values become an address in its notation; the
    /// keys that replace `address:` also have a command-line flag (`--dnc-address`).
    /// None by default.
    fn address_keys(&self) -> AddressKeys {
        AddressKeys::NONE
    }
    /// Checks the family-specific link options before anything is opened; by default the
    /// family has none and refuses every one.
    fn check_link_options(&self, extra: &[(String, String)]) -> Result<(), FamilyError> {
        match extra.first() {
            Some((name, _)) => Err(FamilyError::LinkOption(format!(
                "--link-option {name}: the {} family has no link options",
                self.id()
            ))),
            None => Ok(()),
        }
    }
    /// The range `object` can be written in over a link with `extra` options (already
    /// checked) when the link carries less than the object holds, so a value beyond it is
    /// refused before anything is sent; `None` (the default) when the link adds no limit.
    fn link_range(&self, object: &ObjectDef, extra: &[(String, String)]) -> Option<LinkRange> {
        let _ = (object, extra);
        None
    }
    /// Object access to one drive on `bus`.
    fn open(&self, bus: &Bus, drive: &DriveAddress, options: &LinkOptions, context: LinkContext) -> Opened;
    /// A simulated drive of this family at `drive`, speaking its real bytes.
    fn simulator(&self, drive: &DriveAddress, config: SimConfig) -> SimulatedDevice;
    /// Reads this family's telegrams with the objects of `dictionary`.
    fn explainer(&self, dictionary: Arc<Dictionary>) -> Box<dyn TelegramExplainer>;
    /// An object's address as this family writes it, for listings (`#1.21`, `0x0011`,
    /// `TYPE?`); the default
    /// is the family-neutral `index 395 (0x018b)`.
    fn show_address(&self, address: &Address) -> String {
        address.to_string()
    }
    /// An object the dictionary does not have, named in this family's own notation
    /// (`#5.04`, `0x0011`, `C00061`) for one-off `read` and `write`. `None` when `text` is
    /// not in that notation; `data_type` is the user's `--type`, and the family either
    /// picks a type its protocol makes safe or refuses, saying that `--type` is needed.
    /// The returned object is named `text`, read-write, without unit or limits.
    fn raw_object(&self, text: &str, data_type: Option<DataType>) -> Option<Result<ObjectDef, FamilyError>> {
        let _ = (text, data_type);
        None
    }
    /// A captured telegram written as text in the family's own line notation (ASCII
    /// protocols: `OR:0011`), as bytes for the explainer; `None` when `text` is not one
    /// (then `decode` reads it as hex).
    fn line_telegram(&self, text: &str) -> Option<Vec<u8>> {
        let _ = text;
        None
    }
    /// Recomputes the check bytes of a captured telegram whose data bytes were changed
    /// (masked by `drivescript anonymise`), so it still reads as the drive's; families
    /// whose telegrams carry none keep the default, which leaves it as it is.
    fn reseal(&self, telegram: &mut [u8]) {
        let _ = telegram;
    }
    /// Whether a CAN frame of a capture that does not say (a candump log) was sent to a
    /// drive of this family (a request) or by one (a reply); `None` for traffic that is
    /// neither (heartbeats, process data). Byte families' traces say it themselves.
    fn frame_direction(&self, frame: &crate::bus::CanFrame) -> Option<crate::link::Direction> {
        let _ = frame;
        None
    }
    /// An object's name in the family's own notation, given as an alias to the objects an
    /// EDS adds (the Lenze 9400's `C00099`); none by default.
    fn object_alias(&self, address: &Address) -> Option<String> {
        let _ = address;
        None
    }
    /// The maintenance actions this family's drives offer (`drivescript maintain`),
    /// carried out through `ObjectAccess::maintain`; none by default.
    fn maintenance_actions(&self) -> &'static [crate::drive::MaintenanceAction] {
        &[]
    }
}
