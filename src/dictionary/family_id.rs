//! How a drive family's id is spelled: kebab-case (`sd2`, `ct-ansi`, `lenze-931`,
//! `lenze-9400`), the spelling of dictionary names, because users type both (a
//! dictionary's `family:`, a recipe's `drive:`, `decode --protocol`). Files written before
//! the ids were unified spell some with `_` (`ct_ansi`, `lenze_9400`); that spelling still
//! reads as the same id. Pure text rules: which families exist is the registry's.

/// The family id `written` means: `_` read as `-`, so a file in the field that spells
/// the former `ct_ansi` names the family `ct-ansi`.
pub fn family_id(written: &str) -> String {
    written.replace('_', "-")
}

/// True when `written` is the former spelling of a family id (with `_`), which still
/// works but which a file should change to [`family_id`]'s.
pub fn is_former_spelling(written: &str) -> bool {
    written.contains('_')
}

/// True when `id` is spelled as a family id: lower-case letters and digits in words
/// joined by single `-`, starting with a letter.
pub fn is_family_id(id: &str) -> bool {
    id.starts_with(|c: char| c.is_ascii_lowercase())
        && id.split('-').all(|word| {
            !word.is_empty() && word.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit())
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_former_spelling_reads_as_the_kebab_case_id() {
        for (spelt, id) in [
            ("ct_ansi", "ct-ansi"),
            ("lenze_9400", "lenze-9400"),
            ("lenze-931", "lenze-931"),
        ] {
            assert_eq!(family_id(spelt), id, "{spelt}");
        }
        assert!(is_former_spelling("ct_ansi") && !is_former_spelling("ct-ansi"));
    }

    #[test]
    fn family_ids_are_kebab_case() {
        for good in ["sd2", "ct-ansi", "lenze-9400"] {
            assert!(is_family_id(good), "{good}");
        }
        for bad in [
            "", "ct_ansi", "Ct-ansi", "ct--ansi", "ct-", "-ct", "2ct", "ct ansi",
        ] {
            assert!(!is_family_id(bad), "{bad}");
        }
    }
}
