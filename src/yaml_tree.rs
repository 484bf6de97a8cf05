//! YAML text → a tree of nodes that each know where they stand in the file (byte offset,
//! length, line, column). Recipe validation walks this tree instead of deserialising
//! straight into structs, so it can report every problem of a file at once, each at its
//! place. Parsing only; no meaning is given to any key here.

use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use std::fmt;

/// Where a node stands in its file. `offset`/`len` are in bytes; `line`/`column` 1-based.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Span {
    pub offset: usize,
    pub len: usize,
    pub line: usize,
    pub column: usize,
}

impl Span {
    /// For miette labels.
    pub fn source_span(&self) -> miette::SourceSpan {
        (self.offset, self.len).into()
    }
}

/// A value with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Spanned<T> {
    pub value: T,
    pub span: Span,
}

impl<T> Spanned<T> {
    pub fn new(value: T, span: Span) -> Self {
        Spanned { value, span }
    }
}

/// A YAML node. Mapping entries keep their order and their keys' spans.
#[derive(Debug, Clone, PartialEq)]
pub enum YamlNode {
    Null,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Seq(Vec<Spanned<YamlNode>>),
    Map(Vec<(Spanned<String>, Spanned<YamlNode>)>),
}

impl YamlNode {
    /// What kind of node this is, for messages: "a list", "a number".
    pub fn kind(&self) -> &'static str {
        match self {
            YamlNode::Null => "nothing",
            YamlNode::Bool(_) => "true/false",
            YamlNode::Int(_) | YamlNode::Float(_) => "a number",
            YamlNode::Str(_) => "text",
            YamlNode::Seq(_) => "a list",
            YamlNode::Map(_) => "a mapping",
        }
    }

    /// The node as text: strings as they are, numbers and booleans written out (YAML turns
    /// `6000` into a number, but a recipe value `6000` means the same as `"6000"`).
    pub fn as_text(&self) -> Option<String> {
        match self {
            YamlNode::Str(s) => Some(s.clone()),
            YamlNode::Int(i) => Some(i.to_string()),
            YamlNode::Float(f) => Some(f.to_string()),
            YamlNode::Bool(b) => Some(b.to_string()),
            _ => None,
        }
    }
}

/// YAML that could not be parsed at all, or that goes over a reading limit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct YamlError {
    pub message: String,
    pub span: Span,
    /// The text is YAML but goes over one of the limits below (an alias bomb, a file of
    /// too many values): the message says which, and is not a syntax error.
    pub over_limit: bool,
    /// What to do, for limits (syntax errors get the caller's help).
    pub help: Option<String>,
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

/// Parses `text` into a spanned tree.
pub fn parse(text: &str) -> Result<Spanned<YamlNode>, YamlError> {
    if text.trim().is_empty() {
        return Ok(Spanned::new(YamlNode::Null, Span::default()));
    }
    // YAML 1.1 booleans (`yes`, `on`, `n`) would turn names and values into true/false.
    // `.nan` and `.inf` stay text, so that the reader refuses them where they are used, in
    // its own words, instead of the whole file failing as "not valid YAML".
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
        Ok(root) => Ok(convert(root, text)),
        Err(e) => Err(error_of(&e, text)),
    }
}

fn error_of(e: &serde_saphyr::Error, text: &str) -> YamlError {
    use serde_saphyr::MessageFormatter;
    let span = e
        .location()
        .filter(|loc| loc.line() > 0)
        .map(|loc| span_of_location(&loc, text))
        .unwrap_or_default();
    if let Some((message, help)) = limit_message(e) {
        return YamlError {
            message,
            span,
            over_limit: true,
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

fn span_of_location(loc: &serde_saphyr::Location, text: &str) -> Span {
    let line = loc.line() as usize;
    let column = loc.column() as usize;
    let span = loc.span();
    let offset = span
        .byte_offset()
        .map(|o| o as usize)
        .unwrap_or_else(|| offset_of(text, line, column));
    let len = span.byte_len().map(|l| l as usize).unwrap_or(0);
    Span {
        offset: offset.min(text.len()),
        len: len.min(text.len().saturating_sub(offset)),
        line,
        column,
    }
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

fn convert(node: serde_saphyr::Spanned<Node>, text: &str) -> Spanned<YamlNode> {
    let span = span_of_location(&node.referenced, text);
    let value = match node.value {
        Node::Null => YamlNode::Null,
        Node::Bool(b) => YamlNode::Bool(b),
        Node::Int(i) => YamlNode::Int(i),
        Node::Float(f) => YamlNode::Float(f),
        Node::Str(s) => YamlNode::Str(s),
        Node::Seq(items) => YamlNode::Seq(items.into_iter().map(|n| convert(n, text)).collect()),
        Node::Map(entries) => YamlNode::Map(
            entries
                .into_iter()
                .map(|(k, v)| {
                    let key_span = span_of_location(&k.referenced, text);
                    let key = match k.value {
                        Node::Str(s) => s,
                        other => plain(&other),
                    };
                    (Spanned::new(key, key_span), convert(v, text))
                })
                .collect(),
        ),
    };
    Spanned::new(value, span)
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

    fn map(node: &Spanned<YamlNode>) -> &Vec<(Spanned<String>, Spanned<YamlNode>)> {
        match &node.value {
            YamlNode::Map(m) => m,
            other => panic!("not a map: {other:?}"),
        }
    }

    #[test]
    fn every_node_knows_its_place() {
        let text = "name: Spindle\nsteps:\n  - shutdown\n  - set: { speed_setpoint: \"{{speed}}\" }\n  - dwell: 10\n";
        let root = parse(text).unwrap();
        let m = map(&root);
        assert_eq!(m[0].0.value, "name");
        assert_eq!(m[0].1.value, YamlNode::Str("Spindle".into()));
        assert_eq!((m[0].1.span.line, m[0].1.span.column), (1, 7));
        let YamlNode::Seq(steps) = &m[1].1.value else {
            panic!()
        };
        assert_eq!(steps[0].span.line, 3);
        let set = map(&steps[1]);
        let inner = map(&set[0].1);
        let value = &inner[0].1;
        assert_eq!(
            &text[value.span.offset..value.span.offset + value.span.len],
            "\"{{speed}}\""
        );
        assert_eq!((value.span.line, value.span.column), (4, 28));
        let dwell = map(&steps[2]);
        assert_eq!(dwell[0].1.value, YamlNode::Int(10));
    }

    #[test]
    fn syntax_errors_are_located() {
        let e = parse("a: [1, 2\nb: 3").unwrap_err();
        assert_eq!(e.span.line, 2, "{e:?}");
        assert!(!e.message.contains("-->"), "{}", e.message);
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
        assert!(e.span.line > 1, "located: {e:?}");
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
    fn empty_text_is_null() {
        assert_eq!(parse("  \n").unwrap().value, YamlNode::Null);
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
