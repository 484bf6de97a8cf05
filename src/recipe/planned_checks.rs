//! What a recipe will check and sample, known before it runs: its checks (`expect` checks,
//! `wait_until` conditions, operator steps, coast-downs, and the comparisons with the
//! unit's last passed run that follow them) with the stage that holds each, so reports can show the
//! ones a run never reached, and the objects its sample steps read, for the columns of a
//! wide CSV. Reads the validated recipe only.
//!
//! A check inside a `times: N` repeat is planned once per pass, with the stage the run
//! will give it (`repeat 2 times #2 / …`), so a report names a check the same whether the
//! run reached it or not. A repeat bounded by `for:` has an unknown number of passes: its
//! first pass (which always runs) is planned, later passes are named as they run.
//! At most [`MAX_RECORDS`] checks are planned, as many as a report keeps: a `times:
//! 1000000` repeat costs no memory per pass before it runs, and checks beyond are named
//! as they run.

use super::recipe::Recipe;
use super::step::{Step, StepKind};
use crate::session::{
    compared_key, Condition, LastPass, ObjectRef, PlannedCheck, PromptKind, COMPARED, MAX_RECORDS, WAIT,
};

/// Every check of the recipe's steps in run order (a check inside a `times:` repeat once
/// per pass).
pub fn planned_checks(recipe: &Recipe) -> Vec<PlannedCheck> {
    let mut out = Vec::new();
    walk(&recipe.steps, "", &mut Vec::new(), &mut out);
    out
}

fn walk(steps: &[Step], prefix: &str, stage: &mut Vec<String>, out: &mut Vec<PlannedCheck>) {
    for (i, step) in steps.iter().enumerate() {
        if out.len() >= MAX_RECORDS {
            return;
        }
        // Numbered as the runner numbers steps.
        let number = match prefix {
            "" => format!("{}", i + 1),
            _ => format!("{prefix}.{}", i + 1),
        };
        let stage_text = stage.join(" / ");
        let planned =
            |(name, key): (String, String), object: Option<String>, statistic: Option<String>| PlannedCheck {
                name,
                key,
                object,
                statistic,
                stage: stage_text.clone(),
                step: number.clone(),
                origin: step.origin.clone(),
            };
        let compared = compared(&step.kind);
        for (name, object, statistic) in own_checks(&step.kind) {
            let comparison = compared
                .iter()
                .any(|(n, _)| *n == name)
                .then(|| (format!("{}{COMPARED}", name.0), compared_key(&name.1)));
            out.push(planned(name, object, statistic));
            if let Some(name) = comparison {
                out.push(planned(name, None, None));
            }
        }
        match &step.kind {
            StepKind::Repeat {
                times, steps: nested, ..
            } => {
                for pass in 1..=times.unwrap_or(1) {
                    if out.len() >= MAX_RECORDS {
                        break;
                    }
                    stage.push(format!("{} #{pass}", step.label));
                    walk(nested, &number, stage, out);
                    stage.pop();
                }
            }
            // The first attempt always runs; later ones are named as they run.
            StepKind::Attempts { steps: nested, .. } => {
                stage.push(format!("{} #1", step.label));
                walk(nested, &number, stage, out);
                stage.pop();
            }
            StepKind::Include { steps: nested, .. } => {
                stage.push(step.label.clone());
                walk(nested, &number, stage, out);
                stage.pop();
            }
            _ => {}
        }
    }
}

/// (name, key) of a check.
type Named = (String, String);

/// The checks a step makes itself (its nested steps' aside), in order: ((name, key),
/// object, statistic).
fn own_checks(kind: &StepKind) -> Vec<(Named, Option<String>, Option<String>)> {
    match kind {
        StepKind::Expect(checks) => checks
            .iter()
            .map(|c| {
                let statistic = c.statistic.map(|s| s.id().to_string());
                (
                    (c.name.clone(), c.key.clone()),
                    Some(c.object.name.clone()),
                    statistic,
                )
            })
            .collect(),
        StepKind::WaitUntil { condition, .. } => {
            let object = match condition {
                Condition::Value { object, .. } | Condition::Stable { object, .. } => {
                    Some(object.name.clone())
                }
                Condition::State(_) => None,
            };
            let named = (format!("{WAIT}{condition}"), format!("{WAIT}{}", condition.key()));
            vec![(named, object, None)]
        }
        StepKind::Ask(prompt) => vec![((prompt.text.clone(), prompt.text.clone()), None, None)],
        StepKind::CoastDown(c) => vec![((c.check_name(), c.check_key()), None, Some("coast_down".into()))],
        _ => Vec::new(),
    }
}

/// The checks a step makes itself that compare with the unit's last passed run, each
/// (name, key) with its comparison (a check of its own, right after it).
fn compared(kind: &StepKind) -> Vec<(Named, &LastPass)> {
    match kind {
        StepKind::Expect(checks) => checks
            .iter()
            .filter_map(|c| {
                c.last_pass
                    .as_ref()
                    .map(|lp| ((c.name.clone(), c.key.clone()), lp))
            })
            .collect(),
        StepKind::CoastDown(c) => c
            .last_pass
            .iter()
            .map(|lp| ((c.check_name(), c.check_key()), lp))
            .collect(),
        StepKind::Ask(p) => match &p.kind {
            PromptKind::Value {
                last_pass: Some(lp), ..
            } => vec![((p.text.clone(), p.text.clone()), lp)],
            _ => Vec::new(),
        },
        _ => Vec::new(),
    }
}

