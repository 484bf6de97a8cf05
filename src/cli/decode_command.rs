//! `drivescript decode`: explains captured telegrams, one per argument or per input line.

use super::drive_args::DictionaryArgs;
use super::{FAILED, INVALID, PASSED};
use crate::family::Registry;
use crate::hex::parse_hex;
use clap::Args;
use std::io::{BufRead, Write};

#[derive(Debug, Args)]
/// Explain captured telegrams: direction, addresses, command, object, data, error text,
/// control and status word bits. Hex as `00 0b 02 ...`, `000b02...` or `0x00 0x0b ...`;
/// one telegram per argument, or per line on standard input when no argument is given.
/// CAN families (--protocol lenze-9400) take frames as candump writes them
/// (`60C#409C5F0000000000`, or a candump log line) or as `ID data…`.
pub struct DecodeArgs {
    /// The drive family whose protocol the telegrams are in (default: the family of the
    /// --drive dictionary).
    #[arg(long, value_name = "FAMILY")]
    protocol: Option<String>,
    /// One JSON object per telegram (the keys of the family's golden vectors, e.g.
    /// shared/vectors/sd2-dnc.yaml); a rejected telegram is {"reject": "<reason>"}.
    #[arg(long)]
    json: bool,
    /// Telegrams in hex, one per argument. Lines of a `--trace` file are accepted too.
    hex: Vec<String>,
    #[command(flatten)]
    dictionary: DictionaryArgs,
}

/// Exit code: 0 when every telegram decoded, 1 when any was rejected, 2 for text that is
/// not hex at all.
pub fn run(args: &DecodeArgs) -> i32 {
    let lines: Vec<(String, String)> = if args.hex.is_empty() {
        let stdin = std::io::stdin();
        let mut out = Vec::new();
        for (i, line) in stdin.lock().lines().enumerate() {
            match line {
                Ok(l) => out.push((format!("line {}", i + 1), l)),
                Err(e) => {
                    eprintln!("error: cannot read standard input: {e}");
                    return INVALID;
                }
            }
        }
        out
    } else if args.hex.len() > 1
        && (is_single_byte(&args.hex[0]) || is_can_id(&args.hex[0]))
        && args.hex.iter().skip(1).all(|a| is_single_byte(a))
    {
        // `decode 00 0b 02 ...` (or `decode 60C 40 9C ...`) without quotes: the shell
        // split one telegram into bytes.
        vec![("the arguments".to_string(), args.hex.join(" "))]
    } else {
        args.hex
            .iter()
            .enumerate()
            .map(|(i, h)| (format!("argument {}", i + 1), h.clone()))
            .collect()
    };
    let mut names = match args.dictionary.load() {
        Ok(d) => d,
        Err(text) => {
            eprint!("{text}");
            return INVALID;
        }
    };
    let registry = Registry::builtin();
    let protocol = args.protocol.as_deref().unwrap_or(names.family());
    // --protocol names a family (`lenze_9400`) or, as --drive does, its dictionary (`lenze-9400`).
    let family = match registry
        .family(protocol)
        .or_else(|e| registry.dictionary(protocol).map(|(f, _)| f).map_err(|_| e))
    {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    if family.id() != names.family() {
        // The object names come from the protocol's own dictionary, not the default one.
        if let Some(builtin) = family.dictionaries().first() {
            match registry.load_dictionary(builtin.name) {
                Ok(d) => names = std::sync::Arc::new(d),
                Err(e) => {
                    eprint!("{}", super::render_diagnostic(&e));
                    return INVALID;
                }
            }
        }
    }
    let frames = family.bus_kind() == crate::bus::BusKind::Frames;
    let mut explainer = family.explainer(names);
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut code = PASSED;
    for (place, line) in &lines {
        let mut text = line.trim();
        if frames {
            // CAN frames: candump's `ID#DATA`, a candump log line, or `ID data…`; a
            // meaning after `  # ` (a `-v` trace line) is dropped.
            let frame_text = text.split_once(" #").map_or(text, |(f, _)| f).trim();
            if frame_text.is_empty() || frame_text.starts_with('#') {
                continue;
            }
            let frame = match crate::bus::CanFrame::parse_text(frame_text) {
                Ok(f) => f,
                Err(e) => {
                    eprintln!("error: {place}: {e}");
                    code = INVALID;
                    continue;
                }
            };
            let bytes = frame.to_bytes();
            let (written, valid) = if args.json {
                let (json, valid) = explainer.json(&bytes);
                (writeln!(out, "{json}"), valid)
            } else {
                let (body, valid) = match explainer.explain(&bytes) {
                    Ok(text) => (text, true),
                    Err(e) => (format!("  rejected: {e}\n"), false),
                };
                (writeln!(out, "{}\n{body}", frame.to_candump()), valid)
            };
            if !valid && code == PASSED {
                code = FAILED;
            }
            if written.is_err() {
                return code;
            }
            continue;
        }
        if crate::bus::CanFrame::parse_text(text).is_ok() && (text.starts_with('(') || text.contains('#')) {
            let can: Vec<&str> = registry
                .families()
                .filter(|f| f.bus_kind() == crate::bus::BusKind::Frames)
                .flat_map(|f| f.dictionaries().iter().map(|d| d.name))
                .collect();
            eprintln!(
                "error: {place}: `{text}` is a CAN frame, not a {} telegram; give --protocol {}",
                family.id(),
                can.join(" or --protocol ")
            );
            // One frame says it for the whole input.
            return INVALID;
        }
        // A line of a `--trace` file: only its telegram's hex counts.
        if crate::report::is_trace_line(text) {
            match crate::report::hex_of_trace_line(text) {
                Some(hex) => text = hex,
                None => continue,
            }
        }
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let bytes = match parse_hex(text) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: {place}: {e}");
                code = INVALID;
                continue;
            }
        };
        let (written, valid) = if args.json {
            let (json, valid) = explainer.json(&bytes);
            (writeln!(out, "{json}"), valid)
        } else {
            let (body, valid) = match explainer.explain(&bytes) {
                Ok(text) => (text, true),
                Err(e) => (format!("  rejected: {e}\n"), false),
            };
            (writeln!(out, "{}\n{body}", crate::hex::to_hex(&bytes)), valid)
        };
        if !valid && code == PASSED {
            code = FAILED;
        }
        if written.is_err() {
            // Standard output closed (e.g. piped into `head`): nothing more to say.
            return code;
        }
    }
    code
}

/// `0b`, `0x0b`, `b`: one byte, as the shell leaves an unquoted telegram.
fn is_single_byte(arg: &str) -> bool {
    let digits = arg
        .strip_prefix("0x")
        .or_else(|| arg.strip_prefix("0X"))
        .unwrap_or(arg);
    (1..=2).contains(&digits.len()) && digits.chars().all(|c| c.is_ascii_hexdigit())
}

/// `60C`, `18FF0001`: a CAN identifier as candump writes it (3 or 8 hex digits).
fn is_can_id(arg: &str) -> bool {
    matches!(arg.len(), 3 | 8) && arg.chars().all(|c| c.is_ascii_hexdigit())
}
