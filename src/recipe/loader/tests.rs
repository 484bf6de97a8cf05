//! Tests of the loader's parts on recipe text: every problem at once with its place, and
//! the meaning of keys given with nothing after them. The recipe cases under `tests/cases/`
//! cover whole recipes through the command line.

use super::load_recipe_text;
use crate::recipe::{Recipe, RecipeInvalid, StepKind};
use std::path::Path;

fn load(text: &str) -> Result<Recipe, RecipeInvalid> {
    let dictionary = crate::family::Registry::builtin()
        .load_dictionary(crate::family::DEFAULT_DICTIONARY)
        .expect("built-in dictionary");
    load_recipe_text("r.yaml", text, Path::new("."), &dictionary, &[])
}

/// `path:line:column: message` of every problem, in the order found.
fn problems(text: &str) -> Vec<String> {
    let e = load(text).expect_err("expected problems");
    e.problems.iter().map(|p| p.located()).collect()
}

#[test]
fn every_problem_of_a_file_is_reported_at_its_place() {
    let text = "nme: x\nsteps:\n  - dwell: 5\n  - sample: { objects: [speed_actual], evry: 1 s, for: 2 s }\n  - repeat: { times: 0, steps: [shutdown] }\n";
    assert_eq!(
        problems(text),
        [
            "r.yaml:1:1: unknown key `nme` in this recipe",
            "r.yaml:1:1: this recipe has no `name`",
            "r.yaml:3:12: dwell: `5` has no unit",
            "r.yaml:4:40: unknown key `evry` in this sample",
            "r.yaml:4:13: this sample has no `every`",
            "r.yaml:5:22: `times` 0 is out of range 1..=4294967295",
        ]
    );
    let e = load(text).unwrap_err();
    assert_eq!(
        e.problems.iter().next().and_then(|p| p.help()),
        Some("did you mean `name`?")
    );
    assert!(e
        .render(false)
        .ends_with("r.yaml: 6 problems found; nothing was sent to the drive\n"));
}

#[test]
fn brake_to_standstill_false_opts_out_at_its_place() {
    let off = load("name: x\nsafe_stop: { timeout: 2 s, brake_to_standstill: false }\nsteps: [shutdown]\n")
        .unwrap();
    assert_eq!(off.safe_stop.no_brake_at, Some((2, 49)));
    let on = load("name: x\nsafe_stop: { brake_to_standstill: true }\nsteps: [shutdown]\n").unwrap();
    assert_eq!(on.safe_stop.no_brake_at, None);
    assert_eq!(
        load("name: x\nsteps: [shutdown]\n")
            .unwrap()
            .safe_stop
            .no_brake_at,
        None
    );
    assert_eq!(
        problems("name: x\nsafe_stop: { brake_to_standstill: sometimes }\nsteps: [shutdown]\n"),
        ["r.yaml:2:35: `brake_to_standstill` must be true or false, found text"]
    );
}

#[test]
fn a_key_with_nothing_after_it_is_a_value() {
    // `finally:` with nothing asks for no finally steps; without it the default runs.
    let r = load("name: x\nsteps:\n  - shutdown\nfinally:\n").unwrap();
    assert_eq!(r.finally, Some(Vec::new()));
    assert_eq!(load("name: x\nsteps: [shutdown]\n").unwrap().finally, None);
    assert_eq!(
        problems("name:\nsteps: [shutdown]\n"),
        ["r.yaml:1:5: `name` must be text or a number, found nothing"]
    );
}

#[test]
fn parameters_are_substituted_where_values_are_read() {
    let r = load("name: p\nparams:\n  speed: 1200 rpm\nsteps:\n  - set: { speed_setpoint: \"{{speed}}\" }\n")
        .unwrap();
    assert!(matches!(&r.steps[0].kind, StepKind::Set(writes) if writes.len() == 1));
    assert_eq!(r.steps[0].label, "set speed_setpoint = 1200 rpm");
    assert_eq!(
        problems("name: p\nsteps:\n  - dwell: \"{{sttle}}\"\n"),
        ["r.yaml:3:12: unknown parameter `sttle`"]
    );
}

fn load_for(dictionary: &str, text: &str) -> Result<Recipe, RecipeInvalid> {
    let dictionary = crate::family::Registry::builtin()
        .load_dictionary(dictionary)
        .expect("built-in dictionary");
    load_recipe_text("r.yaml", text, Path::new("."), &dictionary, &[])
}

