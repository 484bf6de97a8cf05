//! The `expect_parameters: FILE` step: a parameter backup (`drivescript backup`) the drive
//! must match, one check per object. The file is read and its objects looked up in the
//! dictionary here, so `check` finds a missing file or a stranger's object; it must not
//! read anything from the drive.

use crate::diag::YamlNode;
use crate::parameters::ParameterFile;
use crate::recipe::loader::{beside, Loader};
use crate::recipe::step::StepKind;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn expect_parameters(
        &mut self,
        body: &YamlNode,
    ) -> Option<(StepKind, String)> {
        let file = self.text(body, "`expect_parameters`")?;
        if self.several_drives() {
            return self.refuse(
                &body.span,
                "`expect_parameters` compares one drive with a backup, and this recipe has several drives",
                "which drive?",
                Some("check each drive's parameters in a recipe of its own (`drivescript diff` compares one drive with a backup)".into()),
            );
        }
        let path = beside(&self.base_dir, &file);
        let parameters = match ParameterFile::load(&path) {
            Ok(p) => p,
            Err(e) => {
                return self.refuse(
                    &body.span,
                    format!(
                        "cannot use {file} as a parameter file: {}",
                        e.to_string().trim_end()
                    ),
                    "not a parameter file",
                    Some("give a file written by `drivescript backup`, relative to this recipe".into()),
                );
            }
        };
        if parameters.family != self.dict.family() {
            return self.refuse(
                &body.span,
                format!(
                    "{file} holds parameters of a {} drive; this recipe runs on {}",
                    parameters.family,
                    self.dict.family()
                ),
                "other drive family",
                None,
            );
        }
        let unknown: Vec<&str> = parameters
            .objects
            .iter()
            .filter(|o| self.dict.get(&o.name).is_none_or(|d| !d.readable()))
            .map(|o| o.name.as_str())
            .collect();
        if !unknown.is_empty() {
            return self.refuse(
                &body.span,
                format!(
                    "{file} names object(s) the {} dictionary cannot read: {}",
                    self.dict.name(),
                    unknown.join(", ")
                ),
                "unknown objects",
                Some("add them with --dictionary FILE, or take the backup again".into()),
            );
        }
        let label = format!(
            "expect parameters of {file} ({} object(s))",
            parameters.objects.len()
        );
        Some((
            StepKind::ExpectParameters {
                file,
                parameters: Box::new(parameters),
            },
            label,
        ))
    }
}
