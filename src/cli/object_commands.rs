//! One-off object access: `read`, `write`, `state`, `ports` (`objects` is in
//! `objects_command`).

use crate::dictionary::{Address, DataType, Dictionary, ObjectDef, Quantity, Unit, ValueError};
use crate::drive::device_control::{status_word_bits, DeviceState};
use crate::drive::DriveError;
use crate::drive::WriteOutcome;
use crate::family::{Family, Registry};
use crate::run::{another_family, ConnectionArgs};
use crate::run::{open_drive, DictionaryArgs, OpenDrive};
use crate::run::{COMMUNICATION, INVALID, PASSED};
use clap::Args;
use serde_json::json;
use std::sync::Arc;

#[derive(Debug, Args)]
/// Read objects by name (or alias) and show their values with units.
pub struct ReadArgs {
    /// Object names or aliases, e.g. status_word speed_actual.
    #[arg(required = true, value_name = "NAME")]
    names: Vec<String>,
    /// One JSON array of {object, value, unit, raw}.
    #[arg(long)]
    json: bool,
    /// The data type of objects named in the family's own notation (`#5.04`, `0x0011`,
    /// `C00061`) rather than from the dictionary: u8, i8, u16, i16, u32, i32, string(N).
    #[arg(long = "type", value_name = "TYPE", value_parser = DataType::parse)]
    data_type: Option<DataType>,
    /// Each value also in this unit: `--in krpm`, or `--in Hz` for an inverter's rpm
    /// where the dictionary knows the motor's pole pairs.
    #[arg(long = "in", value_name = "UNIT", value_parser = parse_unit)]
    in_unit: Option<Unit>,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

fn parse_unit(text: &str) -> Result<Unit, ValueError> {
    Unit::parse(text)
}

#[derive(Debug, Args)]
/// Write one object, e.g. `write speed_setpoint 6000rpm`
///
/// Write one object, e.g. `write speed_setpoint 6000rpm`. Values outside the object's
/// limits, and read-only objects, are refused before anything is sent.
pub struct WriteArgs {
    #[arg(value_name = "NAME")]
    name: String,
    /// The value with its unit (`6000rpm`, `6000 rpm`, `1.5 A`); a bare number is in the
    /// object's own unit.
    #[arg(value_name = "VALUE", allow_hyphen_values = true)]
    value: String,
    /// The data type of an object named in the family's own notation rather than from
    /// the dictionary: u8, i8, u16, i16, u32, i32, string(N).
    #[arg(long = "type", value_name = "TYPE", value_parser = DataType::parse)]
    data_type: Option<DataType>,
    /// The unit, when written apart from the value: `write speed_setpoint 6000 rpm`.
    #[arg(value_name = "UNIT")]
    unit: Option<String>,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

#[derive(Debug, Args)]
/// Read the status word and show the device-control state it means.
pub struct StateArgs {
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

#[derive(Debug, Args)]
/// List this machine's serial ports, with USB IDs where there are some.
pub struct PortsArgs {
    #[arg(long)]
    json: bool,
}

/// The dictionary, or the exit code after printing why not.
pub(super) fn load_dictionary(args: &DictionaryArgs, registry: &Registry) -> Result<Arc<Dictionary>, i32> {
    args.load_for(registry, None).map_err(|text| {
        eprint!("{text}");
        INVALID
    })
}

/// The dictionary with an object added for each of `names` it does not list but the
/// family reads as an address in its own notation (`read '#5.04'`); a name that is
/// neither stays unknown, for the caller's did-you-mean message.
fn with_raw_objects(
    registry: &Registry,
    dictionary: Arc<Dictionary>,
    names: &[String],
    data_type: Option<DataType>,
) -> Result<Arc<Dictionary>, i32> {
    let Ok(family) = registry.family(dictionary.family()) else {
        return Ok(dictionary);
    };
    let mut extended = dictionary;
    for name in names {
        if extended.get(name).is_some() {
            continue;
        }
        match family.raw_object(name, data_type) {
            None => {}
            Some(Ok(def)) => extended = Arc::new(extended.with_raw_object(def)),
            Some(Err(text)) => {
                eprintln!("error: {name}: {text}; nothing was sent");
                return Err(INVALID);
            }
        }
    }
    Ok(extended)
}

/// An address in the family's own notation where it has one (`0x0011`, `TYPE?`).
pub(super) fn shown_address(family: &Option<Arc<dyn Family>>, address: &Address) -> String {
    family
        .as_ref()
        .map_or_else(|| address.to_string(), |f| f.show_address(address))
}

/// The drive, or the exit code after printing why not. Says so when it is the simulated
/// drive, whose state a one-off command cannot keep.
fn open(
    registry: &Registry,
    connection: &ConnectionArgs,
    dictionary: Arc<Dictionary>,
) -> Result<OpenDrive, i32> {
    let open = open_drive(registry, connection, dictionary, true, None, None).map_err(|text| {
        eprintln!("{text}");
        COMMUNICATION
    })?;
    if open.simulator.is_some() {
        eprintln!(
            "using {}; its state is not kept between commands",
            open.description
        );
    }
    Ok(open)
}

/// Says which side of a number's range the dictionary does not give, so that a value
/// checked only against the object's type is not taken for one checked against the
/// drive's limits; `None` for text and for an object with both limits.
fn unchecked_range(def: &ObjectDef) -> Option<String> {
    let unit = def.unit.map(|u| format!(" {}", u.symbol())).unwrap_or_default();
    let limit = |v: f64| format!("{}{unit}", crate::session::number(v));
    let text = match (def.min, def.max) {
        _ if !def.data_type.is_integer() => return None,
        (Some(_), Some(_)) => return None,
        (None, None) => format!(
            "the dictionary gives no range for it, so the value was checked against its type ({}) only, not against the drive's range",
            def.data_type
        ),
        (None, Some(hi)) => format!(
            "the dictionary gives its maximum ({}) but no minimum, so the value was not checked against the drive's lower limit",
            limit(hi)
        ),
        (Some(lo), None) => format!(
            "the dictionary gives its minimum ({}) but no maximum, so the value was not checked against the drive's upper limit",
            limit(lo)
        ),
    };
    Some(format!(
        "note: {}: {text}; the drive may still refuse it",
        def.name
    ))
}

/// Prints a drive error, with the likely wrong `--drive` when the drive did not answer
/// (a drive of another family stays silent), and gives its exit code.
fn failed(e: &DriveError, registry: &Registry, open: &OpenDrive) -> i32 {
    match e {
        DriveError::Access(a) if a.is_unsent() => eprintln!("error: {e}; nothing was sent"),
        _ => eprintln!("error: {e}"),
    }
    if matches!(e, DriveError::Access(a) if a.is_no_reply()) {
        eprintln!("help: {}", another_family(registry, open.drive.dictionary()));
    }
    drive_error_code(e)
}

/// Exit code of a drive error: refused before sending → 2, otherwise 3.
fn drive_error_code(e: &DriveError) -> i32 {
    match e {
        DriveError::UnknownObject { .. }
        | DriveError::ReadOnly { .. }
        | DriveError::WriteOnly { .. }
        | DriveError::Value(_) => INVALID,
        DriveError::Access(a) if a.is_unsent() => INVALID,
        _ => COMMUNICATION,
    }
}

pub fn read(args: &ReadArgs, registry: &Registry) -> i32 {
    let dictionary = match load_dictionary(&args.dictionary.with_pole_pairs_of(&args.connection), registry)
        .and_then(|d| with_raw_objects(registry, d, &args.names, args.data_type))
    {
        Ok(d) => d,
        Err(code) => return code,
    };
    // Every name is checked before the port is opened, so a typo sends nothing.
    for name in &args.names {
        if let Err(e) = check_readable(&dictionary, name) {
            eprintln!("error: {e}");
            return INVALID;
        }
        let def = dictionary.lookup(name).ok();
        if let Some(Err(e)) = args.in_unit.zip(def).map(|(unit, def)| def.factor_to(unit)) {
            eprintln!("error: --in: {e}");
            return INVALID;
        }
    }
    // The value in the unit `--in` asks for, after the object's own.
    let also = |d: &ObjectDef, v: &crate::dictionary::Value| -> Option<(f64, Unit)> {
        let unit = args.in_unit?;
        Some((v.number()? * d.factor_to(unit).ok()?, unit))
    };
    let dictionary_family = registry.family(dictionary.family()).ok();
    let mut open = match open(registry, &args.connection, dictionary) {
        Ok(o) => o,
        Err(code) => return code,
    };
    let mut rows = Vec::new();
    for name in &args.names {
        let def = match open.drive.object(name) {
            Ok(d) => d.clone(),
            Err(e) => {
                eprintln!("error: {e}");
                return INVALID;
            }
        };
        match open.drive.read(name) {
            Ok(v) => rows.push((def, v)),
            Err(e) => return failed(&e, registry, &open),
        }
    }
    if args.json {
        let list: Vec<_> = rows
            .iter()
            .map(|(d, v)| {
                // A whole number beyond a float's precision as the JSON integer it is.
                let exact = v
                    .quantity
                    .filter(Quantity::beyond_float)
                    .and_then(|q| q.whole())
                    .and_then(|n| i64::try_from(n).ok());
                let value = match (exact, v.number()) {
                    (Some(n), _) => json!(n),
                    (None, Some(n)) => json!(n),
                    (None, None) => json!(v.text().unwrap_or_default()),
                };
                let mut row = json!({ "object": d.name, "value": value, "unit": d.unit.map(|u| u.symbol()), "raw": v.raw.to_string() });
                if let Some((n, unit)) = also(d, v) {
                    row["in"] = json!({ "value": n, "unit": unit.symbol() });
                }
                row
            })
            .collect();
        println!("{}", serde_json::Value::Array(list));
    } else {
        let width = rows
            .iter()
            .map(|(d, _)| d.name.chars().count())
            .max()
            .unwrap_or(6)
            .clamp(6, super::MAX_ALIGNED_WIDTH);
        println!("{:<width$}  {:<18}  {:<12}  address", "object", "value", "raw");
        for (d, v) in &rows {
            println!(
                "{:<width$}  {:<18}  {:<12}  {}",
                d.name,
                match also(d, v) {
                    Some((n, unit)) => format!("{v} ({} {unit})", crate::session::number(n)),
                    None => v.to_string(),
                },
                v.raw.to_string(),
                shown_address(&dictionary_family, &d.address)
            );
        }
    }
    PASSED
}

/// `100 Hz (3000 rpm)`: a value written in another unit than its object's, with what it is
/// in the object's unit (for an inverter, with the motor's pole pairs).
fn check_readable(dictionary: &Dictionary, name: &str) -> Result<(), DriveError> {
    let def = dictionary.lookup(name).map_err(|e| DriveError::UnknownObject {
        name: name.to_string(),
        suggestions: e.suggestions.clone(),
        drive: Some(e.dictionary.clone()),
    })?;
    if !def.readable() {
        return Err(DriveError::WriteOnly {
            object: def.name.clone(),
        });
    }
    Ok(())
}

pub fn write(args: &WriteArgs, registry: &Registry) -> i32 {
    // `6000 rpm` as two arguments is the same value as `6000rpm`.
    let value = match &args.unit {
        Some(unit) => format!("{} {unit}", args.value),
        None => args.value.clone(),
    };
    let names = std::slice::from_ref(&args.name);
    let mut raw = false;
    let dictionary = match load_dictionary(&args.dictionary.with_pole_pairs_of(&args.connection), registry)
        .and_then(|d| {
            raw = d.get(&args.name).is_none();
            with_raw_objects(registry, d, names, args.data_type)
        }) {
        Ok(d) => d,
        Err(code) => return code,
    };
    // Refusals happen before the port is opened: nothing is sent for a bad value.
    let def = match dictionary.lookup(&args.name) {
        Ok(d) => d.clone(),
        Err(e) => {
            eprintln!(
                "error: {}",
                DriveError::UnknownObject {
                    name: args.name.clone(),
                    suggestions: e.suggestions.clone(),
                    drive: Some(e.dictionary.clone()),
                }
            );
            return INVALID;
        }
    };
    if !def.writable() {
        eprintln!(
            "error: {}",
            DriveError::ReadOnly {
                object: def.name.clone()
            }
        );
        if raw && args.data_type.is_none() {
            // A family may read its own notation without a type but not write it.
            eprintln!("help: give the object's type with --type (u8, i8, u16, i16, u32, i32 or string(N)) to write an object the dictionary does not list");
        }
        return INVALID;
    }
    let is_text = !def.data_type.is_number();
    let checked = if is_text {
        def.text_to_raw(&value).map(|_| None)
    } else {
        Quantity::parse(&value).and_then(|q| def.to_raw(&q).map(|raw| Some((q, raw))))
    };
    let parsed = match checked {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}; nothing was sent");
            return INVALID;
        }
    };
    if let Some(note) = unchecked_range(&def) {
        println!("{note}");
    }
    let mut open = match open(registry, &args.connection, dictionary) {
        Ok(o) => o,
        Err(code) => return code,
    };
    let result = match &parsed {
        Some((q, _)) => open.drive.write(&def.name, q),
        None => open.drive.write_text(&def.name, &value),
    };
    match result {
        Ok(outcome) => {
            let (shown, raw) = match &parsed {
                Some((q, raw)) => super::held_value::held(&def, q, raw),
                None => (format!("\"{value}\""), String::new()),
            };
            match open.drive.group() {
                // No drive answers a group write: sent is all that is known.
                Some(group) => println!(
                    "{} = {shown}{raw} sent to {group}, not confirmed: no drive answers a write to a group address; read it back at one drive's address to check",
                    def.name
                ),
                None => println!("{} = {shown} written{raw}", def.name),
            }
            if let WriteOutcome::Limited(stored) = outcome {
                println!("warning: the drive limited the value; it stored raw {stored}");
            }
            PASSED
        }
        Err(e) => failed(&e, registry, &open),
    }
}

pub fn state(args: &StateArgs, registry: &Registry) -> i32 {
    let dictionary = match load_dictionary(&args.dictionary.with_pole_pairs_of(&args.connection), registry) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let mut open = match open(registry, &args.connection, dictionary) {
        Ok(o) => o,
        Err(code) => return code,
    };
    let status = match open.drive.status_word() {
        Ok(s) => s,
        Err(e) => return failed(&e, registry, &open),
    };
    let state = open.drive.profile().ok().and_then(|p| p.state_of(status));
    let drive_error = open.drive.drive_error();
    if args.json {
        println!(
            "{}",
            json!({ "status_word": status, "state": state.map(DeviceState::id), "drive_error": drive_error })
        );
    } else {
        let name = state
            .map(|s| s.to_string())
            .unwrap_or_else(|| "no state of the table matches".into());
        println!("status word 0x{status:04x}: {name}");
        // The CiA 402 bit names only where the profile is CiA 402's; other drives' bits
        // mean other things (the dictionary's description of the status word says what).
        let bits = match open.drive.profile() {
            Ok(p) if !p.is_complete() => (0..16)
                .filter(|b| status & (1 << b) != 0)
                .map(|b: u32| b.to_string())
                .collect(),
            _ => status_word_bits(status),
        };
        println!("  bits set: {}", bits.join(", "));
        if let Some(code) = drive_error {
            println!("  drive error: {code}{}", if code == 0 { " (none)" } else { "" });
        }
    }
    PASSED
}

pub fn ports(args: &PortsArgs) -> i32 {
    let ports = match crate::bus::list_ports() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return COMMUNICATION;
        }
    };
    if args.json {
        let rows: Vec<_> = ports
            .iter()
            .map(|p| {
                json!({
                    "name": p.name, "kind": p.kind, "latency_timer_ms": p.latency_timer_ms,
                    "usb": p.usb.as_ref().map(|u| json!({ "vid": format!("{:04x}", u.vid), "pid": format!("{:04x}", u.pid),
                        "serial_number": u.serial_number, "manufacturer": u.manufacturer, "product": u.product })),
                })
            })
            .collect();
        println!("{}", serde_json::Value::Array(rows));
        return PASSED;
    }
    if ports.is_empty() {
        let shows_up_as = if cfg!(windows) {
            "COM3 or the like, under Ports in the Device Manager"
        } else {
            "/dev/ttyUSB* or /dev/ttyACM*"
        };
        println!("no serial ports found (a USB adapter that is plugged in shows up as {shows_up_as})");
        return PASSED;
    }
    let root = crate::bus::sysfs_root();
    for p in ports {
        let line = match p.usb {
            Some(u) => format!(
                "{}  usb {:04x}:{:04x}  {} {}{}",
                p.name,
                u.vid,
                u.pid,
                u.manufacturer.unwrap_or_default(),
                u.product.unwrap_or_default(),
                u.serial_number
                    .map(|s| format!("  serial {s}"))
                    .unwrap_or_default()
            ),
            None => format!("{}  {}", p.name, p.kind),
        };
        println!("{line}");
        if let Some(ms) = p.latency_timer_ms {
            let path = crate::bus::latency_timer_path(&root, &p.name).unwrap_or_default();
            // Every reply waits out the timer: 16 ms allows some 30 exchanges a second.
            let advice = match ms {
                0 | 1 => String::new(),
                _ => format!(
                    "; every reply waits up to {ms} ms in the adapter, lower it with `echo 1 | sudo tee {}` (needs root; resets when the adapter is replugged)",
                    path.display()
                ),
            };
            println!("    latency timer {ms} ms{advice}");
        }
    }
    PASSED
}
