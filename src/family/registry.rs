//! The families drivescript knows, by id, and their built-in dictionaries by name: the one
//! place a family is added. Tests add their own families with [`Registry::with`].

use super::FamilyError;
use super::{
    canopen::CANOPEN_FAMILY, ct_ansi::CtFamily, lenze_931::Lenze931Family, lenze_9400::LENZE_9400_FAMILY,
    modbus::ModbusFamily, sd2::Sd2Family, BuiltinDictionary, Family,
};
use crate::diag::{did_you_mean, Diagnostic};
use crate::dictionary::{family_id, Dictionary, DictionaryError};
use crate::drive::{AddressKeyTable, FamilyAddressKeys};
use std::sync::Arc;

/// The dictionary `--drive` names when it is not given.
pub const DEFAULT_DICTIONARY: &str = "sd2";

#[derive(Clone)]
pub struct Registry {
    families: Vec<Arc<dyn Family>>,
}

impl Registry {
    /// Every family compiled in.
    pub fn builtin() -> Registry {
        Registry {
            families: vec![
                Arc::new(Sd2Family),
                Arc::new(CtFamily),
                Arc::new(Lenze931Family),
                Arc::new(LENZE_9400_FAMILY),
                Arc::new(ModbusFamily::RTU),
                Arc::new(ModbusFamily::TCP),
                Arc::new(CANOPEN_FAMILY),
            ],
        }
    }

    /// This registry with one more family (tests plug in families of their own).
    pub fn with(mut self, family: Arc<dyn Family>) -> Registry {
        self.families.push(family);
        self
    }

    /// The family a dictionary names, also in the former spelling of its id (`ct_ansi`
    /// for `ct-ansi`, see [`family_id`]); the error lists the known ones.
    pub fn family(&self, id: &str) -> Result<Arc<dyn Family>, FamilyError> {
        let wanted = family_id(id);
        self.families
            .iter()
            .find(|f| f.id() == wanted)
            .cloned()
            .ok_or_else(|| {
                let ids: Vec<&str> = self.families.iter().map(|f| f.id()).collect();
                let hint = suggestion(id, &ids);
                FamilyError::Unknown(format!(
                    "no drive family `{id}`; drivescript knows {}{hint}",
                    ids.join(", ")
                ))
            })
    }

    /// The built-in dictionary `name` (what `--drive` names) and its family.
    pub fn dictionary(&self, name: &str) -> Result<(Arc<dyn Family>, BuiltinDictionary), FamilyError> {
        for family in &self.families {
            if let Some(d) = family.dictionaries().iter().find(|d| d.name == name) {
                return Ok((family.clone(), *d));
            }
        }
        let names = self.dictionary_names();
        let hint = suggestion(name, &names);
        Err(FamilyError::Unknown(format!(
            "no built-in dictionary `{name}`; there are {}{hint}",
            names.join(", ")
        )))
    }

    /// The built-in dictionary a recipe's or script's `drive:` means: the dictionary it
    /// names (`ct-unidrive-sp`), or for a family id (`ct-ansi`) that family's first one.
    pub fn dictionary_for_drive(&self, drive: &str) -> Result<&'static str, FamilyError> {
        match self.dictionary(drive) {
            Ok((_, d)) => Ok(d.name),
            Err(not_a_dictionary) => {
                let family = self.family(drive).map_err(|_| not_a_dictionary)?;
                let first = family.dictionaries().first().map(|d| d.name);
                first.ok_or_else(|| {
                    FamilyError::Unknown(format!("the {drive} family has no built-in dictionary"))
                })
            }
        }
    }

    /// The built-in dictionary `name`, parsed and checked.
    pub fn load_dictionary(&self, name: &str) -> Result<Dictionary, DictionaryError> {
        let (family, builtin) = self
            .dictionary(name)
            .map_err(|e| DictionaryError::from(Diagnostic::unlocated("", e)))?;
        Dictionary::from_yaml_for(builtin.path, builtin.text, family.address_parser())
    }

    /// Every built-in dictionary's name.
    pub fn dictionary_names(&self) -> Vec<&'static str> {
        self.families
            .iter()
            .flat_map(|f| f.dictionaries().iter().map(|d| d.name))
            .collect()
    }

    /// Every family's address notation and address keys, for the recipe loader, the
    /// schema and the command line (which must not name a family).
    pub fn address_keys(&self) -> AddressKeyTable {
        AddressKeyTable::new(
            self.families
                .iter()
                .map(|f| FamilyAddressKeys {
                    family: f.id(),
                    drive_names: std::iter::once(f.id())
                        .chain(f.dictionaries().iter().map(|d| d.name).filter(|n| *n != f.id()))
                        .collect(),
                    address_help: f.address_help(),
                    keys: f.address_keys(),
                })
                .collect(),
        )
    }

    pub fn families(&self) -> impl Iterator<Item = &Arc<dyn Family>> {
        self.families.iter()
    }
}

fn suggestion(input: &str, candidates: &[&str]) -> String {
    match did_you_mean(input, candidates.iter().copied()).first() {
        Some(s) => format!("; did you mean `{s}`?"),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_and_dictionaries_are_found_by_name_with_did_you_mean() {
        let r = Registry::builtin();
        assert_eq!(r.family("sd2").unwrap().id(), "sd2");
        let e = r.family("sd3").err().unwrap().to_string();
        assert!(e.contains("did you mean `sd2`"), "{e}");
        let (family, dictionary) = r.dictionary("sd2").unwrap();
        assert_eq!((family.id(), dictionary.path), ("sd2", "dictionary/sd2.yaml"));
        assert!(r.dictionary("lenze").is_err());
    }

    /// One spelling: every family id is kebab-case like the dictionary names, and every
    /// built-in dictionary's `family:` is its family's id as written.
    #[test]
    fn family_ids_and_dictionary_family_values_are_kebab_case() {
        let r = Registry::builtin();
        for family in r.families() {
            assert!(
                crate::dictionary::is_family_id(family.id()),
                "family id `{}`",
                family.id()
            );
            for builtin in family.dictionaries() {
                let d = r.load_dictionary(builtin.name).unwrap();
                assert_eq!(d.family(), family.id(), "{}", builtin.path);
                assert!(d.notes().is_empty(), "{}: {:?}", builtin.path, d.notes());
                assert!(
                    builtin.text.contains(&format!("\nfamily: {}\n", family.id())),
                    "{}",
                    builtin.path
                );
            }
        }
        assert_eq!(r.family("ct_ansi").unwrap().id(), "ct-ansi");
        assert_eq!(r.family("lenze_9400").unwrap().id(), "lenze-9400");
    }

    #[test]
    fn a_drive_names_a_dictionary_or_a_family_whose_first_dictionary_it_means() {
        let r = Registry::builtin();
        assert_eq!(
            r.dictionary_for_drive("ct-unidrive-sp").unwrap(),
            "ct-unidrive-sp"
        );
        let family = r.dictionary("ct-unidrive-sp").unwrap().0.id();
        assert_eq!(r.dictionary_for_drive(family).unwrap(), "ct-unidrive-sp");
        let e = r.dictionary_for_drive("ct-unidrive").unwrap_err().to_string();
        assert!(e.starts_with("no built-in dictionary `ct-unidrive`"), "{e}");
    }
}
