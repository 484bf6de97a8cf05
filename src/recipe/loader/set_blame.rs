//! A `--set` value the recipe cannot use (`--set max_current=5rpm` where amperes are
//! needed), said once, naming the `--set` that gave it and shown where the value is first
//! used, instead of once at every place the parameter is used and again at every include
//! of those places. Finds the problems the
//! value causes by loading the recipe again without it; must not change what is a problem.

use crate::diag::{Diagnostic, Diagnostics};
use crate::recipe::{Recipe, RecipeInvalid};

/// `invalid` with the problems each of `overrides` causes folded into one at that `--set`,
/// in the place of the first of them; `reload` loads the recipe with other overrides.
pub(super) fn blamed_on_set(
    invalid: RecipeInvalid,
    overrides: &[(String, String)],
    reload: impl Fn(&[(String, String)]) -> Result<Recipe, RecipeInvalid>,
) -> RecipeInvalid {
    let problems: Vec<&Diagnostic> = invalid.problems.iter().collect();
    // Per `--set` it is the fault of: the problems it causes, and the one that says so.
    let mut blamed: Vec<(Vec<Key>, Option<Diagnostic>)> = Vec::new();
    for (i, (name, value)) in overrides.iter().enumerate() {
        let others: Vec<(String, String)> = overrides
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, o)| o.clone())
            .collect();
        let without: Vec<Key> = match reload(&others) {
            Ok(_) => Vec::new(),
            Err(e) => e.problems.iter().map(key).collect(),
        };
        let placeholder = format!("{{{{{name}}}}}");
        let caused: Vec<&Diagnostic> = problems
            .iter()
            .copied()
            .filter(|p| !without.contains(&key(p)))
            .collect();
        let direct: Vec<&Diagnostic> = caused
            .iter()
            .copied()
            .filter(|p| p.span().is_some_and(|s| s.written().contains(&placeholder)))
            .collect();
        // Only a value used where it is wrong is the `--set`'s fault; anything else it
        // changes is left at its own place.
        let Some(first) = direct.first() else {
            continue;
        };
        let mut elsewhere: Vec<String> = Vec::new();
        for p in &direct[1..] {
            let place = format!("{}:{}:{}", p.path(), p.line(), p.column());
            let shown = p.path() == first.path() && p.line() == first.line() && p.column() == first.column();
            if !shown && !elsewhere.contains(&place) {
                elsewhere.push(place);
            }
        }
        let mut help: Vec<String> = first.help().map(str::to_string).into_iter().collect();
        if !elsewhere.is_empty() {
            help.push(format!(
                "`{placeholder}` is also used at {}",
                elsewhere.join(", ")
            ));
        }
        // Shown at the first place that uses the value, so the value's use is in view.
        let Some(span) = first.span() else {
            continue;
        };
        let said = Diagnostic::at(
            span,
            format!("--set {name}={value}: {}", first.message()),
            format!("`{placeholder}`, given by --set {name}"),
        )
        .with_optional_help((!help.is_empty()).then(|| help.join("; ")));
        blamed.push((caused.iter().map(|p| key(p)).collect(), Some(said)));
    }
    let mut all = Diagnostics::new();
    for p in problems {
        match blamed.iter_mut().find(|(caused, _)| caused.contains(&key(p))) {
            Some((_, said)) => {
                if let Some(said) = said.take() {
                    all.push(said);
                }
            }
            None => all.push(p.clone()),
        }
    }
    RecipeInvalid {
        path: invalid.path,
        problems: all,
    }
}

/// What makes two problems the same one.
type Key = (String, usize, usize, String);

fn key(p: &Diagnostic) -> Key {
    (
        p.path().to_string(),
        p.line(),
        p.column(),
        p.message().to_string(),
    )
}
