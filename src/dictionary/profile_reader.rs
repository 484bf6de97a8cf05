//! Reads the `profile:` of a dictionary file into a [`Profile`]: role bindings, the writes
//! before every command, each command's control-word write and each state's status-word
//! mask. Part of [`DictionaryReader`]; it must not read object entries, check that the
//! roles name real objects (the validator's job) or do I/O.

use super::profile::{
    command_in, stops_keeping_power, CommandWrite, ObjectWrite, Profile, RoleBinding, StateMask, STOPS,
};
use super::reader::DictionaryReader;
use super::role::Role;
use crate::diag::{Diagnostic, Shape, YamlNode};
use crate::drive::device_control::{DeviceCommand, DeviceState};

/// One pattern per state (`None`: the drive does not show it) and the further patterns of
/// states given with `values:`.
type StateTable = ([Option<StateMask>; 8], Vec<(DeviceState, StateMask)>);

const STATE_KEYS: &[&str] = &["mask", "value", "values"];
const WRITE_KEYS: &[&str] = &["object", "value"];
/// Commands the safe stop sends, so no profile may leave them out.
const REQUIRED_COMMANDS: [DeviceCommand; 3] = [
    DeviceCommand::DisableOperation,
    DeviceCommand::Shutdown,
    DeviceCommand::DisableVoltage,
];
/// States the run (faults) and the safe stop (still enabled?) look for.
const REQUIRED_STATES: [DeviceState; 2] = [DeviceState::OperationEnabled, DeviceState::Fault];

