//! Operator steps as a person meets them: on a real pseudo-terminal (an acknowledged
//! instruction, keystrokes typed before a question thrown away, a "no" failing its check,
//! Ctrl-C, SIGTERM and a closed terminal at a question while the drive is enabled, each
//! stopping it), colours and `NO_COLOR`, the cyclic channel kept going while a question
//! waits (in virtual time), the unit's identity and the answers in JUnit (both XSDs) and
//! HTML, scripts, and output names from the identity.

#[cfg(unix)]
use crate::safety::{traced_writes, CONTROL_WORD, SPEED_SETPOINT};
#[cfg(unix)]
use crate::support::Terminal;
use crate::support::{assert_has, assert_lacks, cli, scratch_file, succeeded, write_file, InProcessRun};

const SPINDLE: &str = "name: Spindle check
steps:
  - instruct: Fit the balancing adapter and close the guard
    name: guard
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - wait_until: { speed_actual: { near: 3000 rpm, within: 1 % }, timeout: 10 s }
  - confirm: Is the spindle running quietly?
    name: quiet
";

/// The control words written after the last enable (15), from a trace.
#[cfg(unix)]
fn control_words_after_enable(trace: &str) -> Vec<i64> {
    let words: Vec<i64> = traced_writes(trace, CONTROL_WORD)
        .into_iter()
        .map(|(_, v)| v)
        .collect();
    let from = words
        .iter()
        .rposition(|w| *w == 15)
        .expect("the drive was enabled");
    words[from + 1..].to_vec()
}

/// An instruction acknowledged with Enter; an answer typed while the spindle runs up, before
/// the question, is thrown away (it would have said yes); the "no" typed after it fails the
/// check and the run goes on to its safe stop. Real time, `NO_COLOR`: no colour codes.
#[cfg(unix)]
#[test]
fn on_a_terminal_an_instruction_is_acknowledged_and_typed_ahead_keys_are_discarded() {
    let (mut t, trace) = spindle_on_a_terminal(
        "operator-terminal",
        &["--unit", "operator=J. Smith"],
        &[("NO_COLOR", "1")],
    );
    t.wait_for(
        "Fit the balancing adapter and close the guard [Enter when done]",
        1,
    );
    t.type_keys("\r");
    // The spindle runs up for about 1.5 s: the keys typed now come before the question.
    t.wait_for("go to operation_enabled", 1);
    t.type_keys("yes\r");
    t.wait_for("Is the spindle running quietly? [yes/no]", 1);
    t.type_keys("no\r");
    let (code, screen) = t.finish();
    assert_eq!(code, Some(1), "{screen}");
    assert_has(
        &screen,
        &[
            "1  ?     Fit the balancing adapter and close the guard [Enter when done]",
            "PASS  Fit the balancing adapter and close the guard: answered `acknowledged` by J. Smith at",
            "FAIL  Is the spindle running quietly?: answered `no` by J. Smith at",
            "drive left in ready to switch on at 0 rpm",
            "FAILED",
        ],
    );
    assert_lacks(&screen, &["answered `yes`", "\x1b["]);
    let trace_text = std::fs::read_to_string(&trace).expect("trace");
    assert_eq!(control_words_after_enable(&trace_text), vec![7, 6]);
}

/// SPINDLE run on a terminal with `more` arguments and `env`, traced to `run.trace` in the
/// scratch folder `name`: the terminal and the trace's path.
#[cfg(unix)]
fn spindle_on_a_terminal(name: &str, more: &[&str], env: &[(&str, &str)]) -> (Terminal, std::path::PathBuf) {
    let (dir, recipe) = scratch_file(name, "spindle.yaml", SPINDLE);
    let trace = dir.join("run.trace");
    let (recipe, trace_arg) = (recipe.to_string_lossy(), trace.to_string_lossy());
    let args = [&["run", &recipe, "--trace", &trace_arg][..], more].concat();
    (Terminal::start(&args, env), trace)
}

