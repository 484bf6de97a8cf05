//! `drivescript decode`: explains captured telegrams, one per argument or per input line, as the
//! drive a `--trace` file's header names unless --protocol or --drive says otherwise.

use crate::dictionary::Dictionary;
use crate::family::{Family, Registry, DEFAULT_DICTIONARY};
use crate::hex::parse_hex;
use crate::link::TelegramExplainer;
use crate::report::{trace_notes_path, TraceHeader};
use crate::run::DictionaryArgs;
use crate::run::{RunError, FAILED, INVALID, PASSED};
use clap::Args;
use std::io::{BufRead, Write};
use std::sync::Arc;

#[derive(Debug, Args)]
/// Explain captured telegrams (hex, candump lines, a --trace file)
///
/// Explain captured telegrams: direction, addresses, command, object, data, error text,
/// control and status word bits. Hex as `00 0b 02 ...`, `000b02...` or `0x00 0x0b ...`;
/// one telegram per argument, or per line on standard input when no argument is given.
/// CAN families (--protocol lenze-9400) take frames as candump writes them
/// (`60C#409C5F0000000000`, or a candump log line) or as `ID data…`.
pub struct DecodeArgs {
    /// The drive family whose protocol the telegrams are in (`--help` lists the family
    /// ids of this build; see [`protocol_help`]).
    #[arg(long, value_name = "FAMILY")]
    protocol: Option<String>,
    /// One JSON object per telegram (the keys of the family's golden vectors, e.g.
    /// tests/vectors/sd2-dnc.yaml); a rejected telegram is {"reject": "<reason>"}.
    #[arg(long)]
    json: bool,
    /// Telegrams in hex, one per argument, or files of them (a `--trace` file, a capture
    /// with one telegram per line).
    #[arg(value_name = "HEX|FILE")]
    hex: Vec<String>,
    #[command(flatten)]
    dictionary: DictionaryArgs,
}

/// Exit code: 0 when every telegram decoded, 1 when any was rejected, 2 for text that is
/// not hex at all.
pub fn run(args: &DecodeArgs, registry: &Registry) -> i32 {
    // Where a trace's own header was found, and what it says.
    let mut headers: Vec<(String, TraceHeader)> = Vec::new();
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
        headers.extend(
            TraceHeader::read(out.iter().map(|(_, l)| l.as_str())).map(|h| ("standard input".to_string(), h)),
        );
        out
    } else if args.hex.len() > 1
        && (is_single_byte(&args.hex[0]) || is_can_id(&args.hex[0]))
        && args.hex.iter().skip(1).all(|a| is_single_byte(a))
    {
        // `decode 00 0b 02 ...` (or `decode 60C 40 9C ...`) without quotes: the shell
        // split one telegram into bytes.
        vec![("the arguments".to_string(), args.hex.join(" "))]
    } else {
        let mut out = Vec::new();
        for (i, arg) in args.hex.iter().enumerate() {
            let path = std::path::Path::new(arg);
            if !path.is_file() {
                // Hex never holds a `/`: this was meant as a file.
                if arg.contains(['/', '\\']) || path.extension().is_some_and(|e| e == "trace" || e == "log") {
                    let what = if path.exists() {
                        "is not a file"
                    } else {
                        "does not exist"
                    };
                    eprintln!(
                        "error: {arg} {what}\n  help: give a --trace file or a candump log, or telegrams as hex (`00 0b 02 ...`)"
                    );
                    return INVALID;
                }
                out.push((format!("argument {}", i + 1), arg.clone()));
                continue;
            }
            match read_lines(path) {
                Ok(lines) => {
                    headers.extend(trace_header_of(path, &lines).map(|h| (arg.clone(), h)));
                    out.extend(
                        lines
                            .into_iter()
                            .enumerate()
                            .map(|(n, l)| (format!("{arg}:{}", n + 1), l)),
                    );
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    return INVALID;
                }
            }
        }
        out
    };
    let recorded = recorded_drive(registry, args, &headers, &lines);
    let (family, names) = match protocol_and_names(registry, args, recorded.as_ref()) {
        Ok(found) => found,
        Err(text) => {
            eprint!("{text}");
            return INVALID;
        }
    };
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
            if frame_text.is_empty() || crate::report::is_trace_line(frame_text) {
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
            let heading = frame.to_candump();
            if !explain_one(
                explainer.as_mut(),
                &frame.to_bytes(),
                &heading,
                args.json,
                &mut out,
                &mut code,
            ) {
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
        // ASCII families read captured lines as they are (`OR:0011`), hex otherwise.
        let bytes = match family.line_telegram(text).map_or_else(|| parse_hex(text), Ok) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: {place}: {e}");
                code = INVALID;
                continue;
            }
        };
        let heading = crate::hex::to_hex(&bytes);
        if !explain_one(
            explainer.as_mut(),
            &bytes,
            &heading,
            args.json,
            &mut out,
            &mut code,
        ) {
            // Standard output closed (e.g. piped into `head`): nothing more to say.
            return code;
        }
    }
    code
}

