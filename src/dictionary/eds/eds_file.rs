//! A CiA 306 EDS or DCF file read into its objects and sub-objects: index and subindex,
//! names, data type, access, limits, default, a DCF's `ParameterValue`, PDO mapping and
//! object links, `CompactSubObj` arrays expanded, each entry with its place. Every problem
//! is recorded with file:line and reading goes on, so a file reports them all. No I/O
//! (the caller reads the file) and no dictionary objects (see `eds_objects`).

use super::eds_number::{EdsLimit, EdsNumber};
use super::eds_type::{access, EdsType};
use super::ini_text::{IniEntry, IniSection, IniText};
use crate::diag::{Diagnostic, Diagnostics, Source, Span};
use crate::dictionary::Access;
use std::collections::HashMap;
use std::sync::Arc;

/// CiA 301 object codes (`ObjectType=`).
const DOMAIN: i128 = 0x2;
const VAR: i128 = 0x7;
const ARRAY: i128 = 0x8;
const RECORD: i128 = 0x9;

/// One object (a VAR or DOMAIN at subindex 0) or sub-object of an ARRAY or RECORD.
#[derive(Debug, Clone)]
pub(crate) struct EdsEntry {
    pub index: u16,
    pub subindex: u8,
    /// `ParameterName` of this entry.
    pub name: String,
    /// For a sub-object, the `ParameterName` of its ARRAY or RECORD.
    pub parent: Option<String>,
    pub data_type: EdsType,
    pub access: Access,
    /// `AccessType` as written, in lower case (`const`, `rww`).
    pub access_text: String,
    pub low: Option<EdsLimit>,
    pub high: Option<EdsLimit>,
    /// `DefaultValue` as written (numbers, `$NODEID` expressions or text).
    pub default: Option<String>,
    /// A DCF's `ParameterValue`: the value the node is configured with.
    pub parameter_value: Option<String>,
    pub pdo_mapping: bool,
    /// The objects `[XXXXObjectLinks]` links to this one.
    pub links: Vec<u16>,
    pub span: Span,
}

/// What a file holds, as far as it could be read.
#[derive(Debug)]
pub(crate) struct EdsFile {
    pub source: Arc<Source>,
    pub entries: Vec<EdsEntry>,
    /// `[DeviceComissioning] NodeID` of a DCF: the node `$NODEID` means.
    pub node_id: Option<u8>,
    /// What is wrong but does not stop the file being read (an object list naming a
    /// section the file does not have), each at its line.
    pub notes: Vec<Diagnostic>,
}

impl EdsFile {
    /// Reads `source`, recording every problem in `out`.
    pub fn parse(source: &Arc<Source>, out: &mut Diagnostics) -> EdsFile {
        let ini = IniText::parse(source, out);
        let mut file = EdsFile {
            source: Arc::clone(source),
            entries: Vec::new(),
            node_id: None,
            notes: Vec::new(),
        };
        if ini.sections.is_empty() {
            out.push(
                Diagnostic::at(&Span::start_of(source), "no `[section]` in the file", "expected `[FileInfo]`")
                    .with_help("an EDS or DCF (CiA 306) is an INI file: `[FileInfo]`, `[DeviceInfo]`, then one section per object such as `[6041]`"),
            );
            return file;
        }
        file.node_id = node_id(&ini, out);
        check_object_lists(&ini, &mut file.notes);
        // `[1018sub2]` by its object's index, found in one pass.
        let mut subs: HashMap<u16, Vec<&IniSection>> = HashMap::new();
        for section in &ini.sections {
            let name = &section.name;
            if name.len() > 7
                && name.is_char_boundary(4)
                && name.is_char_boundary(7)
                && name[4..7].eq_ignore_ascii_case("sub")
            {
                if let Some(index) = object_index(&name[..4]) {
                    subs.entry(index).or_default().push(section);
                }
            }
        }
        for section in &ini.sections {
            if let Some(index) = object_index(&section.name) {
                let own = subs.get(&index).map_or(&[][..], Vec::as_slice);
                file.object(&ini, section, index, own, out);
            }
        }
        file
    }

