//! What the drive says it is, read once at the start for the run's report, certificate,
//! JUnit and store: each identity object its dictionary names (CANopen's device type
//! 0x1000 and identity object 0x1018, the versions; a Lenze code, a Unidrive menu 11
//! parameter, a 931's `TYPE?` and `VERSION?`), each value from its own reply. Best
//! effort: an object the drive does not answer is left out, never guessed. Recognising the
//! drive after a reopen stays with the one `ident` read (`restore_link.rs`): the stop's
//! path reads no more than it must.

use super::session::Session;
use crate::dictionary::Value;

/// The identity objects by the names dictionaries give them, with the label each value is
/// shown under, in the order a reader looks for them. An alias of one already read (a
/// dictionary whose `ident` is its firmware version) is read once.
const IDENTITY_OBJECTS: [(&str, &str); 12] = [
    ("device_type", "device type"),
    ("product_type", "product"),
    ("manufacturer_device_name", "device name"),
    ("vendor_id", "vendor"),
    ("product_code", "product code"),
    ("revision_number", "revision"),
    ("serial_number", "serial"),
    ("hardware_version", "hardware"),
    ("software_version", "software"),
    ("firmware_version", "firmware"),
    ("parameter_set_ident", "parameter set"),
    ("ident", "ident"),
];

impl Session<'_> {
    /// The `ident` value as text, which recognises the drive after a reopen.
    pub(super) fn identity(&mut self) -> Option<String> {
        self.ident_value().map(|v| v.to_string())
    }

    /// The value of the dictionary's `ident` object, which tells this drive from another.
    pub(super) fn ident_value(&mut self) -> Option<Value> {
        let name = self.drive().dictionary().lookup("ident").ok()?.name.clone();
        self.drive().read(&name).ok()
    }
    /// `device type 0x00020192, vendor 0x0000003B, serial 0x00000001, …`: the values of
    /// the identity objects the current drive answered; `None` when its dictionary names
    /// none or it answered none. `ident` is the `ident` object's value already read (to
    /// recognise the drive), not asked for twice.
    pub(super) fn drive_identity(&mut self, ident: Option<&Value>) -> Option<String> {
        let ident_object = self
            .drive()
            .dictionary()
            .lookup("ident")
            .ok()
            .map(|o| o.name.clone());
        let mut read: Vec<String> = Vec::new();
        let mut parts: Vec<String> = Vec::new();
        for (asked, label) in IDENTITY_OBJECTS {
            let Ok(object) = self.drive().dictionary().lookup(asked).map(|o| o.name.clone()) else {
                continue;
            };
            if read.contains(&object) {
                continue;
            }
            read.push(object.clone());
            let value = match ident_object.as_deref() == Some(object.as_str()) {
                true => ident.cloned(),
                false => self.drive().read(&object).ok(),
            };
            if let Some(value) = value {
                // A string without the quotes a console shows it in.
                let text = value.text().map_or_else(|| value.to_string(), str::to_string);
                if !text.trim().is_empty() {
                    parts.push(format!("{label} {}", text.trim()));
                }
            }
        }
        (!parts.is_empty()).then(|| parts.join(", "))
    }
}
