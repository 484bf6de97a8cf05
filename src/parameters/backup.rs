//! Taking a backup: every readable object the dictionary marks as a parameter, read from the
//! drive in dictionary order, an unreadable one recorded with its error; the identity
//! objects beside them. Reads only; must not write to the drive.

use super::parameter_file::{ParameterFile, Reading, SavedObject};
use crate::dictionary::ObjectDef;
use crate::drive::Drive;

/// Names of the objects that identify a drive (its firmware or ident string), where the
/// dictionary has them: a restore onto a drive that answers differently needs `--force`.
pub const IDENTITY_OBJECTS: [&str; 3] = ["ident", "firmware_version", "product_type"];

/// Where the backup came from, for its header.
pub struct Origin {
    pub address: String,
    pub date: String,
    pub tool: String,
}

/// The objects a backup saves, in dictionary order.
pub fn parameters(drive: &Drive) -> Vec<ObjectDef> {
    drive
        .dictionary()
        .objects()
        .filter(|o| o.parameter && o.readable())
        .cloned()
        .collect()
}

/// Reads the parameters; `progress(done, total, name)` is called before each read, and
/// `keep_going()` is asked between reads (a stop request ends the backup early, and the
/// caller reports it as incomplete).
pub fn take(
    drive: &mut Drive,
    origin: Origin,
    progress: &mut dyn FnMut(usize, usize, &str),
    keep_going: &dyn Fn() -> bool,
) -> (ParameterFile, bool) {
    let defs = parameters(drive);
    let mut identity = Vec::new();
    for name in IDENTITY_OBJECTS {
        if drive.dictionary().get(name).is_some_and(|o| o.readable()) {
            if let Ok(v) = drive.read(name) {
                identity.push((
                    name.to_string(),
                    v.text().map_or_else(|| v.to_string(), str::to_string),
                ));
            }
        }
    }
    let mut objects = Vec::with_capacity(defs.len());
    let mut complete = true;
    for (i, def) in defs.iter().enumerate() {
        if !keep_going() {
            complete = false;
            break;
        }
        progress(i, defs.len(), &def.name);
        let reading = match drive.read(&def.name) {
            Ok(v) => Reading::Value {
                shown: v.to_string(),
                raw: raw_text(&v.raw),
            },
            Err(e) => Reading::Error(e.to_string()),
        };
        objects.push(SavedObject {
            name: def.name.clone(),
            address: def.address.to_string(),
            reading,
        });
    }
    let file = ParameterFile {
        family: drive.dictionary().family().to_string(),
        dictionary: drive.dictionary().name().to_string(),
        address: origin.address,
        identity,
        date: origin.date,
        tool: origin.tool,
        objects,
    };
    (file, complete)
}

/// The raw value as a backup stores it: counts and exact decimals as digits, text as is.
pub fn raw_text(raw: &crate::dictionary::RawValue) -> String {
    match raw {
        crate::dictionary::RawValue::Text(t) => t.clone(),
        other => other.to_string(),
    }
}
