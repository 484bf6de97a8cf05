//! The one field reader of every loader (recipes, dictionaries, limits files): checks a
//! mapping's keys against its [`Shape`] (unknown keys with did-you-mean, keys given twice,
//! required keys missing) and reads typed values (text, true/false, whole numbers, finite
//! numbers, lists), recording each problem as a located [`Diagnostic`] and going on, so a
//! file reports them all. What a value means (a unit, an object, a duration) is the
//! loader's to check; this must not know any file format.

use super::diagnostic::Diagnostic;
use super::diagnostics::Diagnostics;
use super::did_you_mean::{did_you_mean, suggestion_text};
use super::fields::Fields;
use super::shape::Shape;
use super::span::{Span, Spanned};
use super::yaml_node::{YamlNode, YamlValue};
use std::collections::HashSet;

/// Reads nodes, recording problems in the diagnostics it was given.
pub struct Reader<'d> {
    out: &'d mut Diagnostics,
}

impl<'d> Reader<'d> {
    pub fn new(out: &'d mut Diagnostics) -> Self {
        Reader { out }
    }

    /// Records a problem.
    pub fn report(&mut self, d: Diagnostic) {
        self.out.push(d);
    }

    /// Records a problem at `span`.
    pub fn problem(
        &mut self,
        span: &Span,
        message: impl Into<String>,
        label: impl Into<String>,
        help: Option<String>,
    ) {
        self.report(Diagnostic::at(span, message, label).with_optional_help(help));
    }

    /// How many problems are recorded so far (to tell whether a part added any).
    pub fn count(&self) -> usize {
        self.out.len()
    }

    /// The diagnostics, for a reader of a nested file that records into the same ones.
    pub fn diagnostics(&mut self) -> &mut Diagnostics {
        self.out
    }

