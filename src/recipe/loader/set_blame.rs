//! A `--set` value the recipe cannot use (`--set max_current=5rpm` where amperes are
//! needed), said once at the `--set` that gave it, instead of once at every place the
//! parameter is used and again at every include of those places. Finds the problems the
//! value causes by loading the recipe again without it; must not change what is a problem.

use crate::diag::{Diagnostic, Diagnostics};
use crate::recipe::{Recipe, RecipeInvalid};

/// `invalid` with the problems each of `overrides` causes folded into one at that `--set`;
/// `reload` loads the recipe with other overrides.
pub(super) fn blamed_on_set(
    invalid: RecipeInvalid,
    overrides: &[(String, String)],
    reload: impl Fn(&[(String, String)]) -> Result<Recipe, RecipeInvalid>,
) -> RecipeInvalid {
    let mut problems: Vec<Diagnostic> = invalid.problems.iter().cloned().collect();
    let mut blamed = Vec::new();
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
        let caused: Vec<Key> = problems
            .iter()
            .map(key)
            .filter(|k| !without.contains(k))
            .collect();
        let mut places: Vec<String> = Vec::new();
        let mut first = None;
        for p in problems.iter().filter(|p| caused.contains(&key(p))) {
            if p.span().is_some_and(|s| s.written().contains(&placeholder)) {
                first.get_or_insert_with(|| p.message().to_string());
                let place = format!("{}:{}:{}", p.path(), p.line(), p.column());
                if !places.contains(&place) {
                    places.push(place);
                }
            }
        }
        // Only a value used where it is wrong is the `--set`'s fault; anything else it
        // changes is left at its own place.
        let Some(first) = first else {
            continue;
        };
        problems.retain(|p| !caused.contains(&key(p)));
        blamed.push(
            Diagnostic::unlocated(invalid.path.clone(), format!("--set {name}={value}: {first}")).with_help(
                format!(
                    "the recipe uses `{placeholder}` at {}; give a value that fits there",
                    places.join(", ")
                ),
            ),
        );
    }
    let mut all = Diagnostics::new();
    for p in blamed.into_iter().chain(problems) {
        all.push(p);
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
