//! Reads a parsed dictionary file (a YAML tree) into objects and a profile, checking
//! everything one entry can tell on its own: known keys, types, units, access, scale,
//! limits against the type's range, the profile's commands and state table. Every problem
//! is recorded with its place; reading goes on so a file reports them all. Cross-entry
//! checks (duplicate names, profile roles) are the validator's. Keys and values are read
//! with `diag::Reader`, the field reader of every loader. This file holds the reader and
//! the top-level keys; object entries are read in `object_reader`, the profile in
//! `profile_reader`. No I/O.

use super::address::AddressParser;
use super::family_id::{family_id, is_family_id, is_former_spelling};
use super::object_def::ObjectDef;
use super::profile::Profile;
use crate::diag::{Diagnostic, Diagnostics, Reader, Shape, Span, YamlNode};

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
    /// `pole_pairs: N`: the motor's pole pairs the speed objects' rpm are given for.
    pub pole_pairs: Option<u32>,
}

/// The names (name first, then aliases) and their places of an object with problems.
pub(crate) struct BrokenObject {
    pub names: Vec<(String, Span)>,
}

const TOP_KEYS: &[&str] = &["family", "title", "pole_pairs", "objects", "profile"];
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

/// Reads one file; the object entries are read in `object_reader`, the profile in
/// `profile_reader`.
pub(super) struct DictionaryReader<'d> {
    pub(super) r: Reader<'d>,
    pub(super) parse_address: Option<AddressParser>,
}

impl DictionaryReader<'_> {
    pub(super) fn push(&mut self, d: Diagnostic) {
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
            pole_pairs: None,
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
        if let Some(node) = f.get("pole_pairs") {
            contents.pole_pairs = self.pole_pairs(node);
        }
        // An inverter's speed objects count its output frequency: their rpm are given for
        // these pole pairs, and Hz converts to them.
        if let Some(pairs) = contents.pole_pairs {
            let speeds = contents.objects.iter_mut().filter(|o| {
                o.unit
                    .is_some_and(|u| u.dimension() == super::unit::Dimension::Speed)
            });
            speeds.for_each(|o| o.pole_pairs = Some(pairs));
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

    /// `pole_pairs: 2`: a whole number from 1 to [`super::MAX_POLE_PAIRS`].
    fn pole_pairs(&mut self, node: &YamlNode) -> Option<u32> {
        let text = self.r.scalar_text(node, "`pole_pairs`")?;
        match super::PolePairs::parse(&text) {
            Ok(n) => Some(n),
            Err(e) => {
                self.push(
                    Diagnostic::at(&node.span, e.to_string(), "not a number of pole pairs").with_help(
                        "the motor's pole pairs, the number its speed objects' rpm are given for (rpm = Hz × 60 / pole pairs)",
                    ),
                );
                None
            }
        }
    }

    pub(super) fn identifier(&mut self, node: &YamlNode, what: &str) -> Option<String> {
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

    pub(super) fn number(&mut self, node: &YamlNode, what: &str) -> Option<f64> {
        self.r.number(node, &format!("`{what}`"), FINITE_HELP)
    }
}

/// `[a-z][a-z0-9_]*`
pub(crate) fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}
