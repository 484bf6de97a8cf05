//! A dictionary file as a YAML tree in which every node keeps its place in the text.
//! serde_saphyr parses; each node is read as `Spanned<RawNode>`, so line, column and byte
//! span survive, and the reader can then report every problem of a file rather than the
//! first one serde meets. Only parsing: no I/O, no knowledge of objects.

use super::dictionary_error::DictionaryError;
use super::text_span::{byte_len_of, byte_offset_of, SourceFile, TextSpan};
use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_saphyr::{MessageFormatter, Spanned};
use std::fmt;
use std::sync::Arc;

/// One node and where it is written. Mappings and lists point at their first character.
#[derive(Debug, Clone)]
pub(crate) struct YamlNode {
    pub kind: NodeKind,
    pub span: TextSpan,
}

#[derive(Debug, Clone)]
pub(crate) enum NodeKind {
    Null,
    /// `true`/`false` (no dictionary key takes one, so the value is not kept).
    Bool,
    Int(i128),
    Float(f64),
    Str(String),
    Seq(Vec<YamlNode>),
    /// Entries in file order; keys are always text.
    Map(Vec<(YamlNode, YamlNode)>),
}

impl YamlNode {
    /// Parses the whole file. YAML syntax errors (and duplicate keys, which the parser
    /// refuses) stop here with one located error.
    pub fn parse(file: &Arc<SourceFile>) -> Result<YamlNode, DictionaryError> {
        if file.text.trim().is_empty() {
            return Err(
                DictionaryError::unlocated(&file.path, "the dictionary file is empty")
                    .with_help("a dictionary starts with `family:` and lists its `objects:`"),
            );
        }
        // YAML 1.1 booleans (`yes`, `on`, `n`) would turn names into true/false.
        let options = serde_saphyr::options! { strict_booleans: true };
        match serde_saphyr::from_str_with_options::<Spanned<RawNode>>(&file.text, options) {
            Ok(raw) => Ok(convert(file, raw)),
            Err(err) => Err(yaml_error(file, &err)),
        }
    }

    /// `a number`, `text`, `a list`, … for "expected X, found Y" messages.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            NodeKind::Null => "nothing",
            NodeKind::Bool => "true/false",
            NodeKind::Int(_) => "a whole number",
            NodeKind::Float(_) => "a number",
            NodeKind::Str(_) => "text",
            NodeKind::Seq(_) => "a list",
            NodeKind::Map(_) => "a mapping",
        }
    }

    pub fn is_null(&self) -> bool {
        matches!(self.kind, NodeKind::Null)
    }
}

fn yaml_error(file: &Arc<SourceFile>, err: &serde_saphyr::Error) -> DictionaryError {
    let inner = err.without_snippet();
    let message: String = serde_saphyr::DefaultMessageFormatter
        .format_message(inner)
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let message = format!("not valid YAML: {message}");
    match err.location() {
        Some(loc) if loc.line() > 0 => {
            let span = span_of(file, &loc);
            DictionaryError::at(&span, message, "here")
        }
        _ => DictionaryError::unlocated(&file.path, message),
    }
}

fn span_of(file: &Arc<SourceFile>, loc: &serde_saphyr::Location) -> TextSpan {
    let line = usize::try_from(loc.line()).unwrap_or(usize::MAX);
    let column = usize::try_from(loc.column()).unwrap_or(usize::MAX);
    let s = loc.span();
    let offset = s
        .byte_offset()
        .and_then(|o| usize::try_from(o).ok())
        .unwrap_or_else(|| byte_offset_of(&file.text, line, column));
    let len = s
        .byte_len()
        .and_then(|l| usize::try_from(l).ok())
        .unwrap_or_else(|| byte_len_of(&file.text, offset, usize::try_from(s.len()).unwrap_or(0)));
    TextSpan::new(file, offset, len, line, column)
}

fn convert(file: &Arc<SourceFile>, raw: Spanned<RawNode>) -> YamlNode {
    let span = span_of(file, &raw.referenced);
    let kind = match raw.value {
        RawNode::Null => NodeKind::Null,
        RawNode::Bool => NodeKind::Bool,
        RawNode::Int(i) => NodeKind::Int(i),
        RawNode::Float(f) => NodeKind::Float(f),
        RawNode::Str(s) => NodeKind::Str(s),
        RawNode::Seq(items) => NodeKind::Seq(items.into_iter().map(|i| convert(file, i)).collect()),
        RawNode::Map(entries) => NodeKind::Map(
            entries
                .into_iter()
                .map(|(k, v)| {
                    let key = YamlNode {
                        span: span_of(file, &k.referenced),
                        kind: NodeKind::Str(k.value),
                    };
                    (key, convert(file, v))
                })
                .collect(),
        ),
    };
    YamlNode { kind, span }
}

