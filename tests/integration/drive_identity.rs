//! The drive's identity, read at the start of a run from the objects its dictionary
//! names (CANopen's 0x1000 and 0x1018, a Lenze code, a 931's TYPE? and VERSION?), kept
//! with the run in the store (SQLite and PostgreSQL) and shown on the run report and the
//! certificates; a family whose dictionary names none says so.

use crate::support::{assert_has, cli, repo_root, scratch_file, with_postgres_store, with_sqlite_store};
use std::path::Path;

/// `drivescript run RECIPE --fast --report DIR/report.html ARGS` (which must pass); the page.
fn report_of(recipe: &Path, dir: &Path, args: &[&str]) -> String {
    let report = dir.join("report.html");
    let recipe = recipe.to_str().expect("utf-8");
    let report_arg = report.to_str().expect("utf-8");
    cli(
        &[&["run", recipe, "--fast", "--report", report_arg], args].concat(),
        0,
    );
    std::fs::read_to_string(&report).expect("the report")
}

/// What the built-in CANopen node answers for 0x1000, 0x1008 and 0x1018/1 (its EDS has no
/// 0x1018/2..4, 0x1009 or 0x100A: those are left out, not guessed).
const CANOPEN_IDENTITY: &str =
    "device type 0x00020192, device name drivescript CiA 402 node, vendor 0x00000000";

/// A CANopen run recorded in `store`: its identity on the report, in the stored run and on
/// its certificate.
fn identity_everywhere(store: &str, dir: &Path) {
    let recipe = repo_root().join("recipes/canopen/commissioning.yaml");
    let report = report_of(&recipe, dir, &["--quiet", "--results", store]);
    assert_has(&report, &["Drive identity", CANOPEN_IDENTITY]);
    let listed = cli(
        &["results", "list", "--simulated", "--json", "--results", store],
        0,
    );
    let runs: serde_json::Value = serde_json::from_str(&listed.stdout).expect("json");
    let id = runs[0]["id"].as_str().expect("a run id");
    let shown = cli(&["results", "show", id, "--json", "--results", store], 0).stdout;
    let json: serde_json::Value = serde_json::from_str(&shown).expect("json");
    assert_eq!(json["end"]["drive_identity"], CANOPEN_IDENTITY, "{shown}");
    let certificate = cli(&["results", "report", id, "--results", store], 0).stdout;
    assert_has(&certificate, &["Drive identity", CANOPEN_IDENTITY]);
    assert!(!certificate.contains("product code"), "a value no reply gave");
}

#[test]
fn a_canopen_drives_identity_is_read_stored_and_shown_on_sqlite() {
    with_sqlite_store("identity", |dir, store| identity_everywhere(store, dir));
}

#[test]
fn a_canopen_drives_identity_is_read_stored_and_shown_on_postgresql() {
    with_postgres_store("identity", |dir, store| identity_everywhere(store, dir));
}

#[test]
fn each_family_reads_what_its_dictionary_names_and_one_without_says_so() {
    let (dir, e500) = scratch_file(
        "identity-families",
        "e500.yaml",
        "name: E500 read\ndrive: sunfar-e500\nsteps:\n  - read: [speed_actual]\n",
    );
    let root = repo_root();
    for (recipe, identity) in [
        (
            root.join("recipes/commissioning.yaml"),
            "parameter set Test Motor",
        ),
        (
            root.join("recipes/lenze-931/commissioning.yaml"),
            "device type 0931, firmware 0100 (status 0000)",
        ),
        (
            root.join("recipes/lenze-9400/commissioning.yaml"),
            "product simulated 9400 HighLine FHB, firmware 05.00.12.07",
        ),
        (
            root.join("recipes/ct-unidrive-sp/commissioning.yaml"),
            "software 1.10",
        ),
        (
            e500,
            "not read: the drive answered no identity object its dictionary names",
        ),
    ] {
        let page = report_of(&recipe, &dir, &["--no-results"]);
        assert_has(&page, &[&format!("Drive identity</th><td>{identity}</td>")]);
    }
}
