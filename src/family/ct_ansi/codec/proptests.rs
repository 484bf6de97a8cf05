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
