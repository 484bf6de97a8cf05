//! `drivescript schema` checked the way editors use it: with a real JSON Schema validator
//! (Python's jsonschema, draft 7, where installed). Every example and every valid test
//! recipe passes; a wrong unit, a wrong dimension, `2 parsecs`, `near` without `within`
//! and a misspelt step are refused, the last one with the list of step keys.

use crate::support::{drivescript, repo_root, stdout, succeeded};
use std::process::Command;

const VALIDATOR: &str = r#"
import json, sys, yaml, jsonschema
schema = json.load(open(sys.argv[1]))
jsonschema.Draft7Validator.check_schema(schema)
v = jsonschema.Draft7Validator(schema)
for path in sys.argv[2:]:
    errors = [e.message for e in v.iter_errors(yaml.safe_load(open(path)))]
    for e in v.iter_errors(yaml.safe_load(open(path))):
        errors.extend(c.message for c in (e.context or []))
    print(json.dumps({"path": path, "errors": errors}))
"#;

/// Whether python3 with jsonschema and yaml is here; where it is not, the test says so
/// (and fails under CI).
fn python_with_jsonschema() -> bool {
    crate::support::python_imports(
        "jsonschema, yaml",
        "python3 with jsonschema and yaml is not installed: the schema is not validated",
    )
}

/// The built-in dictionary a recipe's `drive:` names (`sd2` when it names none).
fn drive_of(path: &std::path::Path) -> String {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .find_map(|l| l.strip_prefix("drive:").map(|d| d.trim().to_string()))
        .unwrap_or_else(|| "sd2".to_string())
}

/// (path, errors) of each recipe, validated against the schema printed for its drive.
fn validate(paths: &[std::path::PathBuf]) -> Vec<(String, Vec<String>)> {
    let mut drives: Vec<String> = paths.iter().map(|p| drive_of(p)).collect();
    drives.sort();
    drives.dedup();
    drives
        .iter()
        .flat_map(|drive| {
            let mine: Vec<std::path::PathBuf> =
                paths.iter().filter(|p| drive_of(p) == *drive).cloned().collect();
            validate_against(drive, &mine)
        })
        .collect()
}

