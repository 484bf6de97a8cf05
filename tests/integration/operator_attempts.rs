//! Operator steps inside `attempts`: a question nobody answers and a scan of another unit
//! each end the run at once, without another attempt (which would move the drive again
//! with nobody watching, or the wrong unit).

use crate::support::{assert_has, assert_lacks, cli, scratch, write_file, InProcessRun};

/// A question nobody answers inside `attempts` ends the run: an absent person is no failed
/// measurement, and another attempt would move the drive again with nobody watching. The
/// question is asked once, its check fails (exit code 1), and no attempt follows.
#[test]
fn a_question_nobody_answers_inside_attempts_ends_the_run_without_another_attempt() {
    let recipe = in_attempts(
        "Unanswered in attempts",
        "confirm: { prompt: \"Is the spindle running quietly?\", timeout: 1 s }",
    );
    let (result, output) = InProcessRun::new(&recipe).run_at_a_silent_terminal();
    ended_without_another_attempt(
        result,
        &output,
        "Is the spindle running quietly?",
        &[
            "Is the spindle running quietly?: nobody answered within 1s",
            "FAIL  attempts: up to 3 times (2 steps)  nobody answered within 1s",
            "FAILED",
        ],
    );
}

/// The recipe `name`: the drive enabled, up to 3 attempts of a setpoint and `question` (a
/// step, as written in the attempts' steps), then a setpoint no run that ends in the
/// attempts reaches.
fn in_attempts(name: &str, question: &str) -> std::path::PathBuf {
    let text = format!(
        "name: {name}
steps:
  - go_to: operation_enabled
  - attempts:
      times: 3
      steps:
        - set: {{ speed_setpoint: 3000 rpm }}
        - {question}
  - set: {{ speed_setpoint: 1000 rpm }}
"
    );
    write_file(&scratch(&name.replace(' ', "-")), "attempts.yaml", &text)
}

/// The run of a recipe whose question inside `attempts` ended it: exit code 1 with
/// `lines`, the question asked once, its check the one failed, and no line promising
/// another attempt (nor the step after the block).
fn ended_without_another_attempt(
    result: drivescript::run::RunResult,
    output: &str,
    question: &str,
    lines: &[&str],
) {
    assert_eq!(result.exit_code, 1, "{output}");
    assert_has(output, lines);
    assert_lacks(
        output,
        &[
            "trying again",
            "set speed_setpoint = 1000 rpm",
            "retried",
            "retrying",
        ],
    );
    let report = result.report.expect("report");
    let asked: Vec<_> = report.checks.iter().filter(|c| c.name == question).collect();
    assert_eq!(asked.len(), 1, "asked once: {asked:?}");
    assert!(!asked[0].passed && !asked[0].retried, "{:?}", asked[0]);
    assert_eq!(report.checks_failed(), 1);
}

/// A scan inside `attempts` that names another unit than the run is for stops the run as
/// one outside does: the spindle on the bench is the wrong one, which no other attempt
/// changes, and another attempt would move it again. Asked once, no attempt follows, and
/// the safe stop runs.
#[test]
fn a_scan_of_another_unit_inside_attempts_ends_the_run_without_another_attempt() {
    let recipe = in_attempts(
        "Other unit in attempts",
        "enter_text: { prompt: \"Scan the spindle's serial number\", pattern: \"SP-[0-9]{6}\", sets: serial, timeout: 1 s }\n          name: serial",
    );
    let out = cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--no-results",
            "--unit",
            "serial=SP-104233",
            "--answer",
            "serial=SP-104233",
        ],
        0,
    );
    assert_has(&out.stdout, &["PASSED"]);
    // The operator scans another spindle; the terminal stays open for another attempt's
    // question, which must not come.
    let mut run = InProcessRun::new(&recipe);
    run.operator.unit = vec![("serial".into(), "SP-104233".into())];
    let (reader, mut typing) = std::io::pipe().expect("pipe");
    std::io::Write::write_all(&mut typing, b"SP-000001\n").expect("typed");
    run.input = Some(drivescript::run::TerminalInput::of(reader));
    let (result, output) = run.run();
    drop(typing);
    ended_without_another_attempt(
        result,
        &output,
        "Scan the spindle's serial number",
        &[
            "this run is for serial SP-104233, not SP-000001",
            "FAIL  attempts: up to 3 times (2 steps)",
            "drive left in ready to switch on",
            "FAILED",
        ],
    );
}
