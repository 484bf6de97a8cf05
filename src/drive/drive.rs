//! [`Drive`]: objects by name with units, device-control commands and the state machine,
//! over any protocol family's [`ObjectAccess`]. Everything that can be refused (unknown
//! object, read-only, value outside limits) is refused here, before a byte is sent.

use super::state_path::{next_step_in, NextStep};
use super::{AccessError, DriveError, ObjectAccess, WriteOutcome};
use crate::clock::SharedClock;
use crate::dictionary::{Dictionary, ObjectDef, Profile, Quantity, RawValue, Role, Value};
use crate::drive::device_control::{DeviceCommand, DeviceState};
use std::sync::Arc;
use std::time::Duration;

/// How often the status word is polled while waiting for a state change.
const STATE_POLL: Duration = Duration::from_millis(10);

/// One step of a state walk, for the log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Transition {
    pub command: DeviceCommand,
    pub from: DeviceState,
    pub to: DeviceState,
    /// Time from the command to the new state.
    pub after: Duration,
}

/// An object's limits as the drive reports them, in its unit: minimum and maximum,
/// `None` on a side the drive says has no limit.
pub type ValueLimits = (Option<Value>, Option<Value>);

/// Objects a `sample` reads again and again, looked up once (see [`Drive::read_set`]).
#[derive(Debug, Clone)]
pub struct ReadSet {
    defs: Vec<ObjectDef>,
    requests: Vec<(crate::dictionary::Address, crate::dictionary::DataType)>,
    /// Where the status word is among `defs`, if the set has it.
    status: Option<usize>,
}

pub struct Drive {
    access: Box<dyn ObjectAccess>,
    dictionary: Arc<Dictionary>,
    clock: SharedClock,
    /// The results of [`Drive::read_set_numbers`] on their way, one list for every sample.
    results: Vec<Result<RawValue, AccessError>>,
    /// The status word the last [`ReadSet`] with it read, and when: the fault watch takes
    /// it instead of a telegram of its own while it is fresh (see [`Drive::state_within`]).
    status_read: Option<(u16, Duration)>,
}

impl Drive {
    pub fn new(access: Box<dyn ObjectAccess>, dictionary: Arc<Dictionary>) -> Self {
        let clock = access.clock();
        Drive {
            access,
            dictionary,
            clock,
            results: Vec::new(),
            status_read: None,
        }
    }

    pub fn dictionary(&self) -> &Arc<Dictionary> {
        &self.dictionary
    }

    pub fn clock(&self) -> &SharedClock {
        &self.clock
    }

    /// The drives a group address reaches, when the drive was opened at one: writes to
    /// them are sent without a reply, so none is confirmed.
    pub fn group(&self) -> Option<String> {
        self.access.group()
    }

    pub fn port(&self) -> String {
        self.access.port()
    }

    /// Opens the port again after the line was lost.
    pub fn reopen(&mut self) -> Result<(), DriveError> {
        Ok(self.access.reopen()?)
    }

    /// The object definition for a name or alias.
    pub fn object(&self, name: &str) -> Result<&ObjectDef, DriveError> {
        lookup(&self.dictionary, name)
    }

    /// The dictionary's device-control profile (a dictionary without one cannot do
    /// device control).
    pub fn profile(&self) -> Result<&Profile, DriveError> {
        self.dictionary.profile().ok_or_else(|| DriveError::NoRole {
            dictionary: self.dictionary.name().to_string(),
            role: "profile",
        })
    }

    fn role_object(&self, role: Role) -> Result<ObjectDef, DriveError> {
        let name = self.profile()?.object(role).ok_or_else(|| DriveError::NoRole {
            dictionary: self.dictionary.name().to_string(),
            role: role.id(),
        })?;
        Ok(self.object(name)?.clone())
    }

    /// Reads an object and decodes it with its type, scale and unit.
    pub fn read(&mut self, name: &str) -> Result<Value, DriveError> {
        // The definition is borrowed from a second handle on the dictionary, not copied:
        // a long run reads millions of times.
        let dictionary = Arc::clone(&self.dictionary);
        self.read_def(lookup(&dictionary, name)?)
    }

