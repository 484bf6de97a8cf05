//! `drivescript objects`: a dictionary's objects as a table or JSON, with where a
//! device's own file (EDS/DCF) replaced a built-in entry's fields and the file's objects
//! drivescript cannot access. Parses arguments and prints; the dictionary decides.

use super::object_commands::{load_dictionary, shown_address};
use crate::dictionary::{FileEntry, ObjectDef};
use crate::family::Registry;
use crate::run::{ConnectionArgs, DictionaryArgs};
use crate::run::{COMMUNICATION, PASSED};
use clap::Args;
use serde_json::json;

#[derive(Debug, Args)]
/// List the objects of a dictionary: names, addresses, units, limits
///
/// List the objects of a dictionary: names, aliases, address, type, unit, access, limits.
/// `drivescript objects speed` lists those whose name, alias or description has `speed`.
pub struct ObjectsArgs {
    /// Only objects whose name, alias or description contains this text.
    filter: Option<String>,
    #[arg(long)]
    json: bool,
    /// Also read each object's minimum and maximum from the drive (families whose drives
    /// report them; without --port/--tcp the simulated drive's).
    #[arg(long)]
    from_drive: bool,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

pub fn objects(args: &ObjectsArgs, registry: &Registry) -> i32 {
    let dictionary = match load_dictionary(&args.dictionary.with_pole_pairs_of(&args.connection), registry) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let family = registry.family(dictionary.family()).ok();
    // Once, before the list: what was read leniently (a file in Windows-1252, an object
    // list naming a missing section), each at its line.
    for note in dictionary.notes() {
        eprintln!("note: {}", note.located());
    }
    let list: Vec<&ObjectDef> = match &args.filter {
        Some(f) => dictionary.filter(f),
        None => dictionary.objects().collect(),
    };
    let needle = args.filter.as_deref().unwrap_or("").trim().to_lowercase();
    let not_accessible: Vec<&FileEntry> = dictionary
        .not_accessible()
        .iter()
        .filter(|f| needle.is_empty() || f.name.to_lowercase().contains(&needle))
        .collect();
    let drive_limits = if args.from_drive {
        let names: Vec<String> = list.iter().map(|d| d.name.clone()).collect();
        match crate::run::drive_limits::read_all(
            registry,
            &names,
            dictionary.clone(),
            &args.connection,
            &mut std::io::stderr(),
        ) {
            Ok((port, limits)) => Some((port, limits)),
            Err(e) => {
                eprintln!("{e}");
                return COMMUNICATION;
            }
        }
    } else {
        None
    };
    let from_drive = |name: &str| drive_limits.as_ref().and_then(|(_, l)| l.get(name).cloned());
    if args.json {
        let rows: Vec<_> = list
            .iter()
            .map(|d| {
                json!({
                    "drive_limits": from_drive(&d.name),
                    "name": d.name, "aliases": d.aliases, "address": shown_address(&family, &d.address),
                    "type": d.data_type.to_string(), "unit": d.unit.map(|u| u.symbol()), "scale": d.scale,
                    "access": d.access.id(), "min": d.min, "max": d.max, "pole_pairs": d.pole_pairs,
                    "bench_limit": d.bench.as_ref().map(|b| b.origin.clone()),
                    "description": d.description, "unconfirmed": d.unconfirmed,
                    "accessible": true, "file": d.file.as_deref().map(file_json),
                })
            })
            .chain(not_accessible.iter().map(|f| {
                json!({
                    "name": f.name, "address": shown_address(&family, &f.address),
                    "type": f.type_name, "accessible": false, "file": file_json(f),
                })
            }))
            .collect();
        println!("{}", serde_json::Value::Array(rows));
        return PASSED;
    }
    if list.is_empty() && not_accessible.is_empty() {
        eprintln!("no object of the {} dictionary matches", dictionary.name());
        return PASSED;
    }
    println!("{} — {} object(s)", dictionary.title(), list.len());
    if let Some((port, _)) = &drive_limits {
        println!("drive limits read from {port} (ON/OX or the family's own commands)");
    }
    if let Some(pairs) = dictionary.pole_pairs() {
        println!(
            "rpm are for a motor with {} pole pair(s) ({}); rpm = Hz × 60 / pole pairs, so Hz may be written too; another motor: --link-option pole-pairs=N",
            pairs.count, pairs.origin
        );
    }
    if let Some(limits) = dictionary.bench_limits() {
        println!(
            "bench limits {} ({}); limits marked (bench) are capped by it",
            limits.summary(),
            limits.source()
        );
    }
    let mut rows = Vec::new();
    // A row of drive limits follows its object's row, in the limits column.
    let mut drive_rows = Vec::new();
    for d in list {
        let limits = match (d.min, d.max) {
            (Some(lo), Some(hi)) => {
                format!("{} .. {}", crate::session::number(lo), crate::session::number(hi))
            }
            (Some(lo), None) => format!(">= {}", crate::session::number(lo)),
            (None, Some(hi)) => format!("<= {}", crate::session::number(hi)),
            (None, None) => String::new(),
        };
        let limits = match &d.bench {
            Some(_) => format!("{limits} (bench)"),
            None => limits,
        };
        let flag = if d.unconfirmed.is_some() {
            " (unconfirmed)"
        } else {
            ""
        };
        rows.push(vec![
            d.name.clone(),
            shown_address(&family, &d.address),
            d.data_type.to_string(),
            d.unit.map(|u| u.symbol()).unwrap_or("").to_string(),
            d.access.id().to_string(),
            limits,
            format!("{}{flag}", d.aliases.join(", ")),
        ]);
        let mut under = Vec::new();
        under.extend(from_drive(&d.name).map(|l| format!("drive limits: {l}")));
        under.extend(d.file.as_ref().and_then(|f| f.overrides_line()));
        drive_rows.push(under);
    }
    let header = ["name", "address", "type", "unit", "access", "limits", "aliases"];
    let lines = super::text_table::table_lines(&header, &rows);
    for (i, line) in lines.iter().enumerate() {
        println!("{}", line.trim_end());
        for l in i
            .checked_sub(1)
            .and_then(|r| drive_rows.get(r))
            .into_iter()
            .flatten()
        {
            println!("{}{l}", " ".repeat(header_offset(&lines[0], "limits")));
        }
    }
    if !not_accessible.is_empty() {
        println!(
            "{} object(s) of the device's file in types drivescript cannot access (read them with a CANopen tool):",
            not_accessible.len()
        );
        for f in not_accessible {
            println!(
                "  {}  {}  {}  ({}:{})",
                shown_address(&family, &f.address),
                f.type_name,
                f.name,
                f.file,
                f.line
            );
        }
    }
    PASSED
}

/// Where `column` starts in a table's header line.
fn header_offset(header: &str, column: &str) -> usize {
    header.find(column).map_or(0, |i| header[..i].chars().count())
}

/// What the device's file says of an object, raw as written there.
fn file_json(f: &FileEntry) -> serde_json::Value {
    json!({
        "path": f.file, "line": f.line, "name": f.name, "type_code": f.type_code,
        "index": f.address.index(), "subindex": f.address.subindex(),
        "type": f.type_name, "access": f.access, "low": f.low, "high": f.high,
        "default": f.default,
        "overrides": f.overrides.iter().map(|o| json!({ "field": o.field, "file": o.file, "built_in": o.built_in })).collect::<Vec<_>>(),
    })
}