    /// `node` as a mapping of `shape`: a node that is not a mapping, unknown keys (with
    /// did-you-mean), keys given twice and missing required keys are reported. `None` only
    /// when it is not a mapping; the other problems leave the fields readable.
    pub fn fields<'n>(&mut self, node: &'n YamlNode, shape: &Shape) -> Option<Fields<'n>> {
        let Some(entries) = node.entries() else {
            let help = shape.help.clone();
            self.report(
                expected(node, shape.what, "a mapping (`key: value` lines)").with_optional_help(help),
            );
            return None;
        };
        let what = shape.what;
        let mut seen = HashSet::new();
        for (k, _) in entries {
            if !seen.insert(k.value.as_str()) {
                self.problem(
                    &k.span,
                    format!("`{}` is given twice in {what}", k.value),
                    "again here",
                    None,
                );
            }
            let Some(allowed) = &shape.allowed else {
                continue;
            };
            if !allowed.contains(&k.value.as_str()) {
                let help = suggestion_text(&did_you_mean(&k.value, allowed.iter().copied()))
                    .unwrap_or_else(|| format!("the keys of {what} are: {}", allowed.join(", ")));
                self.problem(
                    &k.span,
                    format!("unknown key `{}` in {what}", k.value),
                    "unknown key",
                    Some(help),
                );
            }
        }
        let fields = Fields {
            node,
            entries,
            nothing_is_absent: shape.nothing_is_absent,
        };
        for (key, meaning) in &shape.required {
            if fields.get(key).is_some() {
                continue;
            }
            // Written with nothing after it: point at the key, not the whole mapping.
            let place = entries
                .iter()
                .find(|(k, _)| k.value == *key)
                .map_or(&node.span, |(k, _)| &k.span);
            self.problem(
                place,
                format!("{what} has no `{key}`"),
                format!("`{key}` missing"),
                meaning.as_ref().map(|m| format!("add `{key}:` with {m}")),
            );
        }
        Some(fields)
    }

    /// A text value (quoted or not); numbers and true/false are refused.
    pub fn text(&mut self, node: &YamlNode, what: &str) -> Option<String> {
        match &node.value {
            YamlValue::Str(s) => Some(s.clone()),
            _ => self.refuse(expected(node, what, "text")),
        }
    }

    /// A value written as text, a number or true/false, as text: `6000` is `"6000"`.
    pub fn scalar_text(&mut self, node: &YamlNode, what: &str) -> Option<String> {
        match node.as_text() {
            Some(t) => Some(t),
            None => self.refuse(expected(node, what, "text or a number")),
        }
    }

    /// `true` or `false`.
    pub fn bool(&mut self, node: &YamlNode, what: &str) -> Option<bool> {
        match node.value {
            YamlValue::Bool(b) => Some(b),
            _ => self.refuse(expected(node, what, "true or false")),
        }
    }

    /// A whole number from `lo` to `hi` (written in decimal or `0x` hex).
    pub fn int(&mut self, node: &YamlNode, what: &str, lo: i64, hi: i64) -> Option<i64> {
        match node.value {
            YamlValue::Int(i) if (lo..=hi).contains(&i) => Some(i),
            YamlValue::Int(i) => {
                // The range in the notation the number was written in.
                let hex = node.written().starts_with("0x") || node.written().starts_with("0X");
                let range = if hex {
                    format!("{lo}..={hi} (0x{lo:x}..=0x{hi:x})")
                } else {
                    format!("{lo}..={hi}")
                };
                self.refuse(Diagnostic::at(
                    &node.span,
                    format!("{what} {i} is out of range {range}"),
                    "out of range",
                ))
            }
            _ => self.refuse(expected(node, what, "a whole number (decimal or 0x hex)")),
        }
    }

    /// A finite number; `help` says what to write instead of `.nan` or `.inf`.
    pub fn number(&mut self, node: &YamlNode, what: &str, help: &str) -> Option<f64> {
        if self.refuse_non_finite(node, what, help) {
            return None;
        }
        match node.value {
            YamlValue::Int(i) => Some(i as f64),
            YamlValue::Float(f) => Some(f),
            _ => self.refuse(expected(node, what, "a number")),
        }
    }

    /// Refuses a number YAML reads as not finite (`.nan`, `.inf`, `1e400`), naming it as
    /// written; true when it was refused. Numbers with units are text that looks finite
    /// here, so loaders reading quantities call this before parsing them.
    pub fn refuse_non_finite(&mut self, node: &YamlNode, what: &str, help: &str) -> bool {
        let refused = node.is_non_finite_number();
        if refused {
            self.problem(
                &node.span,
                format!("{what} must be a finite number, not `{}`", node.written()),
                "not finite",
                Some(help.to_string()),
            );
        }
        refused
    }

    /// The items of a list; `wanted` describes it for the message (`a list of objects`).
    pub fn list<'n>(&mut self, node: &'n YamlNode, what: &str, wanted: &str) -> Option<&'n [YamlNode]> {
        match &node.value {
            YamlValue::Seq(items) => Some(items),
            _ => self.refuse(expected(node, what, wanted)),
        }
    }

    /// The entries of a mapping whose keys are free (names the file chooses); `wanted`
    /// describes it for the message, with an example.
    pub fn mapping<'n>(
        &mut self,
        node: &'n YamlNode,
        what: &str,
        wanted: &str,
    ) -> Option<&'n [(Spanned<String>, YamlNode)]> {
        match node.entries() {
            Some(entries) => Some(entries),
            None => self.refuse(expected(node, what, wanted)),
        }
    }

    fn refuse<T>(&mut self, d: Diagnostic) -> Option<T> {
        self.report(d);
        None
    }
}

