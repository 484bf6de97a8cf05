//! Comparing a check with the same unit's last passed run of the same recipe
//! (`compared_with_last_pass`): what the recipe allows the value to change by, the past run
//! a results store gives back, and the seam ([`History`]) through which the session asks
//! for it. Pure data and arithmetic; nothing here reads a store (the results layer does).

use super::{identity_stage, number, without_iterations, StepOrigin};
use std::sync::mpsc::Receiver;

/// How far a value may move from the same check's value in the unit's last passed run.
#[derive(Debug, Clone, PartialEq)]
pub struct LastPass {
    /// The change allowed, both ends included: in % of the reference's magnitude
    /// (`relative`), else in the unit a difference of the check's values is written in.
    pub at_least: Option<f64>,
    pub at_most: Option<f64>,
    pub relative: bool,
    /// With no earlier passed run (a unit's first run), the comparison passes (`true`) or
    /// fails.
    pub pass_without_history: bool,
    /// Where `compared_with_last_pass` is written.
    pub written: StepOrigin,
}

impl LastPass {
    /// The change from `reference` to `value`, in % or in the check's unit; `None` when a
    /// relative change from 0 is asked for.
    pub fn change(&self, reference: f64, value: f64) -> Option<f64> {
        match self.relative {
            true if reference == 0.0 => None,
            true => Some((value - reference) / reference.abs() * 100.0),
            false => Some(value - reference),
        }
    }

    /// Whether `change` is within the ends (a change computed exactly at an end, 4 A to
    /// 4.4 A against `at_most: 10 %`, is not failed by the last bit of a float).
    pub fn allows(&self, change: f64) -> bool {
        let slack = |limit: f64| 1e-9 * limit.abs().max(1.0);
        self.at_least.is_none_or(|l| change >= l - slack(l))
            && self.at_most.is_none_or(|h| change <= h + slack(h))
    }

    /// `at most +10 %`, `between -5 % and +10 %`, `at least -0.5 A`.
    pub fn describe(&self, unit: Option<&str>) -> String {
        let u = |v: f64| signed(v, unit);
        match (self.at_least, self.at_most) {
            (Some(l), Some(h)) => format!("between {} and {}", u(l), u(h)),
            (Some(l), None) => format!("at least {}", u(l)),
            (None, Some(h)) => format!("at most {}", u(h)),
            (None, None) => "any change".into(),
        }
    }

    /// What `without_history` chose, as the recipe writes it.
    pub fn without_history_word(&self) -> &'static str {
        if self.pass_without_history {
            "pass"
        } else {
            "fail"
        }
    }
}

/// A change with its sign and unit: `+12.4 %`, `-0.3 A`.
pub fn signed(v: f64, unit: Option<&str>) -> String {
    let sign = if v > 0.0 { "+" } else { "" };
    match unit {
        Some(u) => format!("{sign}{} {u}", number(v)),
        None => format!("{sign}{}", number(v)),
    }
}

