//! An EDS/DCF file's entries as dictionary objects: readable names (`controlword`,
//! `identity_object_vendor_id`) with the index (`0x6041`, `0x1018/1`) and the EDS name as
//! aliases, the carried type, access, limits (with `$NODEID` resolved by the DCF's node
//! id), the default and links in the description, and a DCF's `ParameterValue`s as a
//! parameter set. For an object a built-in dictionary has too, what the file says of it
//! (the caller lays it over the built-in entry: the device's own file wins). Entries
//! drivescript cannot carry are listed as such, with one note saying which. No I/O.

use super::eds_file::{EdsEntry, EdsFile};
use crate::diag::{Diagnostic, Span};
use crate::dictionary::{Access, Address, DataType, FileEntry, Format, ObjectDef};
use std::collections::{BTreeMap, HashSet};

/// What an EDS adds to a dictionary.
#[derive(Debug)]
pub(crate) struct EdsObjects {
    pub objects: Vec<ObjectDef>,
    /// What was left out or not resolved, as notes on the file.
    pub notes: Vec<Diagnostic>,
    /// A DCF's `ParameterValue`s by object name, as written.
    pub parameter_values: Vec<(String, String)>,
    /// For an object the dictionary already has at an address: the EDS's index and name,
    /// as aliases it gains where they are free.
    pub aliases_of_occupied: Vec<(Address, Vec<String>)>,
    /// For those objects, what the file says, to lay over the dictionary's entry.
    pub on_built_in: Vec<OnBuiltIn>,
    /// The entries of types drivescript cannot access (TIME_OF_DAY, complex records …).
    pub not_carried: Vec<FileEntry>,
}

/// The file's word on an object a dictionary already has: its type as carried, its access.
#[derive(Debug)]
pub(crate) struct OnBuiltIn {
    pub file: FileEntry,
    pub data_type: DataType,
    pub access: Access,
    /// The file's limits in raw counts as they apply (`None` where the file gives none or
    /// gives them inverted).
    pub limits: (Option<f64>, Option<f64>),
}

/// The objects of `file`, named so that none clashes with `taken` (names and aliases
/// already in the dictionary, lower case) and none sits at an address in `occupied` (the
/// dictionary's own entry keeps its name, unit and scale, which an EDS does not give; the
/// file's type, access and limits come in `on_built_in`).
pub(crate) fn eds_objects(
    file: &EdsFile,
    taken: &HashSet<String>,
    occupied: &HashSet<Address>,
    family_alias: &dyn Fn(&Address) -> Option<String>,
) -> EdsObjects {
    let mut taken = taken.clone();
    let mut out = EdsObjects {
        objects: Vec::new(),
        notes: Vec::new(),
        parameter_values: Vec::new(),
        aliases_of_occupied: Vec::new(),
        on_built_in: Vec::new(),
        not_carried: Vec::new(),
    };
    out.notes.extend(file.notes.iter().cloned());
    // Per type left out: why, where the first such entry is, and the places.
    let mut not_carried: BTreeMap<u16, (String, Span, Vec<String>)> = BTreeMap::new();
    let mut unresolved: Vec<String> = Vec::new();
    let mut inverted: Vec<String> = Vec::new();
    for entry in &file.entries {
        let address = Address::indexed(entry.index, u32::from(entry.subindex));
        let carried = entry.data_type.carried();
        let limit = |n: Option<super::eds_number::EdsLimit>| n.map(|n| n.resolve(file.node_id));
        let (mut low, mut high) = (limit(entry.low), limit(entry.high));
        if matches!(low, Some(None)) || matches!(high, Some(None)) {
            unresolved.push(index_text(entry));
        }
        // `LowLimit=0 HighLimit=0xFF` on an INTEGER8 (vendors mean "any byte"): no value
        // fits, so the type's own range is used instead.
        if let (Some(Some(lo)), Some(Some(hi))) = (low, high) {
            if lo > hi && carried.is_ok() {
                inverted.push(index_text(entry));
                (low, high) = (None, None);
            }
        }
        let (low, high) = (low.flatten(), high.flatten());
        if let Err(why) = &carried {
            not_carried
                .entry(why.code)
                .or_insert_with(|| (why.to_string(), entry.span.clone(), Vec::new()))
                .2
                .push(index_text(entry));
            out.not_carried.push(file_entry(file, entry));
        }
        if occupied.contains(&address) {
            let free: Vec<String> = [index_text(entry), eds_name(entry)]
                .into_iter()
                .filter(|a| taken.insert(a.to_ascii_lowercase()))
                .collect();
            out.aliases_of_occupied.push((address, free));
            if let Ok((data_type, range)) = carried {
                out.on_built_in.push(OnBuiltIn {
                    file: file_entry(file, entry),
                    data_type,
                    access: entry.access,
                    // A BOOLEAN's 0..1 is its limits where the file gives none.
                    limits: (low.or(range.map(|r| r.0)), high.or(range.map(|r| r.1))),
                });
            }
            continue;
        }
        let Ok((data_type, range)) = carried else {
            continue;
        };
        let name = unique_name(entry, &mut taken);
        let mut def = ObjectDef::new(name.clone(), address, data_type, entry.access);
        let family = family_alias(&address);
        for alias in family.into_iter().chain([index_text(entry), eds_name(entry)]) {
            if taken.insert(alias.to_ascii_lowercase()) {
                def.aliases.push(alias);
            }
        }
        def.min = range.map(|r| r.0).or(low);
        def.max = range.map(|r| r.1).or(high);
        if let (Some(type_range), Some(min)) = (data_type.range(), def.min) {
            def.min = Some(min.max(type_range.0 as f64));
        }
        if let (Some(type_range), Some(max)) = (data_type.range(), def.max) {
            def.max = Some(max.min(type_range.1 as f64));
        }
        if entry.index >= 0x1000 && entry.index < 0x2000 && data_type.is_integer() && data_type.size() == 4 {
            // Communication objects of 32 bits are COB-IDs and bit fields.
            def.format = Format::Hex;
        }
        def.description = description(entry);
        // A setting of the node, not process data (PDO-mapped) and not the store/restore
        // commands 0x1010/0x1011, whose write is an action.
        // A DOMAIN is a block of data, never a setting written back.
        def.parameter = def.readable()
            && def.writable()
            && data_type != DataType::Domain
            && !entry.pdo_mapping
            && !(0x1010..=0x1011).contains(&entry.index);
        def.span = entry.span.clone();
        def.file = Some(Box::new(file_entry(file, entry)));
        if let Some(value) = &entry.parameter_value {
            out.parameter_values.push((name, value.clone()));
        }
        out.objects.push(def);
    }
    let start = Span::start_of(&file.source);
    for (why, first, places) in not_carried.into_values() {
        out.notes.push(Diagnostic::at(
            &first,
            format!("left out: {} ({why})", shortened(&places)),
            "left out",
        ));
    }
    if !inverted.is_empty() {
        out.notes.push(Diagnostic::at(
            &start,
            format!(
                "LowLimit is above HighLimit for {}; the type's own range is used instead",
                shortened(&inverted)
            ),
            "limits inverted",
        ));
    }
    if !unresolved.is_empty() {
        out.notes.push(
            Diagnostic::at(
                &start,
                format!(
                    "limits with $NODEID are left off for {} (the file gives no node id)",
                    shortened(&unresolved)
                ),
                "no node id",
            )
            .with_help("a DCF gives the node id in [DeviceComissioning] NodeID"),
        );
    }
    out
}

