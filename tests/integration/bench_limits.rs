//! Issue 9, item 7: a bench limits file caps speed and current, found by `--limits`, else
//! `DRIVESCRIPT_LIMITS`, else `drivescript-limits.yaml` next to the recipe; `check`, `run`
//! and `write` refuse what exceeds it, and neither a recipe, `--set` nor a user dictionary
//! can raise it. A user profile whose stop commands keep the drive enabled is refused.
//! Through the binary, so the environment variable is the child's alone.

use crate::support::assert_has;
use drivescript::dictionary::LIMITS_ENV;
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

const SD2: &str = include_str!("../../dictionary/sd2.yaml");

/// Runs `drivescript ARGS` in `dir` with `DRIVESCRIPT_LIMITS` set to `env` (or unset).
fn run(dir: &Path, args: &[&str], env: Option<&str>) -> Output {
    let mut command = crate::support::command();
    command
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .env_remove(LIMITS_ENV);
    if let Some(value) = env {
        command.env(LIMITS_ENV, value);
    }
    command.output().expect("the drivescript binary runs")
}

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The command was refused (exit code 2) saying `text`.
fn refused_with(o: &Output, text: &str) {
    assert_eq!(o.status.code(), Some(2), "{}{}", out(o), err(o));
    assert!(err(o).contains(text), "{}", err(o));
}

/// The command succeeded (exit code 0) and printed `text`.
fn accepted_with(o: &Output, text: &str) {
    assert_eq!(o.status.code(), Some(0), "{}{}", out(o), err(o));
    assert!(out(o).contains(text), "{}", out(o));
}

/// A fresh folder with `files` (name, text) in it.
fn bench(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drivescript-bench-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (file, text) in files {
        std::fs::write(dir.join(file), text).expect("write");
    }
    dir
}

const SET_6500: &str = "name: Fast\nsteps:\n  - set: { speed_setpoint: 6500 rpm }\n";

