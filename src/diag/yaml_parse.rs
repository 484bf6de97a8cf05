//! YAML text → a [`YamlNode`] tree whose every node knows its place, within reading limits
//! (nesting depth, number of values, alias copies) that hold before memory or the stack
//! run out. Parsing only; no meaning is given to any key here.

use super::diagnostic::Diagnostic;
use super::source::Source;
use super::span::{Span, Spanned};
use super::yaml_node::{YamlNode, YamlValue};
use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use std::fmt;
use std::sync::Arc;

/// YAML that could not be parsed at all, or that goes over a reading limit.
#[derive(Debug, Clone)]
pub struct YamlError {
    pub message: String,
    /// Where the parser stopped; `None` when it could not say.
    pub span: Option<Span>,
    /// The text is YAML but goes over one of the limits below (an alias bomb, a file of
    /// too many values): the message says which, and is not a syntax error.
    pub over_limit: bool,
    /// What to do, for limits (syntax errors get the caller's help).
    pub help: Option<String>,
}

impl YamlError {
    /// The error as a diagnostic: `not valid YAML: …` with `syntax_help` for a syntax
    /// error, the limit's own sentence and help for a limit.
    pub fn diagnostic(self, path: &str, syntax_help: Option<String>) -> Diagnostic {
        let message = if self.over_limit {
            self.message
        } else {
            format!("not valid YAML: {}", self.message)
        };
        let d = match &self.span {
            Some(span) => Diagnostic::at(span, message, "here"),
            None => Diagnostic::unlocated(path, message),
        };
        d.with_optional_help(self.help.or(syntax_help))
    }
}

/// Deepest nesting of lists and mappings. Recipes nest a few levels (each `repeat` adds
/// three); the parse and the tree walks recurse per level, and at 64 levels a debug build
/// overflowed a 2 MiB thread stack, so 32 keeps them far from the stack's end.
pub const MAX_DEPTH: usize = 32;
/// Most values (text, numbers, lists, mappings) in one file, aliases expanded. The largest
/// real recipes and dictionaries have a few thousand.
pub const MAX_VALUES: usize = 200_000;
/// Most values that aliases (`*name`) may copy in one file: room to reuse a block of steps
/// many times, but an alias bomb ("billion laughs", each alias doubling the last) stops
/// after a few milliseconds instead of filling the memory.
pub const MAX_ALIAS_COPIES: usize = 10_000;

impl YamlNode {
    /// Parses the text of `source` into a spanned tree; text of only blanks and comments is
    /// nothing, at the start of the file.
    pub fn parse(source: &Arc<Source>) -> Result<YamlNode, YamlError> {
        let text = source.text();
        if text.trim().is_empty() {
            return Ok(YamlNode {
                value: YamlValue::Null,
                span: Span::start_of(source),
            });
        }
        // YAML 1.1 booleans (`yes`, `on`, `n`) would turn names and values into true/false.
        // `.nan` and `.inf` stay text, so that the reader refuses them where they are used,
        // in its own words, instead of the whole file failing as "not valid YAML".
        let options = serde_saphyr::options! {
            strict_booleans: true,
            non_finite_float_policy: serde_saphyr::NonFiniteFloatPolicy::AsString,
            budget: serde_saphyr::budget! {
                max_depth: MAX_DEPTH,
                max_nodes: MAX_VALUES,
            },
            alias_limits: serde_saphyr::alias_limits! {
                max_total_replayed_events: MAX_ALIAS_COPIES,
            },
        };
        match serde_saphyr::from_str_with_options::<serde_saphyr::Spanned<Node>>(text, options) {
            Ok(root) => Ok(convert(root, source)),
            Err(e) => Err(error_of(&e, source)),
        }
    }
}

fn error_of(e: &serde_saphyr::Error, source: &Arc<Source>) -> YamlError {
    use serde_saphyr::MessageFormatter;
    let span = e
        .location()
        .filter(|loc| loc.line() > 0)
        .map(|loc| span_of_location(&loc, source));
    let known = limit_message(e)
        .map(|said| (said, true))
        .or_else(|| own_words(e).map(|said| (said, false)));
    if let Some(((message, help), over_limit)) = known {
        return YamlError {
            message,
            span,
            over_limit,
            help: Some(help),
        };
    }
    // The caller renders its own snippet, so only the sentence is kept, on one line.
    let message: String = serde_saphyr::DefaultMessageFormatter
        .format_message(e.without_snippet())
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    YamlError {
        message,
        span,
        over_limit: false,
        help: None,
    }
}

