//! The one error type of the dictionary layer: every problem of a dictionary or limits file
//! (or of files being merged), in file order. Shown as the first problem with
//! `(and N more problems)` and the others below it, with no code above them: the file's
//! name in each problem says where, an internal label would not. The problems themselves
//! are `diag::Diagnostic`s; this only groups them. Pure data: it does no I/O.

use crate::diag::{Diagnostic, Diagnostics};
use std::fmt;

#[derive(Debug, Clone)]
pub struct DictionaryError {
    /// Never empty; in file order. At most `diag::MAX_SHOWN`.
    problems: Vec<Diagnostic>,
    /// How many more problems were found and not kept.
    more: usize,
}

impl DictionaryError {
    /// All `problems` as one error, in file order; `None` when there are none.
    pub fn collect(problems: Diagnostics) -> Option<DictionaryError> {
        let more = problems.more();
        let problems: Vec<Diagnostic> = problems.sorted().into_iter().collect();
        (!problems.is_empty()).then_some(DictionaryError { problems, more })
    }

    /// The first problem in file order (the one the message names).
    pub fn first(&self) -> &Diagnostic {
        &self.problems[0]
    }

    /// Every problem, in file order.
    pub fn problems(&self) -> impl Iterator<Item = &Diagnostic> {
        self.problems.iter()
    }

    /// How many problems were found (the first `diag::MAX_SHOWN` are kept).
    pub fn count(&self) -> usize {
        self.problems.len() + self.more
    }
}

impl From<Diagnostic> for DictionaryError {
    fn from(problem: Diagnostic) -> Self {
        DictionaryError {
            problems: vec![problem],
            more: 0,
        }
    }
}

impl fmt::Display for DictionaryError {
    /// `path:line:column: message`, then `(and N more problems)` when there are others.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.first().located())?;
        match (self.count() - 1, self.more) {
            (0, _) => Ok(()),
            (1, _) => f.write_str(" (and 1 more problem)"),
            (n, 0) => write!(f, " (and {n} more problems)"),
            (n, _) => write!(
                f,
                " (and {n} more problems; the first {} are shown)",
                self.problems.len()
            ),
        }
    }
}

impl std::error::Error for DictionaryError {}

impl miette::Diagnostic for DictionaryError {
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        miette::Diagnostic::help(self.first())
    }
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        miette::Diagnostic::source_code(self.first())
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        miette::Diagnostic::labels(self.first())
    }
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
        Some(Box::new(
            self.problems[1..].iter().map(|p| p as &dyn miette::Diagnostic),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collect_orders_by_place_and_counts() {
        let all = DictionaryError::collect(crate::diag::three_out_of_order()).unwrap();
        assert_eq!(all.count(), 3);
        let lines: Vec<usize> = all.problems().map(Diagnostic::line).collect();
        assert_eq!(lines, [1, 2, 3]);
        assert_eq!(all.to_string(), "d.yaml:1:1: first (and 2 more problems)");
        assert!(DictionaryError::collect(Diagnostics::new()).is_none());
        let mut out = String::new();
        crate::diag::report_handler(false)
            .render_report(&mut out, &all)
            .unwrap();
        assert!(!out.contains("drivescript::"), "no internal label: {out}");
        assert!(out.contains("d.yaml:3:1: third"), "{out}");
    }
}