    fn object(
        &mut self,
        ini: &IniText,
        section: &IniSection,
        index: u16,
        subs: &[&IniSection],
        out: &mut Diagnostics,
    ) {
        let Some(name) = required(section, "ParameterName", out) else {
            return;
        };
        let object_type = match section.get("ObjectType") {
            None => VAR,
            Some(e) => match plain_number(e, |v| [DOMAIN, VAR, ARRAY, RECORD].contains(&v)) {
                Some(object_type) => object_type,
                None => {
                    out.push(
                        Diagnostic::at(
                            &e.span,
                            format!("`ObjectType={}` is not an object type", e.value),
                            "unknown object type",
                        )
                        .with_help("CiA 306 object types: 0x2 DOMAIN, 0x7 VAR, 0x8 ARRAY, 0x9 RECORD"),
                    );
                    return;
                }
            },
        };
        let links = object_links(ini, section, out);
        if object_type == VAR || object_type == DOMAIN {
            let default_type = (object_type == DOMAIN).then_some(EdsType::Domain);
            if let Some(mut entry) = entry(section, index, 0, name.clone(), None, default_type, out) {
                entry.links = links;
                self.entries.push(entry);
            }
            return;
        }
        let compact = section
            .get("CompactSubObj")
            .map(|e| (e, EdsNumber::parse(&e.value)));
        match compact {
            Some((e, Ok(n))) if n.value > 0 && !n.plus_node_id => {
                if object_type != ARRAY || n.value > 254 {
                    out.push(Diagnostic::at(
                        &e.span,
                        format!(
                            "`CompactSubObj={}` needs an ARRAY (ObjectType=0x8) of 1..254 entries",
                            e.value
                        ),
                        "not a compact array",
                    ));
                    return;
                }
                self.compact_array(ini, section, index, &name, n.value as u8, &links, out);
            }
            Some((_, Ok(_))) | None => {
                for sub in subs {
                    let rest = &sub.name[7..];
                    let Ok(subindex) = u8::from_str_radix(rest, 16) else {
                        out.push(Diagnostic::at(
                            &sub.span,
                            format!("`[{}]`: `{rest}` is not a hexadecimal subindex 0..FF", sub.name),
                            "bad subindex",
                        ));
                        continue;
                    };
                    let Some(sub_name) = required(sub, "ParameterName", out) else {
                        continue;
                    };
                    if let Some(mut entry) =
                        entry(sub, index, subindex, sub_name, Some(name.clone()), None, out)
                    {
                        entry.links.clone_from(&links);
                        self.entries.push(entry);
                    }
                }
            }
            Some((e, Err(why))) => out.push(Diagnostic::at(&e.span, why.to_string(), "expected a number")),
        }
    }

    /// `CompactSubObj=n`: subindex 0 holds n (UNSIGNED8, ro), subindexes 1..=n share the
    /// object's type and access; names may come from `[XXXXName]`, values from
    /// `[XXXXValue]`.
    #[allow(clippy::too_many_arguments)]
    fn compact_array(
        &mut self,
        ini: &IniText,
        section: &IniSection,
        index: u16,
        name: &str,
        count: u8,
        links: &[u16],
        out: &mut Diagnostics,
    ) {
        let Some(template) = entry(
            section,
            index,
            1,
            name.to_string(),
            Some(name.to_string()),
            None,
            out,
        ) else {
            return;
        };
        self.entries.push(EdsEntry {
            subindex: 0,
            name: "NrOfObjects".into(),
            data_type: EdsType::Unsigned8,
            access: Access::ReadOnly,
            access_text: "ro".into(),
            low: None,
            high: None,
            default: Some(count.to_string()),
            parameter_value: None,
            pdo_mapping: false,
            links: links.to_vec(),
            ..template.clone()
        });
        let names = ini.section(&format!("{}Name", section.name));
        let values = ini.section(&format!("{}Value", section.name));
        for i in 1..=count {
            let key = i.to_string();
            let sub_name = names
                .and_then(|s| s.get(&key))
                .map_or_else(|| format!("{name}{i}"), |e| e.value.clone());
            self.entries.push(EdsEntry {
                subindex: i,
                name: sub_name,
                parameter_value: values.and_then(|s| s.get(&key)).map(|e| e.value.clone()),
                links: links.to_vec(),
                ..template.clone()
            });
        }
    }
}

/// The value of `key`, or a located problem saying it is missing.
fn required(section: &IniSection, key: &str, out: &mut Diagnostics) -> Option<String> {
    match section.get(key) {
        Some(e) if !e.value.is_empty() => Some(e.value.clone()),
        _ => {
            out.push(
                Diagnostic::at(
                    &section.span,
                    format!("`[{}]` has no `{key}=`", section.name),
                    format!("`{key}` missing"),
                )
                .with_help(format!("add `{key}=` to the section")),
            );
            None
        }
    }
}

