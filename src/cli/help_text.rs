//! The two lengths of help, as other command-line tools give them: `-h` one sentence per
//! option, `--help` the whole text; and the examples at the end of `run --help`. Works on
//! the clap definitions only; must not name a family or print anything itself.

/// Shown at the end of `run --help` (not `run -h`): the runs users type first.
pub const RUN_EXAMPLES: &str = "\
Examples:
  drivescript run recipes/commissioning.yaml --fast
      the built-in simulated drive, in virtual time
  drivescript run recipes/acceptance-test.yaml --port /dev/ttyUSB0 --address 1 \\
      --output-dir out --junit junit.xml --report report.html
  drivescript run recipes/modbus/acceptance.yaml --tcp 192.168.0.20:502
  drivescript run recipes/lenze-9400/commissioning.yaml --can slcan:/dev/ttyACM0";

/// Every option's help shortened to its first sentence for `-h`, the whole text kept for
/// `--help`; a subcommand's first paragraph is its line in the list (clap's `about`), the
/// rest only under its own `--help`. Applied to the whole tree, so an option added later
/// gets both lengths without anyone remembering to.
pub fn short_and_long(mut command: clap::Command) -> clap::Command {
    let ids: Vec<clap::Id> = command
        .get_arguments()
        .filter(|a| a.get_long_help().is_none())
        .map(|a| a.get_id().clone())
        .collect();
    for id in ids {
        command = command.mut_arg(id, |arg| {
            let Some(whole) = arg.get_help().map(|h| h.to_string()) else {
                return arg;
            };
            let short = one_line(&whole);
            if short == whole {
                arg
            } else {
                arg.help(short).long_help(whole)
            }
        });
    }
    let names: Vec<String> = command
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    for name in names {
        command = command.mut_subcommand(name, short_and_long);
    }
    command
}

/// The longest `-h` line an option's text may take before it is cut at its first clause,
/// so that the option, its value name and the text fit one line of a terminal.
const SHORT_HELP_WIDTH: usize = 56;

/// An option's help as one `-h` line: its first sentence without a `[default: …]` the text
/// writes itself, cut at the first clause (`:`, `;`, ` (`, `,`) when it is still longer
/// than [`SHORT_HELP_WIDTH`]; no full stop at the end.
fn one_line(whole: &str) -> String {
    let mut line = first_sentence(whole).unwrap_or(whole).to_string();
    if let Some(start) = line.find(" [default: ") {
        if let Some(len) = line[start..].find(']') {
            line.replace_range(start..=start + len, "");
        }
    }
    if line.chars().count() > SHORT_HELP_WIDTH {
        let cut = [": ", "; ", " (", ", "]
            .iter()
            .filter_map(|mark| line.find(mark))
            .filter(|&at| at >= 12)
            .min();
        if let Some(at) = cut {
            line.truncate(at);
        }
    }
    line.trim_end_matches('.').to_string()
}

/// The first sentence of `text` when there is more after it: up to a full stop followed by
/// a space and a capital (so `e.g. speed` and `1.5 A` do not end it).
fn first_sentence(text: &str) -> Option<&str> {
    let bytes = text.as_bytes();
    (0..bytes.len().saturating_sub(2)).find_map(|i| {
        let ends = bytes[i] == b'.'
            && bytes[i + 1] == b' '
            && bytes[i + 2].is_ascii_uppercase()
            && !text[..i].ends_with("e.g")
            && !text[..i].ends_with("i.e");
        ends.then(|| &text[..=i])
    })
}

#[cfg(test)]
mod tests {
    use super::{first_sentence, one_line};

    #[test]
    fn the_short_line_is_the_first_clause_of_a_long_sentence() {
        assert_eq!(
            one_line("Serial port the drive is on (/dev/ttyUSB0, /dev/serial/by-id/…, COM3)."),
            "Serial port the drive is on"
        );
        assert_eq!(
            one_line("Speeds within ± this count as standstill [default: 10rpm]."),
            "Speeds within ± this count as standstill"
        );
        assert_eq!(one_line("A short one. With a second sentence."), "A short one");
        assert_eq!(one_line("Record nothing"), "Record nothing");
    }

    #[test]
    fn the_first_sentence_ends_at_a_full_stop_before_a_capital() {
        assert_eq!(
            first_sentence("Run in virtual time. Hours take seconds."),
            Some("Run in virtual time.")
        );
        assert_eq!(
            first_sentence("Write e.g. 1.5 A. Then read."),
            Some("Write e.g. 1.5 A.")
        );
        assert_eq!(first_sentence("One sentence only."), None);
        assert_eq!(
            first_sentence("Names, e.g. Speed. Or not"),
            Some("Names, e.g. Speed.")
        );
    }
}