/// How a question is ended without an answer while the drive is enabled and turning.
#[cfg(unix)]
enum Ending {
    CtrlC,
    Sigterm,
    EndOfInput,
}

#[cfg(unix)]
fn ended_at_a_question(how: Ending) {
    let name = match how {
        Ending::CtrlC => "ctrl-c",
        Ending::Sigterm => "sigterm",
        Ending::EndOfInput => "eof",
    };
    let (mut t, trace) = spindle_on_a_terminal(
        &format!("operator-{name}"),
        &["--fast", "--answer", "guard="],
        &[],
    );
    t.wait_for("Is the spindle running quietly? [yes/no]", 1);
    match how {
        Ending::CtrlC => t.type_keys("\x03"),
        Ending::Sigterm => t.signal("TERM"),
        Ending::EndOfInput => t.type_keys("\x04"),
    }
    let (code, screen) = t.finish();
    let (exit, said) = match how {
        Ending::CtrlC => (130, "INTERRUPTED\x1b[0m: interrupted by Ctrl-C (SIGINT) —"),
        Ending::Sigterm => (143, "INTERRUPTED\x1b[0m: interrupted by SIGTERM"),
        Ending::EndOfInput => (
            3,
            "the terminal closed (end of input) while asking `Is the spindle running quietly?`",
        ),
    };
    assert_eq!(code, Some(exit), "{screen}");
    assert_has(&screen, &[said, "drive left in ready to switch on at 0 rpm"]);
    // On a terminal without NO_COLOR the question is in colour.
    assert_has(&screen, &["\x1b[33m?\x1b[0m"]);
    let trace_text = std::fs::read_to_string(&trace).expect("trace");
    assert_eq!(control_words_after_enable(&trace_text), vec![7, 6], "{name}");
    let setpoints: Vec<i64> = traced_writes(&trace_text, SPEED_SETPOINT)
        .into_iter()
        .map(|(_, v)| v)
        .collect();
    assert_eq!(
        setpoints.last(),
        Some(&0),
        "the spindle is braked first: {setpoints:?}"
    );
}

#[cfg(unix)]
#[test]
fn ctrl_c_at_a_question_stops_the_enabled_drive_and_exits_130() {
    ended_at_a_question(Ending::CtrlC);
}

#[cfg(unix)]
#[test]
fn sigterm_at_a_question_stops_the_enabled_drive_and_exits_143() {
    ended_at_a_question(Ending::Sigterm);
}

#[cfg(unix)]
#[test]
fn a_terminal_closed_at_a_question_stops_the_enabled_drive_and_exits_3() {
    ended_at_a_question(Ending::EndOfInput);
}

