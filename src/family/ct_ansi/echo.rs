//! How the start of what came back relates to the message just sent: a half-duplex RS485
//! adapter with echo on hands the master its own message back before the drive answers.
//! An exact echo is never a reply: no drive answer equals a whole request (a read is
//! answered with STX… or EOT, a write with ACK or NAK, a short command with STX… or EOT),
//! and only the lone `EOT` that answers a read of a missing parameter equals a proper
//! start of a request (every addressed message starts with EOT); the link decides that
//! case. Pure: no I/O, no clock.

/// What the bytes received so far are, measured against the message sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EchoMatch {
    /// Nothing has arrived yet.
    Nothing,
    /// The first byte is not the message's: no echo this time.
    NotEcho,
    /// All `n` bytes received match the start of the message; more may follow.
    Prefix(usize),
    /// The whole message came back, exactly: drop these bytes.
    Whole,
    /// The first `n` bytes matched, then a byte differs: an echo that broke off (lost or
    /// damaged bytes); the `n` bytes are dropped and the rest is read as usual.
    Broken(usize),
}

pub fn match_echo(received: &[u8], sent: &[u8]) -> EchoMatch {
    let same = received.iter().zip(sent).take_while(|(r, s)| r == s).count();
    match same {
        _ if received.is_empty() => EchoMatch::Nothing,
        0 => EchoMatch::NotEcho,
        n if n == sent.len() => EchoMatch::Whole,
        n if n == received.len() => EchoMatch::Prefix(n),
        n => EchoMatch::Broken(n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::ct_ansi::codec::{ACK, EOT, NAK, STX};

    const READ: &[u8] = b"\x0411220121\x05";

    #[test]
    fn an_echo_is_recognised_whole_in_part_or_broken() {
        assert_eq!(match_echo(b"", READ), EchoMatch::Nothing);
        assert_eq!(match_echo(READ, READ), EchoMatch::Whole);
        let mut then_reply = READ.to_vec();
        then_reply.extend(b"\x020121+1.0\x03%");
        assert_eq!(match_echo(&then_reply, READ), EchoMatch::Whole);
        assert_eq!(match_echo(&READ[..4], READ), EchoMatch::Prefix(4));
        assert_eq!(match_echo(&[EOT], READ), EchoMatch::Prefix(1));
        assert_eq!(match_echo(b"\x04112x", READ), EchoMatch::Broken(4));
        assert_eq!(match_echo(&[STX, b'0'], READ), EchoMatch::NotEcho);
    }

    #[test]
    fn short_answers_are_not_taken_for_an_echo() {
        // A write's ACK or NAK never matches the write, which starts with EOT or STX.
        let write = b"\x041122\x0201211500.5\x03c";
        assert_eq!(match_echo(&[ACK], write), EchoMatch::NotEcho);
        assert_eq!(match_echo(&[NAK], write), EchoMatch::NotEcho);
        // A short command is one byte: its echo is whole at once, and the drive answers it
        // with a value or EOT, never with the same byte.
        assert_eq!(match_echo(&[ACK], &[ACK]), EchoMatch::Whole);
        assert_eq!(match_echo(&[EOT], &[NAK]), EchoMatch::NotEcho);
    }

    mod properties {
        use super::super::*;
        use crate::family::ct_ansi::codec::{DataValue, NodeAddress, Parameter, Reply, Request, EOT};
        use proptest::prelude::*;

        fn request() -> impl Strategy<Value = Request> {
            let addr = (0u8..=9, 1u8..=9).prop_map(|(g, u)| NodeAddress { group: g, unit: u });
            let par = (0u8..=99, 0u8..=99).prop_map(|(m, p)| Parameter { menu: m, param: p });
            let value = (-99_999i64..99_999, 0u8..=3).prop_map(|(d, p)| DataValue::new(d, p));
            prop_oneof![
                (addr.clone(), par.clone())
                    .prop_map(|(address, parameter)| Request::Read { address, parameter }),
                (proptest::option::of(addr), par, value).prop_map(|(address, parameter, value)| {
                    Request::Write {
                        address,
                        parameter,
                        value,
                    }
                }),
                Just(Request::ReadAgain),
                Just(Request::ReadNext),
                Just(Request::ReadPrevious),
            ]
        }

        fn reply() -> impl Strategy<Value = Reply> {
            let par = (0u8..=99, 0u8..=99).prop_map(|(m, p)| Parameter { menu: m, param: p });
            let value = (-99_999i64..99_999, 0u8..=3).prop_map(|(d, p)| DataValue::new(d, p));
            prop_oneof![
                (par, value).prop_map(|(parameter, value)| Reply::Value { parameter, value }),
                Just(Reply::Accepted),
                Just(Reply::Refused),
                Just(Reply::NoSuchParameter),
            ]
        }

        proptest! {
            /// No answer a drive gives to a request passes for the echo of that request: it
            /// never matches it whole, and a start of it only as the lone EOT the link decides.
            #[test]
            fn no_answer_is_ever_an_echo(request in request(), reply in reply()) {
                // What the protocol lets a drive answer: a write ACK or NAK, a read (also a
                // short one) a value or EOT.
                let is_write = matches!(request, Request::Write { .. });
                let is_ack_or_nak = matches!(reply, Reply::Accepted | Reply::Refused);
                prop_assume!(is_write == is_ack_or_nak);
                let sent = request.encode().unwrap();
                let answer = reply.encode().unwrap();
                match match_echo(&answer, &sent) {
                    EchoMatch::Whole => prop_assert!(false, "{:?} matched {:?}", reply, request),
                    EchoMatch::Prefix(_) => prop_assert_eq!(answer, vec![EOT]),
                    _ => {}
                }
            }

            /// The echo followed by any reply is recognised whole, whatever follows.
            #[test]
            fn an_echo_followed_by_a_reply_is_whole(request in request(), reply in reply()) {
                let sent = request.encode().unwrap();
                let mut line = sent.clone();
                line.extend(reply.encode().unwrap());
                prop_assert_eq!(match_echo(&line, &sent), EchoMatch::Whole);
            }
        }
    }
}
