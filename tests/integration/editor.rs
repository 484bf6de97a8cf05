//! The shipped schemas as an editor shows them: yaml-language-server (what VS Code's YAML
//! extension runs) over its protocol, on the shipped recipes and on recipes being written
//! next to them. Says it skipped where yaml-language-server or node is not installed, and
//! fails so under CI (`.ci/run` installs both).

use crate::examples::{drive_named, each_recipe_in};
use crate::language_server::{position, LanguageServer};
use crate::support::{repo_root, tool_missing};
use drivescript::family::DEFAULT_DICTIONARY;
use std::path::PathBuf;

fn server() -> Option<LanguageServer> {
    let server = LanguageServer::start();
    if server.is_none() {
        tool_missing("yaml-language-server (node) is not installed: the editor test is skipped");
    }
    server
}

/// An SD2 recipe being written in `recipes/`: its modeline as the shipped ones have it.
fn draft(steps: &str) -> String {
    draft_for("sd2", steps)
}

/// A recipe for the built-in dictionary `drive` being written in `recipes/`.
fn draft_for(drive: &str, steps: &str) -> String {
    format!(
        "# yaml-language-server: $schema=../schemas/{drive}.schema.json\n\
         name: Draft\ndrive: {drive}\nsteps:\n{steps}"
    )
}

/// An unsaved buffer in `recipes/` (the file is never written).
fn buffer(name: &str) -> PathBuf {
    repo_root()
        .join("recipes")
        .join(format!("editor-test-{name}.yaml"))
}

/// The hover text without its title and source lines: what the schema says of the spot.
fn said(hover: &str) -> String {
    hover
        .lines()
        .filter(|l| !l.starts_with("#### ") && !l.starts_with("Source: "))
        .collect::<Vec<_>>()
        .join("\n")
        .trim()
        .to_string()
}

#[test]
fn yaml_language_server_finds_no_problem_in_any_shipped_recipe() {
    let Some(mut server) = server() else { return };
    let root = repo_root();
    let folders = [
        (root.join("recipes"), "../".to_string()),
        (root.join("recipes/includes"), "../../".to_string()),
    ];
    each_recipe_in(&folders, 6, |path, text, _| {
        let uri = server.open(path, text);
        let problems = server.diagnostics(&uri);
        assert!(problems.is_empty(), "{}: {problems:?}", path.display());
        // The schema is in force, and it is the one of the recipe's drive.
        let drive = drive_named(text).unwrap_or(DEFAULT_DICTIONARY);
        let hover = server.hover(&uri, position(text, "\nsteps:", Some(2)));
        assert!(
            hover.contains(&format!("{drive}.schema.json")) && !said(&hover).is_empty(),
            "{}: {hover}",
            path.display()
        );
    });
}

#[test]
fn hovering_shows_an_objects_unit_and_range_and_what_each_step_key_does() {
    let Some(mut server) = server() else { return };
    let text = draft(
        "  - go_to: { state: operation_enabled, timeout: 2 s }\n  \
         - set: { speed_setpoint: 0 rpm }\n  \
         - read: [speed_actual]\n  \
         - print: hello\n  \
         - wait_until: { speed_actual: { below: 10 rpm }, timeout: 10 s }\n  \
         - dwell: 5 s\n  \
         - sample: { objects: [speed_actual], every: 100 ms, for: 1 s }\n  \
         - expect: { speed_actual: { mean: { below: 10 rpm } } }\n  \
         - ramp: { object: speed_setpoint, from: 0 rpm, to: 100 rpm, rate: 50 rpm/s }\n  \
         - repeat: { times: 2, steps: [shutdown] }\n  \
         - include: includes/speed-stage.yaml\n  \
         - instruct: Close the guard\n  \
         - confirm: Is the spindle quiet?\n  \
         - enter_value: { prompt: Vibration, unit: mm/s, at_most: 2.8 mm/s }\n  \
         - enter_text: { prompt: Serial number, sets: serial }\n  \
         - coast_down: { from: 5900 rpm, below: 100 rpm, expect: { below: 30 s } }\n  \
         - attempts: { times: 2, steps: [dwell: 1 s] }\n  \
         - expect_parameters: backup.yaml\n    \
           name: parameters\n",
    );
    let uri = server.open(&buffer("hover"), &text);
    for (object, after) in [("speed_setpoint", "set: { "), ("speed_actual", "wait_until: { ")] {
        let hover = server.hover(
            &uri,
            position(&text, &format!("{after}{object}"), Some(after.len() + 2)),
        );
        for part in [&format!("**{object}**"), "| rpm |", "rpm", "resolution"] {
            assert!(hover.contains(part), "{object}: {part} in {hover}");
        }
    }
    let set = server.hover(&uri, position(&text, "set: { speed_setpoint", Some(9)));
    assert!(set.contains(" rpm to ") && set.contains("read-write"), "{set}");
    // Every key a step may have, as the schema lists them (the draft has one step of each).
    let schema: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo_root().join("schemas/sd2.schema.json")).expect("schema"),
    )
    .expect("JSON");
    let keys = schema["$defs"]["step"]["else"]["propertyNames"]["enum"]
        .as_array()
        .expect("the step keys")
        .iter()
        .filter_map(|k| k.as_str())
        .collect::<Vec<_>>();
    assert!(keys.len() >= 13, "{keys:?}");
    for key in keys {
        // The step's own `name:`, not the recipe's.
        let needle = if key == "name" {
            "name: parameters".to_string()
        } else {
            format!("{key}:")
        };
        let hover = server.hover(&uri, position(&text, &needle, Some(1)));
        assert!(said(&hover).len() > 30, "`{key}` has no description: {hover}");
    }
    let wait = server.hover(&uri, position(&text, "wait_until:", Some(1)));
    assert!(said(&wait).starts_with("Poll until a state"), "{wait}");
}

