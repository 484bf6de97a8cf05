//! A recipe's parameters: the `params:` section, `--set` overrides (and an include step's
//! `params`), and `{{name}}` substitution in the text of any value. It must not interpret
//! the substituted text (numbers, units, durations are `values`' job).

use super::{did_you_mean, Loader};
use crate::diag::{read_source, Shape, Span, YamlNode};
use crate::recipe::recipe::Param;
use std::path::Path;

/// The names under a recipe file's `params:`, read before it is loaded, so that a run of
/// several files can give each `--set` to the files that have it. Anything that cannot be
/// read is left to the loader to report.
pub fn declared_params(path: &Path) -> Vec<String> {
    let Ok(source) = read_source(path) else {
        return Vec::new();
    };
    let Ok(root) = YamlNode::parse(&source) else {
        return Vec::new();
    };
    root.get("params")
        .and_then(YamlNode::entries)
        .map(|entries| entries.iter().map(|(k, _)| k.value.clone()).collect())
        .unwrap_or_default()
}

/// A parameter's text and where it was given (`recipe.yaml:3`, `--set`).
pub(super) struct ParamValue {
    text: String,
    origin: String,
}

impl Loader<'_, '_> {
    /// Reads `params:` and applies `overrides`; the parameters as finally resolved.
    pub(super) fn params_section(
        &mut self,
        node: Option<&YamlNode>,
        overrides: &[(String, String)],
    ) -> Vec<Param> {
        let shape = Shape::any_keys("`params`").example("params: { speed: 6000 rpm }");
        if let Some(f) = node
            .filter(|n| !n.is_null())
            .and_then(|n| self.r.fields(n, &shape))
        {
            for (k, v) in f.entries() {
                if !is_identifier(&k.value) {
                    self.problem(
                        &k.span,
                        format!("`{}` is not a parameter name", k.value),
                        "use letters, digits and _",
                        None,
                    );
                    continue;
                }
                match v.as_text() {
                    Some(text) => {
                        let origin = format!("{}:{}", self.source.path(), v.span.line());
                        self.params.insert(k.value.clone(), ParamValue { text, origin });
                    }
                    None => self.problem(
                        &v.span,
                        format!("parameter `{}` needs a value such as `6000 rpm`", k.value),
                        format!("this is {}", v.kind()),
                        None,
                    ),
                }
            }
        }
        for (name, value) in overrides {
            match self.params.get_mut(name) {
                Some(p) => {
                    p.text = value.clone();
                    p.origin = "--set".into();
                }
                None => {
                    let help = did_you_mean(name, self.params.keys().map(String::as_str))
                        .map(|s| format!("did you mean `{s}`?"))
                        .unwrap_or_else(|| format!("this recipe's parameters: {}", self.param_names()));
                    let at = node.map_or_else(|| Span::start_of(&self.source), |n| n.span.clone());
                    self.problem(
                        &at,
                        format!("--set {name}: this recipe has no parameter `{name}`"),
                        "parameters are declared here",
                        Some(help),
                    );
                }
            }
        }
        self.params
            .iter()
            .map(|(name, p)| Param {
                name: name.clone(),
                value: p.text.clone(),
                origin: p.origin.clone(),
            })
            .collect()
    }

    fn param_names(&self) -> String {
        if self.params.is_empty() {
            "none".into()
        } else {
            self.params.keys().cloned().collect::<Vec<_>>().join(", ")
        }
    }

    /// The node as text (`what` names it in messages) with `{{param}}` substituted; `None`
    /// after reporting a problem.
    pub(super) fn text(&mut self, node: &YamlNode, what: &str) -> Option<String> {
        let raw = self.r.scalar_text(node, what)?;
        self.substitute(&raw, &node.span)
    }

    fn substitute(&mut self, raw: &str, span: &Span) -> Option<String> {
        let mut out = String::new();
        let mut rest = raw;
        let mut ok = true;
        while let Some(start) = rest.find("{{") {
            out.push_str(&rest[..start]);
            let after = &rest[start + 2..];
            let Some(end) = after.find("}}") else {
                return self.refuse(
                    span,
                    format!("`{{{{` without a closing `}}}}` in `{raw}`"),
                    "unclosed parameter",
                    Some("write parameters as {{name}}".into()),
                );
            };
            let name = after[..end].trim();
            match self.params.get(name) {
                Some(p) => out.push_str(&p.text),
                None => {
                    ok = false;
                    let help = did_you_mean(name, self.params.keys().map(String::as_str))
                        .map(|s| format!("did you mean `{{{{{s}}}}}`?"))
                        .unwrap_or_else(|| {
                            format!(
                                "declare it under `params:` (this recipe's parameters: {})",
                                self.param_names()
                            )
                        });
                    self.problem(
                        span,
                        format!("unknown parameter `{name}`"),
                        "not declared under params",
                        Some(help),
                    );
                }
            }
            rest = &after[end + 2..];
        }
        out.push_str(rest);
        ok.then_some(out)
    }
}

fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}