/// `{what} must be {wanted}, found {kind}`, labelled with what was expected.
pub fn expected(node: &YamlNode, what: &str, wanted: &str) -> Diagnostic {
    Diagnostic::at(
        &node.span,
        format!("{what} must be {wanted}, found {}", node.kind()),
        format!("expected {}", wanted.split(" (").next().unwrap_or(wanted)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Source;

    fn root(text: &str) -> YamlNode {
        YamlNode::parse(&Source::new("t.yaml", text)).expect("YAML")
    }

    /// The help of the first problem.
    fn first_help(out: &Diagnostics) -> Option<&str> {
        out.iter().next().and_then(Diagnostic::help)
    }

    fn messages(out: &Diagnostics) -> Vec<String> {
        out.iter().map(Diagnostic::located).collect()
    }

    #[test]
    fn keys_are_checked_against_the_shape() {
        let node = root("objcts: [a]\nevery: 1 s\n");
        let mut out = Diagnostics::new();
        let shape = Shape::new("this sample", &["objects", "every", "for"]).require(&["objects", "for"]);
        let f = Reader::new(&mut out).fields(&node, &shape).expect("a mapping");
        assert_eq!(f.get("every").map(YamlNode::written), Some("1 s"));
        assert_eq!(
            messages(&out),
            [
                "t.yaml:1:1: unknown key `objcts` in this sample",
                "t.yaml:1:1: this sample has no `objects`",
                "t.yaml:1:1: this sample has no `for`",
            ]
        );
        assert_eq!(first_help(&out), Some("did you mean `objects`?"));
    }

    #[test]
    fn nothing_is_absent_only_when_the_shape_says_so() {
        let node = root("name:\nsize: 3\n");
        let mut out = Diagnostics::new();
        let strict = Shape::new("an object", &["name", "size"]).require_as("name", "its name");
        let f = Reader::new(&mut out)
            .fields(&node, &strict.clone().nothing_is_absent())
            .unwrap();
        assert!(f.get("name").is_none());
        assert_eq!(messages(&out), ["t.yaml:1:1: an object has no `name`"]);
        assert_eq!(first_help(&out), Some("add `name:` with its name"));
        let mut out = Diagnostics::new();
        let f = Reader::new(&mut out).fields(&node, &strict).unwrap();
        assert!(f.get("name").is_some_and(YamlNode::is_null) && out.is_empty());
    }

    #[test]
    fn keys_given_twice_and_free_keys() {
        // The parser refuses a key given twice, so the tree is built by hand.
        let node = root("a: 1\nb: 2\n");
        let mut twice = node.clone();
        if let YamlValue::Map(entries) = &mut twice.value {
            entries[1].0.value = "a".into();
        }
        let mut out = Diagnostics::new();
        Reader::new(&mut out).fields(&twice, &Shape::any_keys("this set"));
        assert_eq!(messages(&out), ["t.yaml:2:1: `a` is given twice in this set"]);
        let mut out = Diagnostics::new();
        let unknown = Reader::new(&mut out).fields(&node, &Shape::new("the limits file", &["max_speed"]));
        assert!(unknown.is_some());
        assert_eq!(
            first_help(&out),
            Some("the keys of the limits file are: max_speed")
        );
    }

    #[test]
    fn typed_values_say_what_was_expected() {
        let node = root("t: [1]\nb: yes\ni: 70000\nn: .inf\nl: x\nm: 5\nh: 0x10000\n");
        let mut out = Diagnostics::new();
        let mut r = Reader::new(&mut out);
        let f = r.fields(&node, &Shape::any_keys("the file")).unwrap();
        let get = |k| f.get(k).unwrap();
        assert_eq!(r.text(get("t"), "`t`"), None);
        assert_eq!(r.scalar_text(get("m"), "`m`").as_deref(), Some("5"));
        assert_eq!(r.bool(get("b"), "`b`"), None);
        assert_eq!(r.int(get("i"), "`i`", 0, 0xFFFF), None);
        assert_eq!(r.int(get("m"), "`m`", 0, 0xFFFF), Some(5));
        assert_eq!(r.int(get("h"), "`h`", 0, 0xFFFF), None);
        assert_eq!(r.number(get("n"), "`n`", "write 1"), None);
        assert_eq!(r.number(get("m"), "`m`", "write 1"), Some(5.0));
        assert!(r.list(get("l"), "`l`", "a list").is_none());
        assert_eq!(
            messages(&out),
            [
                "t.yaml:1:4: `t` must be text, found a list",
                "t.yaml:2:4: `b` must be true or false, found text",
                "t.yaml:3:4: `i` 70000 is out of range 0..=65535",
                "t.yaml:7:4: `h` 65536 is out of range 0..=65535 (0x0..=0xffff)",
                "t.yaml:4:4: `n` must be a finite number, not `.inf`",
                "t.yaml:5:4: `l` must be a list, found text",
            ]
        );
        assert_eq!(out.iter().next().map(Diagnostic::label), Some("expected text"));
    }
}