    fn read_def(&mut self, def: &ObjectDef) -> Result<Value, DriveError> {
        if !def.readable() {
            return Err(DriveError::WriteOnly {
                object: def.name.clone(),
            });
        }
        let raw = self
            .access
            .read(&def.address, def.data_type)
            .map_err(|e| self.refusal(e, "to read", def))?;
        def.value_of(raw).map_err(|source| DriveError::BadReply {
            object: def.name.clone(),
            source,
        })
    }

    /// Objects to read together again and again (a `sample`), looked up and checked
    /// readable once.
    pub fn read_set(&self, names: &[&str]) -> Result<ReadSet, DriveError> {
        let mut defs = Vec::with_capacity(names.len());
        for name in names {
            let def = lookup(&self.dictionary, name)?;
            if !def.readable() {
                return Err(DriveError::WriteOnly {
                    object: def.name.clone(),
                });
            }
            defs.push(def.clone());
        }
        let requests = defs.iter().map(|d| (d.address, d.data_type)).collect();
        let status_name = self.role_object(Role::StatusWord).ok().map(|d| d.name);
        let status = defs.iter().position(|d| Some(&d.name) == status_name.as_ref());
        Ok(ReadSet {
            defs,
            requests,
            status,
        })
    }

    /// Reads a [`ReadSet`] as numbers in the objects' engineering units into `out` (one
    /// per object), in one round trip where the family's telegram carries them together.
    pub fn read_set_numbers(&mut self, set: &ReadSet, out: &mut [f64]) -> Result<(), DriveError> {
        if let ([def], [slot]) = (&set.defs[..], &mut out[..]) {
            let raw = self.access.read(&def.address, def.data_type);
            if set.status.is_some() {
                self.keep_status(raw.as_ref().ok());
            }
            *slot = self.number_of(def, raw)?;
            return Ok(());
        }
        let mut results = std::mem::take(&mut self.results);
        results.clear();
        self.access.read_many(&set.requests, &mut results);
        if let Some(i) = set.status {
            self.keep_status(results.get(i).and_then(|r| r.as_ref().ok()));
        }
        let numbers = set
            .defs
            .iter()
            .zip(results.drain(..))
            .zip(out.iter_mut())
            .try_for_each(|((def, result), slot)| {
                *slot = self.number_of(def, result)?;
                Ok(())
            });
        self.results = results;
        numbers
    }

    /// Keeps the status word a set's read returned, with the time of its reply.
    fn keep_status(&mut self, raw: Option<&RawValue>) {
        self.status_read = raw
            .and_then(RawValue::as_int)
            .map(|s| (s as u16, self.clock.now()));
    }

    /// The number in `def`'s unit of what a read of it returned.
    fn number_of(&self, def: &ObjectDef, read: Result<RawValue, AccessError>) -> Result<f64, DriveError> {
        let raw = read.map_err(|e| self.refusal(e, "to read", def))?;
        let quantity = def.quantity_of_raw(&raw).map_err(|source| DriveError::BadReply {
            object: def.name.clone(),
            source,
        })?;
        quantity.map(|q| q.value).ok_or_else(|| DriveError::NotANumber {
            object: def.name.clone(),
            data_type: def.data_type,
        })
    }

