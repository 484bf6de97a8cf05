//! `drivescript decode` end to end: the printed telegrams with the right meaning, JSON that
//! matches the vectors field for field, exit codes.

use crate::support::{assert_has, cli, drivescript, sd2_vectors, stderr, stdout};
use serde_json::Value;

#[test]
fn json_output_matches_the_vectors_field_for_field() {
    let vectors = sd2_vectors();
    let input: String = vectors.iter().map(|v| format!("{}\n", v.hex)).collect();
    let out = drivescript(&["decode", "--json"], &input);
    assert_eq!(
        out.status.code(),
        Some(1),
        "two vectors are rejects: {}",
        stderr(&out)
    );
    let lines: Vec<Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), vectors.len());
    for (v, got) in vectors.iter().zip(&lines) {
        v.assert_decoded(got, got.get("reject").is_none());
    }
}

#[test]
fn all_accepted_forms_of_hex_and_exit_zero() {
    let text = cli(
        &[
            "decode",
            "--protocol",
            "sd2",
            "00 0b 02 01 0e 44 00 00 00 00 00 02 0f 00 8e",
            "000401028e006a",
            "0x00 0x09 0x02 0x01 0x0d 0x8e 0x01 0x00 0x00 0x00 0x00 0x57",
        ],
        0,
    )
    .stdout;
    assert_has(
        &text,
        &[
            "control   15: enable operation",
            "reply     write wide object (cmd 0x8e), drive 2 (switch 0, drive A) → PC (1)",
            "error     0x00 no error",
            "398 (0x018e) speed_actual (VCTRL_VELOCITY_ACTUAL_VALUE_UUNIT)",
        ],
    );
}

#[test]
fn a_reply_is_read_as_the_object_its_request_asked_for() {
    let out = drivescript(
        &["decode"],
        "# status word read\n00 09 02 01 0d 43 00 00 00 00 00 a3\n\n00 07 01 02 8d 02 00 37 66 c9\n",
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert_has(&text, &["status    0x6637: operation enabled"]);
}

#[test]
fn rejected_telegram_says_why_and_exits_one() {
    let out = cli(&["decode", "00 0d 02 01 10 05 00 07 00 ff 1f 00 00 00 00 05"], 1);
    assert!(out
        .stdout
        .contains("rejected: bad checksum at byte 15: expected 0xb5, got 0x05"));
}

#[test]
fn text_that_is_not_hex_is_a_usage_error() {
    let out = cli(&["decode", "00 0g"], 2);
    assert_has(&out.stderr, &["argument 1: 'g' at column 5 is not a hex digit"]);
}

#[test]
fn an_unquoted_telegram_is_one_telegram() {
    let bytes: Vec<&str> = "00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97"
        .split(' ')
        .collect();
    let mut args = vec!["decode"];
    args.extend(bytes);
    let text = cli(&args, 0).stdout;
    assert_has(&text, &["control   6: shutdown"]);
    assert_eq!(text.matches("request").count(), 1, "{text}");
}

#[test]
fn objects_are_named_from_the_dictionary() {
    let out = drivescript(
        &["decode", "00 0b 02 01 0e 8b 01 00 00 00 00 04 80 8d 5b 00 eb"],
        "",
    );
    let text = stdout(&out);
    assert_has(
        &text,
        &[
            "395 (0x018b) speed_setpoint (SPG_TARGET_VELOCITY_VL_UUNIT)",
            "= 6000 rpm",
        ],
    );
}

#[test]
fn completions_for_every_shell_name_the_subcommands() {
    for shell in ["bash", "zsh", "fish", "powershell"] {
        let text = cli(&["completions", shell], 0).stdout;
        for sub in ["run", "check", "decode", "simulate", "objects"] {
            assert!(text.contains(sub), "{shell} completion lacks {sub}");
        }
    }
    cli(&["completions", "tcsh"], 2);
}

/// `decode --help` lists every family of the registry (and every built-in dictionary)
/// for `--protocol`, and names the golden vectors where they are.
#[test]
fn decode_help_lists_every_family_of_the_registry() {
    let help = cli(&["decode", "--help"], 0).stdout;
    let registry = drivescript::family::Registry::builtin();
    for id in registry.families().map(|f| f.id()) {
        assert!(
            help.contains(&format!("`{id}`")),
            "--help lacks family {id}:\n{help}"
        );
    }
    for name in registry.dictionary_names() {
        assert!(
            help.contains(&format!("`{name}`")),
            "--help lacks dictionary {name}:\n{help}"
        );
    }
    assert!(help.contains("tests/vectors/sd2-dnc.yaml"), "{help}");
    assert!(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/vectors/sd2-dnc.yaml")
            .is_file(),
        "the path --help names exists"
    );
}
