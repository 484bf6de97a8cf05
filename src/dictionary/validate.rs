//! Checks that need the whole dictionary: names and aliases unique across objects (ignoring
//! case), addresses unique, every profile role naming an object of a fitting type and access.
//! Run after reading a file and again after merging a user's file into the built-in
//! dictionary. Returns the problems; no I/O.

use super::object_def::ObjectDef;
use super::profile::Profile;
use super::reader::BrokenObject;
use crate::diag::{did_you_mean, suggestion_text, Diagnostic, Diagnostics, Source, Span};
use std::collections::HashMap;
use std::sync::Arc;

/// The problems of `objects` and `profile`. `broken` are objects left out because they had
/// problems of their own: their names still count as taken, and a role naming one is not
/// reported again. Where two places clash and one is in `prefer` (the file being added),
/// the error points there.
pub(crate) fn validate(
    objects: &[ObjectDef],
    profile: Option<&Profile>,
    broken: &[BrokenObject],
    prefer: Option<&Arc<Source>>,
) -> Diagnostics {
    let mut errors = Diagnostics::new();
    let in_preferred = |span: &Span| prefer.is_some_and(|f| Arc::ptr_eq(f, span.source()));

    let mut entries: Vec<NameEntry> = Vec::new();
    for (oi, object) in objects.iter().enumerate() {
        for (ni, name) in object.names().enumerate() {
            entries.push(NameEntry {
                owner: oi,
                owner_name: &object.name,
                name,
                alias: ni > 0,
                span: object.name_span(ni),
            });
        }
    }
    for (bi, b) in broken.iter().enumerate() {
        let owner_name = b.names.first().map(|(n, _)| n.as_str()).unwrap_or("?");
        for (ni, (name, span)) in b.names.iter().enumerate() {
            entries.push(NameEntry {
                owner: objects.len() + bi,
                owner_name,
                name,
                alias: ni > 0,
                span,
            });
        }
    }
    entries.sort_by_key(|e| (e.span.path().to_string(), e.span.offset()));
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, entry) in entries.iter().enumerate() {
        let key = entry.name.to_ascii_lowercase();
        let Some(&first_i) = seen.get(&key) else {
            seen.insert(key, i);
            continue;
        };
        let first = &entries[first_i];
        // The same object spelt twice (`parameter_set` with the manual's alias
        // `PARAMETER_SET`) is harmless: both find the same object.
        if first.owner == entry.owner {
            continue;
        }
        let (at, other) = if in_preferred(first.span) && !in_preferred(entry.span) {
            (first, entry)
        } else {
            (entry, first)
        };
        errors.push(
            Diagnostic::at(
                at.span,
                format!("`{}` is {} and already {}", entry.name, at.role(), other.role()),
                "defined again here",
            )
            .with_help(
                "names and aliases must be unique, ignoring case; to replace a built-in object, use its exact name",
            )
            .also_at(other.span, "first defined here"),
        );
    }

    let mut addresses: HashMap<_, usize> = HashMap::new();
    for (oi, object) in objects.iter().enumerate() {
        match addresses.get(&object.address) {
            None => {
                addresses.insert(object.address, oi);
            }
            Some(&first) => {
                let first = &objects[first];
                let (at, other, a, b) = if in_preferred(&first.span) && !in_preferred(&object.span) {
                    (&first.span, &object.span, first, object)
                } else {
                    (&object.span, &first.span, object, first)
                };
                errors.push(
                    Diagnostic::at(
                        at,
                        format!(
                            "`{}` has the same address as `{}`: {}",
                            a.name, b.name, object.address
                        ),
                        "same address",
                    )
                    .also_at(other, "first defined here")
                    .with_optional_help(Some(
                        "give one object several names with `aliases:` instead".into(),
                    )),
                );
            }
        }
    }

    if let Some(profile) = profile {
        for (name, span, what) in profile.object_writes() {
            let Some(object) = objects.iter().find(|o| o.is_named(name)) else {
                if broken
                    .iter()
                    .any(|b| b.names.iter().any(|(n, _)| n.eq_ignore_ascii_case(name)))
                {
                    continue;
                }
                let suggestions = did_you_mean(name, objects.iter().flat_map(|o| o.names()));
                errors.push(
                    Diagnostic::at(
                        span,
                        format!(
                            "the profile writes `{name}` ({what}), which is not an object of this dictionary"
                        ),
                        "unknown object",
                    )
                    .with_optional_help(suggestion_text(&suggestions)),
                );
                continue;
            };
            if !object.data_type.is_integer() || !object.writable() {
                errors.push(
                    Diagnostic::at(
                        span,
                        format!(
                            "the profile writes `{}` ({what}), but it is {} {}",
                            object.name,
                            object.access.describe(),
                            object.data_type
                        ),
                        "not a writable integer",
                    )
                    .also_at(&object.span, "defined here"),
                );
            }
        }
        for binding in profile.bindings() {
            let found = objects.iter().find(|o| o.is_named(&binding.object));
            let Some(object) = found else {
                if broken.iter().any(|b| {
                    b.names
                        .iter()
                        .any(|(n, _)| n.eq_ignore_ascii_case(&binding.object))
                }) {
                    continue;
                }
                let suggestions = did_you_mean(&binding.object, objects.iter().flat_map(|o| o.names()));
                errors.push(
                    Diagnostic::at(
                        &binding.span,
                        format!(
                            "the profile's {} is `{}`, which is not an object of this dictionary",
                            binding.role.id(),
                            binding.object
                        ),
                        "unknown object",
                    )
                    .with_optional_help(suggestion_text(&suggestions)),
                );
                continue;
            };
            if let Some(problem) = binding.role.type_problem(object.data_type) {
                errors.push(
                    Diagnostic::at(
                        &binding.span,
                        problem,
                        format!("`{}` is {}", object.name, object.data_type),
                    )
                    .also_at(&object.span, "defined here"),
                );
            }
            let (ok, needs) = if binding.role.written() {
                (object.writable(), "written")
            } else {
                (object.readable(), "read")
            };
            if !ok {
                errors.push(
                    Diagnostic::at(
                        &binding.span,
                        format!(
                            "the {} is {needs} by the engine, but `{}` is {} ({})",
                            binding.role,
                            object.name,
                            object.access.describe(),
                            object.access
                        ),
                        "wrong access",
                    )
                    .also_at(&object.span, "defined here"),
                );
            }
        }
    }
    errors
}

/// One name or alias of an object, for the uniqueness check.
struct NameEntry<'a> {
    /// Which object (index among the objects, then among the broken ones).
    owner: usize,
    owner_name: &'a str,
    name: &'a str,
    alias: bool,
    span: &'a Span,
}

impl NameEntry<'_> {
    /// `the name of `a`` or `an alias of `a``.
    fn role(&self) -> String {
        if self.alias {
            format!("an alias of `{}`", self.owner_name)
        } else {
            format!("the name of `{}`", self.owner_name)
        }
    }
}
