//! Keys besides `address:` by which a family lets a drive's address be written in a
//! recipe's `drives:` entry (`dnc_address: 2`; `address: 0` with `axis: b`), and the
//! command-line flags that stand for the keys that replace `address:` (`--dnc-address`).
//! Family-neutral data: a family fills it in and turns the keys' values into its own
//! address notation; the recipe loader, the schema and the command line only read it. Must
//! not name a family.

/// How a key relates to `address:`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyUse {
    /// Written instead of `address:` (`dnc_address: 2`); never together with it.
    InsteadOfAddress,
    /// Qualifies the `address:` given with it (`axis: b` with `address: 0`); never alone.
    WithAddress,
}

/// What a key's value may be, for the editor schema (the family checks the value itself).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyValues {
    Number { min: u32, max: u32 },
    OneOf(&'static [&'static str]),
}

/// One address key of a family.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AddressKey {
    /// As written in a `drives:` entry: `dnc_address`.
    pub name: &'static str,
    pub usage: KeyUse,
    pub values: KeyValues,
    /// What it means, for messages and the schema: `the drive's raw DNC address …`.
    pub meaning: &'static str,
}

/// Why the values given cannot make an address: which key's value is wrong (or
/// `address`), what, and what to write instead.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyProblem {
    pub key: String,
    pub message: String,
    pub label: String,
    pub help: Option<String>,
}

/// Turns the `address:` text (when given) and the address keys given (name, value as
/// written) into the address in the family's own notation (`dnc:2`, `0B`). Called only
/// with keys of the family, each used as its [`KeyUse`] says.
pub type ToAddress = fn(address: Option<&str>, given: &[(&str, &str)]) -> Result<String, KeyProblem>;

/// A family's address keys and how their values become its address.
#[derive(Clone, Copy)]
pub struct AddressKeys {
    pub keys: &'static [AddressKey],
    pub to_address: ToAddress,
}

impl AddressKeys {
    /// A family without address keys: `address:` only.
    pub const NONE: AddressKeys = AddressKeys {
        keys: &[],
        to_address: |address, _| Ok(address.unwrap_or_default().to_string()),
    };

    pub fn key(&self, name: &str) -> Option<&'static AddressKey> {
        self.keys.iter().find(|k| k.name == name)
    }
}

impl std::fmt::Debug for AddressKeys {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AddressKeys").field("keys", &self.keys).finish()
    }
}

/// One family's address notation as the layers above the families see it.
#[derive(Debug, Clone)]
pub struct FamilyAddressKeys {
    /// The family's id (what a dictionary's `family:` names): `sd2`.
    pub family: &'static str,
    /// The names a recipe's `drive:` may give for it: the id and its built-in dictionaries.
    pub drive_names: Vec<&'static str>,
    /// How `address:` is written in its notation.
    pub address_help: &'static str,
    pub keys: AddressKeys,
}

/// The address notation and keys of every family, in the registry's order.
#[derive(Debug, Clone, Default)]
pub struct AddressKeyTable {
    families: Vec<FamilyAddressKeys>,
}

impl AddressKeyTable {
    pub fn new(families: Vec<FamilyAddressKeys>) -> Self {
        AddressKeyTable { families }
    }

    /// The family with id `family`.
    pub fn of(&self, family: &str) -> Option<&FamilyAddressKeys> {
        self.families.iter().find(|f| f.family == family)
    }

    pub fn families(&self) -> impl Iterator<Item = &FamilyAddressKeys> {
        self.families.iter()
    }

    /// The families that have the key `name`, with that key.
    pub fn families_with(&self, name: &str) -> Vec<(&FamilyAddressKeys, &'static AddressKey)> {
        self.families
            .iter()
            .filter_map(|f| Some((f, f.keys.key(name)?)))
            .collect()
    }

    /// Every name a `drive:` may give (each family's id and built-in dictionaries), for
    /// help text that must list what the registry has, not a copy of it.
    pub fn drive_names(&self) -> Vec<&'static str> {
        self.families
            .iter()
            .flat_map(|f| f.drive_names.iter().copied())
            .collect()
    }

    /// Every key name of every family, once each, in order.
    pub fn all_key_names(&self) -> Vec<&'static str> {
        let mut names: Vec<&'static str> = Vec::new();
        for key in self.families.iter().flat_map(|f| f.keys.keys) {
            if !names.contains(&key.name) {
                names.push(key.name);
            }
        }
        names
    }
}
