//! One problem found in a file drivescript read (a recipe, a dictionary, a limits file):
//! what happened, where (`path:line:column`, the text underlined with a label), and what to
//! do (help, did-you-mean). miette renders it. Pure data: it does no I/O and decides
//! nothing about the file's meaning.

use super::span::Span;
use miette::{LabeledSpan, NamedSource};
use std::fmt;
use std::sync::Arc;

/// Snippets are left out for text further right than this (a generated recipe written on
/// one line): miette cannot pad that far, and such a snippet would show nothing useful.
/// The place is then said in the headline instead.
const WIDEST_SNIPPET: usize = 10_000;

#[derive(Debug, Clone)]
pub struct Diagnostic {
    message: String,
    label: String,
    help: Option<String>,
    /// The file it is about (`dictionary/sd2.yaml` for a built-in one); empty for none.
    path: String,
    /// Where it is; `None` for a problem of a whole file or of no file.
    span: Option<Span>,
    code: Option<&'static str>,
    /// The file, named, for the snippet; `None` when no snippet is shown.
    snippet: Option<NamedSource<Arc<str>>>,
    secondary: Vec<LabeledSpan>,
}

impl Diagnostic {
    /// A problem at `span`, underlined with `label`. A span not from a file gives a
    /// problem without a place.
    pub fn at(span: &Span, message: impl Into<String>, label: impl Into<String>) -> Self {
        let shown = span.is_known() && span.column() + span.len() <= WIDEST_SNIPPET;
        Diagnostic {
            message: message.into(),
            label: label.into(),
            help: None,
            path: span.path().to_string(),
            span: span.is_known().then(|| span.clone()),
            code: None,
            snippet: shown.then(|| NamedSource::new(span.path(), Arc::clone(span.source().shared_text()))),
            secondary: Vec::new(),
        }
    }

    /// A problem of a whole file (unreadable, empty) or of no file (`path` empty).
    pub fn unlocated(path: impl Into<String>, message: impl Into<String>) -> Self {
        Diagnostic {
            message: message.into(),
            label: String::new(),
            help: None,
            path: path.into(),
            span: None,
            code: None,
            snippet: None,
            secondary: Vec::new(),
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
    pub fn with_optional_help(self, help: Option<String>) -> Self {
        match help {
            Some(h) => self.with_help(h),
            None => self,
        }
    }

    /// The miette code shown above the problem (`drivescript::dictionary`).
    pub fn with_code(mut self, code: &'static str) -> Self {
        self.code = Some(code);
        self
    }

    /// Points at a second place: underlined too when it is in the same file, otherwise
    /// named in the help as `path:line:column`.
    pub fn also_at(mut self, span: &Span, label: impl Into<String>) -> Self {
        let label = label.into();
        let same_source = self.span.as_ref().is_some_and(|s| s.same_source(span));
        if same_source && self.snippet.is_some() && span.is_known() {
            self.secondary
                .push(LabeledSpan::new_with_span(Some(label), span.source_span()));
        } else if span.is_known() {
            let note = format!("{label}: {span}");
            self.help = Some(match self.help.take() {
                Some(h) => format!("{h}\n{note}"),
                None => note,
            });
        }
        self
    }

    pub fn message(&self) -> &str {
        &self.message
    }
    /// The underline's label.
    pub fn label(&self) -> &str {
        &self.label
    }
    pub fn help(&self) -> Option<&str> {
        self.help.as_deref()
    }
    pub fn path(&self) -> &str {
        &self.path
    }
    pub fn span(&self) -> Option<&Span> {
        self.span.as_ref()
    }
    /// 1-based; 0 when the problem has no place in a text.
    pub fn line(&self) -> usize {
        self.span.as_ref().map_or(0, Span::line)
    }
    /// 1-based, in characters; 0 with `line` 0.
    pub fn column(&self) -> usize {
        self.span.as_ref().map_or(0, Span::column)
    }

    /// `path:line:column: message`, `path: message` without a place, or the message alone.
    pub fn located(&self) -> String {
        match (self.path.is_empty(), self.line()) {
            (true, _) => self.message.clone(),
            (false, 0) => format!("{}: {}", self.path, self.message),
            (false, line) => format!("{}:{line}:{}: {}", self.path, self.column(), self.message),
        }
    }

    /// True when rendering shows the place in a snippet (headed `path:line:column`).
    pub(crate) fn has_snippet(&self) -> bool {
        self.snippet.is_some()
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.located())
    }
}

impl std::error::Error for Diagnostic {}

impl miette::Diagnostic for Diagnostic {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.code.map(|c| Box::new(c) as Box<dyn fmt::Display>)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.snippet.as_ref().map(|s| s as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.span.as_ref().filter(|_| self.snippet.is_some())?;
        let primary = LabeledSpan::new_with_span(Some(self.label.clone()), span.source_span());
        Some(Box::new(
            std::iter::once(primary).chain(self.secondary.iter().cloned()),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Source;

    fn plain(d: &dyn miette::Diagnostic) -> String {
        let mut out = String::new();
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .render_report(&mut out, d)
            .unwrap();
        out
    }

    #[test]
    fn renders_with_miette_underlining_the_text() {
        let file = Source::new("d.yaml", "unit: rpn\n");
        let e = Diagnostic::at(&Span::new(&file, 6, 3, 1, 7), "unknown unit `rpn`", "not a unit")
            .with_help("did you mean `rpm`?")
            .also_at(&Span::new(&file, 0, 4, 1, 1), "in this key");
        let out = plain(&e);
        for part in ["d.yaml:1:7", "not a unit", "in this key", "did you mean `rpm`?"] {
            assert!(out.contains(part), "{out}");
        }
        assert_eq!(e.located(), "d.yaml:1:7: unknown unit `rpn`");

        let other = Source::new("e.yaml", "x\n");
        let e = Diagnostic::at(&Span::new(&file, 6, 3, 1, 7), "m", "l")
            .also_at(&Span::new(&other, 0, 1, 1, 1), "first defined");
        assert_eq!(e.help(), Some("first defined: e.yaml:1:1"));
        let io = Diagnostic::unlocated("x.yaml", "cannot read");
        assert_eq!(io.to_string(), "x.yaml: cannot read");
        assert_eq!(Diagnostic::unlocated("", "no file").to_string(), "no file");
    }

    #[test]
    fn text_far_to_the_right_is_named_not_shown() {
        let text = format!("steps: [{}x]\n", " ".repeat(70_000));
        let file = Source::new("r.yaml", text.as_str());
        let d = Diagnostic::at(
            &Span::new(&file, 70_008, 1, 1, 70_009),
            "unknown step `x`",
            "here",
        );
        assert!(!d.has_snippet());
        assert!(plain(&d).contains("r.yaml:1:70009: unknown step `x`"));
    }
}
