//! The `read` and `print` steps: objects to read and show, or a line of text (with its
//! parameters substituted). It must not read anything from the drive.

use crate::diag::{YamlNode, YamlValue};
use crate::recipe::loader::Loader;
use crate::recipe::step::StepKind;
use crate::session::ObjectRef;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn read(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let objects = self.object_list(body, "`read`")?;
        let label = format!("read {}", ObjectRef::names(&objects));
        Some((StepKind::Read(objects), label))
    }

    /// `print: text`, or `print: [objects]` (which reads them).
    pub(in crate::recipe::loader) fn print(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        if let YamlValue::Seq(_) = body.value {
            let objects = self.object_list(body, "`print`")?;
            let label = format!("read {}", ObjectRef::names(&objects));
            return Some((StepKind::Read(objects), label));
        }
        let text = self.text(body, "`print`")?;
        Some((StepKind::Print(text.clone()), format!("print \"{text}\"")))
    }
}