/// The unit's last passed run of the recipe, as a store gives it back.
#[derive(Debug, Clone, PartialEq)]
pub struct PastRun {
    pub id: String,
    /// UTC, RFC 3339.
    pub started_at: String,
    /// Its passed checks with a measured value, in the order they were made.
    pub checks: Vec<PastCheck>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PastCheck {
    pub name: String,
    /// Its key ([`super::check_key`]); `None` for a check stored before keys were, whose
    /// name alone says which check it was.
    pub key: Option<String>,
    /// The iteration-aware step id (`4[2].1`).
    pub step: String,
    /// The stage that held it, as the reports name it (`Stage 2, 12000 rpm`).
    pub stage: String,
    pub measured: f64,
    pub unit: Option<String>,
}

impl PastCheck {
    /// Whether it is the check keyed `key` (named `name` now): by its key (its limits may
    /// have changed since), or by the very same name. A check stored before keys were has
    /// the key the migration read from its name; where the recipe gave that name (`name:
    /// Temperature below 95 °C`) the check keys by the whole name now, and the name alone
    /// still finds it.
    pub fn is(&self, key: &str, name: &str) -> bool {
        self.key.as_deref() == Some(key) || self.name == name
    }
}

impl PastRun {
    /// The check this run's check keyed `key` (named `name`) at step `step` of stage
    /// `stage` compares with: the same measurement, never one of another stage or another
    /// place in the recipe (`speed_actual mean near` at 6000 rpm is not the one at 12000
    /// rpm). The one of that key and stage at the same step, else at the same place in
    /// the recipe (another iteration, or an attempt that passed at another try: the last
    /// one), else the only one of that key in that stage (the recipe moved it); `None`
    /// when several are and none is at this place.
    pub fn check(&self, key: &str, name: &str, step: &str, stage: &str) -> Option<&PastCheck> {
        let stage = identity_stage(stage);
        let path = without_iterations(step);
        let same: Vec<&PastCheck> = self
            .checks
            .iter()
            .filter(|c| c.is(key, name) && identity_stage(&c.stage) == stage)
            .collect();
        let moved = match same.as_slice() {
            [only] => Some(*only),
            _ => None,
        };
        same.iter()
            .find(|c| c.step == step)
            .or_else(|| same.iter().rev().find(|c| without_iterations(&c.step) == path))
            .copied()
            .or(moved)
    }

    /// The last check of key `key` (named `name` now) in this run.
    pub fn last_check(&self, key: &str, name: &str) -> Option<&PastCheck> {
        self.checks.iter().rev().find(|c| c.is(key, name))
    }
}

/// A store that could not answer: the comparison cannot be judged (it fails; it is never
/// taken as "no history").
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{why}")]
pub struct HistoryError {
    /// The store as messages name it (never a password).
    pub store: String,
    /// What went wrong, naming the store.
    pub why: String,
}

/// Where past runs come from: the results layer gives the session one.
pub trait History: Send + Sync {
    /// Starts looking, on a thread of its own, for the last complete run with verdict
    /// passed of `recipe` (its name) on the unit `serial`, among runs as simulated as this
    /// one; the answer comes through the receiver (`None`: no such run).
    fn look_up(&self, recipe: &str, serial: &str) -> Receiver<Result<Option<PastRun>, HistoryError>>;
    /// The store as messages name it.
    fn store(&self) -> String;
    /// `simulated runs` or `runs on real drives`: the runs compared with.
    fn kind_of_runs(&self) -> &'static str;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn allowed(at_least: Option<f64>, at_most: Option<f64>, relative: bool) -> LastPass {
        LastPass {
            at_least,
            at_most,
            relative,
            pass_without_history: true,
            written: StepOrigin {
                path: "r.yaml".into(),
                line: 1,
                column: 1,
            },
        }
    }

    #[test]
    fn a_relative_change_is_of_the_references_magnitude_and_both_ends_are_included() {
        let lp = allowed(Some(-5.0), Some(10.0), true);
        let up = lp.change(4.0, 4.4).expect("a change");
        assert!((up - 10.0).abs() < 1e-9 && lp.allows(up), "{up}");
        assert!(lp.allows(10.0) && lp.allows(-5.0) && !lp.allows(10.01) && !lp.allows(-5.01));
        assert_eq!(
            lp.change(-2.0, -1.0),
            Some(50.0),
            "toward zero from a negative value is up"
        );
        assert_eq!(lp.change(0.0, 1.0), None, "no relative change from 0");
        assert_eq!(lp.describe(Some("%")), "between -5 % and +10 %");
    }

    #[test]
    fn an_absolute_change_is_in_the_checks_unit() {
        let lp = allowed(None, Some(0.5), false);
        assert_eq!(lp.change(4.0, 4.25), Some(0.25));
        assert!(lp.allows(0.5) && !lp.allows(0.51) && lp.allows(-100.0));
        assert_eq!(lp.describe(Some("A")), "at most +0.5 A");
    }

