//! Help as other command-line tools give it (issue 42): `drivescript --help` one line per
//! command, `-h` the short form and `--help` the paragraphs with examples at the end, and
//! the man page and completions generated from the same clap definitions.

use crate::support::{assert_has, cli};

/// The lines of the `Commands:` list of `help`.
fn command_lines(help: &str) -> Vec<&str> {
    help.lines()
        .skip_while(|l| *l != "Commands:")
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .collect()
}

#[test]
fn the_command_list_has_one_line_per_command() {
    let help = cli(&["--help"], 0).stdout;
    let lines = command_lines(&help);
    assert!(lines.len() >= 19, "{help}");
    for line in &lines {
        // A wrapped description would continue on a line that starts with blanks only.
        let name = line.split_whitespace().next().unwrap_or("");
        assert!(
            line.starts_with(&format!("  {name} ")) && line.len() <= 100,
            "one line per command: {line:?}\n{help}"
        );
    }
    assert!(help.contains("Examples:\n  drivescript run"), "{help}");
    assert!(help.len() < 3500, "{} bytes:\n{help}", help.len());
}

#[test]
fn run_h_is_the_short_form_and_run_help_has_the_paragraphs_and_examples() {
    let short = cli(&["run", "-h"], 0).stdout;
    let long = cli(&["run", "--help"], 0).stdout;
    assert!(short.starts_with("Run recipes or scripts"), "{short}");
    assert!(!short.contains("Whatever happens, the safe stop runs"), "{short}");
    assert!(long.contains("Whatever happens, the safe stop runs"), "{long}");
    // Each option one sentence in the short form, the whole text in the long one.
    let flat = |t: &str| t.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        flat(&short).contains("Bench limits file capping speed and current"),
        "{short}"
    );
    assert!(!flat(&short).contains("can raise its limits"), "{short}");
    assert!(
        flat(&long).contains("Nothing (recipe, --set, --dictionary) can raise its limits"),
        "{long}"
    );
    let examples = long.rfind("Examples:").expect("examples at the end");
    assert!(
        long[examples..].contains("drivescript run recipes/commissioning.yaml --fast"),
        "{long}"
    );
    assert!(!short.contains("Examples:"), "{short}");
    assert!(short.lines().count() < long.lines().count());
}

/// `run -h` fits a terminal: one line per option (none wraps), the rarely needed ones
/// (serial framing, the cyclic telegram, colour) only under `--help`.
#[test]
fn run_h_is_at_most_fifty_lines_of_one_line_options() {
    let short = cli(&["run", "-h"], 0).stdout;
    let long = cli(&["run", "--help"], 0).stdout;
    assert!(
        short.lines().count() <= 50,
        "{} lines:\n{short}",
        short.lines().count()
    );
    let continued = |l: &&str| l.starts_with("      ") && !l.trim_start().starts_with('-');
    assert_eq!(
        short.lines().filter(continued).count(),
        0,
        "a wrapped line:\n{short}"
    );
    for hidden in ["--data-bits", "--velocity-scaling", "--color", "--retries"] {
        assert!(!short.contains(hidden), "{hidden} in -h:\n{short}");
        assert!(long.contains(hidden), "{hidden} missing from --help:\n{long}");
    }
    assert_has(
        &short,
        &[
            "--port",
            "--tcp",
            "--can",
            "--address",
            "--fast",
            "--junit",
            "--results",
        ],
    );
}

#[test]
fn the_man_page_lists_every_command_and_each_has_its_own() {
    let help = cli(&["--help"], 0).stdout;
    let page = cli(&["man"], 0).stdout;
    assert!(page.contains(".TH drivescript 1"), "{page}");
    for line in command_lines(&help) {
        let name = line.split_whitespace().next().unwrap_or("");
        if name == "help" {
            continue;
        }
        assert!(
            page.contains(&format!("drivescript\\-{name}(1)")),
            "{name} missing:\n{page}"
        );
    }
    let run = cli(&["man", "run"], 0).stdout;
    assert!(run.contains(".TH drivescript-run 1"), "{run}");
    assert!(run.contains("Whatever happens, the safe stop runs"), "{run}");
    let err = cli(&["man", "rn"], 2).stderr;
    assert!(err.contains("drivescript has no command `rn`"), "{err}");
}

#[test]
fn completions_offer_the_man_command_too() {
    let bash = cli(&["completions", "bash"], 0).stdout;
    assert!(bash.contains("man"), "{bash}");
}