/// Writes one telegram under `heading` (its hex, or the CAN frame as candump writes it)
/// with its explanation, or its JSON line. A rejected telegram makes a passing `code`
/// FAILED; `false` when standard output is closed.
fn explain_one(
    explainer: &mut dyn TelegramExplainer,
    bytes: &[u8],
    heading: &str,
    json: bool,
    out: &mut dyn Write,
    code: &mut i32,
) -> bool {
    let (written, valid) = if json {
        let (json, valid) = explainer.json(bytes);
        (writeln!(out, "{json}"), valid)
    } else {
        let (body, valid) = match explainer.explain(bytes) {
            Ok(text) => (text, true),
            Err(e) => (format!("  rejected: {e}\n"), false),
        };
        (writeln!(out, "{heading}\n{body}"), valid)
    };
    if !valid && *code == PASSED {
        *code = FAILED;
    }
    written.is_ok()
}

/// The help of `--protocol`: every family id and built-in dictionary name of `registry`,
/// so the list is never behind the families this build has.
pub fn protocol_help(registry: &Registry) -> String {
    let quoted = |names: Vec<&str>| {
        names
            .iter()
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "The drive family whose protocol the telegrams are in: a family id ({}; `-` and `_` \
         alike) or a built-in dictionary name ({}) [default: the drive a `--trace` file's \
         header names (a CAN trace's: in FILE.meta), else the family of the --drive \
         dictionary; a candump log without a header: the CAN family]",
        quoted(registry.families().map(|f| f.id()).collect()),
        quoted(registry.dictionary_names()),
    )
}

/// The family `--protocol` names (a family id such as `ct-ansi`, also in its former
/// spelling `ct_ansi`, or a built-in dictionary such as `ct-unidrive-sp`) and the dictionary whose names the
/// explanation uses: the --drive dictionary when it is of that family, else the family's
/// own. On failure, the text to print.
fn protocol_and_names(
    registry: &Registry,
    args: &DecodeArgs,
    recorded: Option<&DictionaryArgs>,
) -> Result<(Arc<dyn Family>, Arc<Dictionary>), RunError> {
    let Some(protocol) = args.protocol.as_deref() else {
        let names = recorded.unwrap_or(&args.dictionary).load_for(registry, None)?;
        let family = registry
            .family(names.family())
            .map_err(|e| RunError::Invalid(format!("error: {e}\n")))?;
        return Ok((family, names));
    };
    let (family, dictionary) = match registry.family(protocol) {
        Ok(f) => (f, None),
        Err(e) => match registry.dictionary(protocol) {
            Ok((f, d)) => (f, Some(d.name)),
            Err(_) => return Err(RunError::Invalid(format!("error: {e}\n"))),
        },
    };
    let mut wanted = args.dictionary.clone();
    match dictionary {
        Some(name) => wanted.name = name.to_string(),
        None => {
            let given_fits = registry
                .dictionary(&wanted.name)
                .is_ok_and(|(f, _)| f.id() == family.id());
            if !given_fits {
                let first = family.dictionaries().first().map(|d| d.name);
                wanted.name = first.unwrap_or_default().to_string();
            }
        }
    }
    let names = wanted.load_for(registry, None)?;
    Ok((family, names))
}