/// The tree as serde_saphyr hands it over, children wrapped in `Spanned`.
enum RawNode {
    Null,
    Bool,
    Int(i128),
    Float(f64),
    Str(String),
    Seq(Vec<Spanned<RawNode>>),
    Map(Vec<(Spanned<String>, Spanned<RawNode>)>),
}

impl<'de> Deserialize<'de> for RawNode {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(RawNodeVisitor)
    }
}

struct RawNodeVisitor;

impl<'de> Visitor<'de> for RawNodeVisitor {
    type Value = RawNode;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any YAML value")
    }
    fn visit_unit<E>(self) -> Result<RawNode, E> {
        Ok(RawNode::Null)
    }
    fn visit_none<E>(self) -> Result<RawNode, E> {
        Ok(RawNode::Null)
    }
    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<RawNode, D::Error> {
        RawNode::deserialize(d)
    }
    fn visit_bool<E>(self, _: bool) -> Result<RawNode, E> {
        Ok(RawNode::Bool)
    }
    fn visit_i64<E>(self, v: i64) -> Result<RawNode, E> {
        Ok(RawNode::Int(v.into()))
    }
    fn visit_u64<E>(self, v: u64) -> Result<RawNode, E> {
        Ok(RawNode::Int(v.into()))
    }
    fn visit_i128<E>(self, v: i128) -> Result<RawNode, E> {
        Ok(RawNode::Int(v))
    }
    fn visit_u128<E: de::Error>(self, v: u128) -> Result<RawNode, E> {
        i128::try_from(v)
            .map(RawNode::Int)
            .or(Ok(RawNode::Float(v as f64)))
    }
    fn visit_f64<E>(self, v: f64) -> Result<RawNode, E> {
        Ok(RawNode::Float(v))
    }
    fn visit_str<E>(self, v: &str) -> Result<RawNode, E> {
        Ok(RawNode::Str(v.to_string()))
    }
    fn visit_string<E>(self, v: String) -> Result<RawNode, E> {
        Ok(RawNode::Str(v))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawNode, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(RawNode::Seq(items))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawNode, A::Error> {
        let mut entries = Vec::new();
        while let Some(entry) = map.next_entry()? {
            entries.push(entry);
        }
        Ok(RawNode::Map(entries))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<YamlNode, DictionaryError> {
        YamlNode::parse(&SourceFile::new("t.yaml", text))
    }

    #[test]
    fn nodes_keep_line_column_and_bytes() {
        let root = parse("family: sd2\nobjects:\n  - index: 0x4F\n    n: yes\n").unwrap();
        let NodeKind::Map(entries) = &root.kind else {
            panic!()
        };
        let (key, value) = &entries[1];
        assert_eq!((key.span.line(), key.span.column()), (2, 1));
        let NodeKind::Seq(items) = &value.kind else {
            panic!()
        };
        let NodeKind::Map(obj) = &items[0].kind else {
            panic!()
        };
        assert_eq!((items[0].span.line(), items[0].span.column()), (3, 5));
        let (k, v) = &obj[0];
        assert!(matches!(&k.kind, NodeKind::Str(s) if s == "index"));
        assert!(matches!(v.kind, NodeKind::Int(0x4F)));
        assert_eq!(
            (v.span.line(), v.span.column(), v.span.offset(), v.span.len()),
            (3, 12, 32, 4)
        );
        // Keys stay text; strict booleans keep `n` a key and `yes` text.
        let (k, v) = &obj[1];
        assert!(matches!(&k.kind, NodeKind::Str(s) if s == "n"));
        assert!(matches!(&v.kind, NodeKind::Str(s) if s == "yes"));
    }

    #[test]
    fn yaml_errors_are_located() {
        let e = parse("a: [1\nb: 2\n").unwrap_err();
        assert_eq!((e.line, e.column), (2, 2));
        assert!(e.message.starts_with("not valid YAML: "), "{}", e.message);
        let e = parse("a: 1\na: 2\n").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("duplicate"), "{}", e.message);
        let e = parse("   \n").unwrap_err();
        assert_eq!(e.message, "the dictionary file is empty");
    }
}