#[test]
fn the_limits_file_is_found_by_flag_then_environment_then_next_to_the_recipe() {
    let dir = bench(
        "routes",
        &[
            ("r.yaml", SET_6500),
            ("flag.yaml", "max_speed: 7000 rpm\n"),
            ("env.yaml", "max_speed: 5000 rpm\n"),
        ],
    );
    // No limits file anywhere: the dictionary's 60000 rpm apply.
    let o = run(&dir, &["check", "r.yaml"], None);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(!out(&o).contains("bench limits"), "{}", out(&o));

    // Next to the recipe.
    std::fs::write(dir.join("drivescript-limits.yaml"), "max_speed: 6000 rpm\n").expect("write");
    let o = run(&dir, &["check", "r.yaml"], None);
    refused_with(
        &o,
        "6500 rpm exceeds the bench limit 6000 rpm of speed_setpoint (limits file drivescript-limits.yaml)",
    );
    let recipe = dir.join("r.yaml");
    let o = run(Path::new("/"), &["check", recipe.to_str().expect("utf-8")], None);
    let next_to = dir.join("drivescript-limits.yaml");
    assert!(
        err(&o).contains(&format!("(limits file {})", next_to.display())),
        "from elsewhere the path names the folder: {}",
        err(&o)
    );

    // The environment beats the file next to the recipe.
    let o = run(&dir, &["check", "r.yaml"], Some("env.yaml"));
    refused_with(&o, "6500 rpm exceeds the bench limit 5000 rpm of speed_setpoint (limits file env.yaml from DRIVESCRIPT_LIMITS)");

    // The flag beats both; check says which limits it checked against.
    let o = run(
        &dir,
        &["check", "r.yaml", "--limits", "flag.yaml"],
        Some("env.yaml"),
    );
    accepted_with(&o, "bench limits max_speed 7000 rpm (limits file flag.yaml)");

    // A limits file that is named but missing is an error, never no limits.
    let o = run(&dir, &["check", "r.yaml"], Some("gone.yaml"));
    assert_eq!(o.status.code(), Some(2));
    assert!(err(&o).contains("cannot read the limits file"), "{}", err(&o));
    assert!(
        err(&o).contains("check the path in DRIVESCRIPT_LIMITS"),
        "{}",
        err(&o)
    );
    let o = run(
        &dir,
        &["write", "speed_setpoint", "100rpm", "--limits", "gone.yaml"],
        None,
    );
    refused_with(&o, "check the path given with --limits");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn limits_file_problems_are_located() {
    let dir = bench(
        "parse",
        &[
            ("r.yaml", SET_6500),
            (
                "bad.yaml",
                "max_sped: 6000 rpm\nmax_current: 8 rpm\nmax_speed: 6000\n",
            ),
        ],
    );
    let o = run(&dir, &["check", "r.yaml", "--limits", "bad.yaml"], None);
    assert_eq!(o.status.code(), Some(2));
    let e = err(&o);
    assert_has(
        &e,
        &[
            "bad.yaml:1:1: unknown key `max_sped` in the limits file",
            "did you mean `max_speed`?",
            "`max_current` is a current, but rpm measures speed",
            "bad.yaml:2:14",
            "`max_speed` 6000 has no unit",
            "bad.yaml:3:12",
            "write the unit, rpm or krpm, e.g. `max_speed: 12000 rpm`",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_and_run_refuse_set_values_ramps_and_overrides_over_the_limit() {
    let recipe = "name: Stages\nparams:\n  speed: 5000 rpm\nsteps:\n  - go_to: operation_enabled\n  - ramp: { object: speed_setpoint, from: 0 rpm, to: \"{{speed}}\", rate: 1000 rpm/s }\n";
    let dir = bench(
        "recipe",
        &[
            ("r.yaml", recipe),
            ("drivescript-limits.yaml", "max_speed: 6000 rpm\n"),
        ],
    );
    let o = run(&dir, &["check", "r.yaml"], None);
    accepted_with(
        &o,
        "bench limits max_speed 6000 rpm (limits file drivescript-limits.yaml)",
    );

    let o = run(&dir, &["check", "r.yaml", "--set", "speed=7 krpm"], None);
    refused_with(
        &o,
        "7 krpm (7000 rpm) exceeds the bench limit 6000 rpm of speed_setpoint",
    );
    assert!(err(&o).contains("r.yaml:6:"), "located at the use: {}", err(&o));

    // run checks first: nothing is sent, the drive is not even opened.
    let o = run(&dir, &["run", "r.yaml", "--fast", "--set", "speed=6001rpm"], None);
    refused_with(&o, "exceeds the bench limit 6000 rpm");
    assert!(!out(&o).contains("using the built-in"), "{}", out(&o));
    let o = run(&dir, &["run", "r.yaml", "--fast", "--set", "speed=6000rpm"], None);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn write_refuses_a_value_over_the_limit_before_sending() {
    let dir = bench("write", &[("l.yaml", "max_speed: 6000 rpm\n")]);
    let o = run(
        &dir,
        &["write", "speed_setpoint", "6500rpm", "--limits", "l.yaml"],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        err(&o).trim(),
        "error: 6500 rpm exceeds the bench limit 6000 rpm of speed_setpoint (limits file l.yaml); nothing was sent"
    );
    assert_eq!(out(&o), "", "nothing written");
    let o = run(&dir, &["write", "speed_setpoint", "-6.5krpm"], Some("l.yaml"));
    refused_with(&o, "-6.5 krpm (-6500 rpm) is below the bench limit -6000 rpm of speed_setpoint (limits file l.yaml from DRIVESCRIPT_LIMITS)");
    let o = run(&dir, &["write", "speed_setpoint", "6000rpm"], Some("l.yaml"));
    accepted_with(&o, "speed_setpoint = 6000 rpm written");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_user_dictionary_cannot_raise_the_limit() {
    // The user's file raises speed_setpoint to 100000 rpm and adds a krpm speed and a
    // current setpoint without limits of their own.
    let user = "family: sd2\nobjects:\n  - name: speed_setpoint\n    index: 395\n    type: i32\n    unit: rpm\n    scale: 0.001\n    access: rw\n    min: -100000\n    max: 100000\n  - name: spindle_speed\n    index: 4000\n    type: i32\n    unit: krpm\n    scale: 0.001\n    access: rw\n  - name: current_limit\n    index: 4001\n    type: u16\n    unit: mA\n    access: rw\n";
    let dir = bench(
        "dictionary",
        &[
            ("user.yaml", user),
            ("l.yaml", "max_speed: 6000 rpm\nmax_current: 8 A\n"),
        ],
    );
    let with = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend(["--dictionary", "user.yaml", "--limits", "l.yaml"]);
        run(&dir, &all, None)
    };
    for (write, refusal) in [
        (
            ["write", "speed_setpoint", "6500rpm"],
            "exceeds the bench limit 6000 rpm of speed_setpoint",
        ),
        (
            ["write", "spindle_speed", "6.5krpm"],
            "6.5 krpm exceeds the bench limit 6 krpm of spindle_speed",
        ),
        (
            ["write", "current_limit", "9A"],
            "9 A (9000 mA) exceeds the bench limit 8000 mA of current_limit",
        ),
    ] {
        refused_with(&with(&write), refusal);
    }

    // objects shows the tightened ranges, marked; read-only speeds keep theirs.
    let o = with(&["objects"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let listing = out(&o);
    assert_has(
        &listing,
        &["bench limits max_speed 6000 rpm, max_current 8 A (limits file l.yaml)"],
    );
    let row = |name: &str| {
        listing
            .lines()
            .find(|l| l.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no row {name} in {listing}"))
            .to_string()
    };
    assert!(
        row("speed_setpoint").contains("-6000 .. 6000 (bench)"),
        "{listing}"
    );
    assert!(row("spindle_speed").contains("-6 .. 6 (bench)"), "{listing}");
    // u16 keeps its own minimum 0 from its type, and the bench caps the maximum.
    assert!(row("current_limit").contains("8000 (bench)"), "{listing}");
    assert!(!row("speed_actual").contains("bench"), "{listing}");
    let o = with(&["objects", "--json", "speed_setpoint"]);
    accepted_with(&o, "\"bench_limit\":\"limits file l.yaml\"");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_profile_whose_stops_keep_the_drive_enabled_is_refused() {
    let profile = &SD2[SD2.find("profile:").expect("a profile")..];
    let disobedient = profile.replace("disable_operation: 7", "disable_operation: 15");
    assert_ne!(&disobedient, profile);
    let dir = bench(
        "profile",
        &[
            ("user.yaml", &format!("family: sd2\nobjects: []\n{disobedient}")),
            ("r.yaml", "name: Stop\nsteps:\n  - shutdown\n"),
        ],
    );
    let line = 2
        + disobedient
            .lines()
            .position(|l| l.contains("disable_operation: 15"))
            .expect("the line")
        + 1;
    for args in [
        &["check", "r.yaml", "--dictionary", "user.yaml"][..],
        &["run", "r.yaml", "--fast", "--dictionary", "user.yaml"][..],
    ] {
        let o = run(&dir, args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}{}", out(&o), err(&o));
        let e = err(&o);
        assert_has(&e, &[&format!(
                "user.yaml:{line}:24: `disable_operation` 15 (0x000F) keeps every bit of `enable_operation` 15 (0x000F): this stop command would leave the drive enabled"
            ), "the CiA 402 profile's disable_operation is 7"]);
        assert!(
            !out(&o).contains("using the built-in"),
            "nothing ran: {}",
            out(&o)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