/// The parser's sentences that name its own options or say nothing a user can act on,
/// in drivescript's words with what to do; `None` for the others.
fn own_words(e: &serde_saphyr::Error) -> Option<(String, String)> {
    use serde_saphyr::Error as E;
    use serde_saphyr::MessageFormatter;
    let mut e = e;
    while let E::AliasError { error, .. } | E::WithSnippet { error, .. } = e {
        e = error;
    }
    if let E::DuplicateMappingKey { key, .. } = e {
        let key = key.as_deref().unwrap_or("this key");
        return Some((
            format!("`{key}` is written twice in the same mapping"),
            format!(
                "keep one `{key}:` (each key once per mapping; for two steps, start each with its own `- `)"
            ),
        ));
    }
    let text = serde_saphyr::DefaultMessageFormatter.format_message(e);
    if text.contains("mapping values are not allowed") {
        return Some((
            "a `key:` where the lines above allow none".into(),
            "indent it under the key it belongs to, start it with `- ` if it is a list item, or check the line above for a missing `key:`".into(),
        ));
    }
    None
}

/// A plain sentence and help for a reading limit, instead of the parser's internal names
/// (`budget breached: Nodes { nodes: 200001 }`); `None` for other errors.
fn limit_message(e: &serde_saphyr::Error) -> Option<(String, String)> {
    use serde_saphyr::budget::BudgetBreach as B;
    use serde_saphyr::Error as E;
    let mut e = e;
    while let E::AliasError { error, .. } | E::WithSnippet { error, .. } = e {
        e = error;
    }
    let aliases = || {
        (
            format!(
                "refused: the aliases (`*name`) in this file copy more than {MAX_ALIAS_COPIES} values, as an alias bomb does"
            ),
            "to run steps several times use `repeat` or `include`, not aliases of aliases".to_string(),
        )
    };
    let too_many = || {
        (
            format!("refused: this file has more than {MAX_VALUES} YAML values (aliases expanded)"),
            "recipes and dictionaries have a few thousand; write repetition as `repeat` steps and split a generated file into included files".to_string(),
        )
    };
    let other = |what: String| {
        (
            format!("refused: {what}"),
            "check that the path names the file you meant".to_string(),
        )
    };
    Some(match e {
        E::AliasReplayLimitExceeded { .. }
        | E::AliasExpansionLimitExceeded { .. }
        | E::AliasReplayStackDepthExceeded { .. }
        | E::AliasReplayCounterOverflow { .. } => aliases(),
        E::Budget { breach, .. } => match breach {
            B::Aliases { .. }
            | B::Anchors { .. }
            | B::AliasAnchorRatio { .. }
            | B::RecordedAnchorEvents { .. }
            | B::RecordedAnchorBytes { .. } => aliases(),
            B::Nodes { .. } | B::Events { .. } => too_many(),
            B::Depth { .. } => (
                format!("refused: lists and mappings nest deeper than {MAX_DEPTH} levels"),
                "recipes nest a few levels; check the indentation and the brackets".to_string(),
            ),
            B::Documents { .. } => other("this file holds too many YAML documents (`---`)".into()),
            B::ScalarBytes { .. } | B::InputBytes { .. } => {
                other("the text in this file is larger than the YAML reader accepts".into())
            }
            _ => other("this file goes over a limit of the YAML reader".into()),
        },
        _ => return None,
    })
}

fn span_of_location(loc: &serde_saphyr::Location, source: &Arc<Source>) -> Span {
    let text = source.text();
    let line = loc.line() as usize;
    let column = loc.column() as usize;
    let span = loc.span();
    let offset = span
        .byte_offset()
        .map(|o| o as usize)
        .unwrap_or_else(|| offset_of(text, line, column));
    let len = span.byte_len().map(|l| l as usize).unwrap_or(0);
    Span::new(source, offset, len, line, column)
}

/// Byte offset of a 1-based line and character column.
fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let mut offset = 0;
    for (i, l) in text.split_inclusive('\n').enumerate() {
        if i + 1 == line {
            return offset
                + l.char_indices()
                    .nth(column.saturating_sub(1))
                    .map(|(b, _)| b)
                    .unwrap_or(l.len());
        }
        offset += l.len();
    }
    text.len()
}

