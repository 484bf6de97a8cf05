//! Parameter backup, diff and restore against the simulated SD2 drive through a real
//! pseudo-terminal (the drive keeps its state between commands there), and the restore's
//! refusals before any write.

use crate::support::Simulator;
use crate::support::{assert_exit, assert_has, drivescript, scratch, stderr, stdout};
use drivescript::parameters::{self, Origin, PlannedWrite};
use drivescript::run::{ConnectionArgs, DictionaryArgs, OpenDrive};

fn run(args: &[&str]) -> (i32, String) {
    let out = drivescript(args, "");
    (
        out.status.code().unwrap_or(-1),
        format!("{}{}", stdout(&out), stderr(&out)),
    )
}

/// A dictionary file that marks the speed setpoint as a parameter too, so a restore has
/// two writes in dictionary order.
fn two_parameters(dir: &std::path::Path) -> String {
    let path = dir.join("more.yaml");
    std::fs::write(
        &path,
        "family: sd2\nobjects:\n  - name: speed_setpoint\n    index: 395\n    type: i32\n    unit: rpm\n    scale: 0.001\n    access: rw\n    min: -30000\n    max: 30000\n    parameter: true\n",
    )
    .expect("dictionary written");
    path.to_string_lossy().to_string()
}

/// A scratch folder `name`, a simulated drive started with `sim_args` on a pty, and the
/// path of a backup file `file` in the folder.
fn on_a_pty(name: &str, sim_args: &[&str], file: &str) -> (std::path::PathBuf, Simulator, String) {
    let dir = scratch(name);
    let sim = Simulator::start(sim_args);
    let file = dir.join(file).to_str().expect("utf-8 path").to_string();
    (dir, sim, file)
}

/// The backup text `saved` with one parameter's raw and shown value changed (each a
/// `(from, to)`), written to `name` in `dir`; its path.
fn edited_copy(
    dir: &std::path::Path,
    name: &str,
    saved: &str,
    raw: (&str, &str),
    value: (&str, &str),
) -> String {
    let path = dir.join(name);
    let text = saved
        .replace(&format!("raw: \"{}\"", raw.0), &format!("raw: \"{}\"", raw.1))
        .replace(
            &format!("value: \"{}\"", value.0),
            &format!("value: \"{}\"", value.1),
        );
    std::fs::write(&path, text).expect("edited copy");
    path.to_str().expect("utf-8 path").to_string()
}

