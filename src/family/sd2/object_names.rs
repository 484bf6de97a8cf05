//! What the SD2 telegram explainer asks about objects ([`ObjectNames`]), and the answers a
//! dictionary gives: names, values with units, states. Formatting only; no I/O.

use crate::dictionary::{Address, Dictionary, Role};

/// What the explainer needs to know about objects (a dictionary, or nothing).
pub trait ObjectNames {
    /// A readable name for the object, e.g. `control_word (DEV_CTRL_CONTROL_WORD)`.
    fn object_name(&self, index: u16, subindex: u32) -> Option<String>;
    /// The object's value with its unit, e.g. `1003.647 rpm`, from its raw bytes.
    fn object_value(&self, index: u16, subindex: u32, data: &[u8]) -> Option<String>;
    /// True for the device-control control word.
    fn is_control_word(&self, index: u16) -> bool;
    /// True for the device-control status word.
    fn is_status_word(&self, index: u16) -> bool;
    /// The state a status word shows under the dictionary's profile.
    fn state_of(&self, status: u16) -> Option<String>;
}

impl ObjectNames for Dictionary {
    fn object_name(&self, index: u16, subindex: u32) -> Option<String> {
        self.by_address(index, subindex).map(|o| o.display_name())
    }

    fn object_value(&self, index: u16, subindex: u32, data: &[u8]) -> Option<String> {
        let object = self.by_address(index, subindex)?;
        let raw = super::wire_value::decode(data, object.data_type).ok()?;
        object.value_of(raw).ok().map(|v| v.to_string())
    }

    fn is_control_word(&self, index: u16) -> bool {
        self.role_index(Role::ControlWord) == Some(index)
    }

    fn is_status_word(&self, index: u16) -> bool {
        self.role_index(Role::StatusWord) == Some(index)
    }

    fn state_of(&self, status: u16) -> Option<String> {
        self.profile()?.state_of(status).map(|s| s.to_string())
    }
}

impl Dictionary {
    fn role_index(&self, role: Role) -> Option<u16> {
        match self.role(role)?.address {
            Address::Indexed { index, .. } => Some(index),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::family::sd2::codec::Telegram;
    use crate::family::sd2::{explain, ObjectNames};

    #[test]
    fn names_and_values_for_the_explainer() {
        let d = crate::family::Registry::builtin().load_dictionary("sd2").unwrap();
        assert_eq!(
            d.object_name(398, 0).as_deref(),
            Some("speed_actual (VCTRL_VELOCITY_ACTUAL_VALUE_UUNIT)")
        );
        assert_eq!(d.object_name(402, 0).as_deref(), Some("store_parameters"));
        assert_eq!(d.object_name(9999, 0), None);
        assert_eq!(
            d.object_value(398, 0, &[0x7f, 0x50, 0x0f, 0x00]).as_deref(),
            Some("1003.647 rpm")
        );
        assert_eq!(d.object_value(67, 0, &[0x37, 0x02]).as_deref(), Some("0x0237"));
        assert_eq!(d.object_value(398, 0, &[0x7f]), None);
        assert!(d.is_control_word(68) && !d.is_control_word(67));
        assert!(d.is_status_word(67) && !d.is_status_word(68));
    }

    #[test]
    fn explained_with_the_dictionary() {
        let d = crate::family::Registry::builtin().load_dictionary("sd2").unwrap();
        let bytes = crate::hex::parse_hex("00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97").unwrap();
        let t = Telegram::decode(&bytes).unwrap();
        let text = explain(&t, &bytes, None, &d);
        assert!(
            text.contains("68 (0x0044) control_word (DEV_CTRL_CONTROL_WORD)"),
            "{text}"
        );
        assert!(text.contains("= 0x0006"), "{text}");
        assert!(text.contains("control   6: shutdown"), "{text}");
    }
}