/// The shortest interval any sample step of the recipe asks for (finally's too), or a
/// `watch:` reads at: what the line must keep up with.
pub fn shortest_sample_interval(recipe: &Recipe) -> Option<std::time::Duration> {
    fn walk(steps: &[Step], out: &mut Option<std::time::Duration>) {
        for step in steps {
            match &step.kind {
                StepKind::Sample { sampling, .. } => {
                    let every = sampling.every;
                    *out = Some(out.map_or(every, |o| o.min(every)));
                }
                StepKind::Repeat { steps, .. }
                | StepKind::Include { steps, .. }
                | StepKind::Attempts { steps, .. } => walk(steps, out),
                _ => {}
            }
        }
    }
    let mut out = None;
    walk(&recipe.steps, &mut out);
    walk(recipe.finally.as_deref().unwrap_or_default(), &mut out);
    all_watches(recipe).into_iter().map(|w| w.every).chain(out).min()
}

/// Every watch of the recipe: its top `watch:` and each repeat's or attempts block's own,
/// in recipe order.
pub fn all_watches(recipe: &Recipe) -> Vec<&crate::session::Watch> {
    fn walk<'a>(steps: &'a [Step], out: &mut Vec<&'a crate::session::Watch>) {
        for step in steps {
            out.extend(step.watches.iter());
            if let StepKind::Repeat { steps, .. }
            | StepKind::Include { steps, .. }
            | StepKind::Attempts { steps, .. } = &step.kind
            {
                walk(steps, out);
            }
        }
    }
    let mut out: Vec<&crate::session::Watch> = recipe.watches.iter().collect();
    walk(&recipe.steps, &mut out);
    out
}

