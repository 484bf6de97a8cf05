//! A script that did not pass its check: every problem (syntax, and names, units, states
//! and durations written as literals), each a `diag::Diagnostic` at its place, rendered
//! one after the other with a closing line saying that nothing was sent. Pure data.

use crate::diag::Diagnostics;
use miette::Diagnostic;

#[derive(Debug, Clone, thiserror::Error)]
#[error("{path}: {} problem{} found; nothing was sent to the drive", problems.len(), if problems.len() == 1 { "" } else { "s" })]
pub struct ScriptInvalid {
    pub path: String,
    pub problems: Diagnostics,
}

impl Diagnostic for ScriptInvalid {
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        Some(Box::new(self.problems.iter().map(|p| p as &dyn Diagnostic)))
    }
}

impl ScriptInvalid {
    /// The problems, each with its snippet headed `path:line:column`, then the closing line.
    pub fn render(&self, colour: bool) -> String {
        let mut out = self.problems.render(colour);
        out.push_str(&format!("{self}\n"));
        out
    }
}