/// The drive the input itself names when neither --protocol nor --drive does: the first
/// trace header found, else for a candump log without one (standard input; a log from
/// another tool) the one CAN family. Says so when the flags contradict a header.
fn recorded_drive(
    registry: &Registry,
    args: &DecodeArgs,
    headers: &[(String, TraceHeader)],
    lines: &[(String, String)],
) -> Option<DictionaryArgs> {
    let flags = args.protocol.is_some() || args.dictionary.name != DEFAULT_DICTIONARY;
    let family_of = |drive: &str| registry.dictionary(drive).map(|(f, _)| f.id()).ok();
    for (source, header) in headers.iter().skip(1) {
        if header.drive != headers[0].1.drive {
            eprintln!(
                "note: {source} is a trace of --drive {}, {} of --drive {}; all is explained as one",
                header.drive, headers[0].0, headers[0].1.drive
            );
        }
    }
    if flags {
        if let Some((source, header)) = headers.first() {
            let given = args.protocol.as_deref().unwrap_or(&args.dictionary.name);
            let given_family = registry
                .family(given)
                .map(|f| f.id())
                .ok()
                .or_else(|| family_of(given));
            if given_family != family_of(&header.drive) {
                eprintln!(
                    "note: {source} is a trace of --drive {}, but its telegrams are explained as {given} as given; leave out --protocol and --drive to explain them as recorded",
                    header.drive
                );
            }
        }
        return None;
    }
    let mut wanted = args.dictionary.clone();
    if let Some((_, header)) = headers.first() {
        wanted.name.clone_from(&header.drive);
        wanted.extra.extend(header.dictionaries.iter().cloned());
        // The rpm as the run showed them: for the motor's pole pairs it recorded.
        let recorded = |n: u32| (n.to_string(), format!("the trace's `pole pairs: {n}`"));
        wanted.pole_pairs = header.pole_pairs.map(recorded).or(wanted.pole_pairs);
        return Some(wanted);
    }
    let first = lines
        .iter()
        .map(|(_, l)| l.trim())
        .find(|l| !l.is_empty() && !l.starts_with('#'))?;
    let candump_log = first.starts_with('(') && crate::bus::CanFrame::parse_text(first).is_ok();
    // A candump log without its notes file names no drive: it is read as the first CAN
    // family's (the registry's order; `--drive`/`--protocol` choose another).
    let first_can = registry
        .families()
        .find(|f| f.bus_kind() == crate::bus::BusKind::Frames)?;
    let dictionary = first_can.dictionaries().first()?;
    candump_log.then(|| {
        wanted.name = dictionary.name.to_string();
        wanted
    })
}

/// The header of a trace file: at its top, or for a CAN trace in its notes file.
fn trace_header_of(path: &std::path::Path, lines: &[String]) -> Option<TraceHeader> {
    TraceHeader::read(lines.iter().map(String::as_str)).or_else(|| {
        let notes = read_lines(&trace_notes_path(path)).ok()?;
        TraceHeader::read(notes.iter().map(String::as_str))
    })
}

/// A capture file that cannot be decoded as a whole.
#[derive(Debug, thiserror::Error)]
enum CaptureError {
    #[error("cannot read {}: {source}", path.display())]
    Unreadable {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    #[error("{} is larger than 64 MiB; split it, or pipe it: drivescript decode < FILE", path.display())]
    TooLarge { path: std::path::PathBuf },
}

/// The lines of a capture file, at most 64 MiB of it; the error says what to do.
fn read_lines(path: &std::path::Path) -> Result<Vec<String>, CaptureError> {
    use std::io::Read;
    const MAX: u64 = 64 << 20;
    let unreadable = |source| CaptureError::Unreadable {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(unreadable)?;
    let mut bytes = Vec::new();
    file.take(MAX + 1).read_to_end(&mut bytes).map_err(unreadable)?;
    if bytes.len() as u64 > MAX {
        return Err(CaptureError::TooLarge {
            path: path.to_path_buf(),
        });
    }
    // Captures from other tools may hold any bytes in comments; the hex is ASCII.
    Ok(String::from_utf8_lossy(&bytes)
        .lines()
        .map(str::to_string)
        .collect())
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
