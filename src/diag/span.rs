//! Where something is written: a byte range of a [`Source`] with its 1-based line and
//! column, for underlining and for people. Pure data: no I/O, no knowledge of YAML.

use super::source::Source;
use std::fmt;
use std::sync::Arc;

/// A byte offset and length (for underlining) and a 1-based line and column in characters
/// (for people) in one [`Source`]. Line 0 means "not from a file" (an object built in code).
#[derive(Debug, Clone)]
pub struct Span {
    source: Arc<Source>,
    offset: usize,
    len: usize,
    line: usize,
    column: usize,
}

impl Span {
    /// A span of `source`; offset and length are kept inside its text.
    pub fn new(source: &Arc<Source>, offset: usize, len: usize, line: usize, column: usize) -> Self {
        let end = source.text().len();
        let offset = offset.min(end);
        Span {
            source: Arc::clone(source),
            offset,
            len: len.min(end - offset),
            line,
            column,
        }
    }

    /// The first character of `source` (for a problem of the whole file that should still
    /// show it, such as an empty recipe).
    pub fn start_of(source: &Arc<Source>) -> Self {
        Span::new(source, 0, 0, 1, 1)
    }

    /// A span for something that was not read from a file.
    pub fn unknown() -> Self {
        Span {
            source: Source::new("", ""),
            offset: 0,
            len: 0,
            line: 0,
            column: 0,
        }
    }

    pub fn source(&self) -> &Arc<Source> {
        &self.source
    }
    pub fn path(&self) -> &str {
        self.source.path()
    }
    /// Byte offset into the source's text.
    pub fn offset(&self) -> usize {
        self.offset
    }
    /// Length in bytes (0 for a mapping or list, which point at their first character).
    pub fn len(&self) -> usize {
        self.len
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// 1-based line; 0 when the span is not from a file.
    pub fn line(&self) -> usize {
        self.line
    }
    /// 1-based column in characters; 0 when the span is not from a file.
    pub fn column(&self) -> usize {
        self.column
    }
    pub fn is_known(&self) -> bool {
        self.line > 0
    }
    /// True when both spans point into the same source (the same text, not just the same path).
    pub fn same_source(&self, other: &Span) -> bool {
        Arc::ptr_eq(&self.source, &other.source)
    }

    /// The text under the span as written, trimmed.
    pub fn written(&self) -> &str {
        let text = self.source.text();
        text.get(self.offset..self.offset + self.len)
            .unwrap_or_default()
            .trim()
    }

    /// For miette labels.
    pub fn source_span(&self) -> miette::SourceSpan {
        (self.offset, self.len).into()
    }
}

impl fmt::Display for Span {
    /// `path:line:column`, or just the path when the line is unknown.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_known() {
            write!(f, "{}:{}:{}", self.path(), self.line, self.column)
        } else {
            f.write_str(self.path())
        }
    }
}

/// A value with the span it was read from.
#[derive(Debug, Clone)]
pub struct Spanned<T> {
    pub value: T,
    pub span: Span,
}

impl<T> Spanned<T> {
    pub fn new(value: T, span: Span) -> Self {
        Spanned { value, span }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_is_path_line_column() {
        let source = Source::new("d.yaml", "a: 1\n");
        assert_eq!(Span::new(&source, 3, 1, 1, 4).to_string(), "d.yaml:1:4");
        assert_eq!(Span::new(&source, 3, 1, 1, 4).written(), "1");
        assert_eq!(Span::unknown().to_string(), "");
        assert!(Span::new(&source, 99, 9, 1, 1).is_empty());
        assert!(Span::start_of(&source).is_known());
    }
}
