//! Reads a parsed dictionary file (a [`YamlNode`] tree) into objects and a profile,
//! checking everything one entry can tell on its own: known keys, types, units, access,
//! scale, limits against the type's range, the profile's commands and state table.
//! Every problem is recorded with its place; reading goes on so a file reports them all.
//! Cross-entry checks (duplicate names, profile roles) are the validator's. No I/O.
//! Its field helpers (known keys with did-you-mean, required keys, text) also read the
//! bench limits file, so both files speak with one voice.

use super::access::Access;
use super::address::Address;
use super::data_type::DataType;
use super::dictionary_error::DictionaryError;
use super::format::Format;
use super::object_def::ObjectDef;
use super::profile::{command_in, stops_keeping_power, Profile, RoleBinding, StateMask};
use super::role::Role;
use super::text_span::TextSpan;
use super::unit::Unit;
use super::yaml_node::{NodeKind, YamlNode};
use crate::diag::{did_you_mean, suggestion_text};
use crate::drive::device_control::{DeviceCommand, DeviceState};

/// What one file holds, as far as it could be read.
pub(crate) struct FileContents {
    pub family: String,
    pub family_span: TextSpan,
    pub title: String,
    pub objects: Vec<ObjectDef>,
    pub profile: Option<Profile>,
    /// Objects left out because they had problems: their names still take part in the
    /// duplicate check, and a profile naming one gets no second, misleading error.
    pub broken: Vec<BrokenObject>,
}

/// The names (name first, then aliases) and their places of an object with problems.
pub(crate) struct BrokenObject {
    pub names: Vec<(String, TextSpan)>,
}

const TOP_KEYS: &[&str] = &["family", "title", "objects", "profile"];
const OBJECT_KEYS: &[&str] = &[
    "name",
    "aliases",
    "index",
    "subindex",
    "type",
    "unit",
    "scale",
    "access",
    "min",
    "max",
    "format",
    "description",
    "unconfirmed",
];
const STATE_KEYS: &[&str] = &["mask", "value"];

/// Reads `root`, recording every problem in `errors`.
pub(crate) fn read(root: &YamlNode, errors: &mut Vec<DictionaryError>) -> FileContents {
    let mut r = Reader { errors };
    r.document(root)
}

pub(crate) struct Reader<'e> {
    errors: &'e mut Vec<DictionaryError>,
}

/// The entries of a mapping whose keys were all known.
pub(crate) struct Fields<'n> {
    node: &'n YamlNode,
    what: &'static str,
    entries: Vec<(&'n str, &'n YamlNode, &'n YamlNode)>,
}

impl<'n> Fields<'n> {
    /// The value of `key`, absent when missing or written as nothing (`key:` or `~`).
    pub(crate) fn get(&self, key: &str) -> Option<&'n YamlNode> {
        self.entries
            .iter()
            .find(|(k, _, v)| *k == key && !v.is_null())
            .map(|(_, _, v)| *v)
    }
}

impl<'e> Reader<'e> {
    /// A reader recording problems in `errors`.
    pub(crate) fn new(errors: &'e mut Vec<DictionaryError>) -> Self {
        Reader { errors }
    }

    pub(crate) fn push(&mut self, e: DictionaryError) {
        self.errors.push(e);
    }

    fn document(&mut self, root: &YamlNode) -> FileContents {
        let mut contents = FileContents {
            family: String::new(),
            family_span: root.span.clone(),
            title: String::new(),
            objects: Vec::new(),
            profile: None,
            broken: Vec::new(),
        };
        let Some(f) = self.fields(root, "the dictionary", TOP_KEYS) else {
            return contents;
        };
        if let Some(node) = self.required(&f, "family", "the protocol family, e.g. `family: sd2`") {
            if let Some(family) = self.identifier(node, "family") {
                contents.family = family;
                contents.family_span = node.span.clone();
            }
        }
        if let Some(node) = f.get("title") {
            contents.title = self.text(node, "title").unwrap_or_default();
        }
        if let Some(node) = self.required(&f, "objects", "a list of objects, each starting `- name:`") {
            match &node.kind {
                NodeKind::Seq(items) => {
                    for item in items {
                        match self.object(item) {
                            Ok(o) => contents.objects.push(o),
                            Err(broken) => contents.broken.push(broken),
                        }
                    }
                }
                _ => self.push(expected(
                    node,
                    "`objects`",
                    "a list of objects (lines starting `- name:`)",
                )),
            }
        }
        if let Some(node) = f.get("profile") {
            contents.profile = self.profile(node);
        }
        contents
    }

