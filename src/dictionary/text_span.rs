//! Where a piece of dictionary text came from: the file (path and text, shared by every
//! span of that file) and the byte span, line and column of one YAML node.
//! Pure data: it does no I/O and knows nothing of YAML or drives.

use std::fmt;
use std::sync::Arc;

/// A dictionary file's path (as given, or `dictionary/sd2.yaml` for the built-in one)
/// and its whole text, kept so that errors can show the offending line.
#[derive(Debug, PartialEq, Eq)]
pub struct SourceFile {
    pub path: String,
    pub text: Arc<str>,
}

impl SourceFile {
    pub fn new(path: impl Into<String>, text: impl Into<Arc<str>>) -> Arc<SourceFile> {
        Arc::new(SourceFile {
            path: path.into(),
            text: text.into(),
        })
    }
}

/// The location of one node in a [`SourceFile`]: byte offset and length (for underlining),
/// and 1-based line and column in characters (for people). Line 0 means "not from a file"
/// (an object built in code).
#[derive(Debug, Clone)]
pub struct TextSpan {
    file: Arc<SourceFile>,
    offset: usize,
    len: usize,
    line: usize,
    column: usize,
}

impl TextSpan {
    pub(crate) fn new(file: &Arc<SourceFile>, offset: usize, len: usize, line: usize, column: usize) -> Self {
        let end = file.text.len();
        let offset = offset.min(end);
        TextSpan {
            file: Arc::clone(file),
            offset,
            len: len.min(end - offset),
            line,
            column,
        }
    }

    /// A span for something that was not read from a file.
    pub fn unknown() -> Self {
        TextSpan {
            file: SourceFile::new("", ""),
            offset: 0,
            len: 0,
            line: 0,
            column: 0,
        }
    }

    pub fn path(&self) -> &str {
        &self.file.path
    }
    pub fn file(&self) -> &Arc<SourceFile> {
        &self.file
    }
    /// Byte offset into the file's text.
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
    /// True when both spans point into the same file (same text, not just the same path).
    pub fn same_file(&self, other: &TextSpan) -> bool {
        Arc::ptr_eq(&self.file, &other.file)
    }
}

impl fmt::Display for TextSpan {
    /// `path:line:column`, or just the path when the line is unknown.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_known() {
            write!(f, "{}:{}:{}", self.file.path, self.line, self.column)
        } else {
            f.write_str(&self.file.path)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_is_path_line_column() {
        let file = SourceFile::new("d.yaml", "a: 1\n");
        assert_eq!(TextSpan::new(&file, 3, 1, 1, 4).to_string(), "d.yaml:1:4");
        assert_eq!(TextSpan::unknown().to_string(), "");
        assert!(TextSpan::new(&file, 99, 9, 1, 1).is_empty());
    }
}
