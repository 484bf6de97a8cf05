//! Reads one `- name: …` entry of a dictionary file into an [`ObjectDef`]: its keys, address,
//! type, unit, scale or decimals, access and limits against the type's range. Part of
//! [`DictionaryReader`]; it must not read the profile, check across entries (the validator's
//! job) or do I/O.

use super::access::Access;
use super::address::Address;
use super::data_type::DataType;
use super::format::Format;
use super::object_def::ObjectDef;
use super::reader::{BrokenObject, DictionaryReader};
use super::unit::Unit;
use crate::diag::{did_you_mean, suggestion_text, Diagnostic, Fields, Shape, Span, YamlNode};

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

impl DictionaryReader<'_> {
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
    pub(super) fn object(&mut self, node: &YamlNode) -> Result<ObjectDef, BrokenObject> {
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
            Err(wrong) => {
                let help = suggestion_text(&did_you_mean(&text, DataType::names()))
                    .unwrap_or_else(|| format!("the types are: {}", DataType::names().join(", ")));
                self.push(Diagnostic::at(&node.span, wrong.to_string(), "not a type").with_help(help));
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
}

fn unit_or_counts(object: &ObjectDef) -> String {
    match object.unit {
        Some(u) => u.symbol().to_string(),
        None => "no unit".into(),
    }
}

/// `[A-Za-z][A-Za-z0-9_]*`
fn is_alias(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}
