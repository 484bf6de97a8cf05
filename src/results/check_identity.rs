//! Which measurement a stored check is, so that a trend, a capability and the comparison
//! with a unit's last passed run never merge two: the recipe (its name; its text's hash
//! is kept beside it, so a recipe edited without renaming stays one trend that shows
//! where its text changed), the stage that holds the check (as the reports name it), the
//! step's place in the recipe (where a run held that check at several places; a trend
//! leaves it out elsewhere, so that a step inserted before it keeps its history), and the
//! check's key (object, statistic and kind of limit,
//! or the name the recipe gave it). Also reads what a user types for a check: the key, a
//! full name as the console shows it, or the JUnit test-case name. Pure text.

use crate::session::{identity_stage, key_of_name, without_iterations};

/// One measurement across runs.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CheckIdentity {
    pub recipe: String,
    /// The stage as the reports name it (`Stage 2, 12000 rpm`, `repeat 2 times (3 steps)
    /// #2`), without the attempt an `attempts` block passed at: a check that passed at its
    /// second attempt is the same check as one that passed at its first.
    pub stage: String,
    /// The step's number in the recipe without repeat iterations: `4.1.3`.
    pub path: String,
    /// The check's key, or its name where it has none.
    pub key: String,
}

impl CheckIdentity {
    /// The identity of a check stored with these facts (`step` iteration-aware, `4[2].1`).
    pub fn of(recipe: &str, stage: &str, step: &str, key: &str) -> CheckIdentity {
        CheckIdentity {
            recipe: recipe.to_string(),
            stage: identity_stage(stage),
            path: without_iterations(step),
            key: key.to_string(),
        }
    }

    /// As the JUnit report names its test case: `Stage 2, 12000 rpm / speed_actual mean
    /// near`, the key alone at the top level.
    pub fn case_name(&self) -> String {
        match self.stage.is_empty() {
            true => self.key.clone(),
            false => format!("{} / {}", self.stage, self.key),
        }
    }
}

/// What a user may have meant by a check's text: the stage (when the text names one) and
/// the keys or names the check may be stored under, and its step (`(step 4.2)` as a JUnit
/// name tells cases of one name apart).
#[derive(Debug, Clone, PartialEq)]
pub struct AskedCheck {
    pub stage: Option<String>,
    /// Keys and full names (a name without a key is its own key).
    pub keys: Vec<String>,
    pub path: Option<String>,
}

/// Every reading of `text`: as a whole (a key or a full name at any stage), and split at
/// each ` / ` into a stage and a check (`Stage 2, 12000 rpm / speed_actual mean near`,
/// a stage may itself hold ` / `), each with a JUnit `(step N)` or `(N)` taken off its end.
pub fn readings(text: &str) -> Vec<AskedCheck> {
    let mut out = vec![asked(None, text)];
    for (at, _) in text.match_indices(" / ") {
        out.push(asked(Some(&text[..at]), &text[at + 3..]));
    }
    out
}