fn validate_against(drive: &str, paths: &[std::path::PathBuf]) -> Vec<(String, Vec<String>)> {
    let dir = std::env::temp_dir().join(format!("drivescript-schema-{}-{drive}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let schema = dir.join("recipe.schema.json");
    std::fs::write(&schema, stdout(&drivescript(&["schema", "--drive", drive], ""))).unwrap();
    let out = succeeded(
        Command::new("python3")
            .args(["-c", VALIDATOR])
            .arg(&schema)
            .args(paths),
        "the schema validator",
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            let errors = v["errors"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| e.as_str().unwrap().to_string())
                .collect();
            (v["path"].as_str().unwrap().to_string(), errors)
        })
        .collect()
}

#[test]
fn the_schema_accepts_good_recipes_and_refuses_bad_units_durations_and_shapes() {
    if !python_with_jsonschema() {
        return;
    }
    let root = repo_root();
    let mut good: Vec<std::path::PathBuf> = Vec::new();
    for dir in ["recipes", "recipes/includes", "recipes/operator"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            // An answers file (`recipes/operator/answers.yaml`) is no recipe.
            let answers = p.file_name().is_some_and(|n| n == "answers.yaml");
            if p.extension().is_some_and(|x| x == "yaml") && !answers {
                good.push(p);
            }
        }
    }
    for kind in ["ok", "failed", "error", "interrupted"] {
        for e in std::fs::read_dir(root.join("tests/cases").join(kind)).unwrap() {
            let path = e.unwrap().path().join("recipe.yaml");
            // A script case (`script.rhai`) has no YAML for the schema.
            if !path.exists() {
                continue;
            }
            // The schema is one dictionary's: a recipe with `drives:` names objects of
            // several (`left.speed_setpoint`), which it does not enumerate.
            let several = std::fs::read_to_string(&path).is_ok_and(|t| t.contains("\ndrives:"));
            if !several {
                good.push(path);
            }
        }
    }
    let dir = std::env::temp_dir().join(format!("drivescript-schema-cases-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, steps: &str| {
        let p = dir.join(name);
        std::fs::write(&p, format!("name: X\ndrive: sd2\nsteps:\n{steps}")).unwrap();
        p
    };
    good.push(write(
        "units.yaml",
        "  - set: { speed_setpoint: \"{{speed}}\" }\n  - dwell: 1h 30min\n  \
         - wait_until: { speed_actual: { between: [1 krpm, 2000 RPM] }, timeout: 5 s }\n  \
         - expect: { speed_actual: { mean: { near: 6000 rpm, within: 0.5 % } } }\n  \
         - ramp: { object: speed_setpoint, from: 0 rpm, to: 100 rpm, rate: 50 rpm/s }\n",
    ));
    good.push(write(
        "last-pass.yaml",
        "  - expect: { motor_temperature: { below: 80 °C, compared_with_last_pass: { at_most: +2 K, at_least: -2 K, without_history: fail } } }\n",
    ));
    for (path, errors) in validate(&good) {
        assert!(errors.is_empty(), "{path}: {errors:?}");
    }
    let bad = [
        write("unit.yaml", "  - set: { speed_setpoint: 6000 rmp }\n"),
        write("dimension.yaml", "  - set: { speed_setpoint: 5 A }\n"),
        write("parsecs.yaml", "  - dwell: 2 parsecs\n"),
        write("near.yaml", "  - expect: { speed_actual: { near: 6000 rpm } }\n"),
        write("misspelt.yaml", "  - wait_untl: { state: operation_enabled }\n"),
        write(
            "last-pass-without-choice.yaml",
            "  - expect: { speed_actual: { below: 9000 rpm, compared_with_last_pass: { at_most: 10 % } } }\n",
        ),
        write(
            "last-pass-unit.yaml",
            "  - expect: { speed_actual: { below: 9000 rpm, compared_with_last_pass: { at_most: 5 A, without_history: pass } } }\n",
        ),
        write(
            "asked-in-finally.yaml",
            "  - dwell: 1 s\nfinally:\n  - confirm: Did the spindle stop?\n",
        ),
    ];
    let results = validate(&bad);
    for (path, errors) in &results {
        assert!(!errors.is_empty(), "{path} passed the schema");
    }
    let misspelt = &results[4].1;
    assert!(
        misspelt
            .iter()
            .any(|e| e.contains("'wait_untl' is not one of") && e.contains("'wait_until'")),
        "{misspelt:?}"
    );
    // An operator step in `finally` is refused as `check` refuses it; in `steps` it is fine.
    let asked = write("asked-in-steps.yaml", "  - confirm: Did the spindle stop?\n");
    for (path, errors) in validate(&[asked]) {
        assert!(errors.is_empty(), "{path}: {errors:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The issue's spelling of drive addresses (`dnc_address: 2`, `address: 0` with `axis: b`)
/// passes the schema of any dictionary; `dnc_address` with `address:`, `axis` without it,
/// either on a drive of another family, and values out of range do not.
#[test]
fn the_schema_offers_sd2_address_keys_in_drives_entries() {
    if !python_with_jsonschema() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("drivescript-schema-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, drives: &str| {
        let p = dir.join(name);
        std::fs::write(&p, format!("name: X\ndrives:\n{drives}steps:\n  - shutdown\n")).unwrap();
        p
    };
    let good = [
        write(
            "issue.yaml",
            "  left: { drive: sd2, dnc_address: 2 }\n  right: { drive: sd2, address: 0, axis: b }\n  feed: { drive: ct-unidrive-sp, address: 1.2 }\n",
        ),
        write("notation.yaml", "  left: { drive: sd2, address: dnc:2 }\n  right: { drive: sd2, address: 0B }\n"),
    ];
    for drive in ["sd2", "ct-unidrive-sp"] {
        for (path, errors) in validate_against(drive, &good) {
            assert!(errors.is_empty(), "{drive}: {path}: {errors:?}");
        }
    }
    let bad = [
        write(
            "both.yaml",
            "  left: { drive: sd2, address: dnc:2, dnc_address: 2 }\n",
        ),
        write("axis_alone.yaml", "  left: { drive: sd2, axis: b }\n"),
        write(
            "other_family.yaml",
            "  feed: { drive: ct-unidrive-sp, dnc_address: 2 }\n",
        ),
        write("master.yaml", "  left: { drive: sd2, dnc_address: 1 }\n"),
        write("axis_c.yaml", "  left: { drive: sd2, address: 0, axis: c }\n"),
    ];
    for (path, errors) in validate_against("sd2", &bad) {
        assert!(!errors.is_empty(), "{path} passed the schema");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
