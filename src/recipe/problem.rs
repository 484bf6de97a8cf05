//! A problem found in a recipe file, rendered as a miette diagnostic with file:line:column,
//! the bad text underlined and a help line; and the set of all problems of one check.

use crate::yaml_tree::Span;
use miette::{Diagnostic, NamedSource, SourceSpan};
use std::fmt;
use std::sync::Arc;

/// A recipe file's path as given and its text, shared by every problem in it.
#[derive(Debug)]
pub struct RecipeSource {
    pub path: String,
    pub text: Arc<str>,
}

/// One problem, at one place.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{message}")]
pub struct Problem {
    pub message: String,
    pub path: String,
    pub line: usize,
    pub column: usize,
    pub help: Option<String>,
    label: String,
    span: SourceSpan,
    source_text: Arc<str>,
}

impl Problem {
    pub fn new(
        source: &RecipeSource,
        span: Span,
        message: impl Into<String>,
        label: impl Into<String>,
        help: Option<String>,
    ) -> Self {
        let len = span.len.min(source.text.len().saturating_sub(span.offset));
        Problem {
            message: message.into(),
            path: source.path.clone(),
            line: span.line,
            column: span.column,
            help,
            label: label.into(),
            span: (span.offset.min(source.text.len()), len).into(),
            source_text: source.text.clone(),
        }
    }

    /// `path:line:column: message`, for logs and tests.
    pub fn one_line(&self) -> String {
        format!("{}:{}:{}: {}", self.path, self.line, self.column, self.message)
    }
}

impl Diagnostic for Problem {
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source_text as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        Some(Box::new(std::iter::once(miette::LabeledSpan::new_with_span(
            Some(self.label.clone()),
            self.span,
        ))))
    }

    fn url<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        None
    }
}

/// Every problem of a recipe (and the files it includes). Nothing was sent to any drive.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{path}: {} problem{} found; nothing was sent to the drive", problems.len(), if problems.len() == 1 { "" } else { "s" })]
pub struct RecipeInvalid {
    pub path: String,
    pub problems: Vec<Problem>,
}

impl Diagnostic for RecipeInvalid {
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        Some(Box::new(self.problems.iter().map(|p| p as &dyn Diagnostic)))
    }
}

/// miette needs the source with a name to print `path:line:column` in the snippet header.
pub fn named(path: &str, text: &Arc<str>) -> NamedSource<String> {
    NamedSource::new(path, text.to_string())
}

impl RecipeInvalid {
    /// The problems rendered for a terminal (or plain, without colours), each with its
    /// snippet. `path:line:column` heads every snippet.
    pub fn render(&self, colour: bool) -> String {
        let mut out = String::new();
        let handler = if colour {
            miette::GraphicalReportHandler::new()
        } else {
            miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
        };
        for p in &self.problems {
            let with_name = NamedProblem {
                problem: p,
                source: named(&p.path, &p.source_text),
            };
            let _ = handler.render_report(&mut out, &with_name);
        }
        out.push_str(&format!("{}\n", self));
        out
    }
}

/// A problem together with its named source, so the snippet header shows the file path.
#[derive(Debug)]
struct NamedProblem<'a> {
    problem: &'a Problem,
    source: NamedSource<String>,
}

impl fmt::Display for NamedProblem<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.problem.message)
    }
}

impl std::error::Error for NamedProblem<'_> {}

impl Diagnostic for NamedProblem<'_> {
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.problem.help()
    }
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        self.problem.labels()
    }
}