fn convert(node: serde_saphyr::Spanned<Node>, source: &Arc<Source>) -> YamlNode {
    let span = span_of_location(&node.referenced, source);
    let value = match node.value {
        Node::Null => YamlValue::Null,
        Node::Bool(b) => YamlValue::Bool(b),
        Node::Int(i) => YamlValue::Int(i),
        Node::Float(f) => YamlValue::Float(f),
        Node::Str(s) => YamlValue::Str(s),
        Node::Seq(items) => YamlValue::Seq(items.into_iter().map(|n| convert(n, source)).collect()),
        Node::Map(entries) => YamlValue::Map(
            entries
                .into_iter()
                .map(|(k, v)| {
                    let key_span = span_of_location(&k.referenced, source);
                    let key = match k.value {
                        Node::Str(s) => s,
                        other => plain(&other),
                    };
                    (Spanned::new(key, key_span), convert(v, source))
                })
                .collect(),
        ),
    };
    YamlNode { value, span }
}

fn plain(node: &Node) -> String {
    match node {
        Node::Null => "null".into(),
        Node::Bool(b) => b.to_string(),
        Node::Int(i) => i.to_string(),
        Node::Float(f) => f.to_string(),
        Node::Str(s) => s.clone(),
        Node::Seq(_) | Node::Map(_) => "(a list or mapping as a key)".into(),
    }
}

/// The raw tree as serde-saphyr hands it over, with its locations.
enum Node {
    Null,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Seq(Vec<serde_saphyr::Spanned<Node>>),
    Map(Vec<(serde_saphyr::Spanned<Node>, serde_saphyr::Spanned<Node>)>),
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NodeVisitor)
    }
}

struct NodeVisitor;

