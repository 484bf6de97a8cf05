//! The objects a recipe names: looked up in the dictionary (did-you-mean for a misspelt
//! name), checked readable, and lists of them (`read`, `sample`'s `objects`). It must not
//! read values for the objects; that is `values`' job.

use super::Loader;
use crate::diag::{expected, Shape, Span, Spanned, YamlNode, YamlValue};
use crate::dictionary::ObjectDef;
use crate::session::ObjectRef;

impl Loader<'_, '_> {
    /// The object called `name` (written at `span`) and the reference steps keep.
    /// In a recipe with `drives:` the name is `drive.object` and the object is looked up
    /// in that drive's dictionary; the reference keeps the drive's name in front.
    pub(super) fn object(&mut self, name: &str, span: &Span) -> Option<(ObjectDef, ObjectRef)> {
        if self.several_drives() {
            let Some((drive, object)) = name.split_once('.') else {
                let first = self
                    .drive_dicts
                    .first()
                    .map(|(n, _)| n.clone())
                    .unwrap_or_default();
                return self.refuse(
                    span,
                    format!("`{name}` does not say which drive it is on"),
                    "which drive?",
                    Some(format!("this recipe has several drives: write the drive's name in front, e.g. `{first}.{name}`")),
                );
            };
            let found = self.on_drive(drive, span, |l| l.lookup_object(object, span))??;
            let (def, r) = found;
            let r = ObjectRef {
                name: format!("{drive}.{}", r.name),
                unit: r.unit,
            };
            return Some((def, r));
        }
        self.lookup_object(name, span)
    }

    /// One value per entry of a mapping keyed by object (`set:`, `expect:`, a sample's
    /// `step:`), made by `each` from the entry's object once it is found. Every entry is
    /// read, so each of its mistakes is reported; `None` when any entry is refused.
    pub(super) fn per_object<T>(
        &mut self,
        node: &YamlNode,
        shape: &Shape,
        mut each: impl FnMut(&mut Self, ObjectDef, ObjectRef, &Spanned<String>, &YamlNode) -> Option<T>,
    ) -> Option<Vec<T>> {
        let f = self.r.fields(node, shape)?;
        let mut out = Vec::new();
        let mut ok = true;
        for (k, v) in f.entries() {
            match self.object(&k.value, &k.span) {
                Some((def, r)) => match each(self, def, r, k, v) {
                    Some(t) => out.push(t),
                    None => ok = false,
                },
                None => ok = false,
            }
        }
        ok.then_some(out)
    }

    /// `list`, or refused at `node` as `message` when it is empty.
    pub(super) fn not_empty<T>(
        &mut self,
        list: Vec<T>,
        node: &YamlNode,
        message: &str,
        help: Option<String>,
    ) -> Option<Vec<T>> {
        match list.is_empty() {
            true => self.refuse(&node.span, message, "empty", help),
            false => Some(list),
        }
    }

    /// The object called `name` in the dictionary in use.
    fn lookup_object(&mut self, name: &str, span: &Span) -> Option<(ObjectDef, ObjectRef)> {
        // Suggestions compare the name with every name of the dictionary: only for a
        // problem that will be shown, so thousands of unknown names cost linear time.
        let shown = self.r.count() < crate::diag::MAX_SHOWN;
        let found = match shown {
            true => self.dict.lookup(name),
            false => self
                .dict
                .get(name)
                .ok_or_else(|| crate::dictionary::UnknownObject {
                    name: name.to_string(),
                    dictionary: self.dict.name().to_string(),
                    suggestions: Vec::new(),
                }),
        };
        match found {
            Ok(def) => {
                let r = ObjectRef {
                    name: def.name.clone(),
                    unit: def.unit.map(|u| u.symbol().to_string()),
                };
                Some((def.clone(), r))
            }
            Err(e) => {
                // A suggestion sharing no word with the name (`spindle_speed` → `parameter_set`)
                // only misleads; the objects about one of its words are what was meant.
                let words: Vec<&str> = name.split(['_', '-', '.']).filter(|w| w.len() >= 3).collect();
                let shares_a_word = |s: &String| {
                    words
                        .iter()
                        .any(|w| s.to_ascii_lowercase().contains(&w.to_ascii_lowercase()))
                };
                let about = words
                    .iter()
                    .rev()
                    .map(|w| (*w, self.dict.filter(w)))
                    .find(|(_, found)| !found.is_empty());
                let help = match about {
                    Some((word, found)) if !e.suggestions.iter().any(shares_a_word) => {
                        let names: Vec<String> =
                            found.iter().take(3).map(|d| format!("`{}`", d.name)).collect();
                        format!(
                            "did you mean {}? `drivescript objects --drive {} {word}` lists every object about {word}",
                            names.join(" or "),
                            self.dict.name()
                        )
                    }
                    _ if e.suggestions.is_empty() => {
                        crate::dictionary::objects_command(Some(self.dict.name()))
                    }
                    _ => format!(
                        "did you mean {}?",
                        e.suggestions
                            .iter()
                            .map(|s| format!("`{s}`"))
                            .collect::<Vec<_>>()
                            .join(" or ")
                    ),
                };
                self.problem(
                    span,
                    format!("unknown object `{name}` in the {} dictionary", self.dict.name()),
                    "unknown object",
                    Some(help),
                );
                None
            }
        }
    }

    /// True when `def` can be read; otherwise says so at `span`.
    pub(super) fn readable(&mut self, def: &ObjectDef, span: &Span) -> bool {
        let problem = || format!("{} is write-only and cannot be read", def.name);
        self.allowed(def.readable(), span, problem, "write-only")
    }

    /// True when `def` can be written; otherwise says so at `span` ("cannot be `verb`").
    pub(super) fn writable(&mut self, def: &ObjectDef, span: &Span, verb: &str) -> bool {
        let problem = || format!("{} is read-only and cannot be {verb}", def.name);
        self.allowed(def.writable(), span, problem, "read-only")
    }

    /// `allowed`, said at `span` as `problem` when it is not.
    fn allowed(&mut self, allowed: bool, span: &Span, problem: impl FnOnce() -> String, label: &str) -> bool {
        if !allowed {
            self.problem(span, problem(), label, None);
        }
        allowed
    }

    /// One readable object's name or a list of them, given as the value of `what`.
    pub(super) fn object_list(&mut self, node: &YamlNode, what: &str) -> Option<Vec<ObjectRef>> {
        let items = match &node.value {
            YamlValue::Seq(items) => items.as_slice(),
            YamlValue::Str(_) => std::slice::from_ref(node),
            _ => {
                self.r
                    .report(expected(node, what, "an object name or a list of them"));
                return None;
            }
        };
        let mut out = Vec::new();
        let mut ok = true;
        for item in items {
            let Some(name) = self.r.scalar_text(item, "an object name") else {
                ok = false;
                continue;
            };
            match self.object(&name, &item.span) {
                Some((def, r)) if self.readable(&def, &item.span) => out.push(r),
                _ => ok = false,
            }
        }
        if out.is_empty() && ok {
            return self.refuse(&node.span, "no object named", "empty", None);
        }
        ok.then_some(out)
    }
}