/// `drive:` names a dictionary or its family; messages name the dictionary in use (what
/// --drive takes), never its family id.
#[test]
fn messages_name_the_dictionary_not_its_family() {
    assert!(load_for(
        "ct-unidrive-sp",
        "name: x\ndrive: ct-unidrive-sp\nsteps: [shutdown]\n"
    )
    .is_ok());
    let family = crate::family::Registry::builtin()
        .load_dictionary("ct-unidrive-sp")
        .unwrap()
        .family()
        .to_string();
    assert!(load_for(
        "ct-unidrive-sp",
        &format!("name: x\ndrive: {family}\nsteps: [shutdown]\n")
    )
    .is_ok());
    let located = |dictionary: &str, text: &str| -> Vec<String> {
        let e = load_for(dictionary, text).expect_err("expected problems");
        e.problems.iter().map(|p| p.located()).collect()
    };
    assert_eq!(
        located("ct-unidrive-sp", "name: x\ndrive: sd2\nsteps: [shutdown]\n"),
        ["r.yaml:2:8: this recipe is for drive `sd2`, the dictionary in use is `ct-unidrive-sp`"]
    );
    assert_eq!(
        located("lenze-9400", "name: x\nsteps: [shutdown]\n"),
        ["r.yaml:2:9: `shutdown` needs device control, but the lenze-9400 dictionary has no `profile:`"]
    );
    assert_eq!(
        located("ct-unidrive-sp", "name: x\nsteps:\n  - read: nothing_here\n"),
        ["r.yaml:3:11: unknown object `nothing_here` in the ct-unidrive-sp dictionary"]
    );
}

#[test]
fn a_misspelt_timeout_gets_a_did_you_mean() {
    let text = "name: x\nsteps:\n  - wait_until: { speed_actual: { below: 10 rpm }, timout: 30 s }\n  - go_to: { state: switched_on, timout: 5 s }\n";
    let e = load(text).expect_err("misspelt keys");
    let found: Vec<(String, Option<&str>)> = e.problems.iter().map(|p| (p.located(), p.help())).collect();
    assert_eq!(
        found,
        [
            (
                "r.yaml:3:52: unknown key `timout` in this wait_until".to_string(),
                Some("did you mean `timeout`?")
            ),
            (
                "r.yaml:4:34: unknown key `timout` in this go_to".to_string(),
                Some("did you mean `timeout`?")
            ),
        ]
    );
    // A misspelt object still gets its own suggestion.
    let text = "name: x\nsteps:\n  - wait_until: { sped_actual: { below: 10 rpm } }\n";
    let e = load(text).expect_err("misspelt object");
    let p = e.problems.iter().next().expect("one problem");
    assert_eq!(
        p.located(),
        "r.yaml:3:19: unknown object `sped_actual` in the sd2 dictionary"
    );
}

#[test]
fn on_failure_is_read_for_the_recipe_and_its_blocks_and_a_misspelt_value_is_refused() {
    use crate::recipe::OnFailure;
    let r = load(
        "name: x\non_failure: stop\nsteps:\n  - repeat: { times: 2, on_failure: continue, steps: [shutdown] }\n  - attempts: { times: 2, on_failure: stop, steps: [shutdown] }\n  - shutdown\n",
    )
    .unwrap();
    assert_eq!(r.on_failure, OnFailure::Stop);
    let own: Vec<Option<OnFailure>> = r.steps.iter().map(|s| s.on_failure).collect();
    assert_eq!(own, [Some(OnFailure::Continue), Some(OnFailure::Stop), None]);
    assert_eq!(
        load("name: x\nsteps: [shutdown]\n").unwrap().on_failure,
        OnFailure::Continue
    );
    let e = load(
        "name: x\non_failure: stpo\nsteps:\n  - repeat: { times: 2, on_failure: go_on, steps: [shutdown] }\n",
    )
    .expect_err("misspelt policies");
    let found: Vec<(String, Option<&str>)> = e.problems.iter().map(|p| (p.located(), p.help())).collect();
    assert_eq!(
        found[0].0,
        "r.yaml:2:13: `on_failure: stpo` is no policy; it is `stop` or `continue`"
    );
    assert_eq!(found[0].1, Some("did you mean `stop`?"));
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[1].0.starts_with("r.yaml:4:"), "{found:?}");
}

#[test]
fn watches_are_checked_like_expect_and_keep_their_hold_and_interval() {
    let r = load(
        "name: x\nwatch:\n  motor_temperature: { below: 80 °C }\n  speed_actual: { below: 9000 rpm, for: 2 s }\n  every: 500 ms\nsteps: [shutdown]\n",
    )
    .unwrap();
    let got: Vec<(String, u128, u128)> = r
        .watches
        .iter()
        .map(|w| (w.condition.to_string(), w.hold.as_millis(), w.every.as_millis()))
        .collect();
    assert_eq!(
        got,
        [
            ("motor_temperature below 80 °C".to_string(), 0, 500),
            ("speed_actual below 9000 rpm".to_string(), 2000, 500)
        ]
    );
    let found = problems(
        "name: x\nwatch:\n  motor_temprature: { below: 80 °C }\n  speed_actual: { below: 9000 V }\n  every: 1 ms\nsteps: [shutdown]\n",
    );
    assert_eq!(found.len(), 3, "{found:?}");
    assert!(
        found
            .iter()
            .any(|p| p.starts_with("r.yaml:3:3: unknown object `motor_temprature`")),
        "{found:?}"
    );
    assert!(found.iter().any(|p| p.starts_with("r.yaml:4:")), "{found:?}");
    assert!(
        found
            .iter()
            .any(|p| p.starts_with("r.yaml:5:10: a watch reads at most every 50 ms")),
        "{found:?}"
    );
}
