//! Hints that send the user the right way: the command `simulate` offers reaches the drive
//! it serves when copied as printed, and a drive that does not answer gets its own
//! family's advice, with another family's drive on the line among the likely causes.

use crate::support::{cli, drivescript, stderr, stdout, Simulator};

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