/// One VAR, DOMAIN or sub-object section read into an entry; `None` after a problem.
fn entry(
    section: &IniSection,
    index: u16,
    subindex: u8,
    name: String,
    parent: Option<String>,
    default_type: Option<EdsType>,
    out: &mut Diagnostics,
) -> Option<EdsEntry> {
    let before = out.len();
    let data_type = match (section.get("DataType"), default_type) {
        (None, Some(t)) => Some(t),
        (None, None) => {
            required(section, "DataType", out);
            None
        }
        (Some(e), _) => match plain_number(e, |v| (0..=0xFFFF).contains(&v)) {
            Some(code) => Some(EdsType::from_code(code as u16)),
            None => {
                out.push(
                    Diagnostic::at(
                        &e.span,
                        format!("`DataType={}` is not a data type code", e.value),
                        "expected 0x0001..0xFFFF",
                    )
                    .with_help("CiA 306 data types are numbers such as 0x0006 (UNSIGNED16)"),
                );
                None
            }
        },
    };
    let access_text = section
        .get("AccessType")
        .map(|e| e.value.trim().to_ascii_lowercase())
        .unwrap_or_default();
    let access = match section.get("AccessType") {
        None => {
            required(section, "AccessType", out);
            None
        }
        Some(e) => access(&e.value)
            .map_err(|why| out.push(Diagnostic::at(&e.span, why.to_string(), "unknown access type")))
            .ok(),
    };
    let real = matches!(data_type, Some(EdsType::Real32 | EdsType::Real64));
    let signed_bits = data_type.and_then(EdsType::signed_bits);
    let mut limit = |key: &str| -> Option<EdsLimit> {
        let e = section.get(key).filter(|e| !e.value.is_empty())?;
        EdsLimit::parse(&e.value, real)
            .map(|l| match signed_bits {
                Some(bits) => l.signed_at(&e.value, bits),
                None => l,
            })
            .map_err(|why| {
                out.push(Diagnostic::at(
                    &e.span,
                    format!("`{key}`: {why}"),
                    "expected a number",
                ))
            })
            .ok()
    };
    let low = limit("LowLimit");
    let high = limit("HighLimit");
    let pdo_mapping = section
        .get("PDOMapping")
        .is_some_and(|e| matches!(EdsNumber::parse(&e.value), Ok(n) if n.value != 0));
    let text = |key: &str| {
        section
            .get(key)
            .map(|e| e.value.clone())
            .filter(|v| !v.is_empty())
    };
    if out.len() > before {
        return None;
    }
    Some(EdsEntry {
        index,
        subindex,
        name,
        parent,
        data_type: data_type?,
        access: access?,
        access_text,
        low,
        high,
        default: text("DefaultValue"),
        parameter_value: text("ParameterValue"),
        pdo_mapping,
        links: Vec::new(),
        span: section.span.clone(),
    })
}

/// `[1018]` → 0x1018; other section names are not objects.
fn object_index(name: &str) -> Option<u16> {
    (name.len() == 4 && name.chars().all(|c| c.is_ascii_hexdigit()))
        .then(|| u16::from_str_radix(name, 16).ok())
        .flatten()
}

/// `e`'s value as a number without `$NODEID` that `fits` takes; `None` for anything else,
/// which the caller names in its problem.
fn plain_number(e: &IniEntry, fits: impl Fn(i128) -> bool) -> Option<i128> {
    let n = EdsNumber::parse(&e.value).ok()?;
    (!n.plus_node_id && fits(n.value)).then_some(n.value)
}

/// `[XXXXObjectLinks]`: `ObjectLinks=n`, then `1=0x6041` …
fn object_links(ini: &IniText, section: &IniSection, out: &mut Diagnostics) -> Vec<u16> {
    let Some(links) = ini.section(&format!("{}ObjectLinks", section.name)) else {
        return Vec::new();
    };
    links
        .entries
        .iter()
        .filter(|e| !e.key.eq_ignore_ascii_case("ObjectLinks"))
        .filter_map(|e| match plain_number(e, |v| (0..=0xFFFF).contains(&v)) {
            Some(index) => Some(index as u16),
            None => {
                out.push(Diagnostic::at(
                    &e.span,
                    format!("`{}` is not an object index", e.value),
                    "expected 0x0000..0xFFFF",
                ));
                None
            }
        })
        .collect()
}

/// A DCF's `[DeviceComissioning] NodeID` (CiA 306 spells the section so).
fn node_id(ini: &IniText, out: &mut Diagnostics) -> Option<u8> {
    let e = ini.section("DeviceComissioning")?.get("NodeID")?;
    match plain_number(e, |v| (1..=127).contains(&v)) {
        Some(node) => Some(node as u8),
        None => {
            out.push(Diagnostic::at(
                &e.span,
                format!("`NodeID={}` is not a node id 1..127", e.value),
                "expected 1..127",
            ));
            None
        }
    }
}

/// Every object `[MandatoryObjects]`, `[OptionalObjects]` and `[ManufacturerObjects]` list
/// has its own section. A list is an index of the file, not its objects: where it and the
/// sections disagree the sections are read and the list's line is a note (real files do
/// this, python-canopen's own `e35.eds` among them).
fn check_object_lists(ini: &IniText, out: &mut Vec<Diagnostic>) {
    for list in ["MandatoryObjects", "OptionalObjects", "ManufacturerObjects"] {
        let Some(section) = ini.section(list) else {
            continue;
        };
        for e in section
            .entries
            .iter()
            .filter(|e| !e.key.eq_ignore_ascii_case("SupportedObjects"))
        {
            match plain_number(e, |v| (0..=0xFFFF).contains(&v)) {
                Some(index) => {
                    let name = format!("{index:04X}");
                    if ini.section(&name).is_none() {
                        out.push(
                            Diagnostic::at(
                                &e.span,
                                format!("[{list}] lists 0x{name}, but there is no `[{name}]` section; the object is left out"),
                                "no such section",
                            )
                            .with_help(format!(
                                "ask the device's maker for a corrected file, or add the object's section `[{name}]` or remove it from the list"
                            )),
                        );
                    }
                }
                None => out.push(Diagnostic::at(
                    &e.span,
                    format!(
                        "[{list}]: `{}` is not an object index; the line is skipped",
                        e.value
                    ),
                    "expected 0x0000..0xFFFF",
                )),
            }
        }
    }
}