impl<'de> Visitor<'de> for NodeVisitor {
    type Value = Node;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any YAML value")
    }
    fn visit_unit<E>(self) -> Result<Node, E> {
        Ok(Node::Null)
    }
    fn visit_none<E>(self) -> Result<Node, E> {
        Ok(Node::Null)
    }
    fn visit_bool<E>(self, v: bool) -> Result<Node, E> {
        Ok(Node::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Node, E> {
        Ok(Node::Int(v))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Node, E> {
        Ok(i64::try_from(v).map(Node::Int).unwrap_or(Node::Float(v as f64)))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Node, E> {
        Ok(Node::Float(v))
    }
    fn visit_str<E>(self, v: &str) -> Result<Node, E> {
        Ok(Node::Str(v.to_string()))
    }
    fn visit_string<E>(self, v: String) -> Result<Node, E> {
        Ok(Node::Str(v))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Node, A::Error> {
        let mut out = Vec::new();
        while let Some(item) = seq.next_element()? {
            out.push(item);
        }
        Ok(Node::Seq(out))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Node, A::Error> {
        let mut out = Vec::new();
        while let Some(key) = map.next_key()? {
            let value = map.next_value()?;
            out.push((key, value));
        }
        Ok(Node::Map(out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn parse(text: &str) -> Result<YamlNode, YamlError> {
        YamlNode::parse(&Source::new("t.yaml", text))
    }

    fn map(node: &YamlNode) -> &[(Spanned<String>, YamlNode)] {
        node.entries().unwrap_or_else(|| panic!("not a map: {node:?}"))
    }

    fn line(e: &YamlError) -> usize {
        e.span.as_ref().map_or(0, Span::line)
    }

    #[test]
    fn every_node_knows_its_place() {
        let text = "name: Spindle\nsteps:\n  - shutdown\n  - set: { speed_setpoint: \"{{speed}}\" }\n  - dwell: 10\n";
        let root = parse(text).unwrap();
        let m = map(&root);
        assert_eq!(m[0].0.value, "name");
        assert!(matches!(&m[0].1.value, YamlValue::Str(s) if s == "Spindle"));
        assert_eq!((m[0].1.span.line(), m[0].1.span.column()), (1, 7));
        let YamlValue::Seq(steps) = &m[1].1.value else {
            panic!()
        };
        assert_eq!(steps[0].span.line(), 3);
        let set = map(&steps[1]);
        let inner = map(&set[0].1);
        let value = &inner[0].1;
        assert_eq!(value.written(), "\"{{speed}}\"");
        assert_eq!((value.span.line(), value.span.column()), (4, 28));
        assert!(matches!(map(&steps[2])[0].1.value, YamlValue::Int(10)));
    }

    #[test]
    fn keys_stay_text_and_booleans_are_strict() {
        let root = parse("family: sd2\nobjects:\n  - index: 0x4F\n    n: yes\n").unwrap();
        let items = match &map(&root)[1].1.value {
            YamlValue::Seq(items) => items,
            other => panic!("{other:?}"),
        };
        assert_eq!((items[0].span.line(), items[0].span.column()), (3, 5));
        let (k, v) = &map(&items[0])[0];
        assert_eq!(k.value, "index");
        assert!(matches!(v.value, YamlValue::Int(0x4F)));
        assert_eq!(
            (v.span.line(), v.span.column(), v.span.offset(), v.span.len()),
            (3, 12, 32, 4)
        );
        let (k, v) = &map(&items[0])[1];
        assert_eq!(k.value, "n");
        assert!(matches!(&v.value, YamlValue::Str(s) if s == "yes"));
    }

    /// A whole number beyond YAML's 64-bit integers reaches the loaders as written, not as
    /// the float the parser rounds it to; other numbers as before.
    #[test]
    fn whole_numbers_beyond_64_bits_are_text_as_written() {
        let root = parse("a: -9223372036854775809\nb: { c: 18446744073709551616 }\nd: 1.5\ne: 1e3\nf: 9223372036854775807\n").unwrap();
        let m = map(&root);
        assert!(matches!(m[0].1.value, YamlValue::Float(_)), "{:?}", m[0].1.value);
        assert_eq!(m[0].1.as_text().as_deref(), Some("-9223372036854775809"));
        assert_eq!(
            map(&m[1].1)[0].1.as_text().as_deref(),
            Some("18446744073709551616")
        );
        assert_eq!(m[2].1.as_text().as_deref(), Some("1.5"));
        assert_eq!(m[3].1.as_text().as_deref(), Some("1000"));
        assert_eq!(m[4].1.as_text().as_deref(), Some("9223372036854775807"));
    }

    #[test]
    fn syntax_errors_are_located() {
        let e = parse("a: [1, 2\nb: 3").unwrap_err();
        assert_eq!(line(&e), 2, "{e:?}");
        assert!(!e.message.contains("-->"), "{}", e.message);
        let d = parse("a: [1\nb: 2\n").unwrap_err().diagnostic("t.yaml", None);
        assert_eq!((d.line(), d.column()), (2, 2));
        assert!(d.message().starts_with("not valid YAML: "), "{}", d.message());
        let e = parse("a: 1\na: 2\n").unwrap_err();
        assert_eq!(line(&e), 2);
        assert_eq!(e.message, "`a` is written twice in the same mapping");
        assert!(!e.help.unwrap_or_default().contains("DuplicateKeyPolicy"));
        // The parser's sentence for a `key:` where none can be is said in our words.
        let e = parse("name: x\n  - a\n  - b: 1\n").unwrap_err();
        assert!(
            !e.message.contains("not allowed in this context"),
            "{}",
            e.message
        );
    }

    #[test]
    fn alias_bombs_are_bounded() {
        let mut text = String::from("a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n");
        for i in 1..12 {
            text.push_str(&format!(
                "a{i}: &a{i} [*a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}]\n",
                p = i - 1
            ));
        }
        let e = parse(&text).unwrap_err();
        assert!(e.over_limit, "{e:?}");
        assert!(e.message.contains("aliases (`*name`)"), "{}", e.message);
        assert!(!e.message.contains('{'), "internal names leak: {}", e.message);
        assert!(line(&e) > 1, "located: {e:?}");
    }

    #[test]
    fn limits_are_said_in_plain_words() {
        let deep = format!("{}1{}", "[".repeat(MAX_DEPTH + 2), "]".repeat(MAX_DEPTH + 2));
        let e = parse(&deep).unwrap_err();
        assert!(e.over_limit && e.message.contains("nest deeper than 32"), "{e:?}");
        // Far deeper than the limit, in a test thread's small stack: refused, no overflow.
        let e = parse(&format!("{}1{}", "[".repeat(5000), "]".repeat(5000))).unwrap_err();
        assert!(!e.message.contains('{'), "{e:?}");
        let e = parse(&"- ".repeat(5000)).unwrap_err();
        assert!(!e.message.contains('{'), "{e:?}");
        let many = format!("[{}]", vec!["1"; MAX_VALUES + 1].join(","));
        let e = parse(&many).unwrap_err();
        assert!(
            e.over_limit && e.message.contains("more than 200000 YAML values"),
            "{e:?}"
        );
        assert!(!e.message.contains("Nodes"), "{}", e.message);
        let e = parse("a: [1").unwrap_err();
        assert!(!e.over_limit && e.help.is_none(), "{e:?}");
    }

    #[test]
    fn blank_text_is_nothing_at_the_start() {
        let root = parse("  \n").unwrap();
        assert!(root.is_null());
        assert_eq!((root.span.line(), root.span.column()), (1, 1));
    }

    proptest! {
        #[test]
        fn never_panics(text in "\\PC{0,200}") {
            let _ = parse(&text);
        }

        #[test]
        fn never_panics_on_yamlish(text in "[a-z:\\-\\[\\]{}, \\n\"'&*!|>#0-9]{0,200}") {
            let _ = parse(&text);
        }
    }
}
