//! Every problem of one check at once (a recipe and its included files, a dictionary, a
//! limits file), in the order found or sorted by place, and their rendering for a terminal
//! or a log. Collects and shows; what a set of problems means (nothing was sent, the
//! dictionary is refused) is the caller's to say. Keeps the first [`MAX_SHOWN`] problems
//! and counts the rest, so a file of thousands of problems costs linear time and constant
//! memory (each problem shown renders its snippet from the file's text).

use super::diagnostic::Diagnostic;
use std::fmt;

/// How many problems of one check are kept and shown; the others are counted.
pub const MAX_SHOWN: usize = 100;

#[derive(Debug, Clone, Default)]
pub struct Diagnostics {
    /// The first [`MAX_SHOWN`] problems found.
    items: Vec<Diagnostic>,
    /// How many more were found and not kept.
    more: usize,
}

impl Diagnostics {
    pub fn new() -> Self {
        Diagnostics::default()
    }

    /// Keeps `d` if fewer than [`MAX_SHOWN`] are kept; counts it otherwise.
    pub fn push(&mut self, d: Diagnostic) {
        if self.items.len() < MAX_SHOWN {
            self.items.push(d);
        } else {
            self.more += 1;
        }
    }

    /// Every problem found, kept or only counted.
    pub fn len(&self) -> usize {
        self.items.len() + self.more
    }

    /// How many problems were found beyond the kept ones.
    pub fn more(&self) -> usize {
        self.more
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    pub fn iter(&self) -> std::slice::Iter<'_, Diagnostic> {
        self.items.iter()
    }

    /// In file order: by path, line and column; problems at one place keep their order.
    pub fn sorted(mut self) -> Self {
        self.items
            .sort_by(|a, b| (a.path(), a.line(), a.column()).cmp(&(b.path(), b.line(), b.column())));
        self
    }

    /// Each problem on its own, headed by its message, with its snippet (`path:line:column`
    /// heads it) and help; colours for a terminal, plain otherwise.
    pub fn render(&self, colour: bool) -> String {
        let handler = report_handler(colour);
        let mut out = String::new();
        for d in &self.items {
            let _ = handler.render_report(&mut out, &Headline(d));
        }
        if self.more > 0 {
            out.push_str(&format!(
                "… and {} more problem{} (the first {MAX_SHOWN} are shown)\n",
                self.more,
                if self.more == 1 { "" } else { "s" }
            ));
        }
        out
    }
}

impl Extend<Diagnostic> for Diagnostics {
    fn extend<I: IntoIterator<Item = Diagnostic>>(&mut self, iter: I) {
        for d in iter {
            self.push(d);
        }
    }
}

impl FromIterator<Diagnostic> for Diagnostics {
    fn from_iter<I: IntoIterator<Item = Diagnostic>>(iter: I) -> Self {
        let mut all = Diagnostics::new();
        all.extend(iter);
        all
    }
}

/// The kept problems (see [`Diagnostics::more`] for the count of the others).
impl IntoIterator for Diagnostics {
    type Item = Diagnostic;
    type IntoIter = std::vec::IntoIter<Diagnostic>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.into_iter()
    }
}

impl<'a> IntoIterator for &'a Diagnostics {
    type Item = &'a Diagnostic;
    type IntoIter = std::slice::Iter<'a, Diagnostic>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter()
    }
}

/// miette's graphical handler: with colours, or plain for logs and files.
pub fn report_handler(colour: bool) -> miette::GraphicalReportHandler {
    if colour {
        miette::GraphicalReportHandler::new()
    } else {
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
    }
}

/// A diagnostic rendered for standard error: with colours on a terminal, plain otherwise
/// (CI logs), always with the file:line:column snippet header.
pub fn render_diagnostic(d: &dyn miette::Diagnostic) -> String {
    use std::io::IsTerminal;
    let mut out = String::new();
    if report_handler(std::io::stderr().is_terminal())
        .render_report(&mut out, d)
        .is_err()
    {
        out = format!("error: {d}\n");
    }
    out
}

/// A problem headed by its bare message, since its snippet's header already says
/// `path:line:column`; one without a snippet says its file and place in the headline.
#[derive(Debug)]
struct Headline<'a>(&'a Diagnostic);

impl fmt::Display for Headline<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.has_snippet() {
            f.write_str(self.0.message())
        } else {
            f.write_str(&self.0.located())
        }
    }
}

impl std::error::Error for Headline<'_> {}

impl miette::Diagnostic for Headline<'_> {
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        miette::Diagnostic::help(self.0)
    }
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.0.source_code()
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        self.0.labels()
    }
}

/// Test support: three problems of `d.yaml` out of order, `third` (line 3) first, then
/// `first` (line 1) and `second` (line 2).
#[cfg(test)]
pub(crate) fn three_out_of_order() -> Diagnostics {
    use crate::diag::{Source, Span};
    let file = Source::new("d.yaml", "a: 1\nb: 2\nc: 3\n");
    let at =
        |offset, line, message: &str| Diagnostic::at(&Span::new(&file, offset, 1, line, 1), message, "here");
    [at(10, 3, "third"), at(0, 1, "first"), at(5, 2, "second")]
        .into_iter()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::{Source, Span};

    #[test]
    fn sorted_by_place_and_rendered_each_on_its_own() {
        let all = three_out_of_order();
        let lines: Vec<usize> = all.clone().sorted().iter().map(Diagnostic::line).collect();
        assert_eq!(lines, [1, 2, 3]);
        let out = all.render(false);
        assert!(out.contains("× third") && out.contains("[d.yaml:3:1]"), "{out}");
        assert!(!out.contains("d.yaml:3:1: third"), "{out}");
    }

    #[test]
    fn the_first_problems_are_kept_and_the_others_counted() {
        let file = Source::new("d.yaml", "a: 1\n");
        let all: Diagnostics = (0..MAX_SHOWN + 250)
            .map(|i| Diagnostic::at(&Span::new(&file, 0, 1, 1, 1), format!("problem {i}"), "here"))
            .collect();
        assert_eq!(all.len(), MAX_SHOWN + 250);
        assert_eq!(all.iter().count(), MAX_SHOWN);
        assert_eq!(all.more(), 250);
        let out = all.render(false);
        assert!(
            out.contains("problem 99") && !out.contains("problem 100"),
            "{out}"
        );
        assert!(
            out.ends_with("… and 250 more problems (the first 100 are shown)\n"),
            "{out}"
        );
    }
}
