//! `drivescript man`: the man page, rendered by clap_mangen from the same clap definitions
//! as `--help` and the completions, so the three cannot disagree. Prints only.

use crate::run::{INVALID, PASSED};

#[derive(Debug, clap::Args)]
/// Print the man page (roff), e.g. `drivescript man | man -l -`
///
/// Print the man page (roff) of drivescript, or of one command as `drivescript-COMMAND`.
/// Install with `drivescript man > ~/.local/share/man/man1/drivescript.1` and
/// `drivescript man run > ~/.local/share/man/man1/drivescript-run.1`.
pub struct ManArgs {
    /// The command whose page to print [default: the page of drivescript itself].
    command: Option<String>,
}

/// Writes the page of `args.command` (or of the whole tool) in `root` to standard output;
/// the exit code.
pub fn man(args: &ManArgs, root: clap::Command) -> i32 {
    let mut root = root;
    root.build();
    let page = match &args.command {
        None => root,
        Some(name) => match root.find_subcommand(name) {
            // Built, a subcommand is displayed as `drivescript-run`: the page's name and title.
            Some(sub) => sub.clone(),
            None => {
                let names: Vec<&str> = root.get_subcommands().map(|c| c.get_name()).collect();
                eprintln!(
                    "error: drivescript has no command `{name}`\n  help: one of {}",
                    names.join(", ")
                );
                return INVALID;
            }
        },
    };
    let mut text = Vec::new();
    if let Err(e) = clap_mangen::Man::new(page).render(&mut text) {
        eprintln!("error: the man page could not be written: {e}");
        return INVALID;
    }
    use std::io::Write;
    let _ = std::io::stdout().write_all(&text);
    PASSED
}
