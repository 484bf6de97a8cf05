//! The shipped example recipes stay valid and pass against the simulated drive, the
//! committed schemas (`schemas/`, one per built-in dictionary) are what `drivescript schema`
//! prints and each recipe points at its own, and sample CSV files keep every pass of a
//! repeated stage.

use crate::support::{cli, drivescript, repo_root, stderr, stdout};
use drivescript::family::{Registry, DEFAULT_DICTIONARY};

/// The folders of shipped recipes: `recipes/` (the SD2's), and one per family's dictionary
/// (`recipes/ct-unidrive-sp/`, ...), each with the path back to `schemas/`.
fn recipe_folders() -> Vec<(std::path::PathBuf, String)> {
    let root = repo_root().join("recipes");
    let mut folders = vec![(root.clone(), "../".to_string())];
    for name in Registry::builtin().dictionary_names() {
        let dir = root.join(name);
        if dir.is_dir() {
            folders.push((dir, "../../".to_string()));
        }
    }
    folders
}

/// The `.yaml` recipes directly in `dir`, in name order.
fn recipes_in(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .expect("recipes/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("yaml"))
        .collect();
    paths.sort();
    paths
}

/// Calls `check` with the path, the text and the path back to `schemas/` of every recipe in
/// `folders` (each folder with that path); there must be at least `least` of them.
pub(crate) fn each_recipe_in(
    folders: &[(std::path::PathBuf, String)],
    least: usize,
    mut check: impl FnMut(&std::path::Path, &str, &str),
) {
    let mut seen = 0;
    for (dir, up) in folders {
        for path in recipes_in(dir) {
            let text = std::fs::read_to_string(&path).expect("recipe");
            check(&path, &text, up);
            seen += 1;
        }
    }
    assert!(seen >= least, "only {seen} shipped recipes in {folders:?}");
}

/// The dictionary a recipe's `drive:` line names, if it has one.
pub(crate) fn drive_named(text: &str) -> Option<&str> {
    text.lines()
        .find_map(|l| l.strip_prefix("drive:"))
        .map(|d| d.split('#').next().unwrap_or("").trim())
}

#[test]
fn every_example_recipe_checks_and_passes_in_virtual_time() {
    let out_dir = crate::support::scratch("outputs");
    each_recipe_in(&recipe_folders(), 16, |path, text, _| {
        let p = path.to_str().expect("utf-8 path");
        // Each recipe runs with the built-in dictionary its `drive:` names, and with the
        // device's own EDS where one lies beside it (recipes/canopen/).
        let drive = drive_named(text).expect("a `drive:` line").to_string();
        let mut extra: Vec<String> = vec!["--drive".into(), drive.clone()];
        let folder = path.parent().expect("a folder");
        for eds in std::fs::read_dir(folder)
            .expect("folder")
            .map(|e| e.expect("entry").path())
        {
            if eds.extension().and_then(|e| e.to_str()) == Some("eds") {
                extra.extend(["--dictionary".into(), eds.to_string_lossy().into_owned()]);
            }
        }
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        cli(&[&["check", p][..], &extra].concat(), 0);
        let run = drivescript(
            &[
                &[
                    "run",
                    p,
                    "--fast",
                    "--output-dir",
                    out_dir.to_str().expect("utf-8"),
                ][..],
                &extra,
            ]
            .concat(),
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
        // The simulator is said on the first line (by its family: `CT-ANSI drive`).
        assert!(
            stdout(&run).starts_with("using the built-in simulated "),
            "{p}:\n{}",
            stdout(&run)
        );
    });
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
    let mut folders = recipe_folders();
    folders.push((repo_root().join("recipes/includes"), "../../".into()));
    each_recipe_in(&folders, 16, |path, text, up| {
        let drive = drive_named(text).unwrap_or(DEFAULT_DICTIONARY);
        assert_eq!(
            text.lines().next(),
            Some(format!("# yaml-language-server: $schema={up}schemas/{drive}.schema.json").as_str()),
            "{}",
            path.display()
        );
    });
}

/// Every family other than the SD2's has a commissioning and an acceptance recipe of its
/// own, and the CiA 402 recipes' EDS is the simulated node's, which CI runs them against.
#[test]
fn every_family_has_a_commissioning_and_an_acceptance_recipe() {
    for name in [
        "ct-unidrive-sp",
        "lenze-931",
        "lenze-9400",
        "canopen",
        "modbus-inverter",
        "modbus-tcp-inverter",
    ] {
        for kind in ["commissioning", "acceptance"] {
            let path = repo_root()
                .join("recipes")
                .join(name)
                .join(format!("{kind}.yaml"));
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(text.contains(&format!("\ndrive: {name}\n")), "{}", path.display());
        }
    }
    assert_eq!(
        std::fs::read(repo_root().join("recipes/canopen/cia402-node.eds")).expect("shipped EDS"),
        std::fs::read(repo_root().join("src/family/canopen/sim/cia402_node.eds")).expect("simulator's EDS"),
        "recipes/canopen/cia402-node.eds is the simulated node's own EDS: copy it again"
    );
}