    /// The mapping's entries; unknown keys are reported (with suggestions) and left out.
    pub(crate) fn fields<'n>(
        &mut self,
        node: &'n YamlNode,
        what: &'static str,
        allowed: &[&str],
    ) -> Option<Fields<'n>> {
        let NodeKind::Map(entries) = &node.kind else {
            self.push(expected(node, what, "a mapping (`key: value` lines)"));
            return None;
        };
        let mut known = Vec::new();
        for (key, value) in entries {
            let NodeKind::Str(k) = &key.kind else { continue };
            if allowed.contains(&k.as_str()) {
                known.push((k.as_str(), key, value));
            } else {
                let help = suggestion_text(&did_you_mean(k, allowed.iter().copied()))
                    .unwrap_or_else(|| format!("the keys of {what} are: {}", allowed.join(", ")));
                self.push(
                    DictionaryError::at(&key.span, format!("unknown key `{k}` in {what}"), "unknown key")
                        .with_help(help),
                );
            }
        }
        Some(Fields {
            node,
            what,
            entries: known,
        })
    }

    /// The value of a required key; reports its absence at the start of the mapping.
    fn required<'n>(&mut self, f: &Fields<'n>, key: &str, meaning: &str) -> Option<&'n YamlNode> {
        let found = f.get(key);
        if found.is_none() {
            let place = f
                .entries
                .iter()
                .find(|(k, _, _)| *k == key)
                .map(|(_, k, _)| &k.span)
                .unwrap_or(&f.node.span);
            self.push(
                DictionaryError::at(
                    place,
                    format!("{} has no `{key}`", f.what),
                    format!("`{key}` missing"),
                )
                .with_help(format!("add `{key}:` with {meaning}")),
            );
        }
        found
    }

    fn text(&mut self, node: &YamlNode, what: &str) -> Option<String> {
        match &node.kind {
            NodeKind::Str(s) => Some(s.clone()),
            _ => {
                self.push(expected(node, &format!("`{what}`"), "text"));
                None
            }
        }
    }

    /// Text of the form `[a-z][a-z0-9_]*`.
    fn identifier(&mut self, node: &YamlNode, what: &str) -> Option<String> {
        let s = self.text(node, what)?;
        if is_identifier(&s) {
            Some(s)
        } else {
            self.push(
                DictionaryError::at(
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

    fn int(&mut self, node: &YamlNode, what: &str, lo: i128, hi: i128) -> Option<i128> {
        match node.kind {
            NodeKind::Int(i) if (lo..=hi).contains(&i) => Some(i),
            NodeKind::Int(i) => {
                self.push(DictionaryError::at(
                    &node.span,
                    format!("`{what}` {i} is out of range {lo}..={hi} (0x{lo:x}..=0x{hi:x})"),
                    "out of range",
                ));
                None
            }
            _ => {
                self.push(expected(
                    node,
                    &format!("`{what}`"),
                    "a whole number (decimal or 0x hex)",
                ));
                None
            }
        }
    }

    fn number(&mut self, node: &YamlNode, what: &str) -> Option<f64> {
        match &node.kind {
            NodeKind::Int(i) => Some(*i as f64),
            NodeKind::Float(f) if f.is_finite() => Some(*f),
            // YAML's `.nan`, `.inf` and numbers too large for a float (`1e400`), which the
            // parser hands over as text.
            NodeKind::Float(_) | NodeKind::Str(_) if node.is_non_finite_number() => {
                self.push(
                    DictionaryError::at(
                        &node.span,
                        format!("`{what}` must be a finite number, not `{}`", node.written()),
                        "not finite",
                    )
                    .with_help("write a number such as `60000` or `0.001`"),
                );
                None
            }
            _ => {
                self.push(expected(node, &format!("`{what}`"), "a number"));
                None
            }
        }
    }

    /// One `- name: …` entry; its names when it has problems.
    fn object(&mut self, node: &YamlNode) -> Result<ObjectDef, BrokenObject> {
        let before = self.errors.len();
        let f = self
            .fields(node, "an object", OBJECT_KEYS)
            .ok_or(BrokenObject { names: Vec::new() })?;
        let name_node = self.required(&f, "name", "the identifier recipes use, e.g. `speed_setpoint`");
        let name = name_node.and_then(|n| self.identifier(n, "object name"));
        let mut name_spans: Vec<TextSpan> = name_node.map(|n| n.span.clone()).into_iter().collect();
        let mut names: Vec<(String, TextSpan)> = match name_node.map(|n| (&n.kind, &n.span)) {
            Some((NodeKind::Str(s), span)) => vec![(s.clone(), span.clone())],
            _ => Vec::new(),
        };

        let mut aliases = Vec::new();
        if let Some(node) = f.get("aliases") {
            match &node.kind {
                NodeKind::Seq(items) => {
                    for item in items {
                        let Some(alias) = self.text(item, "alias") else {
                            continue;
                        };
                        if is_alias(&alias) {
                            names.push((alias.clone(), item.span.clone()));
                            aliases.push(alias);
                            name_spans.push(item.span.clone());
                        } else {
                            self.push(
                                DictionaryError::at(&item.span, format!("`{alias}` is not a valid alias"), "not a name")
                                    .with_help("aliases are letters, digits and `_`, starting with a letter, e.g. `SPG_TARGET_VELOCITY_VL_UUNIT`"),
                            );
                        }
                    }
                }
                _ => self.push(expected(
                    node,
                    "`aliases`",
                    "a list, e.g. `[target_speed, SPG_TARGET_VELOCITY_VL_UUNIT]`",
                )),
            }
        }

        let index = self
            .required(
                &f,
                "index",
                "the object's 16-bit index, e.g. `index: 395` or `index: 0x18B`",
            )
            .and_then(|n| self.int(n, "index", 0, u16::MAX.into()));
        let subindex = match f.get("subindex") {
            Some(n) => self.int(n, "subindex", 0, u32::MAX.into()),
            None => Some(0),
        };

        let data_type = self
            .required(&f, "type", "one of u8 i8 u16 i16 u32 i32 string(N)")
            .and_then(|n| self.data_type(n));
        let access = self
            .required(&f, "access", "ro (read-only), rw (read-write) or wo (write-only)")
            .and_then(|n| self.access(n));
        let unit = f.get("unit").map(|n| self.unit(n));
        let scale = match f.get("scale") {
            Some(n) => self.scale(n),
            None => Some(1.0),
        };
        let min = f.get("min").map(|n| (n, self.number(n, "min")));
        let max = f.get("max").map(|n| (n, self.number(n, "max")));
        let format = f.get("format").and_then(|n| {
            let id = self.text(n, "format")?;
            let found = Format::from_id(&id);
            if found.is_none() {
                self.push(
                    DictionaryError::at(&n.span, format!("unknown format `{id}`"), "not a format").with_help(
                        "write `decimal` (the default) or `hex` (for bit fields such as status words)",
                    ),
                );
            }
            found
        });
        let description = f.get("description").and_then(|n| self.text(n, "description"));
        let unconfirmed = f.get("unconfirmed").and_then(|n| self.text(n, "unconfirmed"));

        // Keys that make no sense for text.
        if let Some(DataType::String { .. }) = data_type {
            for key in ["unit", "scale", "min", "max", "format"] {
                if let Some((_, k, _)) = f.entries.iter().find(|(k, _, v)| *k == key && !v.is_null()) {
                    self.push(
                        DictionaryError::at(
                            &k.span,
                            format!("a string object has no `{key}`"),
                            "not for text",
                        )
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

        let (Some(name), Some(index), Some(subindex), Some(data_type), Some(access), Some(scale)) =
            (name, index, subindex, data_type, access, scale)
        else {
            return Err(BrokenObject { names });
        };
        let mut object = ObjectDef::new(
            name,
            Address::Indexed {
                index: index as u16,
                subindex: subindex as u32,
            },
            data_type,
            access,
        );
        object.aliases = aliases;
        object.unit = unit.flatten();
        object.scale = scale;
        object.format = format.unwrap_or_default();
        object.description = description.unwrap_or_default();
        object.unconfirmed = unconfirmed;
        object.span = node.span.clone();
        object.name_spans = name_spans;
        object.min = min.and_then(|(_, v)| v);
        object.max = max.and_then(|(_, v)| v);
        if self.errors.len() > before {
            return Err(BrokenObject { names });
        }
        Ok(object)
    }

    fn data_type(&mut self, node: &YamlNode) -> Option<DataType> {
        let text = self.text(node, "type")?;
        match DataType::parse(&text) {
            Ok(t) => Some(t),
            Err(message) => {
                let help = suggestion_text(&did_you_mean(&text, DataType::names()))
                    .unwrap_or_else(|| format!("the types are: {}", DataType::names().join(", ")));
                self.push(DictionaryError::at(&node.span, message, "not a type").with_help(help));
                None
            }
        }
    }

    fn access(&mut self, node: &YamlNode) -> Option<Access> {
        let text = self.text(node, "access")?;
        let found = Access::from_id(&text);
        if found.is_none() {
            self.push(
                DictionaryError::at(&node.span, format!("unknown access `{text}`"), "not an access")
                    .with_help("write ro (read-only), rw (read-write) or wo (write-only)"),
            );
        }
        found
    }

    /// `Some(None)` never: an unknown unit is an error (`None`).
    fn unit(&mut self, node: &YamlNode) -> Option<Unit> {
        let text = self.text(node, "unit")?;
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
                DictionaryError::at(&node.span, format!("unknown unit `{text}`"), "not a unit")
                    .with_help(help),
            );
        }
        found
    }

    fn scale(&mut self, node: &YamlNode) -> Option<f64> {
        let scale = self.number(node, "scale")?;
        if scale > 0.0 {
            Some(scale)
        } else {
            self.push(
                DictionaryError::at(
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
                    DictionaryError::at(
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
                    DictionaryError::at(
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
        let before = self.errors.len();
        let mut allowed: Vec<&str> = Role::ALL.iter().map(|r| r.id()).collect();
        allowed.extend(["commands", "states"]);
        let f = self.fields(node, "the profile", &allowed)?;
        let mut roles = Vec::new();
        for role in Role::ALL {
            let value = if role.required() {
                self.required(
                    &f,
                    role.id(),
                    &format!("the name of the object that is the {role}"),
                )
            } else {
                f.get(role.id())
            };
            if let Some(v) = value {
                if let Some(object) = self.text(v, role.id()) {
                    roles.push(RoleBinding {
                        role,
                        object,
                        span: v.span.clone(),
                    });
                }
            }
        }
        let commands = self
            .required(&f, "commands", "the control-word value of each command")
            .and_then(|n| self.commands(n));
        let states = self
            .required(&f, "states", "the status-word mask and value of each state")
            .and_then(|n| self.states(n));
        let (Some(commands), Some(states)) = (commands, states) else {
            return None;
        };
        (self.errors.len() == before).then(|| Profile {
            roles,
            commands,
            states,
            span: node.span.clone(),
        })
    }

    fn commands(&mut self, node: &YamlNode) -> Option<[u16; 7]> {
        let allowed: Vec<&str> = DeviceCommand::ALL.iter().map(|c| c.id()).collect();
        let f = self.fields(node, "the commands", &allowed)?;
        let mut values = [0u16; 7];
        let mut nodes: [Option<&YamlNode>; 7] = [None; 7];
        let mut complete = true;
        for (i, command) in DeviceCommand::ALL.into_iter().enumerate() {
            let meaning = format!(
                "its control-word value (the SD2 manual's is {})",
                command.default_control_word()
            );
            match self.required(&f, command.id(), &meaning) {
                Some(n) => match self.int(n, command.id(), 0, u16::MAX.into()) {
                    Some(v) => {
                        values[i] = v as u16;
                        nodes[i] = Some(n);
                    }
                    None => complete = false,
                },
                None => complete = false,
            }
        }
        if !complete {
            return None;
        }
        let node_of = |c: DeviceCommand| nodes[DeviceCommand::ALL.iter().position(|x| *x == c).unwrap_or(0)];
        let before = self.errors.len();
        for kept in [DeviceCommand::EnableOperation, DeviceCommand::SwitchOn] {
            if let (0, Some(node)) = (command_in(&values, kept), node_of(kept)) {
                self.push(
                    DictionaryError::at(
                        &node.span,
                        format!(
                            "`{}` is 0: it sets no control-word bit, so no stop command could undo it",
                            kept.id()
                        ),
                        "sets no bit",
                    )
                    .with_help(format!(
                        "the SD2 manual's {} is {}",
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
                DictionaryError::at(
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
                    "a stop command must clear at least one bit of `{}`; the SD2 manual's {} is {}",
                    kept.id(),
                    stop.id(),
                    stop.default_control_word()
                ))),
            );
        }
        (self.errors.len() == before).then_some(values)
    }

    fn states(&mut self, node: &YamlNode) -> Option<[StateMask; 8]> {
        let allowed: Vec<&str> = DeviceState::ALL.iter().map(|s| s.id()).collect();
        let f = self.fields(node, "the states", &allowed)?;
        let mut masks = [StateMask { mask: 0, value: 0 }; 8];
        let mut read: Vec<(DeviceState, StateMask, &YamlNode)> = Vec::new();
        let mut complete = true;
        for (i, state) in DeviceState::ALL.into_iter().enumerate() {
            let (m, v) = state.default_mask_value();
            let meaning = format!("its mask and value, e.g. `{{ mask: 0x{m:02X}, value: 0x{v:02X} }}`");
            let Some(n) = self.required(&f, state.id(), &meaning) else {
                complete = false;
                continue;
            };
            match self.state(n, state) {
                Some(sm) => {
                    masks[i] = sm;
                    read.push((state, sm, n));
                }
                None => complete = false,
            }
        }
        for (j, (state, sm, node)) in read.iter().enumerate() {
            for (earlier, esm, enode) in &read[..j] {
                if let Some(word) = sm.overlap(*esm) {
                    self.push(
                        DictionaryError::at(
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
        let f = self.fields(node, "a state", STATE_KEYS)?;
        let mask_node = self.required(&f, "mask", "the status-word bits this state looks at");
        let value_node = self.required(&f, "value", "the value of those bits in this state");
        let mask = mask_node.and_then(|n| self.int(n, "mask", 0, u16::MAX.into()));
        let value = value_node.and_then(|n| self.int(n, "value", 0, u16::MAX.into()));
        let (Some(mask_node), Some(value_node), Some(mask), Some(value)) =
            (mask_node, value_node, mask, value)
        else {
            return None;
        };
        let (mask, value) = (mask as u16, value as u16);
        if mask == 0 {
            self.push(
                DictionaryError::at(
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
                DictionaryError::at(
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

fn expected(node: &YamlNode, what: &str, wanted: &str) -> DictionaryError {
    DictionaryError::at(
        &node.span,
        format!("{what} must be {wanted}, found {}", node.kind_name()),
        format!("expected {}", wanted.split(" (").next().unwrap_or(wanted)),
    )
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
