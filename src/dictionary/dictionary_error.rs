//! The one error type of the dictionary layer: a located problem in a dictionary file
//! (path, line, column, message, help) that miette renders with the offending text
//! underlined, plus the file's other problems, so that one run reports them all.
//! Pure data: it does no I/O.

use super::text_span::TextSpan;
use miette::{LabeledSpan, NamedSource, SourceSpan};
use std::fmt;
use std::sync::Arc;

#[derive(Debug, Clone, miette::Diagnostic)]
#[diagnostic(code(drivescript::dictionary))]
pub struct DictionaryError {
    /// The dictionary file (`dictionary/sd2.yaml` for the built-in one); empty when the
    /// problem is not in a file.
    pub path: String,
    /// 1-based; 0 when the problem has no place in the text (an unreadable file).
    pub line: usize,
    /// 1-based, in characters; 0 with `line` 0.
    pub column: usize,
    pub message: String,
    #[help]
    pub help: Option<String>,
    #[source_code]
    source_code: Option<NamedSource<Arc<str>>>,
    #[label("{label}")]
    span: Option<SourceSpan>,
    label: String,
    #[label(collection)]
    secondary: Vec<LabeledSpan>,
    /// The other problems of the same file (or of the files being merged), in file order.
    #[related]
    pub more: Vec<DictionaryError>,
}

impl DictionaryError {
    /// A problem at `span`, underlined with `label`.
    pub fn at(span: &TextSpan, message: impl Into<String>, label: impl Into<String>) -> Self {
        let file = span.file();
        let known = span.is_known();
        DictionaryError {
            path: span.path().to_string(),
            line: span.line(),
            column: span.column(),
            message: message.into(),
            help: None,
            source_code: known.then(|| NamedSource::new(file.path.clone(), Arc::clone(&file.text))),
            span: known.then(|| SourceSpan::new(span.offset().into(), span.len())),
            label: label.into(),
            secondary: Vec::new(),
            more: Vec::new(),
        }
    }

    /// A problem of a whole file or of no file (unreadable file, unknown family).
    pub fn unlocated(path: impl Into<String>, message: impl Into<String>) -> Self {
        DictionaryError {
            path: path.into(),
            line: 0,
            column: 0,
            message: message.into(),
            help: None,
            source_code: None,
            span: None,
            label: String::new(),
            secondary: Vec::new(),
            more: Vec::new(),
        }
    }

    /// Sets the help; a note added by [`Self::also_at`] is kept after it.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        let help = help.into();
        self.help = Some(match self.help.take() {
            Some(note) => format!("{help}\n{note}"),
            None => help,
        });
        self
    }

    /// Adds help only when there is some.
    pub(crate) fn with_optional_help(self, help: Option<String>) -> Self {
        match help {
            Some(h) => self.with_help(h),
            None => self,
        }
    }

    /// Points at a second place: underlined too when it is in the same file, otherwise
    /// named in the help as `path:line:column`.
    pub fn also_at(mut self, span: &TextSpan, label: impl Into<String>) -> Self {
        let label = label.into();
        let same_file = self.path == span.path()
            && self
                .source_code
                .as_ref()
                .is_some_and(|s| Arc::ptr_eq(s.inner(), &span.file().text));
        if same_file && span.is_known() {
            self.secondary.push(LabeledSpan::new_with_span(
                Some(label),
                SourceSpan::new(span.offset().into(), span.len()),
            ));
        } else if span.is_known() {
            let note = format!("{label}: {span}");
            self.help = Some(match self.help.take() {
                Some(h) => format!("{h}\n{note}"),
                None => note,
            });
        }
        self
    }

    /// All `problems` as one error: the first in file order, the rest in [`Self::more`].
    /// `None` when there are none.
    pub fn collect(mut problems: Vec<DictionaryError>) -> Option<DictionaryError> {
        let mut flat = Vec::new();
        for mut p in problems.drain(..) {
            let more = std::mem::take(&mut p.more);
            flat.push(p);
            flat.extend(more);
        }
        flat.sort_by(|a, b| (&a.path, a.line, a.column).cmp(&(&b.path, b.line, b.column)));
        let mut iter = flat.into_iter();
        let mut first = iter.next()?;
        first.more = iter.collect();
        Some(first)
    }

    /// This problem and the others, in file order.
    pub fn problems(&self) -> impl Iterator<Item = &DictionaryError> {
        std::iter::once(self).chain(self.more.iter())
    }

    /// How many problems this error reports.
    pub fn count(&self) -> usize {
        1 + self.more.len()
    }

    /// `path:line:column: message` for this problem alone.
    pub fn located_message(&self) -> String {
        match (self.path.is_empty(), self.line) {
            (true, _) => self.message.clone(),
            (false, 0) => format!("{}: {}", self.path, self.message),
            (false, _) => format!("{}:{}:{}: {}", self.path, self.line, self.column, self.message),
        }
    }

    /// The underline label (for tests and plain-text output).
    pub fn label(&self) -> &str {
        &self.label
    }
}

impl fmt::Display for DictionaryError {
    /// `path:line:column: message`, then `(and N more problems)` when there are others.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.located_message())?;
        match self.more.len() {
            0 => Ok(()),
            1 => f.write_str(" (and 1 more problem)"),
            n => write!(f, " (and {n} more problems)"),
        }
    }
}

impl std::error::Error for DictionaryError {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::text_span::SourceFile;

    #[test]
    fn collect_orders_by_place_and_counts() {
        let file = SourceFile::new("d.yaml", "a: 1\nb: 2\nc: 3\n");
        let c = DictionaryError::at(&TextSpan::new(&file, 10, 1, 3, 1), "third", "here");
        let a = DictionaryError::at(&TextSpan::new(&file, 0, 1, 1, 1), "first", "here");
        let b = DictionaryError::at(&TextSpan::new(&file, 5, 1, 2, 1), "second", "here");
        let all = DictionaryError::collect(vec![c, a, b]).unwrap();
        assert_eq!(all.count(), 3);
        let lines: Vec<usize> = all.problems().map(|p| p.line).collect();
        assert_eq!(lines, [1, 2, 3]);
        assert_eq!(all.to_string(), "d.yaml:1:1: first (and 2 more problems)");
        assert!(DictionaryError::collect(Vec::new()).is_none());
    }

    #[test]
    fn renders_with_miette_underlining_the_text() {
        let file = SourceFile::new("d.yaml", "unit: rpn\n");
        let e = DictionaryError::at(
            &TextSpan::new(&file, 6, 3, 1, 7),
            "unknown unit `rpn`",
            "not a unit",
        )
        .with_help("did you mean `rpm`?")
        .also_at(&TextSpan::new(&file, 0, 4, 1, 1), "in this key");
        let mut out = String::new();
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .render_report(&mut out, &e)
            .unwrap();
        assert!(out.contains("d.yaml:1:7"), "{out}");
        assert!(out.contains("not a unit"), "{out}");
        assert!(out.contains("in this key"), "{out}");
        assert!(out.contains("did you mean `rpm`?"), "{out}");

        let other = SourceFile::new("e.yaml", "x\n");
        let e = DictionaryError::at(&TextSpan::new(&file, 6, 3, 1, 7), "m", "l")
            .also_at(&TextSpan::new(&other, 0, 1, 1, 1), "first defined");
        assert_eq!(e.help.as_deref(), Some("first defined: e.yaml:1:1"));
        let io = DictionaryError::unlocated("x.yaml", "cannot read");
        assert_eq!(io.to_string(), "x.yaml: cannot read");
    }
}
