//! The small trait each drive family implements so the drive layer can read and write
//! objects without knowing bytes on the wire: typed raw values in and out, family-neutral
//! errors. Implementations own (or share) their link.

use super::AccessError;
use crate::clock::SharedClock;
use crate::dictionary::{Address, DataType, RawValue};
use std::time::Duration;

/// What a write did. Some drives store a value other than the one sent (Lenze 931:
/// "written, but limited to X"); that is neither success nor failure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum WriteOutcome {
    Stored,
    /// Written, but the drive stored this value instead.
    Limited(RawValue),
}

/// The smallest and largest value a drive itself accepts for an object, as it reports
/// them (Lenze 931: `ON`/`OX`); `None` on a side the drive says has no limit.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DriveLimits {
    pub min: Option<RawValue>,
    pub max: Option<RawValue>,
}

/// What [`ObjectAccess::write`] returns: the outcome, or why the value was not written.
pub type WriteResult = Result<WriteOutcome, AccessError>;

pub trait ObjectAccess: Send {
    fn read(&mut self, address: &Address, data_type: DataType) -> Result<RawValue, AccessError>;
    fn write(&mut self, address: &Address, value: &RawValue, data_type: DataType) -> WriteResult;
    /// Several objects at once, their results appended to `out` in the objects' order (a
    /// sampling loop reuses one list); a family with a cyclic channel answers them in one
    /// round trip. The default reads them one by one.
    fn read_many(&mut self, objects: &[(Address, DataType)], out: &mut Vec<Result<RawValue, AccessError>>) {
        out.extend(objects.iter().map(|(a, t)| self.read(a, *t)));
    }
    /// What the drive's error code `code` (the profile's drive_error) means in the family's
    /// protocol (CANopen: the CiA 301/402 emergency error codes); `None` when unknown.
    fn error_code_text(&self, code: u16) -> Option<&'static str> {
        let _ = code;
        None
    }
    /// What the link did on its own since the last call that the console should say
    /// (CANopen: the NMT start a CiA 402 node got before it enabled operation). Empty by
    /// default.
    fn notices(&mut self) -> Vec<String> {
        Vec::new()
    }
    /// The run is over and its safe stop done, and the drive is not left enabled: hands
    /// the drive back as it was found where the link changed something on its own
    /// (CANopen: a node it started goes back to pre-operational), and says what it did.
    /// Never called before the safe stop; `None` (the default) when there is nothing.
    fn release(&mut self) -> Option<String> {
        None
    }
    /// The run is over but its safe stop could not verify the drive stopped: what
    /// [`ObjectAccess::release`] would hand back is kept as it is (CANopen: a node it
    /// started stays operational), and this says so; `None` (the default) when the link
    /// changed nothing.
    fn withhold_release(&mut self) -> Option<String> {
        None
    }
    /// A fault the drive reported on its own since the last call, in the family's words
    /// (CANopen: an EMCY frame with its error code and text), which its state may not show:
    /// the fault watch stops the run on it as on a fault state. `None` (the default) for
    /// families whose drives report nothing on their own.
    fn reported_fault(&mut self) -> Option<String> {
        None
    }
    /// Sends what the channel needs to stay alive, when it is due (a cyclic telegram the
    /// drive expects at a fixed period), and says how long until it is due again. The
    /// session calls it while it waits; `None` means nothing needs keeping alive.
    fn keep_alive(&mut self) -> Result<Option<Duration>, AccessError> {
        Ok(None)
    }
    /// Whether writing this object changes how the drive talks on the line (a baud-rate
    /// parameter): after it, nothing can reach the drive at the old settings, not even a
    /// stop, so the drive layer writes it only to a drive that is not powered.
    fn changes_line(&self, address: &Address) -> bool {
        let _ = address;
        false
    }
    /// The drive's own limits of an object, for families whose drives report them; `None`
    /// (the default) when the family cannot ask.
    fn limits(&mut self, address: &Address, data_type: DataType) -> Option<Result<DriveLimits, AccessError>> {
        let _ = (address, data_type);
        None
    }
    /// Every object the drive itself can list, with its value, for `backup --all`
    /// (Control Techniques: `ACK` reads the next parameter); `keep_going()` is asked
    /// between reads, `progress(text)` says where the scan is. `None` (the default) for a
    /// family whose drives cannot list their objects.
    fn list_objects(
        &mut self,
        keep_going: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&str),
    ) -> Option<Result<Vec<(Address, RawValue)>, AccessError>> {
        let _ = (keep_going, progress);
        None
    }
    /// Stores the drive's parameters in its non-volatile memory, where the protocol has a
    /// documented command for it (Lenze 931 `SAVE!`); `None` (the default) where it has
    /// none.
    fn store_parameters(&mut self) -> Option<Result<(), AccessError>> {
        None
    }
    /// Carries out one of the family's maintenance actions (`Family::maintenance_actions`)
    /// by its name, with its number where it takes one; sent once, never repeated. `None`
    /// (the default) for a family that has none.
    fn maintain(
        &mut self,
        action: &str,
        argument: Option<u32>,
    ) -> Option<Result<super::MaintenanceOutcome, AccessError>> {
        let _ = (action, argument);
        None
    }
    /// The drives addressed at once when the address is a group's (Control Techniques
    /// `1.0`: `every drive of group 1 (group address 1.0)`): none of them answers a write,
    /// so nothing can confirm it. `None` (the default) for one drive's address.
    fn group(&self) -> Option<String> {
        None
    }
    /// What we are talking to, for messages: `drive 2 on /dev/ttyUSB0 at 57600 8N1`.
    fn port(&self) -> String;
    /// The clock the link waits on (real, or virtual with the simulator).
    fn clock(&self) -> SharedClock;
    /// Opens the port again after the line was lost (see `Transport::reopen`).
    fn reopen(&mut self) -> Result<(), AccessError>;
}

/// The [`ObjectAccess`] methods of an access that keeps its link in a field `link`, written
/// inside its `impl ObjectAccess`: the link's clock, and its reopen.
#[macro_export]
macro_rules! link_access_core {
    () => {
        fn clock(&self) -> $crate::clock::SharedClock {
            self.link.clock().clone()
        }

        fn reopen(&mut self) -> Result<(), $crate::drive::AccessError> {
            self.link.reopen()
        }
    };
}
