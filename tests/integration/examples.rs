//! The shipped example recipes stay valid and pass against the simulated drive, the
//! committed `recipe.schema.json` is what `drivescript schema` prints, and sample CSV files
//! keep every pass of a repeated stage.

use crate::support::{cli, drivescript, repo_root, stderr, stdout};

#[test]
fn every_example_recipe_checks_and_passes_in_virtual_time() {
    let dir = repo_root().join("recipes");
    let out_dir = std::env::temp_dir().join("drivescript-examples");
    let _ = std::fs::remove_dir_all(&out_dir);
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
                && stdout(&run).contains(&format!("{} drive", drive.replace('-', "_").to_uppercase())),
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

#[test]
fn the_committed_schema_is_current() {
    let out = drivescript(&["schema"], "");
    assert_eq!(out.status.code(), Some(0));
    let committed =
        std::fs::read_to_string(repo_root().join("recipe.schema.json")).expect("recipe.schema.json");
    assert_eq!(
        committed.trim(),
        stdout(&out).trim(),
        "recipe.schema.json is out of date: run `cargo run -- schema > recipe.schema.json`"
    );
}
