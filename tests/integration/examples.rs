//! The shipped example recipes stay valid and pass against the simulated drive, the
//! committed schemas (`schemas/`, one per built-in dictionary) are what `drivescript schema`
//! prints and each recipe points at its own, and sample CSV files keep every pass of a
//! repeated stage.

use crate::support::{cli, drivescript, repo_root, stderr, stdout};
use drivescript::family::{Registry, DEFAULT_DICTIONARY};

#[test]
fn every_example_recipe_checks_and_passes_in_virtual_time() {
    let dir = repo_root().join("recipes");
    let out_dir = crate::support::scratch("outputs");
    let mut ran = 0;
    for entry in std::fs::read_dir(&dir).expect("recipes/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("yaml") {
            continue;
        }
        let p = path.to_str().expect("utf-8 path");
        // Each recipe runs with the built-in dictionary its `drive:` names.
        let text = std::fs::read_to_string(&path).expect("recipe");
        let drive = text
            .lines()
            .find_map(|l| l.strip_prefix("drive:"))
            .map(|d| d.split('#').next().unwrap_or("").trim().to_string())
            .expect("a `drive:` line");
        cli(&["check", p, "--drive", &drive], 0);
        let run = drivescript(
            &[
                "run",
                p,
                "--fast",
                "--output-dir",
                out_dir.to_str().expect("utf-8"),
                "--drive",
                &drive,
            ],
            "",
        );
        assert_eq!(
            run.status.code(),
            Some(0),
            "{p}:\n{}{}",
            stdout(&run),
            stderr(&run)
        );
        assert!(stdout(&run).contains("PASSED"), "{p}");
        assert!(
            stdout(&run).contains("using the built-in simulated ")
                && stdout(&run).contains(&format!("{} drive", drive.to_uppercase())),
            "{p}"
        );
        ran += 1;
    }
    assert!(ran >= 4, "only {ran} example recipes");
    // The run-in's stage 2 runs twice; its CSV holds both passes under one header.
    let csv = std::fs::read_to_string(out_dir.join("run-in-stage-2.csv")).expect("stage 2 csv");
    assert_eq!(csv.lines().filter(|l| l.starts_with("time")).count(), 1);
    // The long layout: a row per object and sample, the passes told apart by step id.
    assert_eq!(
        csv.lines().count(),
        1 + 2 * 2 * 901,
        "15 min at 1 s, two objects, twice"
    );
    assert!(csv.starts_with("time [s],utc,step,object,value,unit\n"));
    for pass in ["8[1].3", "8[2].3"] {
        let rows = csv.lines().filter(|l| l.split(',').nth(2) == Some(pass)).count();
        assert_eq!(rows, 2 * 901, "{pass}");
    }
}

/// `schemas/NAME.schema.json` for every built-in dictionary, each what `drivescript schema
/// --drive NAME` prints, and no other schema.
#[test]
fn the_committed_schemas_are_current() {
    let names = Registry::builtin().dictionary_names();
    for name in &names {
        let out = drivescript(&["schema", "--drive", name], "");
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let path = repo_root().join("schemas").join(format!("{name}.schema.json"));
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert_eq!(
            committed.trim(),
            stdout(&out).trim(),
            "schemas/{name}.schema.json is out of date: run \
             `cargo run -- schema --drive {name} > schemas/{name}.schema.json`"
        );
    }
    let mut shipped: Vec<String> = std::fs::read_dir(repo_root().join("schemas"))
        .expect("schemas/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    shipped.sort();
    let mut expected: Vec<String> = names.iter().map(|n| format!("{n}.schema.json")).collect();
    expected.sort();
    assert_eq!(shipped, expected, "one schema per built-in dictionary");
}

/// Every shipped recipe's first line points an editor at the schema of the dictionary its
/// `drive:` names (an included file without one: the default dictionary's), so an editor
/// completes and checks the objects that drive has.
#[test]
fn every_shipped_recipe_points_at_the_schema_of_its_drive() {
    let mut seen = 0;
    for (dir, up) in [("recipes", "../"), ("recipes/includes", "../../")] {
        for entry in std::fs::read_dir(repo_root().join(dir)).expect("recipes/") {
            let path = entry.expect("entry").path();
            if path.extension().and_then(|e| e.to_str()) != Some("yaml") {
                continue;
            }
            let text = std::fs::read_to_string(&path).expect("recipe");
            let drive = text
                .lines()
                .find_map(|l| l.strip_prefix("drive:"))
                .map(|d| d.split('#').next().unwrap_or("").trim())
                .unwrap_or(DEFAULT_DICTIONARY);
            assert_eq!(
                text.lines().next(),
                Some(format!("# yaml-language-server: $schema={up}schemas/{drive}.schema.json").as_str()),
                "{}",
                path.display()
            );
            seen += 1;
        }
    }
    assert!(seen >= 6, "only {seen} shipped recipes");
}
