//! The names of JUnit test cases, the same in every run of a recipe so that a CI server's
//! history follows each check: a name several cases share is told apart by where the
//! recipe holds each one (its step number), never by the order a run happened to reach
//! them. Pure naming; knows no XML and no run.

use crate::session::without_iterations;
use std::collections::HashMap;

/// Names for cases given as (name, step that holds it), in the same order. The step may
/// carry repeat iterations (`4[2].3`); they are left out, as the stage already names the
/// pass. Of the cases sharing a name, the one earliest in the recipe keeps it; another
/// gets its step, `x (step 5)`; a second one in the same step its count there, `x (2)`
/// or `x (step 5, 2)`.
pub(crate) fn case_names(cases: &[(String, String)]) -> Vec<String> {
    let mut count: HashMap<(&str, String), u32> = HashMap::new();
    let placed: Vec<(&str, String, u32)> = cases
        .iter()
        .map(|(name, step)| {
            let step = without_iterations(step);
            let k = count.entry((name.as_str(), step.clone())).or_insert(0);
            *k += 1;
            (name.as_str(), step, *k)
        })
        .collect();
    let mut first: HashMap<&str, Place> = HashMap::new();
    for (name, step, k) in &placed {
        let place = (step_order(step), *k);
        match first.get(name) {
            Some(seen) if *seen <= place => {}
            _ => {
                first.insert(name, place);
            }
        }
    }
    placed
        .iter()
        .map(|(name, step, k)| {
            let (first_step, first_k) = &first[name];
            if step_order(step) == *first_step {
                match *k == *first_k {
                    true => name.to_string(),
                    false => format!("{name} ({k})"),
                }
            } else if *k == 1 {
                format!("{name} (step {step})")
            } else {
                format!("{name} (step {step}, {k})")
            }
        })
        .collect()
}

/// Where a case stands in the recipe: its step in recipe order, and its count there.
type Place<'a> = (Vec<(u64, &'a str)>, u32);

/// Step numbers in recipe order: `2` before `10`, `finally.1` after every step.
fn step_order(step: &str) -> Vec<(u64, &str)> {
    step.split('.')
        .map(|part| match part.parse::<u64>() {
            Ok(n) => (n, ""),
            Err(_) => (u64::MAX, part),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(cases: &[(&str, &str)]) -> Vec<String> {
        let cases: Vec<(String, String)> = cases
            .iter()
            .map(|(n, s)| (n.to_string(), s.to_string()))
            .collect();
        case_names(&cases)
    }

    #[test]
    fn shared_names_are_told_apart_by_their_place_not_by_run_order() {
        let in_order = names(&[("x", "2"), ("y", "3"), ("x", "10"), ("x", "10")]);
        assert_eq!(in_order, ["x", "y", "x (step 10)", "x (step 10, 2)"]);
        // A run that reached step 10 first (or only) names each case the same.
        let reversed = names(&[("x", "10"), ("x", "10"), ("x", "2")]);
        assert_eq!(reversed, ["x (step 10)", "x (step 10, 2)", "x"]);
        assert_eq!(without_iterations("4[2].3[10].1"), "4.3.1");
        assert_eq!(
            names(&[("x", "finally.1"), ("x", "3")]),
            ["x (step finally.1)", "x"]
        );
    }
}