#[test]
fn backup_change_diff_restore_diff() {
    let (dir, sim, file) = on_a_pty("round-trip", &["--pty"], "backup.yaml");
    let (file, port) = (file.as_str(), sim.endpoint.as_str());
    let extra = two_parameters(&dir);
    let dict = ["--dictionary", extra.as_str(), "--port", port];

    assert_eq!(run(&["write", "speed_setpoint", "1500rpm", "--port", port]).0, 0);
    let (code, out) = run(&[&["backup", "-o", file][..], &dict[..]].concat());
    assert_eq!(code, 0, "{out}");
    let saved = std::fs::read_to_string(file).expect("backup written");
    assert!(
        saved.contains("name: \"parameter_set\"") && saved.contains("raw: \"1500000\""),
        "{saved}"
    );
    assert_has(&saved, &["ident: \"Test Motor\""]);

    let (code, out) = run(&[&["diff", file][..], &dict[..]].concat());
    assert_eq!(code, 0, "{out}");

    assert_eq!(run(&["write", "parameter_set", "7", "--port", port]).0, 0);
    assert_eq!(run(&["write", "speed_setpoint", "2500rpm", "--port", port]).0, 0);
    let (code, out) = run(&[&["diff", file][..], &dict[..]].concat());
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("parameter_set") && out.contains("drive: 7"), "{out}");
    assert_has(&out, &["2 difference(s)"]);

    // Without --apply: the plan only, in dictionary order.
    let (code, out) = run(&[&["restore", file][..], &dict[..]].concat());
    assert_eq!(code, 0, "{out}");
    let first = out.find("1. parameter_set: 7 → 0").expect(&out);
    let second = out.find("2. speed_setpoint: 2500 rpm → 1500 rpm").expect(&out);
    assert!(first < second);
    assert_has(&out, &["nothing written"]);
    assert_eq!(run(&[&["diff", file][..], &dict[..]].concat()).0, 1);

    assert_exit(
        run(&[&["restore", file, "--apply"][..], &dict[..]].concat()),
        0,
        &["restored 2 parameter(s)"],
    );
    let (code, out) = run(&[&["diff", file][..], &dict[..]].concat());
    assert_eq!(code, 0, "{out}");

    // Two backups compared with each other.
    let copy = edited_copy(
        &dir,
        "copy.yaml",
        &saved,
        ("1500000", "1500400"),
        ("1500 rpm", "1500.4 rpm"),
    );
    assert_eq!(run(&["diff", file, &copy]).0, 1);
    assert_eq!(run(&["diff", file, &copy, "--tolerance", "0.5"]).0, 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn restore_refuses_before_writing() {
    let (dir, sim, file) = on_a_pty("refusals", &["--pty"], "backup.yaml");
    let (file, port) = (file.as_str(), sim.endpoint.as_str());
    assert_eq!(run(&["backup", "-o", file, "--port", port]).0, 0);
    let saved = std::fs::read_to_string(file).expect("backup written");
    assert_eq!(run(&["write", "parameter_set", "7", "--port", port]).0, 0);

    // A value beyond the dictionary's limit (0..64): refused, nothing written.
    let beyond = dir.join("beyond.yaml");
    std::fs::write(&beyond, saved.replace("raw: \"0\"", "raw: \"99\"")).expect("edited");
    let (code, out) = run(&[
        "restore",
        beyond.to_str().expect("path"),
        "--apply",
        "--port",
        port,
    ]);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("parameter_set") && out.contains("nothing was written"),
        "{out}"
    );

    // Another drive's identity needs --force.
    let other = dir.join("other.yaml");
    std::fs::write(&other, saved.replace("Test Motor", "Other Motor")).expect("edited");
    let other = other.to_str().expect("path");
    let (code, out) = run(&["restore", other, "--apply", "--port", port]);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("identity differs") && out.contains("--force"),
        "{out}"
    );
    let (code, _) = run(&["read", "parameter_set", "--port", port, "--json"]);
    assert_eq!(code, 0);

    // In operation enabled: refused even with --force.
    for word in ["6", "7", "15"] {
        assert_eq!(run(&["write", "control_word", word, "--port", port]).0, 0);
    }
    assert_exit(
        run(&["restore", file, "--apply", "--force", "--port", port]),
        2,
        &["operation enabled"],
    );
    for word in ["7", "6"] {
        assert_eq!(run(&["write", "control_word", word, "--port", port]).0, 0);
    }
    let out = drivescript(&["read", "parameter_set", "--port", port, "--json"], "");
    assert_has(&stdout(&out), &["\"value\":7"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The simulated drive with `dictionary`, and the plan that restores what it held before
/// `changes` were written to it.
fn planned_restore(dictionary: &DictionaryArgs, changes: &[(&str, &str)]) -> (OpenDrive, Vec<PlannedWrite>) {
    let registry = drivescript::family::Registry::builtin();
    let dictionary = dictionary.load_for(&registry, None).expect("dictionary");
    let connection = ConnectionArgs::simulated();
    let mut open = drivescript::run::open_drive(&registry, &connection, dictionary.clone(), true, None, None)
        .expect("open");
    let origin = || Origin {
        address: "sim".into(),
        date: String::new(),
        tool: String::new(),
    };
    let (backup, _) = parameters::take(&mut open.drive, origin(), &mut |_, _, _| {}, &|| true);
    for (name, value) in changes {
        open.drive
            .write(name, &value.parse().expect("quantity"))
            .expect("write");
    }
    let (live, _) = parameters::take(&mut open.drive, origin(), &mut |_, _, _| {}, &|| true);
    let plan = parameters::plan(&dictionary, &backup, &live).expect("plan");
    (open, plan)
}

/// A stop request between writes ends the restore there, and the result lists exactly
/// what was written.
#[test]
fn an_interrupted_restore_says_what_was_written() {
    use drivescript::parameters::Outcome;
    let dir = scratch("interrupted");
    let mut dictionary = DictionaryArgs::builtin_default();
    dictionary.extra.push(two_parameters(&dir).into());
    let (mut open, plan) = planned_restore(
        &dictionary,
        &[("parameter_set", "9"), ("speed_setpoint", "2000 rpm")],
    );
    assert_eq!(plan.len(), 2);
    let writes = std::cell::Cell::new(0);
    let done = parameters::apply(
        &mut open.drive,
        &plan,
        false,
        &|| writes.get() < 1,
        &mut |_, _| writes.set(writes.get() + 1),
    )
    .expect("a disabled drive is cleared for the restore");
    assert_eq!(done, [("parameter_set".to_string(), Outcome::Written)]);
    assert_eq!(open.drive.read_number("parameter_set").expect("read"), 0.0);
    assert_eq!(open.drive.read_number("speed_setpoint").expect("read"), 2000.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The restore interlock is the library's: `apply` itself refuses a drive in operation
/// enabled, even with `force`, and writes nothing.
#[test]
fn a_restore_is_refused_by_the_library_while_the_drive_is_enabled() {
    use drivescript::drive::DeviceState;
    use drivescript::parameters::RestoreRefused;
    let (mut open, plan) = planned_restore(&DictionaryArgs::builtin_default(), &[("parameter_set", "9")]);
    assert!(!plan.is_empty());
    for word in ["6", "7", "15"] {
        open.drive
            .write("control_word", &word.parse().expect("quantity"))
            .expect("control word");
    }
    assert_eq!(open.drive.state().expect("state"), DeviceState::OperationEnabled);
    for force in [false, true] {
        let refused = parameters::clear_for_restore(&mut open.drive, force).expect_err("refused");
        assert!(matches!(refused, RestoreRefused::Powered { .. }), "{refused}");
        let mut progress = 0;
        let refused = parameters::apply(&mut open.drive, &plan, force, &|| true, &mut |_, _| progress += 1)
            .expect_err("refused");
        assert!(refused.to_string().contains("operation enabled"), "{refused}");
        assert!(refused.to_string().contains("nothing was written"), "{refused}");
        assert!(
            refused
                .to_string()
                .contains("disable it first with `drivescript stop`"),
            "{refused}"
        );
        assert_eq!(progress, 0);
    }
    assert_eq!(open.drive.read_number("parameter_set").expect("read"), 9.0);
}

/// `backup --all` on a Control Techniques drive scans every menu with the ACK short
/// command and saves the parameters beyond the dictionary too; `diff` compares them,
/// `restore` writes the dictionary's and names the ones it leaves alone.
#[test]
fn a_control_techniques_scan_saves_and_compares_parameters_beyond_the_dictionary() {
    let (dir, sim, file) = on_a_pty("ct-all", &["--drive", "ct-unidrive-sp", "--pty"], "all.yaml");
    let (file, port) = (file.as_str(), sim.endpoint.as_str());
    let ct = ["--drive", "ct-unidrive-sp", "--port", port];
    let (code, out) = run(&[&["backup", "--all", "-o", file][..], &ct[..]].concat());
    assert_eq!(code, 0, "{out}");
    // Every object the drive lists is saved or said to be left out, with why, one line
    // each; the scan's tries are no lines of their own in a log.
    assert!(out.contains("the drive lists 21 object(s)"), "{out}");
    assert!(
        out.contains(
            "  left out #3.02 speed_actual: read-only: a live value the drive reports, not a setting"
        ),
        "{out}"
    );
    assert_eq!(out.matches("  left out ").count(), 16, "{out}");
    assert!(out.contains("5 parameter(s) saved"), "{out}");
    assert!(out.lines().count() < 30, "{out}");
    let saved = std::fs::read_to_string(file).expect("backup");
    assert!(
        saved.contains("name: \"max_speed\"") && saved.contains("address: \"#1.06\""),
        "{saved}"
    );
    assert!(
        saved.contains("name: \"#2.11\""),
        "a parameter beyond the dictionary: {saved}"
    );
    assert!(
        !saved.contains("name: \"#3.02\""),
        "a live value the dictionary knows is not saved: {saved}"
    );

    // Two backups compared: the scanned parameter is compared like any other (a scan of
    // every menu takes a while, so the second set is the first one edited).
    let changed = edited_copy(
        &dir,
        "changed.yaml",
        &saved,
        ("2.000", "3.500"),
        ("2.000", "3.500"),
    );
    let (code, out) = run(&["diff", file, &changed]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("#2.11") && out.contains("3.500"), "{out}");

    assert_eq!(run(&[&["write", "max_speed", "2500"][..], &ct[..]].concat()).0, 0);

    let (code, out) = run(&[&["restore", file, "--apply"][..], &ct[..]].concat());
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("not restored") && out.contains("#2.11"), "{out}");
    assert_has(&out, &["wrote max_speed"]);
    let _ = std::fs::remove_dir_all(&dir);
}
