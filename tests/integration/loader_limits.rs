//! Issue 9, item 8: what drivescript reads is bounded before it costs memory or time. Files
//! over 8 MiB, devices and endless pipes as recipes, included files and dictionaries; YAML
//! alias bombs; includes that multiply. Each input is generated into a temporary folder and
//! run through the binary with a hard timeout, so the old behaviour (9 GB read from
//! `/dev/zero`, 30 s of include fan-out) fails the test instead of hanging it. The wall-time
//! bounds are generous (debug build, shared machine); benches hold the tight targets.
//!
//! Also property tests: whatever numbers a recipe gives, an accepted recipe keeps the
//! runner's time arithmetic in range.

use crate::support::scratch;
use drivescript::recipe::{load_recipe_text, StepKind, MAX_DURATION, MAX_RUN_TIME, MAX_SAMPLES};
use drivescript::session::{Predicate, Tolerance};
use proptest::prelude::*;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// Refusals take milliseconds; the old behaviour (an alias bomb expanded, a long line drawn)
/// took minutes. This bound tells the two apart even on a machine loaded twenty-fold; the
/// loader's speed itself is measured by `cargo bench`, not here.
const FAST: Duration = Duration::from_secs(10);
/// Past this the child is killed and the test fails: the old behaviour would run on.
const HANG: Duration = Duration::from_secs(30);

struct Outcome {
    code: Option<i32>,
    stderr: String,
    took: Duration,
}