/// What the file says of `entry`, for `objects` to show.
fn file_entry(file: &EdsFile, entry: &EdsEntry) -> FileEntry {
    let limit = |n: Option<super::eds_number::EdsLimit>| n.and_then(|n| n.resolve(file.node_id));
    FileEntry {
        file: file.source.path().to_string(),
        line: entry.span.line(),
        address: Address::indexed(entry.index, u32::from(entry.subindex)),
        name: eds_name(entry),
        type_code: entry.data_type.code(),
        type_name: entry.data_type.name(),
        access: entry.access_text.clone(),
        low: limit(entry.low),
        high: limit(entry.high),
        default: entry.default.clone(),
        overrides: Vec::new(),
    }
}

/// The first places and how many more.
fn shortened(places: &[String]) -> String {
    let shown: Vec<&str> = places.iter().take(5).map(String::as_str).collect();
    match places.len() {
        n if n > 5 => format!("{} and {} more", shown.join(", "), n - 5),
        _ => shown.join(", "),
    }
}

/// `0x6041` for an object, `0x1018/2` for a sub-object.
pub(super) fn index_text(entry: &EdsEntry) -> String {
    match entry.parent {
        None => format!("0x{:04X}", entry.index),
        Some(_) => format!("0x{:04X}/{}", entry.index, entry.subindex),
    }
}

/// The EDS name as written: `Controlword`, `Identity object/Vendor-ID`.
fn eds_name(entry: &EdsEntry) -> String {
    match &entry.parent {
        None => entry.name.clone(),
        Some(parent) => format!("{parent}/{}", entry.name),
    }
}

/// `controlword`, `identity_object_vendor_id`; with the index appended when the name is
/// taken (`reserved_2001`).
fn unique_name(entry: &EdsEntry, taken: &mut HashSet<String>) -> String {
    let base = match &entry.parent {
        None => slug(&entry.name),
        Some(parent) => format!("{}_{}", slug(parent), slug(&entry.name)),
    };
    let mut name = base.clone();
    if taken.contains(&name) {
        name = match entry.parent {
            None => format!("{base}_{:04x}", entry.index),
            Some(_) => format!("{base}_{:04x}_{}", entry.index, entry.subindex),
        };
    }
    let mut n = 2;
    let unique = name.clone();
    while taken.contains(&name) {
        name = format!("{unique}_{n}");
        n += 1;
    }
    taken.insert(name.clone());
    name
}

/// Lower-case letters, digits and single `_`, starting with a letter.
fn slug(text: &str) -> String {
    let mut s = String::new();
    for c in text.chars() {
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('_') && !s.is_empty() {
            s.push('_');
        }
    }
    let s = s.trim_end_matches('_').to_string();
    if s.starts_with(|c: char| c.is_ascii_alphabetic()) {
        s
    } else {
        format!("o_{s}").trim_end_matches('_').to_string()
    }
}

fn description(entry: &EdsEntry) -> String {
    let mut text = format!("{} ({}", eds_name(entry), entry.data_type.name());
    if let Some(default) = &entry.default {
        text.push_str(&format!(", default {default}"));
    }
    if entry.pdo_mapping {
        text.push_str(", PDO-mappable");
    }
    if !entry.links.is_empty() {
        let links: Vec<String> = entry.links.iter().map(|l| format!("0x{l:04X}")).collect();
        text.push_str(&format!(", linked with {}", links.join(", ")));
    }
    text.push_str(") from the EDS");
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readable_names() {
        for (name, id) in [
            ("Controlword", "controlword"),
            ("Vendor-ID", "vendor_id"),
            ("  Highest sub-index supported ", "highest_sub_index_supported"),
            ("1st value", "o_1st_value"),
            ("ÄÖÜ", "o"),
            ("", "o"),
        ] {
            assert_eq!(slug(name), id, "{name:?}");
        }
    }
}