    fn past(name: &str, key: Option<&str>, step: &str, measured: f64) -> PastCheck {
        PastCheck {
            name: name.into(),
            key: key.map(str::to_string),
            step: step.into(),
            stage: String::new(),
            measured,
            unit: None,
        }
    }

    #[test]
    fn the_reference_is_the_same_step_else_the_last_of_that_key() {
        let (key, name) = ("c below", "c below 5 A");
        let run = PastRun {
            id: "r".into(),
            started_at: "t".into(),
            checks: vec![
                past("c below 5 A", Some(key), "3[1].1", 1.0),
                past("c below 5 A", Some(key), "3[2].1", 2.0),
            ],
        };
        assert_eq!(run.check(key, name, "3[1].1", "").map(|c| c.measured), Some(1.0));
        assert_eq!(
            run.check(key, name, "3[3].1", "").map(|c| c.measured),
            Some(2.0),
            "another iteration of the same place: the last"
        );
        assert_eq!(
            run.check(key, name, "9", ""),
            None,
            "two of that key, neither at this place: which one it was cannot be told"
        );
        // Its limit tightened since: still the same check.
        assert_eq!(
            run.check(key, "c below 4.5 A", "3[2].1", "").map(|c| c.measured),
            Some(2.0)
        );
        assert_eq!(run.check("d below", "d below 5 A", "3[1].1", ""), None);
        assert_eq!(
            run.check("c above", "c above 5 A", "3[1].1", ""),
            None,
            "another key and another name"
        );
    }

    /// The same key in two stages is two measurements: each compares with its own, even
    /// when the recipe moved them (a step inserted before them), and a check that was in
    /// one stage only is not compared with another stage's.
    #[test]
    fn a_check_compares_only_with_the_same_stage() {
        let key = "speed_actual mean near";
        let staged = |stage: &str, step: &str, v: f64| PastCheck {
            stage: stage.into(),
            ..past(&format!("{key} {v} rpm ± 1 %"), Some(key), step, v)
        };
        let run = PastRun {
            id: "r".into(),
            started_at: "t".into(),
            checks: vec![
                staged("Stage 1, 6000 rpm", "2.3", 6000.0),
                staged("Stage 2, 12000 rpm", "3.3", 12000.0),
                staged("Stage 3, 18000 rpm", "4.3", 18000.0),
            ],
        };
        let found = |step: &str, stage: &str| run.check(key, "n", step, stage).map(|c| c.measured);
        assert_eq!(found("3.3", "Stage 2, 12000 rpm"), Some(12000.0));
        assert_eq!(found("4.3", "Stage 2, 12000 rpm"), Some(12000.0), "moved");
        assert_eq!(found("4.3", "Stage 4, 3000 rpm"), None, "a stage new since");
        assert_eq!(found("4.3", ""), None, "at the top level now: another check");
    }

    /// A name the recipe gave that reads like one drivescript makes: the migration keyed
    /// it by what it shows (`Temperature below`), the check keys by the whole name now.
    #[test]
    fn a_migrated_check_the_recipe_named_is_found_by_its_name() {
        let name = "Temperature below 95 °C";
        let run = PastRun {
            id: "r".into(),
            started_at: "t".into(),
            checks: vec![past(name, Some("Temperature below"), "4", 24.8)],
        };
        assert_eq!(run.check(name, name, "4", "").map(|c| c.measured), Some(24.8));
    }

    #[test]
    fn a_check_stored_without_a_key_is_found_by_its_full_name() {
        let run = PastRun {
            id: "r".into(),
            started_at: "t".into(),
            checks: vec![past("bearing current", None, "4", 1.5)],
        };
        let found = run.check("bearing current", "bearing current", "4", "");
        assert_eq!(found.map(|c| c.measured), Some(1.5));
        assert_eq!(run.check("x below", "x below 5 A", "4", ""), None);
    }
}