#[test]
fn completing_an_object_inserts_its_key_and_an_empty_step_offers_device_commands() {
    let Some(mut server) = server() else { return };
    let text = draft("  - set:\n      speed_se\n");
    let uri = server.open(&buffer("complete-object"), &text);
    let items = server.completion(&uri, position(&text, "speed_se", None));
    assert!(
        items
            .iter()
            .any(|(label, inserted)| label == "speed_setpoint" && inserted.starts_with("speed_setpoint: ")),
        "{items:?}"
    );
    for (name, steps) in [
        ("finally", "  - shutdown\nfinally:\n  - \n"),
        (
            "finally-second",
            "  - shutdown\nfinally:\n  - disable_operation\n  - \n",
        ),
        ("steps", "  - \n"),
    ] {
        let text = draft(steps);
        let uri = server.open(&buffer(name), &text);
        let at = position(&text, "  - \n", Some(4));
        let items = server.completion(&uri, at);
        for command in ["disable_operation", "shutdown", "fault_reset"] {
            assert!(
                items
                    .iter()
                    .any(|(label, inserted)| label == command && inserted == command),
                "{name}: {command} not offered: {items:?}"
            );
        }
    }
    // A drive without a device-control profile has no device commands to offer.
    let text = draft_for("lenze-9400", "  - \n");
    let uri = server.open(&buffer("no-profile"), &text);
    let items = server.completion(&uri, position(&text, "  - \n", Some(4)));
    assert!(
        !items.iter().any(|(label, _)| label == "shutdown") && !items.is_empty(),
        "{items:?}"
    );
}

#[test]
fn a_value_that_does_not_match_is_explained_in_words_not_as_a_pattern() {
    let Some(mut server) = server() else { return };
    let text = draft(
        "  - dwell: 5 parsecs\n  \
         - set: { speed_setpoint: 6000 rmp }\n  \
         - set: { speed_setpoint: 5 A }\n  \
         - ramp: { object: speed_setpoint, from: 0 rpm, to: 100 rpm, rate: 50 rpm/parsec }\n",
    );
    let uri = server.open(&buffer("patterns"), &text);
    let problems = server.diagnostics(&uri);
    let speed = "expected a speed with its unit (rpm, krpm), a bare number in rpm, or {{param}}";
    assert_eq!(
        problems,
        [
            "5: expected a duration with its unit: 500 ms, 5 s, 10 min, 2 h, 1h 30min, or {{param}}"
                .to_string(),
            format!("6: {speed}"),
            format!("7: {speed}"),
            "8: expected a change per time with units: 1000 rpm/s, 50 rpm/min".to_string(),
        ]
    );
}

/// A device command where the drive has no device-control profile is marked as `check`
/// refuses it, with the reason.
#[test]
fn a_device_command_without_a_profile_is_marked_with_the_reason() {
    let Some(mut server) = server() else { return };
    let text = draft_for("lenze-9400", "  - read: [ident]\n  - shutdown\n");
    let uri = server.open(&buffer("no-profile-command"), &text);
    assert_eq!(
        server.diagnostics(&uri),
        ["6: a device command needs device control, but the lenze-9400 dictionary has no `profile:`"]
    );
}
