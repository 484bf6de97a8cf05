//! SD2's address keys in a recipe's `drives:` entry, as issue 18 spelled them:
//! `dnc_address: N` (a raw DNC address, the notation's `dnc:N`) and `axis: a|b` with
//! `address: N` (the address switch position and the axis of a double-axis device, the
//! notation's `NA`/`NB`: DNC address switch × 2 + 2, drive B + 3). Turns them into the
//! notation `parse_drive_address` reads; must not invent another mapping.

use super::codec::dnc_address;
use crate::drive::{AddressKey, AddressKeys, KeyProblem, KeyUse, KeyValues};

const KEYS: &[AddressKey] = &[
    AddressKey {
        name: "dnc_address",
        usage: KeyUse::InsteadOfAddress,
        values: KeyValues::Number { min: 2, max: 255 },
        meaning: "the drive's raw DNC address, 2..=255 (0 and 1 are the master's); the same as `address: dnc:N`",
    },
    AddressKey {
        name: "axis",
        usage: KeyUse::WithAddress,
        values: KeyValues::OneOf(&["a", "b", "A", "B"]),
        meaning: "the axis of a double-axis device whose address switch position `address:` gives: a (DNC address switch × 2 + 2) or b (+ 3); the same as `address: NA` / `address: NB`",
    },
];

pub const SD2_ADDRESS_KEYS: AddressKeys = AddressKeys {
    keys: KEYS,
    to_address,
};

fn problem(key: &str, message: String, label: &str, help: &str) -> KeyProblem {
    KeyProblem {
        key: key.to_string(),
        message,
        label: label.to_string(),
        help: Some(help.to_string()),
    }
}

fn to_address(address: Option<&str>, given: &[(&str, &str)]) -> Result<String, KeyProblem> {
    if let Some((_, value)) = given.iter().find(|(k, _)| *k == "dnc_address") {
        return match value.trim().parse::<u8>() {
            Ok(n) if n >= 2 => Ok(format!("dnc:{n}")),
            _ => Err(problem(
                "dnc_address",
                format!("`{value}` is not a drive's DNC address"),
                "not 2..=255",
                "a drive's DNC address is 2..=255; 0 and 1 belong to the master",
            )),
        };
    }
    let Some((_, axis)) = given.iter().find(|(k, _)| *k == "axis") else {
        return Ok(address.unwrap_or_default().to_string());
    };
    let drive_b = match axis.trim() {
        "a" | "A" => false,
        "b" | "B" => true,
        other => {
            return Err(problem(
                "axis",
                format!("`axis: {other}` is not an axis of a double-axis SD2 device"),
                "a or b",
                "write `axis: a` or `axis: b`",
            ))
        }
    };
    let switch_text = address.unwrap_or_default().trim();
    let Ok(switch) = switch_text.parse::<u8>() else {
        return Err(problem(
            "address",
            format!("with `axis:`, `address: {switch_text}` must be the address switch position alone"),
            "switch position 0..=126",
            "write the switch position and the axis apart (`address: 3` with `axis: b`), or the address alone (`address: 3B`, `address: dnc:9`) without `axis:`",
        ));
    };
    if dnc_address(switch, drive_b).is_none() {
        return Err(problem(
            "address",
            format!(
                "switch position {switch} × 2 + {} exceeds DNC address 255",
                2 + u8::from(drive_b)
            ),
            "switch position 0..=126",
            "the highest switch position is 126",
        ));
    }
    Ok(format!("{switch}{}", if drive_b { 'B' } else { 'A' }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::{sd2::Sd2Family, Family};

    /// The DNC address the keys give, through the notation `parse_drive_address` reads.
    fn number(address: Option<&str>, given: &[(&str, &str)]) -> u32 {
        let text = to_address(address, given).unwrap_or_else(|p| panic!("{}: {}", p.key, p.message));
        match Sd2Family.parse_drive_address(Some(&text)) {
            Ok(drive) => drive.number,
            Err(e) => panic!("`{text}`: {e}"),
        }
    }

    #[test]
    fn the_keys_name_the_dnc_addresses_the_notation_names() {
        assert_eq!(number(None, &[("dnc_address", "2")]), 2);
        assert_eq!(number(None, &[("dnc_address", "255")]), 255);
        // Switch N, axis a: N × 2 + 2; axis b: + 3, exactly as `NA` and `NB`.
        for switch in [0u32, 3, 126] {
            let s = switch.to_string();
            assert_eq!(number(Some(&s), &[("axis", "a")]), switch * 2 + 2);
            assert_eq!(number(Some(&s), &[("axis", "b")]), switch * 2 + 3);
            assert_eq!(number(Some(&s), &[("axis", "B")]), switch * 2 + 3);
            let b = format!("{switch}B");
            assert_eq!(number(Some(&s), &[("axis", "b")]), number(Some(&b), &[]));
        }
    }

    #[test]
    fn wrong_values_name_their_key() {
        let key = |address, given: &[(&str, &str)]| to_address(address, given).map_err(|p| p.key);
        assert_eq!(key(None, &[("dnc_address", "1")]), Err("dnc_address".into()));
        assert_eq!(key(None, &[("dnc_address", "256")]), Err("dnc_address".into()));
        assert_eq!(key(None, &[("dnc_address", "two")]), Err("dnc_address".into()));
        assert_eq!(key(Some("0"), &[("axis", "c")]), Err("axis".into()));
        assert_eq!(key(Some("3B"), &[("axis", "b")]), Err("address".into()));
        assert_eq!(key(Some("dnc:2"), &[("axis", "a")]), Err("address".into()));
        assert_eq!(key(Some("127"), &[("axis", "a")]), Err("address".into()));
    }
}