    /// Every object the drive can list, with its value (see [`ObjectAccess::list_objects`]);
    /// `None` where the family cannot.
    pub fn list_objects(
        &mut self,
        keep_going: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&str),
    ) -> Option<Result<Vec<(crate::dictionary::Address, RawValue)>, DriveError>> {
        self.access
            .list_objects(keep_going, progress)
            .map(|r| r.map_err(DriveError::Access))
    }

    /// Stores the parameters in the drive's non-volatile memory; `None` where the family
    /// has no documented command for it.
    pub fn store_parameters(&mut self) -> Option<Result<(), DriveError>> {
        self.access
            .store_parameters()
            .map(|r| r.map_err(DriveError::Access))
    }

    /// The interlock of maintenance actions: a destructive `action` is cleared only after
    /// the drive's state is read, now, and refused while the drive is enabled, whatever
    /// else is said; where the state cannot be read, only `force` clears it. A harmless
    /// action is cleared without a read.
    pub fn clear_for_maintenance(
        &mut self,
        action: &super::MaintenanceAction,
        argument: Option<u32>,
        force: bool,
    ) -> Result<super::MaintenanceClearance, DriveError> {
        let mut clearance = super::MaintenanceClearance {
            action: *action,
            argument,
            state: None,
            unchecked: None,
        };
        let Some(why) = action.destructive else {
            return Ok(clearance);
        };
        match self.state() {
            Ok(state) if state.is_powered() => Err(DriveError::EnabledForMaintenance {
                action: clearance.shown(),
                state,
                why,
            }),
            Ok(state) => {
                clearance.state = Some(state);
                Ok(clearance)
            }
            Err(cause) if force => {
                clearance.unchecked = Some(super::drive_error::state_unknown(&cause));
                Ok(clearance)
            }
            Err(cause) => Err(DriveError::MaintenanceStateUnknown {
                action: clearance.shown(),
                why,
                cause: Box::new(cause),
            }),
        }
    }

    /// Carries out the maintenance action `clearance` was given for; `None` where the
    /// family has no such action.
    pub fn maintain(
        &mut self,
        clearance: super::MaintenanceClearance,
    ) -> Option<Result<super::MaintenanceOutcome, DriveError>> {
        self.access
            .maintain(clearance.action.name, clearance.argument)
            .map(|r| r.map_err(DriveError::Access))
    }

    /// Sends what the link must send to stay alive, if due; how long until the next.
    pub fn keep_alive(&mut self) -> Result<Option<Duration>, DriveError> {
        Ok(self.access.keep_alive()?)
    }

    /// Reads an object as a number in its engineering unit.
    pub fn read_number(&mut self, name: &str) -> Result<f64, DriveError> {
        self.read_quantity(name).map(|q| q.value)
    }

    /// Reads an object as a quantity in its engineering unit: a count at scale 1 exactly.
    pub fn read_quantity(&mut self, name: &str) -> Result<Quantity, DriveError> {
        let dictionary = Arc::clone(&self.dictionary);
        let def = lookup(&dictionary, name)?;
        let value = self.read_def(def)?;
        quantity_of(def, &value)
    }

    /// Writes a number with its unit (a bare number is in the object's unit). Refused
    /// before sending when the object is read-only or the value outside its limits.
    pub fn write(&mut self, name: &str, quantity: &Quantity) -> Result<WriteOutcome, DriveError> {
        let def = self.writable_object(name)?;
        let raw = def.to_raw(quantity)?;
        self.write_raw(&def, &raw)
    }

    /// Writes text to a string object.
    pub fn write_text(&mut self, name: &str, text: &str) -> Result<WriteOutcome, DriveError> {
        let def = self.writable_object(name)?;
        let raw = def.text_to_raw(text)?;
        self.write_raw(&def, &raw)
    }

    /// The object `name`, refused when it is read-only (before anything is sent).
    fn writable_object(&self, name: &str) -> Result<ObjectDef, DriveError> {
        let def = self.object(name)?;
        if !def.writable() {
            return Err(DriveError::ReadOnly {
                object: def.name.clone(),
            });
        }
        Ok(def.clone())
    }

    fn write_raw(&mut self, def: &ObjectDef, raw: &RawValue) -> Result<WriteOutcome, DriveError> {
        if self.access.changes_line(&def.address) {
            self.refuse_line_change_while_powered(def)?;
        }
        self.access
            .write(&def.address, raw, def.data_type)
            .map_err(|e| self.refusal(e, "to write", def))
    }

    /// A write after which the drive talks differently goes only to a drive known to be
    /// without power: one that is running could not be stopped any more.
    fn refuse_line_change_while_powered(&mut self, def: &ObjectDef) -> Result<(), DriveError> {
        let why = match self.state() {
            Ok(state) if !state.is_powered() => return Ok(()),
            Ok(state) => format!("the drive is in {state}"),
            Err(DriveError::NoRole { .. }) => {
                "the dictionary has no device-control profile, so whether the drive is powered cannot be checked".to_string()
            }
            Err(DriveError::Interrupted) => return Err(DriveError::Interrupted),
            Err(e) => format!("the drive's state could not be read ({e})"),
        };
        Err(DriveError::LineChangeRefused {
            object: def.name.clone(),
            why,
        })
    }

    /// Names the object in a drive's refusal (the link only knows the index).
    fn refusal(&self, e: AccessError, operation: &'static str, def: &ObjectDef) -> DriveError {
        match e {
            AccessError::Refused { port, code, text, .. } => DriveError::Refused {
                port,
                operation,
                object: def.name.clone(),
                code,
                text,
            },
            other => DriveError::Access(other),
        }
    }

    /// The drive's own minimum and maximum of an object, read from the drive and shown
    /// with the object's type, scale and unit (`None` on a side the drive says has no
    /// limit); `None` when the family cannot ask its drives for limits.
    pub fn limits(&mut self, name: &str) -> Option<Result<ValueLimits, DriveError>> {
        let def = match self.object(name) {
            Ok(d) => d.clone(),
            Err(e) => return Some(Err(e)),
        };
        let limits = match self.access.limits(&def.address, def.data_type)? {
            Ok(l) => l,
            Err(e) => return Some(Err(self.refusal(e, "to read the limits of", &def))),
        };
        let value = |raw: Option<RawValue>| -> Result<Option<Value>, DriveError> {
            raw.map(|r| def.value_of(r))
                .transpose()
                .map_err(|source| DriveError::BadReply {
                    object: def.name.clone(),
                    source,
                })
        };
        Some(value(limits.min).and_then(|min| Ok((min, value(limits.max)?))))
    }

    /// Writes what `command` writes in the profile: first the profile's writes before
    /// every command (a control-word enable), then the control-word value, or the value of
    /// another object for a command that has one. A fault reset on the control word needs
    /// a rising edge of bit 7, so the bit is cleared first.
    pub fn command(&mut self, command: DeviceCommand) -> Result<(), DriveError> {
        let profile = self.profile()?;
        let write = profile
            .command(command)
            .cloned()
            .ok_or_else(|| DriveError::NoCommand {
                dictionary: self.dictionary.name().to_string(),
                command,
                has: profile.command_ids().join(", "),
            })?;
        let before = profile.before_commands().to_vec();
        for w in &before {
            let def = self.object(&w.object)?.clone();
            self.write_raw(&def, &RawValue::Int(i64::from(w.value)))?;
        }
        let value = write.value;
        match &write.object {
            Some(name) => {
                let def = self.object(name)?.clone();
                self.write_raw(&def, &RawValue::Int(i64::from(value)))?;
            }
            None => {
                let control = self.role_object(Role::ControlWord)?;
                if command == DeviceCommand::FaultReset {
                    self.write_raw(&control, &RawValue::Int(i64::from(value & !0x80)))?;
                }
                self.write_raw(&control, &RawValue::Int(i64::from(value)))?;
            }
        }
        Ok(())
    }

    pub fn status_word(&mut self) -> Result<u16, DriveError> {
        let status = self.role_object(Role::StatusWord)?;
        let v = self.read_def(&status)?;
        Ok(v.raw.as_int().unwrap_or(0) as u16)
    }

    /// The state the status word shows.
    pub fn state(&mut self) -> Result<DeviceState, DriveError> {
        let status = self.status_word()?;
        self.state_of(status)
    }

    fn state_of(&self, status: u16) -> Result<DeviceState, DriveError> {
        self.profile()?
            .state_of(status)
            .ok_or(DriveError::UnknownStatus { status })
    }

    /// The state the status word shows, taken from a sample's read of it when that reply
    /// came within `age` (the value of its own request, only younger than the fault watch
    /// asks for), else read now: a sample that reads the status word spares the fault
    /// watch a telegram of its own.
    pub fn state_within(&mut self, age: Duration) -> Result<DeviceState, DriveError> {
        let fresh = self.clock.now().saturating_sub(age);
        match self.status_read {
            Some((status, at)) if at >= fresh => self.state_of(status),
            _ => self.state(),
        }
    }

    /// The drive's error code, when the profile has one and it can be read (best effort:
    /// this is called while explaining another failure).
    pub fn drive_error(&mut self) -> Option<u16> {
        let def = self.role_object(Role::DriveError).ok()?;
        let v = self.read_def(&def).ok()?;
        v.raw.as_int().map(|c| c as u16)
    }

    /// What the link did on its own that the console should say (see
    /// `ObjectAccess::notices`).
    pub fn notices(&mut self) -> Vec<String> {
        self.access.notices()
    }

    /// Hands the drive back as found after the run (see `ObjectAccess::release`).
    pub fn release(&mut self) -> Option<String> {
        self.access.release()
    }

    /// Keeps what the link changed after a stop that was not verified, and says so (see
    /// `ObjectAccess::withhold_release`).
    pub fn withhold_release(&mut self) -> Option<String> {
        self.access.withhold_release()
    }

    /// A fault the drive reported on its own since the last look (see
    /// `ObjectAccess::reported_fault`).
    pub fn reported_fault(&mut self) -> Option<String> {
        self.access.reported_fault()
    }

    /// ` (drive error 12816, 0x3210 DC link over-voltage)`: the drive's error code for a
    /// message, with its meaning where the family knows it; empty for 0.
    pub fn drive_error_note(&self, code: u16) -> String {
        match (code, self.access.error_code_text(code)) {
            (0, _) => String::new(),
            (c, Some(text)) => format!(" (drive error {c}, 0x{c:04x} {text})"),
            (c, None) => format!(" (drive error {c}, 0x{c:04x})"),
        }
    }

    /// Walks the state machine to `target`, one transition at a time, each within
    /// `timeout`. A drive in fault is not reset here: that is an explicit `fault_reset`.
    /// `cancelled` is asked between polls; when it says yes the walk stops.
    pub fn go_to(
        &mut self,
        target: DeviceState,
        timeout: Duration,
        cancelled: &dyn Fn() -> bool,
    ) -> Result<Vec<Transition>, DriveError> {
        let mut done = Vec::new();
        let profile = self.profile()?;
        if !profile.has_state(target) {
            return Err(DriveError::NoState {
                dictionary: self.dictionary.name().to_string(),
                state: target,
                has: profile.state_ids().join(", "),
            });
        }
        let mut state = self.state()?;
        loop {
            if matches!(state, DeviceState::Fault) && target != DeviceState::Fault {
                return Err(DriveError::Fault {
                    state,
                    drive_error: self.drive_error(),
                });
            }
            let command = match next_step_in(self.profile()?, state, target) {
                NextStep::Arrived => return Ok(done),
                NextStep::Unreachable => {
                    return Err(DriveError::Unreachable {
                        from: state,
                        to: target,
                    })
                }
                NextStep::Wait => None,
                NextStep::Command(c) => Some(c),
            };
            let started = self.clock.now();
            if let Some(c) = command {
                self.command(c)?;
            }
            let from = state;
            loop {
                if cancelled() {
                    return Err(DriveError::Interrupted);
                }
                state = self.state()?;
                if state != from {
                    break;
                }
                let waited = self.clock.now() - started;
                if waited >= timeout {
                    let drive_error = self.drive_error();
                    let hint = match command {
                        Some(c) => format!("the drive did not accept {c}; check that its control channel is the serial interface and that no other master holds it"),
                        None => "the drive did not leave this state by itself".into(),
                    };
                    return Err(DriveError::StateTimeout {
                        target,
                        stuck_in: from,
                        waited,
                        drive_error,
                        hint,
                    });
                }
                self.clock.sleep(STATE_POLL);
            }
            if let Some(c) = command {
                done.push(Transition {
                    command: c,
                    from,
                    to: state,
                    after: self.clock.now() - started,
                });
            }
        }
    }
}

/// The object definition for a name or alias, or the refusal with suggestions.
fn lookup<'d>(dictionary: &'d Dictionary, name: &str) -> Result<&'d ObjectDef, DriveError> {
    dictionary.lookup(name).map_err(|e| DriveError::UnknownObject {
        name: name.to_string(),
        suggestions: e.suggestions.clone(),
        drive: Some(e.dictionary.clone()),
    })
}

/// The engineering quantity of a value read from `def`; text is an error.
fn quantity_of(def: &ObjectDef, value: &Value) -> Result<Quantity, DriveError> {
    value.quantity.ok_or_else(|| DriveError::NotANumber {
        object: def.name.clone(),
        data_type: def.data_type,
    })
}
