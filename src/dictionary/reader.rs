//! Reads a parsed dictionary file (a YAML tree) into objects and a profile, checking
//! everything one entry can tell on its own: known keys, types, units, access, scale,
//! limits against the type's range, the profile's commands and state table. Every problem
//! is recorded with its place; reading goes on so a file reports them all. Cross-entry
//! checks (duplicate names, profile roles) are the validator's. Keys and values are read
//! with `diag::Reader`, the field reader of every loader. No I/O.

use super::access::Access;
use super::address::{Address, AddressParser};
use super::data_type::DataType;
use super::family_id::{family_id, is_family_id, is_former_spelling};
use super::format::Format;
use super::object_def::ObjectDef;
use super::profile::{
    command_in, stops_keeping_power, CommandWrite, ObjectWrite, Profile, RoleBinding, StateMask, STOPS,
};
use super::role::Role;
use super::unit::Unit;
use crate::diag::{
    did_you_mean, suggestion_text, Diagnostic, Diagnostics, Fields, Reader, Shape, Span, YamlNode,
};
use crate::drive::device_control::{DeviceCommand, DeviceState};

/// What one file holds, as far as it could be read.
pub(crate) struct FileContents {
    pub family: String,
    pub family_span: Span,
    pub title: String,
    pub objects: Vec<ObjectDef>,
    pub profile: Option<Profile>,
    /// Objects left out because they had problems: their names still take part in the
    /// duplicate check, and a profile naming one gets no second, misleading error.
    pub broken: Vec<BrokenObject>,
    /// What works but should be written otherwise (a family id's former spelling).
    pub notes: Vec<Diagnostic>,
}

/// The names (name first, then aliases) and their places of an object with problems.
pub(crate) struct BrokenObject {
    pub names: Vec<(String, Span)>,
}

const TOP_KEYS: &[&str] = &["family", "title", "objects", "profile"];
const OBJECT_KEYS: &[&str] = &[
    "name",
    "aliases",
    "index",
    "subindex",
    "address",
    "type",
    "unit",
    "scale",
    "decimals",
    "access",
    "min",
    "max",
    "format",
    "description",
    "unconfirmed",
    "parameter",
];
const STATE_KEYS: &[&str] = &["mask", "value"];
const WRITE_KEYS: &[&str] = &["object", "value"];
/// Commands the safe stop sends, so no profile may leave them out.
const REQUIRED_COMMANDS: [DeviceCommand; 3] = [
    DeviceCommand::DisableOperation,
    DeviceCommand::Shutdown,
    DeviceCommand::DisableVoltage,
];
/// States the run (faults) and the safe stop (still enabled?) look for.
const REQUIRED_STATES: [DeviceState; 2] = [DeviceState::OperationEnabled, DeviceState::Fault];
const FINITE_HELP: &str = "write a number such as `60000` or `0.001`";

/// Reads `root`, recording every problem in `out`; `address:` texts are read with the
/// family's `parse_address`.
pub(crate) fn read(
    root: &YamlNode,
    out: &mut Diagnostics,
    parse_address: Option<AddressParser>,
) -> FileContents {
    DictionaryReader {
        r: Reader::new(out),
        parse_address,
    }
    .document(root)
}

struct DictionaryReader<'d> {
    r: Reader<'d>,
    parse_address: Option<AddressParser>,
}

