//! The EDS reader against python-canopen's `import_od`, field by field, on vendors' own
//! files (Faulhaber, maxon, SYS TEC; `tests/eds/vendor/README.md` says where each comes
//! from) and the test files: every variable python-canopen sees is an object of
//! `drivescript objects --json` (or listed as one drivescript cannot access) with the same
//! data type, access, limits, default and name, and where the built-in `canopen`
//! dictionary has the object too, the file's limits are the ones in force.

use crate::support::{cli, python_imports, succeeded};
use serde_json::Value;
use std::collections::HashMap;
use std::process::Command;

const FILES: &[&str] = &[
    "vendor/faulhaber-mcbl3006-trimmed.eds",
    "vendor/maxon-epos2-347717-trimmed.eds",
    "vendor/systec-iox4-8ai-trimmed.eds",
    "servo-limits.eds",
    "cia402-wide-integers.dcf",
    "cia402-wide-types.dcf",
];

fn path(file: &str) -> String {
    format!("{}/tests/eds/{file}", env!("CARGO_MANIFEST_DIR"))
}

/// python-canopen's variables of `file`, or `None` where python-canopen is not installed.
fn python_view(file: &str) -> Option<Vec<Value>> {
    let missing = "python3 with python-canopen (pip install canopen) is not installed: EDS files are not compared with it";
    if !python_imports("canopen", missing) {
        return None;
    }
    let out = succeeded(
        Command::new("python3")
            .arg(path("python_canopen_view.py"))
            .arg(path(file)),
        &format!("the python-canopen view of {file}"),
    );
    let view: Value = serde_json::from_slice(&out.stdout).expect("JSON from the view script");
    Some(view["variables"].as_array().expect("variables").clone())
}

/// `drivescript objects --json` for the built-in canopen dictionary and `file`, by
/// (index, subindex) of the file's entry.
fn our_view(file: &str) -> HashMap<(u64, u64), Value> {
    let out = cli(
        &[
            "objects",
            "--drive",
            "canopen",
            "--dictionary",
            &path(file),
            "--json",
        ],
        0,
    );
    let rows: Vec<Value> = serde_json::from_str(&out.stdout).expect("JSON rows");
    rows.into_iter()
        .filter(|r| r["file"].is_object())
        .map(|r| {
            let f = &r["file"];
            ((f["index"].as_u64().unwrap(), f["subindex"].as_u64().unwrap()), r)
        })
        .collect()
}

/// A default as python-canopen reads it: integers (hex, `$NODEID` resolved), floats or text.
fn default_of(text: &str, node_id: Option<i64>) -> Value {
    let t: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    let upper = t.to_ascii_uppercase();
    let int = |s: &str| -> Option<i64> {
        match s.strip_prefix("0X") {
            Some(hex) => i64::from_str_radix(hex, 16)
                .ok()
                .or_else(|| u64::from_str_radix(hex, 16).ok().map(|v| v as i64)),
            None => s.parse().ok(),
        }
    };
    if upper.contains("$NODEID") {
        let rest = upper.replace("$NODEID", "").replace('+', "");
        let n = if rest.is_empty() { Some(0) } else { int(&rest) };
        return match (n, node_id) {
            (Some(n), Some(id)) => Value::from(n + id),
            _ => Value::Null,
        };
    }
    match (int(&upper), t.parse::<f64>()) {
        (Some(n), _) => Value::from(n),
        (None, Ok(x)) => Value::from(x),
        (None, Err(_)) => Value::from(text.trim_matches('"')),
    }
}

fn same_number(ours: &Value, theirs: &Value) -> bool {
    match (ours.as_f64(), theirs.as_f64()) {
        (Some(a), Some(b)) => a == b || (a - b).abs() <= 1e-9 * b.abs(),
        (None, None) => true,
        _ => false,
    }
}

#[test]
fn every_variable_python_canopen_reads_is_read_alike() {
    for file in FILES {
        let Some(theirs) = python_view(file) else {
            return;
        };
        let ours = our_view(file);
        let node_id = file.ends_with(".dcf").then_some(1);
        let mut compared = 0;
        // `[DummyUsage]` entries (0x0001..0x0007) are python-canopen's stand-ins for PDO
        // mapping gaps, not objects a node answers SDO for; drivescript lists none.
        let theirs: Vec<&Value> = theirs
            .iter()
            .filter(|v| v["index"].as_u64().is_some_and(|i| i >= 0x1000))
            .collect();
        for v in &theirs {
            let key = (v["index"].as_u64().unwrap(), v["subindex"].as_u64().unwrap());
            let at = format!("{file} 0x{:04X}/{}", key.0, key.1);
            let row = ours.get(&key).unwrap_or_else(|| panic!("{at}: not in `objects`"));
            let f = &row["file"];
            assert_eq!(f["type_code"], v["data_type"], "{at}: data type");
            assert_eq!(f["access"], v["access"], "{at}: access");
            // python-canopen reads limits with int(text, 0), so a REAL's `LowLimit=0.0` is
            // dropped there; drivescript keeps it.
            let real = [0x8, 0x11].contains(&v["data_type"].as_u64().unwrap_or(0));
            for (mine, theirs) in [(&f["low"], &v["min"]), (&f["high"], &v["max"])] {
                let dropped_there = real && theirs.is_null() && mine.is_number();
                assert!(
                    same_number(mine, theirs) || dropped_there,
                    "{at}: limit {mine} vs {theirs}"
                );
            }
            let name = match v["parent"].as_str() {
                Some(parent) => format!("{parent}/{}", v["name"].as_str().unwrap()),
                None => v["name"].as_str().unwrap().to_string(),
            };
            assert_eq!(f["name"].as_str(), Some(name.as_str()), "{at}: name");
            if !v["default"].is_null() {
                let mine = f["default"].as_str().map(|d| default_of(d, node_id));
                let matches = match &mine {
                    Some(m) if m.is_number() => same_number(m, &v["default"]),
                    // An OCTET_STRING's hex digits in either case.
                    Some(m) => {
                        m.as_str().map(str::to_ascii_lowercase)
                            == v["default"].as_str().map(str::to_ascii_lowercase)
                    }
                    None => false,
                };
                assert!(matches, "{at}: default {:?} vs {}", f["default"], v["default"]);
            }
            // Where the file's limits apply, they are the object's limits (times its scale).
            if let (Some(lo), Some(hi), true) =
                (v["min"].as_f64(), v["max"].as_f64(), row["accessible"] == true)
            {
                if lo <= hi {
                    let scale = row["scale"].as_f64().unwrap();
                    assert!(
                        same_number(&row["min"], &Value::from(lo * scale)),
                        "{at}: min {}",
                        row["min"]
                    );
                    assert!(
                        same_number(&row["max"], &Value::from(hi * scale)),
                        "{at}: max {}",
                        row["max"]
                    );
                }
            }
            compared += 1;
        }
        assert_eq!(
            ours.len(),
            theirs.len(),
            "{file}: objects python-canopen does not have"
        );
        assert!(compared > 0, "{file}: nothing compared");
    }
}