impl DictionaryReader<'_> {
    pub(super) fn profile(&mut self, node: &YamlNode) -> Option<Profile> {
        let before = self.r.count();
        let mut allowed: Vec<&str> = Role::ALL.iter().map(|r| r.id()).collect();
        allowed.extend(["commands", "states", "before_commands", "control"]);
        let mut shape = Shape::new("the profile", &allowed).nothing_is_absent();
        for role in Role::ALL.into_iter().filter(|r| r.required()) {
            shape = shape.require_as(role.id(), format!("the name of the object that is the {role}"));
        }
        let shape = shape
            .require_as("commands", "the control-word value of each command")
            .require_as("states", "the status-word mask and value of each state");
        let f = self.r.fields(node, &shape)?;
        let mut roles = Vec::new();
        for role in Role::ALL {
            if let Some(v) = f.get(role.id()) {
                if let Some(object) = self.r.text(v, &format!("`{}`", role.id())) {
                    roles.push(RoleBinding {
                        role,
                        object,
                        span: v.span.clone(),
                    });
                }
            }
        }
        let before_commands = match f.get("before_commands") {
            Some(n) => self.before_commands(n),
            None => Some(Vec::new()),
        };
        let command_codes = match f.get("control") {
            None => false,
            Some(n) => match &n.value {
                crate::diag::YamlValue::Str(s) if s == "codes" => true,
                crate::diag::YamlValue::Str(s) if s == "bits" => false,
                _ => {
                    self.push(
                        Diagnostic::at(&n.span, "`control` is `bits` or `codes`", "unknown")
                            .with_help("`codes` when the control word takes whole command codes (an inverter's run command register), `bits` (the default) for a CiA 402 control word"),
                    );
                    return None;
                }
            },
        };
        let commands = f.get("commands").and_then(|n| self.commands(n, command_codes));
        let states = f.get("states").and_then(|n| self.states(n));
        let (Some(commands), Some((states, more_states)), Some(before_commands)) =
            (commands, states, before_commands)
        else {
            return None;
        };
        (self.r.count() == before).then(|| Profile {
            roles,
            commands,
            states,
            before_commands,
            more_states,
            span: node.span.clone(),
        })
    }

    /// `before_commands: [{ object: NAME, value: N }, …]`.
    fn before_commands(&mut self, node: &YamlNode) -> Option<Vec<ObjectWrite>> {
        let wanted = "a list of writes, e.g. `[{ object: control_word_enable, value: 1 }]`";
        let items = self.r.list(node, "`before_commands`", wanted)?;
        let mut writes = Vec::new();
        let mut complete = true;
        for item in items {
            match self.object_write(item, "a write before every command") {
                Some((object, value)) => writes.push(ObjectWrite {
                    object,
                    value,
                    span: item.span.clone(),
                }),
                None => complete = false,
            }
        }
        complete.then_some(writes)
    }

    /// `{ object: NAME, value: N }`.
    fn object_write(&mut self, node: &YamlNode, what: &str) -> Option<(String, u16)> {
        let shape = Shape::new(what, WRITE_KEYS)
            .require_as("object", "the name of the object to write")
            .require_as("value", "the value to write (0..=65535)")
            .nothing_is_absent();
        let f = self.r.fields(node, &shape)?;
        let object = f.get("object").and_then(|n| self.r.text(n, "`object`"));
        let value = f
            .get("value")
            .and_then(|n| self.r.int(n, "`value`", 0, u16::MAX.into()));
        Some((object?, u16::try_from(value?).ok()?))
    }

    /// `none`: the drive has no such command or state.
    fn is_none(node: &YamlNode) -> bool {
        matches!(&node.value, crate::diag::YamlValue::Str(s) if s == "none")
    }

    fn commands(&mut self, node: &YamlNode, codes: bool) -> Option<[Option<CommandWrite>; 7]> {
        let allowed: Vec<&str> = DeviceCommand::ALL.iter().map(|c| c.id()).collect();
        let mut shape = Shape::new("the commands", &allowed).nothing_is_absent();
        for command in DeviceCommand::ALL {
            let meaning = format!(
                "its control-word value (the CiA 402 profile's is {}), `{{ object: NAME, value: N }}`, or `none` when the drive has no such command",
                command.default_control_word()
            );
            shape = shape.require_as(command.id(), meaning);
        }
        let f = self.r.fields(node, &shape)?;
        let mut writes: [Option<CommandWrite>; 7] = Default::default();
        let mut nodes: [Option<&YamlNode>; 7] = [None; 7];
        let mut complete = true;
        for (i, command) in DeviceCommand::ALL.into_iter().enumerate() {
            let Some(n) = f.get(command.id()) else {
                complete = false;
                continue;
            };
            nodes[i] = Some(n);
            if Self::is_none(n) {
                if REQUIRED_COMMANDS.contains(&command) {
                    self.push(
                        Diagnostic::at(
                            &n.span,
                            format!("`{}` cannot be `none`: the safe stop needs it", command.id()),
                            "required",
                        )
                        .with_help(format!(
                            "every profile has {}; give the control-word value that stops the drive this way",
                            REQUIRED_COMMANDS.map(DeviceCommand::id).join(", ")
                        )),
                    );
                    complete = false;
                }
                continue;
            }
            if let crate::diag::YamlValue::Map(_) = n.value {
                if STOPS.iter().any(|(stop, _)| *stop == command) {
                    self.push(
                        Diagnostic::at(
                            &n.span,
                            format!("`{}` must write the control word", command.id()),
                            "a stop command",
                        )
                        .with_help("a stop command is checked against the control-word bits it clears; give its control-word value"),
                    );
                    complete = false;
                    continue;
                }
                match self.object_write(n, "a command writing another object") {
                    Some((object, value)) => {
                        writes[i] = Some(CommandWrite {
                            object: Some(object),
                            value,
                            span: n.span.clone(),
                        })
                    }
                    None => complete = false,
                }
                continue;
            }
            match self.r.int(n, &format!("`{}`", command.id()), 0, u16::MAX.into()) {
                Some(v) => {
                    writes[i] = Some(CommandWrite {
                        object: None,
                        value: v as u16,
                        span: n.span.clone(),
                    })
                }
                None => complete = false,
            }
        }
        if !complete {
            return None;
        }
        // The checks look at control-word values only; a command the drive lacks, or one
        // writing another object, takes no part (0 is left out by the rule).
        let values: [u16; 7] = std::array::from_fn(|i| match &writes[i] {
            Some(CommandWrite {
                object: None, value, ..
            }) => *value,
            _ => 0,
        });
        let node_of = |c: DeviceCommand| nodes[DeviceCommand::ALL.iter().position(|x| *x == c).unwrap_or(0)];
        let before = self.r.count();
        if codes {
            self.stop_codes(&values, &node_of);
            return (self.r.count() == before).then_some(writes);
        }
        for kept in [DeviceCommand::EnableOperation, DeviceCommand::SwitchOn] {
            let i = DeviceCommand::ALL.iter().position(|x| *x == kept).unwrap_or(0);
            let is_control_word = matches!(&writes[i], Some(CommandWrite { object: None, .. }));
            if let (0, Some(node), true) = (command_in(&values, kept), node_of(kept), is_control_word) {
                self.push(
                    Diagnostic::at(
                        &node.span,
                        format!(
                            "`{}` is 0: it sets no control-word bit, so no stop command could undo it",
                            kept.id()
                        ),
                        "sets no bit",
                    )
                    .with_help(format!(
                        "the CiA 402 profile's {} is {}",
                        kept.id(),
                        kept.default_control_word()
                    )),
                );
            }
        }
        for (stop, kept) in stops_keeping_power(&values) {
            let (Some(node), Some(kept_node)) = (node_of(stop), node_of(kept)) else {
                continue;
            };
            let (v, k) = (command_in(&values, stop), command_in(&values, kept));
            let state = if kept == DeviceCommand::EnableOperation {
                "enabled"
            } else {
                "switched on"
            };
            self.push(
                Diagnostic::at(
                    &node.span,
                    format!(
                        "`{}` {v} (0x{v:04X}) keeps every bit of `{}` {k} (0x{k:04X}): this stop command would leave the drive {state}",
                        stop.id(),
                        kept.id()
                    ),
                    "keeps the drive running",
                )
                .also_at(&kept_node.span, kept.id())
                .with_optional_help(Some(format!(
                    "a stop command must clear at least one bit of `{}`; the CiA 402 profile's {} is {}",
                    kept.id(),
                    stop.id(),
                    stop.default_control_word()
                ))),
            );
        }
        (self.r.count() == before).then_some(writes)
    }

    /// With command codes a stop is a code of its own: it must not be the run code.
    fn stop_codes<'n>(&mut self, values: &[u16; 7], node_of: &dyn Fn(DeviceCommand) -> Option<&'n YamlNode>) {
        let run = command_in(values, DeviceCommand::EnableOperation);
        for (stop, _) in STOPS {
            let (Some(node), true) = (node_of(stop), command_in(values, stop) == run) else {
                continue;
            };
            if run == 0 {
                continue;
            }
            self.push(
                Diagnostic::at(
                    &node.span,
                    format!(
                        "`{}` is the run code {run} of `enable_operation`: it would keep the drive running",
                        stop.id()
                    ),
                    "the run code",
                )
                .with_help("give the inverter's stop command code"),
            );
        }
    }

    fn states(&mut self, node: &YamlNode) -> Option<StateTable> {
        let allowed: Vec<&str> = DeviceState::ALL.iter().map(|s| s.id()).collect();
        let mut shape = Shape::new("the states", &allowed).nothing_is_absent();
        for state in DeviceState::ALL {
            let (m, v) = state.default_mask_value();
            shape = shape.require_as(
                state.id(),
                format!("its mask and value, e.g. `{{ mask: 0x{m:02X}, value: 0x{v:02X} }}`, or `none` when the drive does not show it"),
            );
        }
        let f = self.r.fields(node, &shape)?;
        let mut masks: [Option<StateMask>; 8] = [None; 8];
        let mut read: Vec<(DeviceState, StateMask, &YamlNode)> = Vec::new();
        let mut complete = true;
        for (i, state) in DeviceState::ALL.into_iter().enumerate() {
            let Some(n) = f.get(state.id()) else {
                complete = false;
                continue;
            };
            if Self::is_none(n) {
                if REQUIRED_STATES.contains(&state) {
                    self.push(
                        Diagnostic::at(
                            &n.span,
                            format!(
                                "`{}` cannot be `none`: the run and the safe stop watch for it",
                                state.id()
                            ),
                            "required",
                        )
                        .with_help(
                            "every profile shows operation_enabled and fault; give their mask and value",
                        ),
                    );
                    complete = false;
                }
                continue;
            }
            match self.state(n, state) {
                Some(patterns) => {
                    masks[i] = patterns.first().copied();
                    for sm in patterns {
                        read.push((state, sm, n));
                    }
                }
                None => complete = false,
            }
        }
        if complete
            && !read
                .iter()
                .any(|(s, _, _)| !s.is_powered() && *s != DeviceState::Fault)
        {
            self.push(
                Diagnostic::at(&node.span, "the states have no state where the drive is stopped", "no stopped state")
                    .with_help("give at least one of switch_on_disabled, ready_to_switch_on and switched_on, so a stop can be confirmed"),
            );
            complete = false;
        }
        for (j, (state, sm, node)) in read.iter().enumerate() {
            for (earlier, esm, enode) in &read[..j] {
                if earlier == state {
                    continue;
                }
                if let Some(word) = sm.overlap(*esm) {
                    self.push(
                        Diagnostic::at(
                            &node.span,
                            format!(
                                "states `{earlier}` and `{state}` overlap: status word 0x{word:04X} matches both",
                                earlier = earlier.id(),
                                state = state.id()
                            ),
                            "overlaps",
                        )
                        .also_at(&enode.span, "this state")
                        .with_optional_help(Some(
                            "two states must differ in a bit that both masks include".into(),
                        )),
                    );
                    complete = false;
                }
            }
        }
        let more = read
            .iter()
            .filter(|(s, sm, _)| {
                masks[DeviceState::ALL.iter().position(|x| x == s).unwrap_or(0)] != Some(*sm)
            })
            .map(|(s, sm, _)| (*s, *sm))
            .collect();
        complete.then_some((masks, more))
    }

    /// `{ mask, value }`, or `{ mask, values: [..] }` for a state several values show.
    fn state(&mut self, node: &YamlNode, state: DeviceState) -> Option<Vec<StateMask>> {
        if let crate::diag::YamlValue::Map(entries) = &node.value {
            if let Some((_, list)) = entries.iter().find(|(k, _)| k.value == "values") {
                let mask_node = entries.iter().find(|(k, _)| k.value == "mask").map(|(_, n)| n);
                let Some(mask_node) = mask_node else {
                    self.push(Diagnostic::at(
                        &node.span,
                        format!("`{}` has `values` but no `mask`", state.id()),
                        "no mask",
                    ));
                    return None;
                };
                let items = self
                    .r
                    .list(list, "`values`", "a list of status values, e.g. `[0x01, 0x11]`")?;
                let mut patterns = Vec::new();
                for item in items {
                    let mut single = node.clone();
                    single.value = crate::diag::YamlValue::Map(vec![
                        (
                            crate::diag::Spanned {
                                value: "mask".into(),
                                span: mask_node.span.clone(),
                            },
                            mask_node.clone(),
                        ),
                        (
                            crate::diag::Spanned {
                                value: "value".into(),
                                span: item.span.clone(),
                            },
                            item.clone(),
                        ),
                    ]);
                    patterns.push(self.single_state(&single, state)?);
                }
                if patterns.is_empty() {
                    self.push(Diagnostic::at(
                        &list.span,
                        format!("`{}` has no values", state.id()),
                        "empty",
                    ));
                    return None;
                }
                return Some(patterns);
            }
        }
        self.single_state(node, state).map(|sm| vec![sm])
    }

    fn single_state(&mut self, node: &YamlNode, state: DeviceState) -> Option<StateMask> {
        let shape = Shape::new("a state", STATE_KEYS)
            .require_as("mask", "the status-word bits this state looks at")
            .require_as("value", "the value of those bits in this state")
            .nothing_is_absent();
        let f = self.r.fields(node, &shape)?;
        let mask_node = f.get("mask");
        let value_node = f.get("value");
        let mask = mask_node.and_then(|n| self.r.int(n, "`mask`", 0, u16::MAX.into()));
        let value = value_node.and_then(|n| self.r.int(n, "`value`", 0, u16::MAX.into()));
        let (Some(mask_node), Some(value_node), Some(mask), Some(value)) =
            (mask_node, value_node, mask, value)
        else {
            return None;
        };
        let (mask, value) = (mask as u16, value as u16);
        if mask == 0 {
            self.push(
                Diagnostic::at(
                    &mask_node.span,
                    format!(
                        "the mask of `{}` is 0, so every status word would match it",
                        state.id()
                    ),
                    "mask 0",
                )
                .with_help("the mask selects the status-word bits that identify the state, e.g. 0x6F"),
            );
            return None;
        }
        if value & !mask != 0 {
            self.push(
                Diagnostic::at(
                    &value_node.span,
                    format!(
                        "value 0x{value:02X} of `{}` has bits outside its mask 0x{mask:02X} (0x{:02X}), so no status word can match",
                        state.id(),
                        value & !mask
                    ),
                    "bits outside the mask",
                )
                .also_at(&mask_node.span, "mask"),
            );
            return None;
        }
        Some(StateMask { mask, value })
    }
}
