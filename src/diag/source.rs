//! One file drivescript read (a recipe, an included file, a dictionary, a limits file): its
//! path as given and its whole text, shared by every span and diagnostic that points into
//! it. Pure data: reading the file is `text_file`'s job, showing it is `Diagnostic`'s.

use std::sync::Arc;

/// A file's path (as given, or `dictionary/sd2.yaml` for a built-in one) and its text.
#[derive(Debug, PartialEq, Eq)]
pub struct Source {
    path: String,
    text: Arc<str>,
}

impl Source {
    pub fn new(path: impl Into<String>, text: impl Into<Arc<str>>) -> Arc<Source> {
        Arc::new(Source {
            path: path.into(),
            text: text.into(),
        })
    }

    pub fn path(&self) -> &str {
        &self.path
    }

    pub fn text(&self) -> &str {
        &self.text
    }

    /// The text, shared (miette keeps it for the snippet).
    pub(crate) fn shared_text(&self) -> &Arc<str> {
        &self.text
    }
}
