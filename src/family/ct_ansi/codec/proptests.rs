//! Property tests of the codec: what is built reads back the same, and no bytes at all
//! make a decoder or the framer panic or loop.

use super::*;
use proptest::prelude::*;

fn parameter() -> impl Strategy<Value = Parameter> {
    (0u8..=99, 0u8..=99).prop_map(|(m, p)| Parameter { menu: m, param: p })
}

fn address() -> impl Strategy<Value = NodeAddress> {
    (0u8..=9, 0u8..=9).prop_map(|(g, u)| NodeAddress { group: g, unit: u })
}

/// Values whose write field fits in 12 characters.
fn value() -> impl Strategy<Value = DataValue> {
    (0u8..=6).prop_flat_map(|places| {
        let max = 10i64.pow(10 - u32::from(places.min(1)));
        (-max + 1..max).prop_map(move |digits| DataValue::new(digits, places))
    })
}

proptest! {
    #[test]
    fn requests_round_trip(addr in proptest::option::of(address()), parameter in parameter(), value in value(), read in any::<bool>()) {
        let request = match (read, addr) {
            (true, Some(address)) => Request::Read { address, parameter },
            _ => Request::Write { address: addr, parameter, value },
        };
        let bytes = request.encode().unwrap();
        prop_assert_eq!(split(&bytes, Sender::Master), Split::Message(bytes.len()));
        prop_assert_eq!(Request::decode(&bytes), Ok(request));
    }

    #[test]
    fn replies_round_trip(parameter in parameter(), value in value()) {
        let reply = Reply::Value { parameter, value };
        let bytes = reply.encode().unwrap();
        prop_assert_eq!(split(&bytes, Sender::Drive), Split::Message(bytes.len()));
        prop_assert_eq!(Reply::decode(&bytes), Ok(reply));
    }

    #[test]
    fn data_fields_round_trip_exactly(value in value()) {
        let field = value.write_field().unwrap();
        prop_assert_eq!(DataValue::parse(&field, 0), Ok(value));
        prop_assert_eq!(String::from_utf8(field).unwrap(), value.to_string());
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
        let _ = Request::decode(&bytes);
        let _ = Reply::decode(&bytes);
        let _ = DataValue::parse(&bytes, 0);
        let _ = show_bytes(&bytes);
        for sender in [Sender::Master, Sender::Drive] {
            // The framer always makes progress or asks for more.
            let mut rest: &[u8] = &bytes;
            while !rest.is_empty() {
                match split(rest, sender) {
                    Split::Incomplete => break,
                    Split::Message(n) | Split::Noise(n) => {
                        prop_assert!(n >= 1 && n <= rest.len());
                        rest = &rest[n..];
                    }
                }
            }
        }
    }

    #[test]
    fn a_flipped_bit_in_a_reply_never_passes_as_the_same_value(parameter in parameter(), value in value(), at in any::<prop::sample::Index>(), bit in 0u8..7) {
        let reply = Reply::Value { parameter, value };
        let mut bytes = reply.encode().unwrap();
        let i = at.index(bytes.len());
        bytes[i] ^= 1 << bit;
        prop_assert_ne!(Reply::decode(&bytes), Ok(reply));
    }
}

/// The byte offset a decode error names, if any.
fn error_offset(e: &DecodeError) -> Option<usize> {
    match *e {
        DecodeError::Unexpected { offset, .. }
        | DecodeError::BadData { offset, .. }
        | DecodeError::DataTooLong { offset, .. } => Some(offset),
        _ => None,
    }
}

proptest! {
    #[test]
    fn hex_fields_read_as_whole_numbers(value in 0i64..0x100_0000_0000, lower in any::<bool>(), spaces in 0usize..3, at in 0usize..40) {
        let digits = if lower { format!("{value:x}") } else { format!("{value:X}") };
        let text = format!("{}X{digits}", " ".repeat(spaces));
        prop_assume!(text.len() <= MAX_DATA_LEN);
        prop_assert_eq!(DataValue::parse(text.as_bytes(), at), Ok(DataValue::new(value, 0)));
    }

    #[test]
    fn a_bad_hex_digit_is_refused_at_its_own_byte(value in 0i64..0x1000_0000, at in 0usize..40, bad in "[G-Zg-z.+ -]", place in any::<prop::sample::Index>()) {
        let mut text = format!("X{value:X}").into_bytes();
        let i = 1 + place.index(text.len());
        text.insert(i, bad.as_bytes()[0]);
        prop_assume!(text.len() <= MAX_DATA_LEN);
        let e = DataValue::parse(&text, at).unwrap_err();
        prop_assert_eq!(error_offset(&e), Some(at + i), "{}", e);
    }

    #[test]
    fn decimal_fields_in_every_spelling(value in value(), zeros in 0usize..3, style in 0u8..3, spaces in 0usize..3) {
        // `+0047.6`, ` 47.6` (a space for +), `47.6`; leading zeros; leading spaces.
        let abs = DataValue::new(value.digits.abs(), value.places).to_string();
        let sign = match (value.digits < 0, style) {
            (true, _) => "-",
            (false, 0) => "+",
            (false, 1) => " ",
            (false, _) => "",
        };
        let text = format!("{}{sign}{}{abs}", " ".repeat(spaces), "0".repeat(zeros));
        prop_assume!(text.len() <= MAX_DATA_LEN);
        prop_assert_eq!(DataValue::parse(text.as_bytes(), 0), Ok(value));
    }

    #[test]
    fn any_field_is_read_or_refused_with_an_offset_inside_it(text in "[ +\\-.0-9A-Fa-fXx]{0,14}", at in 0usize..40) {
        match DataValue::parse(text.as_bytes(), at) {
            Ok(v) => prop_assert!(text.len() <= MAX_DATA_LEN && v.places <= 11),
            Err(e) => {
                let offset = error_offset(&e).unwrap_or(at);
                prop_assert!(offset >= at && offset < at + text.len().max(1), "{} at {}", e, offset);
            }
        }
    }
}
