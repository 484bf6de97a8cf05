//! The command line as users meet it (issue 17): several recipes in one `run` with the
//! worst exit code, `--output-dir` and the printed output paths, `decode FILE`, a value
//! with a space before its unit, colour that follows `--color` and `NO_COLOR`, examples
//! and exit codes in `--help`, build information in `--version`, and plain messages for
//! a port that is not a serial port and a recipe that is not UTF-8.

use crate::support::{
    assert_has, assert_lacks, cli, drivescript, scratch, scratch_file, stderr, stdout,
    wide_speed_and_current_rows, Ran,
};
use std::path::PathBuf;

/// `drivescript run RECIPES --fast --output-dir DIR MORE`, DIR the fresh scratch folder
/// `name`, which must exit with `code`: the folder and what the run wrote.
#[track_caller]
fn run_into_scratch(name: &str, recipes: &[&str], more: &[&str], code: i32) -> (PathBuf, Ran) {
    let dir = scratch(name);
    let output_dir = ["--fast", "--output-dir", dir.to_str().expect("a UTF-8 path")];
    let args = [&["run"][..], recipes, &output_dir, more].concat();
    let ran = cli(&args, code);
    (dir, ran)
}

#[test]
fn several_recipes_run_in_turn_and_the_worst_exit_code_wins() {
    let (dir, ran) = run_into_scratch(
        "several",
        &[
            "tests/cases/ok/identity/recipe.yaml",
            "tests/cases/failed/expect_out_of_tolerance/recipe.yaml",
        ],
        &["--junit", "junit.xml"],
        1,
    );
    let text = ran.stdout;
    assert_has(
        &text,
        &[
            "== recipe 1 of 2: tests/cases/ok/identity/recipe.yaml",
            "== recipe 2 of 2:",
        ],
    );
    assert_eq!(
        text.matches("drive left in").count(),
        2,
        "each its own safe stop: {text}"
    );
    assert_has(&text, &["exit code 1 (the worst of them)"]);
    // One JUnit file for both recipes under --output-dir, announced (its suites:
    // tests/integration/several_files.rs).
    let written: Vec<String> = text
        .lines()
        .filter_map(|l| l.strip_prefix("outputs "))
        .map(str::to_string)
        .collect();
    assert_eq!(written, [dir.join("junit.xml").display().to_string()], "{text}");
    for path in &written {
        assert!(path.starts_with(dir.to_str().unwrap()), "{path}");
        assert!(std::path::Path::new(path).is_file(), "{path}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sample_csv_files_go_to_the_output_dir_and_are_announced() {
    let (dir, out) = run_into_scratch("csv", &["recipes/spindle-run-in.yaml"], &[], 0);
    let line = out
        .stdout
        .lines()
        .find_map(|l| l.strip_prefix("outputs ").map(str::to_string))
        .expect("an outputs line");
    for n in 1..=4 {
        let file = dir.join(format!("run-in-stage-{n}.csv"));
        assert!(file.is_file(), "{}", file.display());
        assert!(line.contains(&file.display().to_string()), "{line}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn decode_reads_trace_files() {
    let dir = scratch("decode");
    let trace = dir.join("run.trace");
    cli(
        &[
            "run",
            "recipes/identity.yaml",
            "--fast",
            "--trace",
            trace.to_str().unwrap(),
        ],
        0,
    );
    let decoded = drivescript(&["decode", trace.to_str().unwrap(), trace.to_str().unwrap()], "");
    assert_eq!(decoded.status.code(), Some(0), "{}", stderr(&decoded));
    let text = stdout(&decoded);
    assert_has(&text, &["read wide object"]);
    assert_lacks(&stderr(&decoded), &["not a hex digit"]);
    let once = stdout(&drivescript(&["decode", trace.to_str().unwrap()], ""));
    assert_eq!(text.len(), 2 * once.len(), "both files decoded");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn write_takes_the_unit_as_its_own_argument() {
    let out = cli(&["write", "speed_setpoint", "6000", "rpm"], 0);
    assert_has(&out.stdout, &["speed_setpoint = 6000 rpm written"]);
}

#[test]
fn write_suggests_the_unit_meant() {
    let out = drivescript(&["write", "speed_setpoint", "6000", "rmp"], "");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let text = stderr(&out);
    assert!(text.contains("unknown unit `rmp`"), "{text}");
    assert!(text.contains("did you mean `rpm`?"), "{text}");
    assert!(text.contains("nothing was sent"), "{text}");
}

#[test]
fn colour_follows_the_color_option_and_is_off_in_pipes() {
    let run = |extra: &[&str]| {
        let mut args = vec!["run", "recipes/identity.yaml", "--fast"];
        args.extend_from_slice(extra);
        stdout(&drivescript(&args, ""))
    };
    assert!(!run(&[]).contains('\x1b'), "a pipe gets no escape codes");
    let always = run(&["--color", "always"]);
    assert_has(&always, &["\x1b[32mPASSED\x1b[0m"]);
    assert!(!run(&["--color", "never"]).contains('\x1b'));
}

#[test]
fn help_shows_examples_and_exit_codes_and_version_the_build() {
    let help = stdout(&drivescript(&["--help"], ""));
    assert_has(
        &help,
        &[
            "Examples:",
            "drivescript write speed_setpoint 6000 rpm",
            "Exit codes:",
            "3  communication failure",
        ],
    );
    let version = stdout(&drivescript(&["--version"], ""));
    assert!(version.starts_with("drivescript 0."), "{version}");
    assert_has(&version, &["(commit ", ", built 20"]);
}

/// Unix: a device file that takes no line settings.
#[test]
#[cfg_attr(windows, ignore = "Windows has no device file to name in its place")]
fn a_file_that_is_no_serial_port_is_said_plainly() {
    let out = drivescript(&["state", "--port", "/dev/null"], "");
    assert_ne!(out.status.code(), Some(0));
    let err = stderr(&out);
    assert_has(&err, &["/dev/null: it is not a serial port"]);
    assert_lacks(&err, &["typewriter"]);
}

#[test]
fn a_windows_1252_recipe_is_said_plainly() {
    let dir = scratch("cp1252");
    let path = dir.join("prüfung.yaml");
    std::fs::write(&path, b"name: Pr\xfcfung\ndrive: sd2\nsteps:\n  - shutdown\n").unwrap();
    let err = cli(&["check", path.to_str().unwrap()], 2).stderr;
    assert_has(&err, &["is not UTF-8 text", "Windows-1252"]);
    assert_lacks(&err, &["check the path"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A drive at another address never answers: one early message naming the address as
/// typed and the three likely causes, exit code 3, nothing run, reports written.
#[test]
fn a_drive_that_never_answers_gets_one_early_message() {
    let err = said_early_that_the_drive_does_not_answer("recipes/identity.yaml", "silent");
    assert_has(&err, &["the recipe did not start"]);
}

/// Runs `file` (a recipe or a script) against a drive that never answers: it is said
/// once, before anything runs, with the three likely causes, and in the JUnit file; what
/// it said on standard error.
pub(crate) fn said_early_that_the_drive_does_not_answer(file: &str, name: &str) -> String {
    let sim = crate::support::Simulator::start(&["--tcp", "127.0.0.1:0"]);
    let dir = scratch(name);
    let junit = dir.join("junit.xml");
    let out = cli(
        &[
            "run",
            file,
            "--tcp",
            &sim.endpoint,
            "--address",
            "1",
            "--timeout",
            "50ms",
            "--retries",
            "0",
            "--junit",
            junit.to_str().unwrap(),
        ],
        3,
    );
    let err = out.stderr;
    assert_has(&err, &["the drive does not answer (--address 1,"]);
    assert_eq!(err.matches("no reply from").count(), 1, "said once: {err}");
    // Over TCP the causes are the server's and the network's, not a serial line's.
    assert_has(
        &err,
        &[
            "1. the address: you gave --address 1",
            "2. the server: --tcp",
            "a serial server's own baud rate and parity must match the drive's",
            "3. the network",
        ],
    );
    assert!(!out.stdout.contains("     1  "), "no step ran: {}", out.stdout);
    let xml = std::fs::read_to_string(&junit).expect("junit");
    assert_has(&xml, &["the drive does not answer"]);
    std::fs::remove_dir_all(&dir).unwrap();
    err
}

/// `--csv-wide`: one column per object in `--csv` and in the `csv:` files of sample steps,
/// with the same time, UTC and iteration-aware step columns as the long layout.
#[test]
fn csv_wide_gives_one_column_per_object_everywhere() {
    let (dir, _) = run_into_scratch(
        "wide",
        &["recipes/spindle-run-in.yaml"],
        &["--csv", "all.csv", "--csv-wide"],
        0,
    );
    for name in ["all.csv", "run-in-stage-2.csv"] {
        let rows = wide_speed_and_current_rows(&dir.join(name));
        assert!(rows
            .iter()
            .all(|r| r.len() == 5 && humantime::parse_rfc3339(&r[1]).is_ok()));
        if name == "run-in-stage-2.csv" {
            assert_eq!(rows.len(), 2 * 901);
            assert_eq!((&rows[0][2], &rows[901][2]), ("8[1].3", "8[2].3"));
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `objects` sizes its columns from what they hold: a long address (SD2's
/// `index 22 (0x0016)`) or name (CT's `control_word_enable`) does not push its row out of
/// line, so every cell of a column starts where its heading does.
#[test]
fn objects_columns_line_up_whatever_their_width() {
    for drive in ["sd2", "ct-unidrive-sp"] {
        let listing = crate::support::cli(&["objects", "--drive", drive], 0).stdout;
        let lines: Vec<Vec<char>> = listing.lines().map(|l| l.chars().collect()).collect();
        let header = lines
            .iter()
            .position(|l| l.starts_with(&['n', 'a', 'm', 'e', ' ']))
            .unwrap_or_else(|| panic!("no header in {listing}"));
        let heading: String = lines[header].iter().collect();
        // The columns that are never empty.
        for column in ["address", "type", "access"] {
            let at = heading[..heading.find(column).expect("column")].chars().count();
            for row in &lines[header + 1..] {
                let row_text: String = row.iter().collect();
                assert!(
                    row.get(at - 1) == Some(&' ') && row.get(at).is_some_and(|c| *c != ' '),
                    "{drive}: `{column}` is not at column {at} in\n{row_text}\n{listing}"
                );
            }
        }
    }
}

/// The cyclic channel carries the speed setpoint as a fraction of the velocity scaling:
/// a value beyond it is refused by `check` (exit 2, at its place) and by `run` before the
/// port is opened (the port here does not exist, so opening it would be exit 3), for
/// `set`, `ramp` points and a `--set` value alike.
#[test]
fn a_setpoint_beyond_the_cyclic_velocity_scaling_is_refused_before_anything_is_sent() {
    let dir = crate::support::scratch("cyclic-range");
    let recipe = crate::support::write_file(
        &dir,
        "cyclic.yaml",
        "name: cyclic\nparams:\n  top: 20000 rpm\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 30000 rpm }\n  - ramp: { object: speed_setpoint, from: 0 rpm, to: \"{{top}}\", step: 5000 rpm, every: 1 s }\n",
    );
    let recipe = recipe.to_str().expect("utf-8");
    let set_line = "cyclic.yaml:6:5: set speed_setpoint = 30000 rpm is beyond -24000 .. 24000 rpm: the cyclic channel carries at most ±100 % of the velocity scaling, 24000 rpm";

    let err = refused_on_the_cyclic_channel(&["check", recipe]);
    assert_has(&err, &[set_line, "1 value(s) the link cannot carry"]);
    // On the object channel the same recipe is fine.
    cli(&["check", recipe], 0);

    let port = ["--port", "/nonexistent/ttyUSB9"];
    let err = refused_on_the_cyclic_channel(&[&["run", recipe, "--set", "top=26000rpm"][..], &port].concat());
    assert_has(
        &err,
        &[
            set_line,
            "cyclic.yaml:7:5: ramp speed_setpoint = 26000 rpm is beyond -24000 .. 24000 rpm",
            "nothing was sent",
        ],
    );
    assert!(!err.contains("ttyUSB9"), "the port was never opened: {err}");
}

/// What `drivescript ARGS` on the SD2's cyclic channel (velocity scaling 24000 rpm) says
/// on stderr, refusing with exit 2.
#[track_caller]
fn refused_on_the_cyclic_channel(args: &[&str]) -> String {
    let cyclic = ["--channel", "cyclic", "--velocity-scaling", "24000rpm"];
    cli(&[args, &cyclic].concat(), 2).stderr
}

/// A spindle and a feed drive on one line, the spindle's setpoint beyond the cyclic scaling.
const TWO_SD2_DRIVES: &str = "name: two
drives:
  spindle: { drive: sd2, address: dnc:2 }
  feed: { drive: sd2, address: dnc:3 }
steps:
  - set: { spindle.speed_setpoint: 30000 rpm }
  - set: { feed.speed_setpoint: 20000 rpm }
";

/// With `drives:`, each drive's values are compared with the range of its own family's
/// link: the setpoint beyond the cyclic scaling is refused by `check` and by `run` before
/// any port opens, and the other drive's setpoint within it is not.
#[test]
fn a_named_drives_setpoint_beyond_its_links_range_is_refused_before_anything_is_sent() {
    let (_, recipe) = scratch_file("cyclic-range-drives", "two.yaml", TWO_SD2_DRIVES);
    let recipe = recipe.to_str().expect("utf-8");
    let line = "two.yaml:6:5: set spindle.speed_setpoint = 30000 rpm is beyond -24000 .. 24000 rpm: the cyclic channel carries";

    let err = refused_on_the_cyclic_channel(&["check", recipe]);
    assert_has(&err, &[line, "1 value(s) the link cannot carry"]);
    assert_lacks(&err, &["feed.speed_setpoint"]);

    let err = refused_on_the_cyclic_channel(&["run", recipe, "--port", "/nonexistent/ttyUSB9"]);
    assert_has(&err, &[line, "nothing was sent"]);
    assert_lacks(&err, &["ttyUSB9"]);
}

/// `ports` shows a USB-serial adapter's latency timer where the system exposes it (here a
/// fake sysfs tree), and how to lower it. Linux's sysfs; Windows keeps the timer in the
/// adapter driver's settings.
#[cfg(target_os = "linux")]
#[test]
fn ports_show_the_usb_serial_latency_timer() {
    let root = crate::support::scratch("sysfs");
    let tty = root.join("bus/usb-serial/devices/ttyUSB7");
    std::fs::create_dir_all(&tty).expect("fake sysfs");
    std::fs::write(tty.join("latency_timer"), "16\n").expect("timer");
    let out = crate::support::command()
        .arg("ports")
        .env("DRIVESCRIPT_SYSFS", &root)
        .output()
        .expect("drivescript runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.contains("/dev/ttyUSB7  usb"), "{text}");
    let timer = tty.join("latency_timer");
    assert!(
        text.contains(&format!(
            "    latency timer 16 ms; every reply waits up to 16 ms in the adapter, lower it with `echo 1 | sudo tee {}`",
            timer.display()
        )),
        "{text}"
    );
    let json = crate::support::command()
        .args(["ports", "--json"])
        .env("DRIVESCRIPT_SYSFS", &root)
        .output()
        .expect("drivescript runs");
    let json = String::from_utf8_lossy(&json.stdout);
    assert!(json.contains("\"latency_timer_ms\":16"), "{json}");
}

/// A run on a USB-serial adapter whose latency timer alone slows the line or is longer
/// than the recipe's sample interval says so once, before the first step, with how to
/// lower it; a script's run says it of the line too. The port is a pty with the simulated
/// drive; the timer comes from a fake sysfs tree named after it.
#[cfg(unix)]
#[test]
fn a_run_says_once_when_the_latency_timer_slows_its_line_or_its_samples() {
    let dir = crate::support::scratch("latency");
    let sim = crate::support::Simulator::start(&["--pty"]);
    let port = sim.endpoint.as_str();
    let tty = std::path::Path::new(port).file_name().expect("pty name");
    let timer_dir = dir.join("sysfs/bus/usb-serial/devices").join(tty);
    std::fs::create_dir_all(&timer_dir).expect("fake sysfs");
    let recipe = crate::support::write_file(
        &dir,
        "fast.yaml",
        "name: fast samples\nsteps:\n  - sample: { objects: [speed_actual], every: 10 ms, for: 100 ms }\n",
    );
    let script = crate::support::write_file(
        &dir,
        "read.rhai",
        "let d = drive();\nprint(d.read(\"speed_actual\"));\n",
    );
    let run = |file: &std::path::Path, timer_ms: u32, every: &str| {
        std::fs::write(timer_dir.join("latency_timer"), format!("{timer_ms}\n")).expect("timer");
        let text = std::fs::read_to_string(&recipe).expect("recipe");
        let text = text.replace("every: 10 ms", &format!("every: {every}"));
        let text = text.replace("every: 50 ms", &format!("every: {every}"));
        std::fs::write(&recipe, text).expect("recipe");
        let out = crate::support::command()
            .args(["run", file.to_str().expect("utf-8"), "--port", port])
            .env("DRIVESCRIPT_SYSFS", dir.join("sysfs"))
            .output()
            .expect("drivescript runs");
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(0), "{err}");
        err
    };
    // 16 ms: an SD2 read of speed_actual (24 bytes, 4.2 ms at 57600 8N1) is held far
    // longer than the wire takes, and 10 ms samples cannot be kept.
    let err = run(&recipe, 16, "10 ms");
    assert_eq!(err.matches("latency timer of 16 ms").count(), 1, "{err}");
    crate::support::assert_has(
        &err,
        &[
            "so reads of speed_actual (24 bytes, 4.2 ms on the wire at 57600 8N1) drop from about 240/s to as few as 50/s",
            ", and samples every 10 ms cannot be kept; lower it with `echo 1 | sudo tee",
        ],
    );
    // 50 ms samples are reachable; the line is still slowed.
    let err = run(&recipe, 16, "50 ms");
    crate::support::assert_has(&err, &["latency timer of 16 ms", "drop from about 240/s"]);
    crate::support::assert_lacks(&err, &["samples every"]);
    // A script's reads are slowed alike.
    let err = run(&script, 16, "50 ms");
    crate::support::assert_has(&err, &["latency timer of 16 ms", "so reads of"]);
    // A 1 ms timer is shorter than an exchange on the wire: nothing is said.
    assert!(!run(&recipe, 1, "50 ms").contains("latency timer"));
}