/// A question may stand for minutes while the spindle turns: the cyclic channel's telegram
/// (the drive's heartbeat) keeps going out every 20 ms while it waits, and the fault watch
/// with it. In virtual time, with a question nobody answers within its timeout.
#[test]
fn the_cyclic_channel_keeps_sending_while_a_question_waits() {
    let (dir, recipe) = scratch_file(
        "operator-cyclic",
        "cyclic.yaml",
        "name: Cyclic question
link: { channel: cyclic, velocity_scaling: 24000 rpm }
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - confirm: { prompt: \"Is the spindle running quietly?\", timeout: 1 s }
",
    );
    let trace = dir.join("run.trace");
    let mut run = InProcessRun::new(&recipe);
    run.outputs.trace = Some(trace.clone());
    let (result, output) = run.run_at_a_silent_terminal();
    assert_eq!(result.exit_code, 1, "{output}");
    assert_has(
        &output,
        &["FAIL  Is the spindle running quietly?: nobody answered within 1s"],
    );
    let report = result.report.expect("report");
    let asked = report
        .checks
        .iter()
        .find(|c| c.name == "Is the spindle running quietly?")
        .expect("the question's check");
    let (from, until) = ((asked.at - asked.duration).as_secs_f64(), asked.at.as_secs_f64());
    assert!(until - from >= 1.0, "the question waited {:.3} s", until - from);
    let text = std::fs::read_to_string(&trace).expect("trace");
    let sent: Vec<f64> = text
        .lines()
        .filter_map(|l| {
            let mut t = l.split_whitespace();
            let at: f64 = t.next()?.parse().ok()?;
            (t.next()? == "TX" && at >= from && at <= until).then_some(at)
        })
        .collect();
    assert!(
        sent.len() >= 48,
        "{} telegrams in {:.3} s",
        sent.len(),
        until - from
    );
    let gap = sent.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    assert!(
        gap <= 0.025,
        "a gap of {gap:.3} s between telegrams during the question"
    );
}

const BALANCING: &str = "name: Balancing check
steps:
  - enter_text: { prompt: \"Scan the spindle's serial number\", pattern: \"SP-[0-9]{6}\", sets: serial }
  - instruct: Fit the balancing adapter and close the guard
    name: guard
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - confirm: Is the spindle running quietly?
    name: quiet
  - enter_value: { prompt: Vibration on the hand-held meter, unit: mm/s, at_most: 2.8 mm/s }
    name: vibration
";

/// The unit's identity (from `--unit` and from an answer) and every answer with who gave
/// it and when: JUnit properties and cases valid against both vendored XSDs, and the HTML
/// report's Run table and checks, parsed as browsers do and rendered by Chromium.
#[test]
fn junit_and_html_carry_the_identity_and_every_answer() {
    use crate::reports::markup::{html, junit, junit_xsd, select, text};
    let (dir, recipe) = scratch_file("operator-reports", "balancing.yaml", BALANCING);
    let answers = write_file(&dir, "answers.yaml", "serial: SP-104233\nguard: ''\nquiet: no\n");
    let mut run = InProcessRun::new(&recipe);
    run.operator.unit = vec![
        ("operator".into(), "J. Smith".into()),
        ("station".into(), "Bench 3".into()),
    ];
    run.operator.answers = Some(answers);
    run.operator.answer = vec![("vibration".into(), "1.2 mm/s".into())];
    let (junit_path, html_path) = run.reports_in(&dir);
    run.run_expecting(
        1,
        &[
            "unit    operator J. Smith, station Bench 3",
            "unit: serial SP-104233",
        ],
    );

    let xml = std::fs::read_to_string(&junit_path).expect("junit");
    let doc = junit(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    let property = |name: &str| {
        doc.descendants()
            .find(|n| n.has_tag_name("property") && n.attribute("name") == Some(name))
            .and_then(|n| n.attribute("value"))
            .map(str::to_string)
    };
    assert_eq!(property("unit.serial").as_deref(), Some("SP-104233"));
    assert_eq!(property("unit.operator").as_deref(), Some("J. Smith"));
    assert_eq!(property("unit.station").as_deref(), Some("Bench 3"));
    assert_eq!(property("unit.part"), None, "an unknown part is left out");
    let failure = doc
        .descendants()
        .find(|n| {
            n.has_tag_name("testcase") && n.attribute("name") == Some("Is the spindle running quietly?")
        })
        .and_then(|c| c.children().find(|n| n.has_tag_name("failure")))
        .expect("the \"no\" is a failed case");
    assert!(
        failure
            .attribute("message")
            .unwrap_or_default()
            .contains("answered `no` (given with"),
        "{xml}"
    );
    assert_has(
        &xml,
        &[
            "measured: SP-104233",
            "measured: acknowledged",
            "measured: 1.2 mm/s",
            // `at_most` lets the value equal the limit: ≤, not the strict < of `below`.
            "limits: ≤ 2.8 mm/s",
            "answered `1.2 mm/s` (given with --answer) at 20",
        ],
    );
    match junit_xsd(&xml) {
        None => crate::support::tool_missing("xmllint is not installed: the XSDs were not checked"),
        Some(result) => result.unwrap_or_else(|e| panic!("{e}\n{xml}")),
    }

    let page = std::fs::read_to_string(&html_path).expect("html");
    let doc = html(&page).unwrap_or_else(|e| panic!("{e}"));
    let unit_row = select(&doc, "table.facts tr")
        .iter()
        .map(text)
        .find(|r| r.contains("Unit under test"))
        .expect("a Unit under test row");
    assert!(
        unit_row.contains("serial SP-104233, operator J. Smith, station Bench 3"),
        "{unit_row}"
    );
    assert_has(
        &page,
        &[
            "Is the spindle running quietly?",
            "answered `no`",
            "Vibration on the hand-held meter",
            "1.2 mm/s",
            "≤ 2.8 mm/s",
        ],
    );
    let Some(mut chromium) = crate::support::headless_chromium(&dir.join("profile")) else {
        return;
    };
    let out = succeeded(chromium.arg("--dump-dom").arg(&html_path), "chromium");
    let rendered = String::from_utf8_lossy(&out.stdout);
    assert_has(
        &rendered,
        &[
            "serial SP-104233, operator J. Smith, station Bench 3",
            "Is the spindle running quietly?",
            "answered `no`",
        ],
    );
}

const SCRIPT: &str = "//! name: Scripted balancing
let d = drive();
let serial = enter_text(\"Scan the spindle's serial number\", #{ pattern: \"SP-[0-9]{6}\", sets: \"serial\" });
instruct(\"Fit the balancing adapter\");
d.go_to(\"operation_enabled\");
if !confirm(\"Is the guard closed?\") { fail(\"the guard is open\"); }
let v = enter_value(\"Vibration\", #{ unit: \"mm/s\", at_most: \"2.8 mm/s\", name: \"vibration\" });
print(`serial ${serial}, vibration ${v} mm/s`);
";

/// A script asks the same questions as functions: their answers are its values, and they
/// are checks in the report; without a terminal its literal questions need answers before
/// anything is sent; `check` knows the functions (a misspelt one is found with
/// did-you-mean).
#[test]
fn scripts_ask_the_operator_with_functions() {
    let (dir, script) = scratch_file("operator-script", "balancing.rhai", SCRIPT);
    let path = script.to_string_lossy();
    let refused = cli(&["run", &path, "--fast", "--answer", "serial=SP-104233"], 2);
    assert_has(
        &refused.stderr,
        &[
            "3 operator step(s) have no answer; nothing was sent",
            "balancing.rhai:4:1: fit_the_balancing_adapter: instruct \"Fit the balancing adapter\"",
            "balancing.rhai:6:5: is_the_guard_closed: confirm \"Is the guard closed?\"",
            "balancing.rhai:7:9: vibration: enter_value \"Vibration\"",
        ],
    );
    assert_lacks(&refused.stdout, &["using the built-in simulated"]);
    let ran = cli(
        &[
            "run",
            &path,
            "--fast",
            "--answer",
            "serial=SP-104233",
            "--answer",
            "fit_the_balancing_adapter=",
            "--answer",
            "is_the_guard_closed=y",
            "--answer",
            "vibration=3.5",
        ],
        1,
    );
    assert_has(
        &ran.stdout,
        &[
            "unit: serial SP-104233",
            "PASS  Is the guard closed?: answered `yes` (given with --answer)",
            "FAIL  Vibration: answered `3.5 mm/s` (given with --answer)",
            "serial SP-104233, vibration 3.5 mm/s",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
    let misspelt = write_file(&dir, "misspelt.rhai", "confrim(\"Guard closed?\");\n");
    let checked = cli(&["check", &misspelt.to_string_lossy()], 2);
    assert_has(&checked.stderr, &["confrim", "did you mean `confirm`?"]);
}

/// Output names from the identity: `{serial}` and `{date}` filled from `--unit` and the
/// start; a part not given (an operator step would learn it only during the run) or an
/// unknown name is refused before anything is sent.
#[test]
fn output_names_are_filled_from_the_unit() {
    let (dir, recipe) = scratch_file("operator-names", "spindle.yaml", SPINDLE);
    let (path, out_dir) = (recipe.to_string_lossy(), dir.to_string_lossy());
    let common = [
        "run",
        &path,
        "--fast",
        "--output-dir",
        &out_dir,
        "--answer",
        "guard=",
        "--answer",
        "quiet=yes",
    ];
    let ran = cli(
        &[
            &common[..],
            &[
                "--unit",
                "serial=SP-104233",
                "--report",
                "{serial}-{date}.html",
                "--junit",
                "{serial}.xml",
            ],
        ]
        .concat(),
        0,
    );
    let today = humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string();
    let report = dir.join(format!("SP-104233-{}.html", &today[..10]));
    assert!(report.is_file(), "{}", ran.stdout);
    assert!(dir.join("SP-104233.xml").is_file(), "{}", ran.stdout);
    let refused = cli(&[&common[..], &["--report", "{serial}-{date}.html"]].concat(), 2);
    assert_has(
        &refused.stderr,
        &[
            "`{serial}` needs the unit's serial, which is not given: give it with --unit serial=",
            "nothing was sent",
        ],
    );
    let unknown = cli(
        &[&common[..], &["--unit", "serial=SP-1", "--csv", "{colour}.csv"]].concat(),
        2,
    );
    assert_has(&unknown.stderr, &["`{colour}` is no name an output may use"]);
}

/// The shipped balancing check passes unattended with its answers file, and `check` lists
/// it; without the answers and a terminal it is refused before anything is sent.
#[test]
fn the_shipped_balancing_check_runs_with_its_answers() {
    let recipe = "recipes/operator/balancing-check.yaml";
    let checked = cli(&["check", recipe], 0);
    assert_has(
        &checked.stdout,
        &[
            "    asks serial: enter_text \"Scan the spindle's serial number\" (recipes/operator/balancing-check.yaml:10:5)",
            "    asks quiet: confirm \"Is the spindle running quietly?\" (recipes/operator/balancing-check.yaml:16:5)",
        ],
    );
    let ran = cli(
        &[
            "run",
            recipe,
            "--fast",
            "--answers",
            "recipes/operator/answers.yaml",
            "--unit",
            "station=Bench 3",
        ],
        0,
    );
    assert_has(
        &ran.stdout,
        &[
            "unit    station Bench 3",
            "unit: serial SP-104233, station Bench 3",
            "PASS  Vibration on the hand-held meter: answered `1.2 mm/s`",
            "PASSED",
        ],
    );
    let refused = cli(&["run", recipe, "--fast"], 2);
    assert_has(
        &refused.stderr,
        &["4 operator step(s) have no answer; nothing was sent"],
    );
}

/// In real time: SIGTERM while a question waits wakes the wait at once; the first stop
/// telegram (the speed setpoint 0 that brakes the spindle) follows within 100 ms.
#[cfg(unix)]
#[test]
fn a_stop_signal_at_a_question_is_served_at_once_in_real_time() {
    let (t, trace) = spindle_on_a_terminal("operator-latency", &["--answer", "guard="], &[]);
    t.wait_for("Is the spindle running quietly? [yes/no]", 1);
    // The question has waited a while, its slices served in between.
    std::thread::sleep(std::time::Duration::from_millis(300));
    let before = std::fs::read_to_string(&trace).expect("trace").lines().count();
    let sent = std::time::Instant::now();
    t.signal("TERM");
    let latency = loop {
        let text = std::fs::read_to_string(&trace).expect("trace");
        let fresh = text.lines().skip(before).collect::<Vec<_>>().join("\n");
        if traced_writes(&fresh, SPEED_SETPOINT).iter().any(|(_, v)| *v == 0) {
            break sent.elapsed();
        }
        assert!(
            sent.elapsed() < std::time::Duration::from_secs(10),
            "no stop telegram: {fresh}"
        );
        std::thread::sleep(std::time::Duration::from_millis(1));
    };
    let (code, screen) = t.finish();
    assert_eq!(code, Some(143), "{screen}");
    assert!(
        latency < std::time::Duration::from_millis(100),
        "the stop telegram came {latency:?} after the signal"
    );
}
