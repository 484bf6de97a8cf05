//! A dictionary file as a YAML tree in which every node keeps its place in the text, as
//! [`TextSpan`]s into the shared [`SourceFile`]. Parsing is `crate::yaml_tree`'s (one
//! spanned parser for recipes and dictionaries); this only attaches the file. No I/O, no
//! knowledge of objects.

use super::dictionary_error::DictionaryError;
use super::text_span::{SourceFile, TextSpan};
use crate::yaml_tree::{self, Span, Spanned};
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
        match yaml_tree::parse(&file.text) {
            Ok(root) => Ok(convert(file, root)),
            Err(e) => {
                let message = if e.over_limit {
                    e.message
                } else {
                    format!("not valid YAML: {}", e.message)
                };
                let error = if e.span.line > 0 {
                    DictionaryError::at(&text_span(file, e.span), message, "here")
                } else {
                    DictionaryError::unlocated(&file.path, message)
                };
                Err(error.with_optional_help(e.help))
            }
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

    /// True for a number that is not finite: `.nan`, `.inf`, or `1e400` (too large for a
    /// float), which the parser hands over as the text `.nan`, `.inf` or `-.inf`.
    pub fn is_non_finite_number(&self) -> bool {
        match &self.kind {
            NodeKind::Float(f) => !f.is_finite(),
            NodeKind::Str(s) => matches!(s.as_str(), ".nan" | ".inf" | "-.inf" | "+.inf"),
            _ => false,
        }
    }

    /// The node's text as written in the file.
    pub fn written(&self) -> &str {
        let text = &self.span.file().text;
        let start = self.span.offset().min(text.len());
        let end = (start + self.span.len()).min(text.len());
        text.get(start..end).unwrap_or_default().trim()
    }
}

fn text_span(file: &Arc<SourceFile>, span: Span) -> TextSpan {
    TextSpan::new(file, span.offset, span.len, span.line, span.column)
}

fn convert(file: &Arc<SourceFile>, node: Spanned<yaml_tree::YamlNode>) -> YamlNode {
    use yaml_tree::YamlNode as Y;
    let span = text_span(file, node.span);
    let kind = match node.value {
        Y::Null => NodeKind::Null,
        Y::Bool(_) => NodeKind::Bool,
        Y::Int(i) => NodeKind::Int(i.into()),
        Y::Float(f) => NodeKind::Float(f),
        Y::Str(s) => NodeKind::Str(s),
        Y::Seq(items) => NodeKind::Seq(items.into_iter().map(|i| convert(file, i)).collect()),
        Y::Map(entries) => NodeKind::Map(
            entries
                .into_iter()
                .map(|(k, v)| {
                    let key = YamlNode {
                        span: text_span(file, k.span),
                        kind: NodeKind::Str(k.value),
                    };
                    (key, convert(file, v))
                })
                .collect(),
        ),
    };
    YamlNode { kind, span }
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
