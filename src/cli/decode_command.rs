//! `drivescript decode`: explains captured telegrams, one per argument or per input line.

use super::{FAILED, INVALID, PASSED};
use crate::hex::parse_hex;
use crate::protocol::sd2::{explain, to_json, ObjectNames, Telegram};
use clap::{Args, ValueEnum};
use std::io::{BufRead, Write};

#[derive(Debug, Args)]
/// Explain captured telegrams: direction, addresses, command, object, data, error text,
/// control and status word bits. Hex as `00 0b 02 ...`, `000b02...` or `0x00 0x0b ...`;
/// one telegram per argument, or per line on standard input when no argument is given.
pub struct DecodeArgs {
    /// The protocol the telegrams are in.
    #[arg(long, value_enum, default_value_t = Protocol::Sd2)]
    protocol: Protocol,
    /// One JSON object per telegram (the keys of shared/vectors/sd2-dnc.yaml);
    /// a rejected telegram is {"reject": "<reason>"}.
    #[arg(long)]
    json: bool,
    /// Telegrams in hex, one per argument.
    hex: Vec<String>,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Protocol {
    /// Sieb & Meyer SD2 / SD2S DNC (object access and the 8-byte cyclic telegram).
    Sd2,
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
    } else {
        args.hex
            .iter()
            .enumerate()
            .map(|(i, h)| (format!("argument {}", i + 1), h.clone()))
            .collect()
    };
    let names = BuiltinNames;
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut code = PASSED;
    let mut last_request: Option<Telegram> = None;
    for (place, line) in &lines {
        let text = line.trim();
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
        let result = Telegram::decode(&bytes);
        if result.is_err() && code == PASSED {
            code = FAILED;
        }
        let written = if args.json {
            writeln!(out, "{}", to_json(&result))
        } else {
            let body = match &result {
                Ok(t) => explain(t, &bytes, last_request.as_ref(), &names),
                Err(e) => format!("  rejected: {e}\n"),
            };
            writeln!(out, "{}\n{body}", crate::hex::to_hex(&bytes))
        };
        if written.is_err() {
            // Standard output closed (e.g. piped into `head`): nothing more to say.
            return code;
        }
        if let Ok(t) = result {
            if !t.is_reply() {
                last_request = Some(t);
            }
        }
    }
    code
}

/// Object names from the SD2 sources (`shared/protocols/sd2-dnc.md`), used until a
/// dictionary is loaded.
struct BuiltinNames;

const SD2_OBJECTS: &[(u16, &str)] = &[
    (22, "DEVICE_PARAMETER_IDENT_STRING"),
    (33, "DC bus voltage, actual"),
    (39, "POWER_STAGE_LOAD_ACTUAL"),
    (67, "DEV_CTRL_STATUS_WORD"),
    (68, "DEV_CTRL_CONTROL_WORD"),
    (168, "actual speed, second source"),
    (352, "PARAMETER_SET"),
    (395, "SPG_TARGET_VELOCITY_VL_UUNIT"),
    (398, "VCTRL_VELOCITY_ACTUAL_VALUE_UUNIT"),
];

impl ObjectNames for BuiltinNames {
    fn object_name(&self, index: u16, _subindex: u32) -> Option<String> {
        SD2_OBJECTS
            .iter()
            .find(|(i, _)| *i == index)
            .map(|(_, n)| n.to_string())
    }
    fn object_value(&self, _index: u16, _subindex: u32, _data: &[u8]) -> Option<String> {
        None
    }
    fn is_control_word(&self, index: u16) -> bool {
        index == 68
    }
    fn is_status_word(&self, index: u16) -> bool {
        index == 67
    }
}