/// Runs `drivescript ARGS` in `dir`, killing it after [`HANG`].
fn run(dir: &Path, args: &[&str]) -> Outcome {
    let started = Instant::now();
    let mut child = crate::support::command()
        .args(args)
        .current_dir(dir)
        .env_remove("DRIVESCRIPT_LIMITS")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the drivescript binary starts");
    loop {
        if child.try_wait().expect("waitable").is_some() {
            break;
        }
        if started.elapsed() > HANG {
            let _ = child.kill();
            let _ = child.wait();
            panic!("drivescript {args:?} still running after {HANG:?}: the limit does not hold");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let took = started.elapsed();
    let output = child.wait_with_output().expect("output");
    Outcome {
        code: output.status.code(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        took,
    }
}

/// Runs each of `cases` (the arguments, the parts of the refusal) in `dir` and checks each
/// is refused fast; then removes `dir`.
fn assert_each_refused_fast(dir: &Path, cases: &[(&[&str], &[&str])]) {
    for (args, refusal) in cases {
        assert_refused_fast(&run(dir, args), refusal);
    }
    let _ = std::fs::remove_dir_all(dir);
}

fn assert_refused_fast(o: &Outcome, expected: &[&str]) {
    assert_eq!(o.code, Some(2), "{}", o.stderr);
    for e in expected {
        assert!(o.stderr.contains(e), "missing `{e}` in:\n{}", o.stderr);
    }
    assert!(o.took < FAST, "took {:?}:\n{}", o.took, o.stderr);
    for internal in ["Nodes {", "budget breached", "Budget", "AliasReplay"] {
        assert!(
            !o.stderr.contains(internal),
            "internal text `{internal}`:\n{}",
            o.stderr
        );
    }
}

/// Valid YAML a little over 8 MiB: the old loader read and accepted it.
fn oversized_recipe() -> String {
    let mut text = String::from("name: Large\nsteps:\n  - shutdown\n");
    let line = format!("# {}\n", "x".repeat(1000));
    while text.len() as u64 <= drivescript::diag::MAX_TEXT_FILE_BYTES {
        text.push_str(&line);
    }
    text
}

#[test]
fn recipes_includes_and_dictionaries_over_8_mib_are_refused() {
    let dir = scratch("large");
    std::fs::write(dir.join("large.yaml"), oversized_recipe()).expect("write");
    std::fs::write(
        dir.join("includes.yaml"),
        "name: Includes\nsteps:\n  - include: large.yaml\n",
    )
    .expect("write");
    std::fs::write(dir.join("small.yaml"), "name: Small\nsteps:\n  - shutdown\n").expect("write");

    let cases: [(&[&str], &[&str]); 3] = [
        (&["check", "large.yaml"], &["the recipe large.yaml is larger than 8 MiB, the limit for one recipe, included file, dictionary or limits file", "check that the path names the file you meant"]),
        (&["check", "includes.yaml"], &["the included file", "large.yaml is larger than 8 MiB", "includes.yaml:3:14"]),
        (&["check", "small.yaml", "--dictionary", "large.yaml"], &["large.yaml: the dictionary file is larger than 8 MiB"]),
    ];
    assert_each_refused_fast(&dir, &cases);
}

#[test]
#[cfg_attr(windows, ignore = "Windows has no /dev/zero")]
fn dev_zero_is_refused_at_once_as_recipe_include_and_dictionary() {
    let dir = scratch("dev-zero");
    std::fs::write(dir.join("small.yaml"), "name: Small\nsteps:\n  - shutdown\n").expect("write");
    std::fs::write(
        dir.join("zero.yaml"),
        "name: Zero\nsteps:\n  - include: /dev/zero\n",
    )
    .expect("write");
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &["check", "/dev/zero"],
            &[
                "the recipe /dev/zero is a device, not a file",
                "give the path of a YAML file",
            ],
        ),
        (
            &["check", "zero.yaml"],
            &[
                "the included file /dev/zero is a device, not a file",
                "zero.yaml:3:14",
            ],
        ),
        (
            &["objects", "--dictionary", "/dev/zero"],
            &["/dev/zero: the dictionary file is a device, not a file"],
        ),
    ];
    assert_each_refused_fast(&dir, &cases);
}

/// A pipe that never ends (`check <(yes)`): read up to the limit, then refused.
#[cfg(unix)]
#[test]
fn an_endless_pipe_is_read_only_up_to_the_limit() {
    use std::io::Write;
    use std::os::unix::ffi::OsStrExt;
    let dir = scratch("fifo");
    let fifo = dir.join("endless.yaml");
    let c_path = std::ffi::CString::new(fifo.as_os_str().as_bytes()).expect("path");
    // SAFETY: a valid NUL-terminated path; mkfifo only creates a file system entry.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0, "mkfifo");
    let writer_path = fifo.clone();
    let writer = std::thread::spawn(move || {
        let mut pipe = std::fs::OpenOptions::new()
            .write(true)
            .open(&writer_path)
            .expect("the reader opens the pipe");
        let block = vec![b'#'; 64 * 1024];
        let mut written = 0u64;
        // Until the reader closes its end (the write fails) or it has had far too much.
        while written < 64 * drivescript::diag::MAX_TEXT_FILE_BYTES {
            if pipe.write_all(&block).is_err() {
                break;
            }
            written += block.len() as u64;
        }
        written
    });
    let o = run(&dir, &["check", "endless.yaml"]);
    // Had drivescript not opened the pipe, the writer would wait for a reader for ever:
    // open it here and let it go, so the writer ends either way.
    {
        use std::os::unix::fs::OpenOptionsExt;
        let _reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(&fifo);
    }
    assert_refused_fast(&o, &["the recipe endless.yaml is larger than 8 MiB"]);
    let written = writer.join().expect("writer");
    assert!(
        written < 2 * drivescript::diag::MAX_TEXT_FILE_BYTES,
        "the reader took {written} bytes"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each level refers to the one before it ten times: 10^9 values if expanded.
fn alias_bomb(head: &str) -> String {
    let mut text = String::from(head);
    text.push_str("lol0: &l0 \"lol\"\n");
    for i in 1..10 {
        let refs = vec![format!("*l{}", i - 1); 10].join(", ");
        text.push_str(&format!("lol{i}: &l{i} [{refs}]\n"));
    }
    text
}

#[test]
fn alias_bombs_are_refused_fast_in_plain_words() {
    let dir = scratch("alias-bomb");
    std::fs::write(
        dir.join("bomb.yaml"),
        alias_bomb("name: Bomb\nsteps: [shutdown]\n"),
    )
    .expect("write");
    std::fs::write(dir.join("dict.yaml"), alias_bomb("family: sd2\nobjects: []\n")).expect("write");
    std::fs::write(dir.join("small.yaml"), "name: Small\nsteps:\n  - shutdown\n").expect("write");
    let expected = [
        "refused: the aliases (`*name`) in this file copy more than 10000 values, as an alias bomb does",
        "to run steps several times use `repeat` or `include`, not aliases of aliases",
    ];
    let o = run(&dir, &["check", "bomb.yaml"]);
    assert_refused_fast(&o, &expected);
    assert!(o.stderr.contains("bomb.yaml:"), "located: {}", o.stderr);
    let o = run(&dir, &["check", "small.yaml", "--dictionary", "dict.yaml"]);
    assert_refused_fast(&o, &expected);
    // In-process, the parse alone is far below the 100 ms even in a debug build.
    let source = drivescript::diag::Source::new("bomb.yaml", alias_bomb("name: Bomb\nsteps: [shutdown]\n"));
    let started = Instant::now();
    assert!(drivescript::diag::YamlNode::parse(&source).is_err());
    assert!(started.elapsed() < FAST, "{:?}", started.elapsed());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_include_fan_out_is_refused_fast_where_it_goes_over() {
    let dir = scratch("fan-out");
    // Eight files, each including the next ten times: 10^7 loads if nothing stopped it.
    for level in 0..8 {
        let mut text = format!("name: level {level}\nsteps:\n");
        if level < 7 {
            for _ in 0..10 {
                text.push_str(&format!("  - include: f{}.yaml\n", level + 1));
            }
        } else {
            text.push_str("  - shutdown\n");
        }
        std::fs::write(dir.join(format!("f{level}.yaml")), text).expect("write");
    }
    let o = run(&dir, &["check", "f0.yaml"]);
    assert_refused_fast(
        &o,
        &[
            "this include goes over 1000 included files for one recipe",
            "f6.yaml:10:14",
            "include number 1001",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A problem far to the right of a long line (a generated file written on one line) made
/// miette's renderer panic; it is now named in the headline, without a snippet.
#[test]
fn problems_far_right_on_a_long_line_are_named_not_drawn() {
    let dir = scratch("wide");
    let steps = vec!["shutdown"; 9000].join(", ");
    std::fs::write(
        dir.join("wide.yaml"),
        format!("name: Wide\nsteps: [{steps}, frob]\n"),
    )
    .expect("write");
    let gap = " ".repeat(70_000);
    std::fs::write(
        dir.join("wide-limits.yaml"),
        format!("{{ max_speed: 6000 rpm,{gap}max_sped: 1 rpm }}\n"),
    )
    .expect("write");
    std::fs::write(dir.join("small.yaml"), "name: Small\nsteps:\n  - shutdown\n").expect("write");
    let o = run(&dir, &["check", "wide.yaml"]);
    assert_refused_fast(&o, &["wide.yaml:2:90009: unknown step `frob`"]);
    let o = run(&dir, &["check", "small.yaml", "--limits", "wide-limits.yaml"]);
    assert_refused_fast(
        &o,
        &["wide-limits.yaml:1:70023: unknown key `max_sped` in the limits file"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn load(steps: &str) -> Option<Vec<drivescript::recipe::Step>> {
    let dictionary = drivescript::family::Registry::builtin()
        .load_dictionary("sd2")
        .expect("built-in dictionary");
    let text = format!("name: p\nsteps:\n{steps}");
    load_recipe_text("p.yaml", &text, Path::new("."), &dictionary, &[])
        .ok()
        .map(|r| r.steps)
}

/// Durations as people (and typos) write them.
fn duration_text() -> impl Strategy<Value = String> {
    let unit = prop::sample::select(vec!["ns", "us", "ms", "s", "min", "h", "days", "weeks", "years"]);
    let number = prop_oneof![
        4 => (1u64..5000).prop_map(|n| n.to_string()),
        1 => any::<u64>().prop_map(|n| n.to_string()),
        1 => "[0-9]{1,30}",
    ];
    (number, unit).prop_map(|(n, u)| format!("{n} {u}"))
}

/// Numbers, including ones that are not finite or too large for a float.
fn number_text() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => (-7000i64..7000).prop_map(|n| n.to_string()),
        2 => "-?[0-9]{1,3}(\\.[0-9]{1,3})?(e[0-9]{1,3})?",
        1 => Just(".nan".to_string()),
        1 => Just(".inf".to_string()),
        1 => Just("-.inf".to_string()),
        1 => Just("1e400".to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// `every * k` for every sample k of an accepted `sample` step fits, and k fits a u32.
    #[test]
    fn accepted_samples_stay_countable(every in duration_text(), length in duration_text()) {
        let steps = format!("  - sample: {{ objects: [speed_actual], every: {every}, for: {length} }}\n");
        if let Some(steps) = load(&steps) {
            let StepKind::Sample { sampling, .. } = &steps[0].kind else {
                panic!("a sample step")
            };
            let (every, duration) = (&sampling.every, &sampling.duration);
            prop_assert!(*every <= MAX_DURATION && *duration <= MAX_DURATION);
            let samples = duration.as_nanos() / every.as_nanos() + 1;
            prop_assert!(samples <= u128::from(MAX_SAMPLES));
            let k = u32::try_from(samples).expect("fits a u32");
            prop_assert!(every.checked_mul(k).is_some());
            prop_assert!(steps[0].longest_time() <= MAX_RUN_TIME);
        }
    }

    /// An accepted repeat of dwells ends within what the clock can count.
    #[test]
    fn accepted_repeats_fit_the_clock(times in any::<u32>(), dwell in duration_text()) {
        let steps = format!("  - repeat: {{ times: {times}, steps: [ {{ dwell: {dwell} }} ] }}\n");
        if let Some(steps) = load(&steps) {
            let total = steps[0].longest_time();
            prop_assert!(total <= MAX_RUN_TIME, "{total:?}");
            // Steps, on_fault and finally together stay below the virtual clock's 584 years.
            prop_assert!(total.checked_mul(3).is_some_and(|t| t < Duration::from_nanos(u64::MAX)));
        }
    }

    /// An accepted ramp writes finite values in a countable number of steps, and an
    /// accepted tolerance is finite.
    #[test]
    fn accepted_ramps_and_tolerances_are_finite(
        to in number_text(),
        rate in number_text(),
        within in number_text(),
        every in duration_text(),
    ) {
        let steps = format!(
            "  - ramp: {{ object: speed_setpoint, from: 0 rpm, to: {to}, rate: {rate} rpm/s, every: {every} }}\n  - wait_until: {{ speed_actual: {{ near: {to}, within: {within} % }}, timeout: 5 s }}\n"
        );
        if let Some(steps) = load(&steps) {
            let StepKind::Ramp { points, every, .. } = &steps[0].kind else {
                panic!("a ramp step")
            };
            prop_assert!(points.iter().all(|p| p.is_finite()));
            let n = u32::try_from(points.len()).expect("fits a u32");
            prop_assert!(every.checked_mul(n).is_some());
            let StepKind::WaitUntil { condition, .. } = &steps[1].kind else {
                panic!("a wait step")
            };
            if let drivescript::session::Condition::Value { predicate: Predicate::Near { target, tolerance }, .. } = condition {
                prop_assert!(target.is_finite());
                let Tolerance::Percent(p) = tolerance else { panic!("a percentage") };
                prop_assert!(p.is_finite());
            }
        }
    }
}
