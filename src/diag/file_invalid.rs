//! A recipe or script that did not pass its check: every problem of the file and the files
//! it includes (each a `diag::Diagnostic` at its place), rendered one after the other with
//! a closing line saying that nothing was sent. Pure data: finding the problems is the
//! loaders' job.

use super::diagnostics::Diagnostics;
use miette::Diagnostic;

/// Every problem of a recipe or script (and the files it includes). Nothing was sent to
/// any drive.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{path}: {} problem{} found; nothing was sent to the drive", problems.len(), if problems.len() == 1 { "" } else { "s" })]
pub struct FileInvalid {
    pub path: String,
    pub problems: Diagnostics,
}

impl Diagnostic for FileInvalid {
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        Some(Box::new(self.problems.iter().map(|p| p as &dyn Diagnostic)))
    }
}

impl FileInvalid {
    /// The problems rendered for a terminal (or plain, without colours), each with its
    /// snippet headed `path:line:column`, then the closing line.
    pub fn render(&self, colour: bool) -> String {
        let mut out = self.problems.render(colour);
        out.push_str(&format!("{self}\n"));
        out
    }
}