impl DictionaryReader<'_> {
    fn push(&mut self, d: Diagnostic) {
        self.r.report(d);
    }

    fn document(&mut self, root: &YamlNode) -> FileContents {
        let mut contents = FileContents {
            family: String::new(),
            family_span: root.span.clone(),
            title: String::new(),
            objects: Vec::new(),
            profile: None,
            broken: Vec::new(),
            notes: Vec::new(),
        };
        let shape = Shape::new("the dictionary", TOP_KEYS)
            .require_as("family", "the drive family, the protocol it speaks")
            .require_as("objects", "a list of objects, each starting `- name:`")
            .nothing_is_absent();
        let Some(f) = self.r.fields(root, &shape) else {
            return contents;
        };
        if let Some(node) = f.get("family") {
            if let Some(family) = self.family(node, &mut contents.notes) {
                contents.family = family;
                contents.family_span = node.span.clone();
            }
        }
        if let Some(node) = f.get("title") {
            contents.title = self.r.text(node, "`title`").unwrap_or_default();
        }
        if let Some(node) = f.get("objects") {
            let wanted = "a list of objects (lines starting `- name:`)";
            for item in self.r.list(node, "`objects`", wanted).unwrap_or_default() {
                match self.object(item) {
                    Ok(o) => contents.objects.push(o),
                    Err(broken) => contents.broken.push(broken),
                }
            }
        }
        if let Some(node) = f.get("profile") {
            contents.profile = self.profile(node);
        }
        contents
    }

    /// Text of the form `[a-z][a-z0-9_]*`; a family id may also use `-` (`lenze-931`).
    /// The family id `family:` names. The former spelling (`ct_ansi`) is read as the id
    /// (`ct-ansi`) with a note saying what to write, so files in the field keep working.
    fn family(&mut self, node: &YamlNode, notes: &mut Vec<Diagnostic>) -> Option<String> {
        let written = self.r.text(node, "`family`")?;
        let id = family_id(&written);
        if !is_family_id(&id) {
            self.push(
                Diagnostic::at(
                    &node.span,
                    format!("`{written}` is not a family id"),
                    "not a family id",
                )
                .with_help("a family id is lower-case letters and digits joined by `-`, e.g. `ct-ansi`"),
            );
            return None;
        }
        if is_former_spelling(&written) {
            notes.push(
                Diagnostic::at(
                    &node.span,
                    format!(
                        "`family: {written}` is the former spelling of the family id `{id}`; it still works"
                    ),
                    "former spelling",
                )
                .with_help(format!("write `family: {id}`")),
            );
        }
        Some(id)
    }

    fn identifier(&mut self, node: &YamlNode, what: &str) -> Option<String> {
        let s = self.r.text(node, &format!("`{what}`"))?;
        if is_identifier(&s) {
            Some(s)
        } else {
            self.push(
                Diagnostic::at(
                    &node.span,
                    format!("`{s}` is not a valid {what}"),
                    "not an identifier",
                )
                .with_help(
                    "use lower-case letters, digits and `_`, starting with a letter, e.g. `speed_setpoint`",
                ),
            );
            None
        }
    }

    fn number(&mut self, node: &YamlNode, what: &str) -> Option<f64> {
        self.r.number(node, &format!("`{what}`"), FINITE_HELP)
    }

    /// Where the object is: `index` and `subindex`. Kept apart because each drive family
    /// will write addresses its own way.
    fn address(&mut self, f: &Fields) -> Option<Address> {
        if let Some(node) = f.get("address") {
            let text = self.r.scalar_text(node, "`address`")?;
            let Some(parse) = self.parse_address else {
                self.push(
                    Diagnostic::at(
                        &node.span,
                        "this dictionary's family has no address notation here",
                        "not readable",
                    )
                    .with_help("write `index:` (and `subindex:`) instead"),
                );
                return None;
            };
            return match parse(&text) {
                Ok(address) => Some(address),
                Err(why) => {
                    self.push(Diagnostic::at(
                        &node.span,
                        format!("address `{text}`: {why}"),
                        "not an address",
                    ));
                    None
                }
            };
        }
        if f.get("index").is_none() {
            // A key written with nothing after it is pointed at; otherwise the object.
            let at = f
                .entries()
                .iter()
                .find(|(k, _)| k.value == "index")
                .map_or(f.span(), |(k, _)| &k.span);
            self.push(
                Diagnostic::at(at, "an object has no `index` (or `address`)", "where is it?").with_help(
                    "write the object's 16-bit index, e.g. `index: 395` or `index: 0x18B` (and `subindex:`), or `address:` in the family's notation",
                ),
            );
            return None;
        }
        let index = f
            .get("index")
            .and_then(|n| self.r.int(n, "`index`", 0, u16::MAX.into()));
        let subindex = match f.get("subindex") {
            Some(n) => self.r.int(n, "`subindex`", 0, u32::MAX.into()),
            None => Some(0),
        };
        Some(Address::Indexed {
            index: u16::try_from(index?).ok()?,
            subindex: u32::try_from(subindex?).ok()?,
        })
    }

    /// One `- name: …` entry; its names when it has problems.
    fn object(&mut self, node: &YamlNode) -> Result<ObjectDef, BrokenObject> {
        let before = self.r.count();
        let shape = Shape::new("an object", OBJECT_KEYS)
            .require_as("name", "the identifier recipes use, e.g. `speed_setpoint`")
            .require_as("type", "one of u8 i8 u16 i16 u32 i32 string(N)")
            .require_as("access", "ro (read-only), rw (read-write) or wo (write-only)")
            .nothing_is_absent();
        let f = self
            .r
            .fields(node, &shape)
            .ok_or(BrokenObject { names: Vec::new() })?;
        let name_node = f.get("name");
        let name = name_node.and_then(|n| self.identifier(n, "object name"));
        let mut name_spans: Vec<Span> = name_node.map(|n| n.span.clone()).into_iter().collect();
        let mut names: Vec<(String, Span)> = match name_node {
            Some(YamlNode {
                value: crate::diag::YamlValue::Str(s),
                span,
            }) => vec![(s.clone(), span.clone())],
            _ => Vec::new(),
        };

        let mut aliases = Vec::new();
        if let Some(node) = f.get("aliases") {
            let wanted = "a list, e.g. `[target_speed, SPG_TARGET_VELOCITY_VL_UUNIT]`";
            for item in self.r.list(node, "`aliases`", wanted).unwrap_or_default() {
                let Some(alias) = self.r.text(item, "`alias`") else {
                    continue;
                };
                if is_alias(&alias) {
                    names.push((alias.clone(), item.span.clone()));
                    aliases.push(alias);
                    name_spans.push(item.span.clone());
                } else {
                    self.push(
                        Diagnostic::at(&item.span, format!("`{alias}` is not a valid alias"), "not a name")
                            .with_help("aliases are letters, digits and `_`, starting with a letter, e.g. `SPG_TARGET_VELOCITY_VL_UUNIT`"),
                    );
                }
            }
        }

        let address = self.address(&f);
        let data_type = f.get("type").and_then(|n| self.data_type(n));
        let access = f.get("access").and_then(|n| self.access(n));
        let unit = f.get("unit").map(|n| self.unit(n));
        let decimals = f.get("decimals").and_then(|n| self.decimals(n, &f));
        let scale = match (f.get("scale"), decimals) {
            (Some(n), _) => self.scale(n),
            (None, Some(places)) => Some(10f64.powi(-i32::from(places))),
            (None, None) => Some(1.0),
        };
        let min = f.get("min").map(|n| (n, self.number(n, "min")));
        let max = f.get("max").map(|n| (n, self.number(n, "max")));
        let format = f.get("format").and_then(|n| {
            let id = self.r.text(n, "`format`")?;
            let found = Format::from_id(&id);
            if found.is_none() {
                self.push(
                    Diagnostic::at(&n.span, format!("unknown format `{id}`"), "not a format").with_help(
                        "write `decimal` (the default) or `hex` (for bit fields such as status words)",
                    ),
                );
            }
            found
        });
        let description = f.get("description").and_then(|n| self.r.text(n, "`description`"));
        let unconfirmed = f.get("unconfirmed").and_then(|n| self.r.text(n, "`unconfirmed`"));
        let parameter = f.get("parameter").and_then(|n| self.r.bool(n, "`parameter`"));

        // Keys that make no sense for text.
        if let Some(DataType::String { .. }) = data_type {
            for key in ["unit", "scale", "decimals", "min", "max", "format"] {
                if let Some(k) = f.key(key) {
                    self.push(
                        Diagnostic::at(&k.span, format!("a string object has no `{key}`"), "not for text")
                            .with_help("units, scale, limits and formats apply to integer types only"),
                    );
                }
            }
        }

        // Limits are checked whenever the type and scale are known, whatever else is wrong.
        if let (Some(data_type), Some(scale)) = (data_type, scale) {
            if data_type.is_integer() {
                let mut shape = ObjectDef::new("", Address::indexed(0, 0), data_type, Access::ReadOnly);
                shape.scale = scale;
                shape.unit = unit.flatten();
                self.limits(&shape, min, max);
            }
        }

        let (Some(name), Some(address), Some(data_type), Some(access), Some(scale)) =
            (name, address, data_type, access, scale)
        else {
            return Err(BrokenObject { names });
        };
        let mut object = ObjectDef::new(name, address, data_type, access);
        object.aliases = aliases;
        object.unit = unit.flatten();
        object.scale = scale;
        object.decimal_places = decimals.map(super::object_def::DecimalPlaces::Fixed);
        object.format = format.unwrap_or_default();
        object.description = description.unwrap_or_default();
        object.unconfirmed = unconfirmed;
        object.parameter = parameter.unwrap_or(false);
        object.span = node.span.clone();
        object.name_spans = name_spans;
        object.min = min.and_then(|(_, v)| v);
        object.max = max.and_then(|(_, v)| v);
        if self.r.count() > before {
            return Err(BrokenObject { names });
        }
        Ok(object)
    }

    fn data_type(&mut self, node: &YamlNode) -> Option<DataType> {
        let text = self.r.text(node, "`type`")?;
        match DataType::parse(&text) {
            Ok(t) => Some(t),
            Err(message) => {
                let help = suggestion_text(&did_you_mean(&text, DataType::names()))
                    .unwrap_or_else(|| format!("the types are: {}", DataType::names().join(", ")));
                self.push(Diagnostic::at(&node.span, message, "not a type").with_help(help));
                None
            }
        }
    }

    fn access(&mut self, node: &YamlNode) -> Option<Access> {
        let text = self.r.text(node, "`access`")?;
        let found = Access::from_id(&text);
        if found.is_none() {
            self.push(
                Diagnostic::at(&node.span, format!("unknown access `{text}`"), "not an access")
                    .with_help("write ro (read-only), rw (read-write) or wo (write-only)"),
            );
        }
        found
    }

    /// `Some(None)` never: an unknown unit is an error (`None`).
    fn unit(&mut self, node: &YamlNode) -> Option<Unit> {
        let text = self.r.text(node, "`unit`")?;
        let found = Unit::from_symbol(&text);
        if found.is_none() {
            let known: Vec<&str> = Unit::symbols().collect();
            let mut help = format!(
                "the units are: {}; omit `unit` for raw counts and bit fields",
                known.join(", ")
            );
            if let Some(s) = suggestion_text(&did_you_mean(&text, Unit::symbols())) {
                help = format!("{s} ({help})");
            }
            self.push(
                Diagnostic::at(&node.span, format!("unknown unit `{text}`"), "not a unit").with_help(help),
            );
        }
        found
    }

    /// `decimals: N`: the drive sends the value as decimal text with N places (0..=10: the
    /// data field of a text protocol holds at most 12 characters with sign and point).
    /// It sets the scale, so `scale:` beside it is refused.
    fn decimals(&mut self, node: &YamlNode, f: &Fields) -> Option<u8> {
        let places = self.r.int(node, "`decimals`", 0, 10)?;
        if let Some(k) = f.key("scale") {
            self.push(
                Diagnostic::at(
                    &k.span,
                    "give `decimals` or `scale`, not both",
                    "scale and decimals",
                )
                .also_at(&node.span, "decimals")
                .with_help("`decimals: 1` already means 0.1 units per count; remove `scale`"),
            );
            return None;
        }
        u8::try_from(places).ok()
    }

    fn scale(&mut self, node: &YamlNode) -> Option<f64> {
        let scale = self.number(node, "scale")?;
        if scale > 0.0 {
            Some(scale)
        } else {
            self.push(
                Diagnostic::at(
                    &node.span,
                    format!("`scale` must be greater than 0, not {scale}"),
                    "not a scale",
                )
                .with_help("scale is engineering units per raw count, e.g. 0.001 for 0.001 rpm per count"),
            );
            None
        }
    }

    /// min ≤ max, and both inside the type's range once divided by the scale.
    fn limits(
        &mut self,
        object: &ObjectDef,
        min: Option<(&YamlNode, Option<f64>)>,
        max: Option<(&YamlNode, Option<f64>)>,
    ) {
        let Some((lo, hi)) = object.data_type.range() else {
            return;
        };
        for (what, limit) in [("min", min), ("max", max)] {
            let Some((node, Some(value))) = limit else {
                continue;
            };
            let counts = (value / object.scale).round();
            if counts < lo as f64 || counts > hi as f64 {
                let range = format!(
                    "{}..={}",
                    object.with_unit(object.engineering(lo)),
                    object.with_unit(object.engineering(hi))
                );
                self.push(
                    Diagnostic::at(
                        &node.span,
                        format!(
                            "`{what}` {} is {counts:.0} counts, outside the range of {}: {range}",
                            object.with_unit(value),
                            object.data_type
                        ),
                        "outside the type's range",
                    )
                    .with_help(format!(
                        "{what} is in engineering units ({}), the raw count is {what} / scale",
                        unit_or_counts(object)
                    )),
                );
            }
        }
        if let (Some((min_node, Some(lo))), Some((max_node, Some(hi)))) = (min, max) {
            if lo > hi {
                self.push(
                    Diagnostic::at(
                        &min_node.span,
                        format!(
                            "`min` {} is greater than `max` {}",
                            object.with_unit(lo),
                            object.with_unit(hi)
                        ),
                        "min",
                    )
                    .also_at(&max_node.span, "max")
                    .with_optional_help(Some("swap them, or correct the one that is wrong".into())),
                );
            }
        }
    }

    fn profile(&mut self, node: &YamlNode) -> Option<Profile> {
        let before = self.r.count();
        let mut allowed: Vec<&str> = Role::ALL.iter().map(|r| r.id()).collect();
        allowed.extend(["commands", "states", "before_commands"]);
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
        let commands = f.get("commands").and_then(|n| self.commands(n));
        let states = f.get("states").and_then(|n| self.states(n));
        let (Some(commands), Some(states), Some(before_commands)) = (commands, states, before_commands)
        else {
            return None;
        };
        (self.r.count() == before).then(|| Profile {
            roles,
            commands,
            states,
            before_commands,
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

    fn commands(&mut self, node: &YamlNode) -> Option<[Option<CommandWrite>; 7]> {
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

    fn states(&mut self, node: &YamlNode) -> Option<[Option<StateMask>; 8]> {
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
                Some(sm) => {
                    masks[i] = Some(sm);
                    read.push((state, sm, n));
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
        complete.then_some(masks)
    }

    fn state(&mut self, node: &YamlNode, state: DeviceState) -> Option<StateMask> {
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

fn unit_or_counts(object: &ObjectDef) -> String {
    match object.unit {
        Some(u) => u.symbol().to_string(),
        None => "no unit".into(),
    }
}

/// `[a-z][a-z0-9_]*`
pub(crate) fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

/// `[A-Za-z][A-Za-z0-9_]*`
fn is_alias(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}
