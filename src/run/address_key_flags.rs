//! Command-line flags that stand for a family's address key that replaces `--address`
//! (`--dnc-address 2` is a recipe's `dnc_address: 2`). The flag names only the key: the
//! drive's family says whether it has that key and turns the value into its own notation,
//! so the command line names no family. Checks and converts; opens nothing.

use super::RunError;
use crate::drive::KeyUse;
use crate::family::{Family, Registry};

/// `--dnc-address`: a drive's raw DNC address.
pub const DNC_ADDRESS: AddressKeyFlag = AddressKeyFlag {
    flag: "--dnc-address",
    key: "dnc_address",
};

/// A flag and the address key it stands for.
#[derive(Debug, Clone, Copy)]
pub struct AddressKeyFlag {
    pub flag: &'static str,
    pub key: &'static str,
}

impl AddressKeyFlag {
    /// `value` as an address in `family`'s notation (`2` → `dnc:2`); refused with what to
    /// write for a family without the key, naming the families of `registry` that have it.
    pub fn address(&self, registry: &Registry, family: &dyn Family, value: &str) -> Result<String, RunError> {
        let (flag, key) = (self.flag, self.key);
        let keys = family.address_keys();
        match keys.key(key) {
            Some(k) if k.usage == KeyUse::InsteadOfAddress => (keys.to_address)(None, &[(key, value.trim())])
                .map_err(|p| {
                    let help = p.help.map(|h| format!("; {h}")).unwrap_or_default();
                    RunError::Invalid(format!("{flag} {value}: {}{help}", p.message))
                }),
            _ => {
                let table = registry.address_keys();
                let takers: Vec<&str> = table.families_with(key).iter().map(|(f, _)| f.family).collect();
                Err(RunError::Invalid(format!(
                    "{flag} is for drives of the {} family; a {} drive has no `{key}`: give --address, {}",
                    takers.join(", "),
                    family.id(),
                    family.address_help()
                )))
            }
        }
    }

    /// A comma-separated list (`2,3`) as addresses in `family`'s notation, comma-separated.
    pub fn addresses(
        &self,
        registry: &Registry,
        family: &dyn Family,
        list: &str,
    ) -> Result<String, RunError> {
        list.split(',')
            .map(|v| self.address(registry, family, v))
            .collect::<Result<Vec<_>, _>>()
            .map(|all| all.join(","))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dnc_address_becomes_the_familys_notation_or_is_refused_saying_why() {
        let registry = Registry::builtin();
        let sd2 = registry.family("sd2").unwrap();
        assert_eq!(
            DNC_ADDRESS
                .address(&registry, sd2.as_ref(), "2")
                .map_err(|e| e.to_string()),
            Ok("dnc:2".into())
        );
        assert_eq!(
            DNC_ADDRESS
                .addresses(&registry, sd2.as_ref(), "2, 3")
                .map_err(|e| e.to_string()),
            Ok("dnc:2,dnc:3".into())
        );
        let e = DNC_ADDRESS
            .address(&registry, sd2.as_ref(), "1")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("--dnc-address 1: ") && e.contains("2..=255"), "{e}");
        let ct = registry.family("ct-ansi").unwrap();
        let e = DNC_ADDRESS
            .address(&registry, ct.as_ref(), "2")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("--dnc-address is for drives of the sd2 family; a ct-ansi drive has no `dnc_address`: give --address, "),
            "{e}"
        );
    }
}
