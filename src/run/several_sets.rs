//! `--set` in a run of several files: each file gets the parameters it has, and a name
//! that no file has is refused before anything runs (exit code 2), with a did-you-mean
//! across every file's parameters. Reads the files' parameter names; must not load or run
//! them (each run checks its own values).

use super::RunError;
use crate::diag::{did_you_mean, suggestion_text};
use crate::recipe::declared_params;
use crate::script::{declared_script_params, is_script};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The `--set` parameters of each of `files`, in order; the refusal of every name none of
/// them has.
pub fn sets_per_file(
    files: &[PathBuf],
    set: &[(String, String)],
) -> Result<Vec<Vec<(String, String)>>, RunError> {
    let params: Vec<Vec<String>> = files
        .iter()
        .map(|f| {
            if is_script(f) {
                declared_script_params(f)
            } else {
                declared_params(f)
            }
        })
        .collect();
    let mut refused = String::new();
    for (name, value) in set {
        if params.iter().any(|p| p.contains(name)) {
            continue;
        }
        let all = params.iter().flatten().map(String::as_str);
        let help = suggestion_text(&did_you_mean(name, all)).unwrap_or_else(|| "check the name".into());
        let _ = writeln!(
            refused,
            "error: --set {name}={value}: no file of this run has a parameter `{name}`; nothing was sent\n  help: {help}"
        );
    }
    if !refused.is_empty() {
        let _ = writeln!(refused, "  the files' parameters:");
        for (file, names) in files.iter().zip(&params) {
            let names = if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            };
            let _ = writeln!(refused, "    {}: {names}", file.display());
        }
        return Err(RunError::Invalid(refused.trim_end().to_string()));
    }
    Ok(params
        .iter()
        .map(|names| set.iter().filter(|(n, _)| names.contains(n)).cloned().collect())
        .collect())
}
