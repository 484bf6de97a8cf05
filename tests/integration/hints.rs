//! Hints that send the user the right way: the command `simulate` offers reaches the drive
//! it serves when copied as printed, and a drive that does not answer gets its own
//! family's advice, with another family's drive on the line among the likely causes.

use crate::support::{cli, scratch, Simulator};
#[cfg(unix)]
use crate::support::{drivescript, stderr, stdout};

/// A recipe for the dictionary `drive` that reads `object`, in a scratch folder.
fn recipe(name: &str, drive: &str, object: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = scratch(name);
    let file = dir.join("r.yaml");
    let text = format!("name: {name}\ndrive: {drive}\nsteps:\n  - read: [{object}]\n");
    std::fs::write(&file, text).expect("recipe");
    (dir, file)
}

/// The words of a `try:` hint, as a shell would split them.
fn words(hint: &str) -> Vec<&str> {
    let rest = hint
        .strip_prefix("drivescript ")
        .unwrap_or_else(|| panic!("a drivescript command: {hint}"));
    rest.split_whitespace().collect()
}

#[cfg(unix)]
#[test]
fn the_command_simulate_offers_reaches_the_drive_it_serves() {
    for args in [
        &["--drive", "ct-unidrive-sp", "--pty"][..],
        &["--drive", "ct-unidrive-sp", "--pty", "--address", "2.3"],
        &["--drive", "lenze-931", "--pty"],
        &["--pty", "--address", "1B"],
    ] {
        let (_sim, hint) = Simulator::start_with_hint(args);
        let out = drivescript(&words(&hint), "");
        assert_eq!(
            out.status.code(),
            Some(0),
            "`{hint}` (simulate {args:?}) works as printed: {}{}",
            stdout(&out),
            stderr(&out)
        );
        let text = stdout(&out);
        assert!(text.contains("status word") || text.contains("ident"), "{text}");
    }
}

#[test]
fn the_tcp_hint_names_the_dictionary_too() {
    let (_sim, hint) = Simulator::start_with_hint(&["--drive", "ct-unidrive-sp", "--tcp", "127.0.0.1:0"]);
    assert!(hint.contains("--drive ct-unidrive-sp --tcp 127.0.0.1:"), "{hint}");
    cli(&words(&hint), 0);
}

/// A one-off command with the default dictionary against a Unidrive SP: the error names a
/// wrong `--drive` as the likely cause and the dictionary to give.
#[test]
fn a_silent_drive_names_a_wrong_drive_flag() {
    let sim = Simulator::start(&["--drive", "ct-unidrive-sp", "--tcp", "127.0.0.1:0"]);
    let quick = ["--tcp", &sim.endpoint, "--timeout", "50ms", "--retries", "0"];
    let err = cli(&[&["state"][..], &quick].concat(), 3).stderr;
    assert!(
        err.contains("help: drivescript spoke Sieb & Meyer SD2")
            && err.contains("give the drive's own dictionary with --drive")
            && err.contains("ct-unidrive-sp"),
        "{err}"
    );
    // A recipe: the fourth likely cause, and the spoken family's own advice said once.
    let err = cli(&[&["run", "recipes/identity.yaml"][..], &quick].concat(), 3).stderr;
    assert!(
        err.contains("4. the drive family: drivescript spoke Sieb & Meyer SD2"),
        "{err}"
    );
    assert_eq!(
        err.matches("the drive's DNC address (address switch)").count(),
        1,
        "{err}"
    );
}

/// The advice for a silent drive is the family's own: a Unidrive SP's serial address, not
/// an SD2's DNC address.
#[test]
fn the_advice_for_a_silent_drive_is_its_familys_own() {
    let sim = Simulator::start(&["--tcp", "127.0.0.1:0"]);
    let quick = ["--tcp", &sim.endpoint, "--timeout", "50ms", "--retries", "0"];
    let err = cli(&[&["state", "--drive", "ct-unidrive-sp"][..], &quick].concat(), 3).stderr;
    assert!(
        err.contains("the drive's serial address (--address G.U)"),
        "{err}"
    );
    assert!(!err.contains("DNC"), "no SD2 advice for a CT drive: {err}");
    let (dir, ct) = recipe("ct", "ct-unidrive-sp", "ident");
    let err = cli(&[&["run", ct.to_str().unwrap()][..], &quick].concat(), 3).stderr;
    assert!(
        err.contains("For a drive of this family: check the cable (RS485 A/B)"),
        "{err}"
    );
    assert!(err.contains("(the drive's serial address as group.unit"), "{err}");
    assert!(!err.contains("DNC"), "no SD2 advice for a CT drive: {err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An unknown object points at the objects of the dictionary in use, with the `--drive`
/// that names it (not the family id, which `--drive` does not take, and not the default
/// dictionary's objects), from the command line and from a recipe.
#[test]
fn an_unknown_object_points_at_the_objects_of_the_dictionary_in_use() {
    let err = cli(&["read", "nothing_like_it", "--drive", "ct-unidrive-sp"], 2).stderr;
    assert!(
        err.contains("`drivescript objects --drive ct-unidrive-sp` lists the objects"),
        "{err}"
    );
    let (dir, recipe) = recipe("objects", "lenze-931", "nothing_like_it");
    let err = cli(&["check", recipe.to_str().unwrap()], 2).stderr;
    assert!(
        err.contains("`drivescript objects --drive lenze-931` lists the objects"),
        "{err}"
    );
    // The hint works as printed.
    let listed = cli(&["objects", "--drive", "lenze-931"], 0).stdout;
    assert!(listed.contains("Lenze"), "{listed}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A path to a file that is not there is said to be one, not read as hex.
#[test]
fn decode_of_a_missing_file_says_it_does_not_exist() {
    let err = cli(&["decode", "/path/that/does/not/exist"], 2).stderr;
    assert!(
        err.contains("error: /path/that/does/not/exist does not exist"),
        "{err}"
    );
    assert!(!err.contains("hex digit"), "{err}");
}

/// A limits-file problem names the file, with no internal label above it.
#[test]
fn a_limits_file_error_has_no_internal_label() {
    let dir = scratch("limits-label");
    let limits = dir.join("limits.yaml");
    std::fs::write(&limits, "max_speed: 12000 rpm\nmax_sped: 3 A\n").expect("limits");
    let (_, recipe) = recipe("limits-label-recipe", "sd2", "ident");
    let err = cli(
        &[
            "check",
            recipe.to_str().unwrap(),
            "--limits",
            limits.to_str().unwrap(),
        ],
        2,
    )
    .stderr;
    assert!(
        err.contains("limits.yaml:2:1: unknown key `max_sped` in the limits file"),
        "{err}"
    );
    assert!(!err.contains("drivescript::"), "{err}");
}