fn asked(stage: Option<&str>, check: &str) -> AskedCheck {
    let (check, path) = without_case_suffix(check);
    let mut keys = vec![check.to_string()];
    if let Some(k) = key_of_name(check) {
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    AskedCheck {
        stage: stage.map(identity_stage),
        keys,
        path,
    }
}

impl AskedCheck {
    /// Whether a stored check (its identity, and its full name) is what this reading asks
    /// for.
    pub fn takes(&self, id: &CheckIdentity, name: &str) -> bool {
        self.stage.as_ref().is_none_or(|s| *s == id.stage)
            && self.path.as_ref().is_none_or(|p| *p == id.path)
            && self.keys.iter().any(|k| *k == id.key || k == name)
    }
}

/// `x (step 4.2)` → (`x`, `4.2`); `x (step 4.2, 2)` and `x (2)` (a second case of one
/// name in a step, which the store cannot tell apart) → `x` with the step or none.
fn without_case_suffix(check: &str) -> (&str, Option<String>) {
    let Some(open) = check
        .strip_suffix(')')
        .and_then(|c| c.rfind(" (").map(|at| (at, c)))
    else {
        return (check, None);
    };
    let (at, inner) = (open.0, &open.1[open.0 + 2..]);
    let stem = &check[..at];
    if let Some(step) = inner.strip_prefix("step ") {
        let step = step.split(", ").next().unwrap_or(step);
        if !step.is_empty() && step.split('.').all(|p| !p.is_empty() && !p.contains(' ')) {
            return (stem, Some(step.to_string()));
        }
    } else if inner.parse::<u32>().is_ok() {
        return (stem, None);
    }
    (check, None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn id(recipe: &str, stage: &str, step: &str, key: &str) -> CheckIdentity {
        CheckIdentity::of(recipe, stage, step, key)
    }

    #[test]
    fn the_junit_name_the_key_and_the_full_name_each_find_their_check_and_no_other() {
        let stage2 = id("Run-in", "Stage 2, 12000 rpm", "3.4", "speed_actual mean near");
        let stage1 = id("Run-in", "Stage 1, 6000 rpm", "2.4", "speed_actual mean near");
        let junit = "Stage 2, 12000 rpm / speed_actual mean near";
        assert_eq!(stage2.case_name(), junit);
        let takes =
            |text: &str, c: &CheckIdentity, name: &str| readings(text).iter().any(|r| r.takes(c, name));
        let name = "speed_actual mean near 12000 rpm ± 1 %";
        assert!(takes(junit, &stage2, name));
        assert!(!takes(junit, &stage1, "speed_actual mean near 6000 rpm ± 1 %"));
        assert!(takes(&format!("{junit} (step 3.4)"), &stage2, name));
        assert!(!takes(&format!("{junit} (step 3.5)"), &stage2, name));
        assert!(takes(
            "Stage 2, 12000 rpm / speed_actual mean near 12000 rpm ± 1 %",
            &stage2,
            name
        ));
        // The key alone and the full name find it at any stage: the caller tells them apart.
        assert!(takes("speed_actual mean near", &stage1, "x") && takes(name, &stage2, name));
        assert!(!takes("current_actual max below", &stage2, name));
        // A stage that holds ` / ` itself.
        let nested = id("R", "repeat 2 times (3 steps) #2 / Stage", "4[2].1.3", "x below");
        assert_eq!(nested.path, "4.1.3");
        assert!(takes(
            "repeat 2 times (3 steps) #2 / Stage / x below",
            &nested,
            "x below 5 A"
        ));
        assert!(!takes(
            "repeat 2 times (3 steps) #1 / Stage / x below",
            &nested,
            "x below 5 A"
        ));
    }

    #[test]
    fn an_attempt_number_is_no_part_of_a_stage_and_a_repeats_iteration_is() {
        assert_eq!(
            identity_stage("Warm-up / attempts: up to 3 times (2 steps) #2"),
            "Warm-up / attempts: up to 3 times (2 steps)"
        );
        assert_eq!(
            identity_stage("repeat 2 times (3 steps) #2"),
            "repeat 2 times (3 steps) #2"
        );
        assert_eq!(
            id("R", "attempts: up to 3 times (2 steps) #1", "2[1].1", "k"),
            id("R", "attempts: up to 3 times (2 steps) #3", "2[3].1", "k")
        );
    }

    #[test]
    fn a_junit_suffix_is_read_off_only_where_it_is_one() {
        assert_eq!(without_case_suffix("x (step 10)"), ("x", Some("10".into())));
        assert_eq!(without_case_suffix("x (step 4.1, 2)"), ("x", Some("4.1".into())));
        assert_eq!(without_case_suffix("x (2)"), ("x", None));
        assert_eq!(without_case_suffix("bearing (front)"), ("bearing (front)", None));
        assert_eq!(without_case_suffix("x (step )"), ("x (step )", None));
    }

    proptest! {
        /// Whatever a user types, reading it neither panics nor loses the text as a key.
        #[test]
        fn any_text_reads_without_panic(text in "\\PC{0,80}") {
            let all = readings(&text);
            prop_assert!(text.starts_with(all[0].keys[0].as_str()));
        }
    }
}