/// The objects the recipe's sample steps read (finally's too), each once, in recipe order.
pub fn sampled_objects(recipe: &Recipe) -> Vec<ObjectRef> {
    fn walk(steps: &[Step], out: &mut Vec<ObjectRef>) {
        for step in steps {
            match &step.kind {
                StepKind::Sample { sampling, .. } => {
                    for o in &sampling.objects {
                        if !out.iter().any(|seen| seen.name == o.name) {
                            out.push(o.clone());
                        }
                    }
                }
                StepKind::Repeat { steps, .. }
                | StepKind::Include { steps, .. }
                | StepKind::Attempts { steps, .. } => walk(steps, out),
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    walk(&recipe.steps, &mut out);
    walk(recipe.finally.as_deref().unwrap_or_default(), &mut out);
    out
}

/// Every operator step of the recipe (its `finally` and `on_fault` too) with its place,
/// in the order written, each once: a run without a terminal needs an answer for each.
pub fn operator_prompts(recipe: &Recipe) -> Vec<(crate::session::Prompt, crate::session::StepOrigin)> {
    fn walk(steps: &[Step], out: &mut Vec<(crate::session::Prompt, crate::session::StepOrigin)>) {
        for step in steps {
            match &step.kind {
                StepKind::Ask(p) => out.push((p.clone(), step.origin.clone())),
                _ => walk(step.nested(), out),
            }
        }
    }
    let mut out = Vec::new();
    walk(&recipe.steps, &mut out);
    walk(recipe.finally.as_deref().unwrap_or_default(), &mut out);
    walk(&recipe.on_fault, &mut out);
    out
}

/// The checks that compare with the unit's last passed run, (name, key) of each key once,
/// with where the first of them writes `compared_with_last_pass`. (One in `finally` judges
/// by what was looked up before: the safe stop never waits for a store.)
pub fn last_pass_checks(recipe: &Recipe) -> (Vec<(String, String)>, Option<crate::session::StepOrigin>) {
    fn walk(steps: &[Step], names: &mut Vec<Named>, first: &mut Option<crate::session::StepOrigin>) {
        for step in steps {
            for (name, lp) in compared(&step.kind) {
                first.get_or_insert_with(|| lp.written.clone());
                if !names.iter().any(|(_, key)| *key == name.1) {
                    names.push(name);
                }
            }
            walk(step.nested(), names, first);
        }
    }
    let (mut names, mut first) = (Vec::new(), None);
    walk(&recipe.steps, &mut names, &mut first);
    walk(
        recipe.finally.as_deref().unwrap_or_default(),
        &mut names,
        &mut first,
    );
    walk(&recipe.on_fault, &mut names, &mut first);
    (names, first)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    const WEAR: &str = "name: Wear
drive: sd2
steps:
  - expect: { motor_temperature: { below: 80 °C } }
  - coast_down:
      from: 5900 rpm
      below: 100 rpm
      expect: { above: 15 s, compared_with_last_pass: { at_least: -10 %, without_history: pass } }
  - enter_value: { prompt: Vibration, unit: mm/s, compared_with_last_pass: { at_most: 0.3 mm/s, without_history: fail } }
";

    fn wear() -> Recipe {
        let dictionary = crate::family::Registry::builtin()
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .expect("built-in dictionary");
        crate::recipe::load_recipe_text("r.yaml", WEAR, Path::new("."), &dictionary, &[]).expect("valid")
    }

    /// A question in a long repeat (a 238-byte recipe once took 3.1 GB planning it): the
    /// plan holds no more checks than a report keeps, however many passes are asked for.
    #[test]
    fn a_long_repeat_plans_no_more_checks_than_a_report_keeps() {
        let dictionary = crate::family::Registry::builtin()
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .expect("built-in dictionary");
        let text = "name: Loop\nsteps:\n  - repeat:\n      times: 200000\n      steps:\n        - instruct: Press Enter\n          name: go\n        - confirm: Fine?\n          name: fine\n";
        let recipe =
            crate::recipe::load_recipe_text("r.yaml", text, Path::new("."), &dictionary, &[]).expect("valid");
        let planned = planned_checks(&recipe);
        assert_eq!(planned.len(), MAX_RECORDS);
        // The first passes are planned as the run will name them.
        assert_eq!(planned[0].stage, "repeat 200000 times (2 steps) #1");
        assert_eq!(
            planned[MAX_RECORDS - 1].stage,
            format!("repeat 200000 times (2 steps) #{}", MAX_RECORDS / 2)
        );
    }

    #[test]
    fn a_coast_down_and_a_typed_value_are_followed_by_their_comparisons() {
        let planned = planned_checks(&wear());
        let names: Vec<(&str, &str)> = planned
            .iter()
            .map(|c| (c.step.as_str(), c.name.as_str()))
            .collect();
        let want = [
            ("1", "motor_temperature below 80 °C"),
            ("2", "coast-down from 5900 rpm below 100 rpm above 15 s"),
            (
                "2",
                "coast-down from 5900 rpm below 100 rpm above 15 s compared with last pass",
            ),
            ("3", "Vibration"),
            ("3", "Vibration compared with last pass"),
        ];
        assert_eq!(names, want);
        // Each keyed as the run keys it: without its limits.
        let keys: Vec<&str> = planned.iter().map(|c| c.key.as_str()).collect();
        let want = [
            "motor_temperature below",
            "coast-down from 5900 rpm below 100 rpm",
            "coast-down from 5900 rpm below 100 rpm compared with last pass",
            "Vibration",
            "Vibration compared with last pass",
        ];
        assert_eq!(keys, want);
    }

    #[test]
    fn the_first_comparison_is_where_a_serial_is_needed() {
        let (names, first) = last_pass_checks(&wear());
        let names: Vec<(&str, &str)> = names.iter().map(|(n, k)| (n.as_str(), k.as_str())).collect();
        assert_eq!(
            names,
            [
                (
                    "coast-down from 5900 rpm below 100 rpm above 15 s",
                    "coast-down from 5900 rpm below 100 rpm"
                ),
                ("Vibration", "Vibration")
            ]
        );
        let first = first.expect("a place");
        assert_eq!((first.line, first.column), (8, 30));
    }

    /// A watch reads its objects as a sample does: its interval is one the line must keep.
    #[test]
    fn a_watch_interval_counts_as_the_shortest_sample_interval() {
        let dictionary = crate::family::Registry::builtin()
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .expect("built-in dictionary");
        let load = |text: &str| {
            crate::recipe::load_recipe_text("r.yaml", text, Path::new("."), &dictionary, &[]).expect("valid")
        };
        let sample = "  - sample: { objects: [speed_actual], every: 1 s, for: 5 s }\n";
        let plain = load(&format!("name: x\nsteps:\n{sample}"));
        assert_eq!(
            shortest_sample_interval(&plain),
            Some(std::time::Duration::from_secs(1))
        );
        let watched = load(&format!(
            "name: x\nwatch: {{ motor_temperature: {{ below: 80 °C }}, every: 200 ms }}\nsteps:\n{sample}"
        ));
        assert_eq!(
            shortest_sample_interval(&watched),
            Some(std::time::Duration::from_millis(200))
        );
        // A block's own watch counts too, and is found with the run's.
        let block = "  - repeat:\n      times: 2\n      watch: { speed_actual: { below: 3000 rpm }, every: 100 ms }\n      steps:\n        - dwell: 1 s\n";
        let both = load(&format!(
            "name: x\nwatch: {{ motor_temperature: {{ below: 80 °C }}, every: 200 ms }}\nsteps:\n{sample}{block}"
        ));
        assert_eq!(
            shortest_sample_interval(&both),
            Some(std::time::Duration::from_millis(100))
        );
        let named: Vec<String> = all_watches(&both)
            .iter()
            .map(|w| w.condition.to_string())
            .collect();
        assert_eq!(
            named,
            ["motor_temperature below 80 °C", "speed_actual below 3000 rpm"]
        );
    }
}
