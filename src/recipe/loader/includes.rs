//! The `include` step: another recipe file's steps, read with their own parameters (given
//! in the step) and their own places, within the include depth and the expansion limits,
//! and never including themselves. It must not read the included steps itself: the
//! included file is read by a nested loader.

use super::{beside, canonical, Loader};
use crate::diag::{read_source, Reader, Shape, YamlNode};
use crate::recipe::step::StepKind;
use std::collections::BTreeMap;
use std::path::Path;

/// Nested includes beyond this are a mistake (or a cycle the path check missed).
const MAX_INCLUDE_DEPTH: usize = 8;

impl Loader<'_, '_> {
    /// `include: file.yaml` or `include: { file: file.yaml, params: { speed: 8000 rpm } }`.
    pub(super) fn include(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        if self.expansion.is_over() {
            return None;
        }
        let (file_node, params_node) = match body.entries() {
            Some(_) => {
                let shape = Shape::new("this include", &["file", "params", "on_failure"]).require(&["file"]);
                let f = self.r.fields(body, &shape)?;
                (f.get("file")?, f.get("params"))
            }
            None => (body, None),
        };
        let file = self.text(file_node, "`include`")?;
        let path = beside(&self.base_dir, &file);
        let canon = canonical(&path);
        if self.include_chain.contains(&canon) {
            return self.refuse(
                &file_node.span,
                format!(
                    "{file} includes itself (through {} file(s))",
                    self.include_chain.len()
                ),
                "include cycle",
                None,
            );
        }
        if self.include_chain.len() >= MAX_INCLUDE_DEPTH {
            return self.refuse(
                &file_node.span,
                format!("includes nest deeper than {MAX_INCLUDE_DEPTH} files"),
                "too deep",
                None,
            );
        }
        if let Err(over) = self.expansion.load() {
            self.over_limit(&file_node.span, over);
            return None;
        }
        let source = match read_source(&path) {
            Ok(source) => source,
            Err(e) => {
                let help = e
                    .help()
                    .unwrap_or_else(|| "include paths are relative to the including recipe".into());
                return self.refuse(
                    &file_node.span,
                    e.sentence(&format!("the included file {}", path.display())),
                    "included file",
                    Some(help),
                );
            }
        };
        self.digest.add(source.text());
        let given = params_node.map(|p| self.given_params(p)).unwrap_or_default();
        let shown = source.path().to_string();
        let before = self.r.count();
        let mut include_chain = self.include_chain.clone();
        include_chain.push(canon);
        let mut inner = Loader {
            dict: self.dict,
            drive_dicts: self.drive_dicts,
            address_keys: self.address_keys,
            source,
            r: Reader::new(self.r.diagnostics()),
            expansion: self.expansion,
            digest: self.digest,
            params: BTreeMap::new(),
            sampled: self.sampled.clone(),
            sample_refused: self.sample_refused,
            base_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            include_chain,
        };
        let recipe = inner.recipe(&given);
        self.sampled = inner.sampled;
        self.sample_refused = inner.sample_refused;
        if self.r.count() > before {
            return self.refuse(
                &file_node.span,
                format!("{file} has problems (listed with their own places)"),
                "included here",
                None,
            );
        }
        let recipe = recipe?;
        let label = format!("include {file} ({})", recipe.name);
        Some((
            StepKind::Include {
                path: shown,
                steps: recipe.steps,
            },
            label,
        ))
    }

    /// The include step's `params`, resolved in this file's parameters, as `--set` pairs
    /// for the included file.
    fn given_params(&mut self, node: &YamlNode) -> Vec<(String, String)> {
        let shape = Shape::any_keys("`params`").example("params: { speed: 8000 rpm }");
        let Some(f) = self.r.fields(node, &shape) else {
            return Vec::new();
        };
        let mut given = Vec::new();
        for (k, v) in f.entries() {
            if let Some(t) = self.text(v, &format!("parameter `{}`", k.value)) {
                given.push((k.value.clone(), t));
            }
        }
        given
    }
}
