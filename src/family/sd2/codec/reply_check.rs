//! Does a reply answer a request? Address swap, command bit 7, service-channel index echo.
//! Pure comparison; the link decides what to do about a mismatch.

use super::{Body, DecodeError, Telegram, REPLY_BIT};

/// `Ok` when `reply` is the answer to `request`: it comes from the drive the request went
/// to, is addressed to the request's sender, carries the request's command with bit 7 set
/// and, for a service channel, echoes the index.
pub fn check_reply(request: &Telegram, reply: &Telegram) -> Result<(), DecodeError> {
    let expected_cmd = request.command() | REPLY_BIT;
    if reply.command() != expected_cmd {
        return Err(mismatch(
            "command",
            format!("0x{expected_cmd:02x}"),
            format!("0x{:02x}", reply.command()),
        ));
    }
    if reply.source != request.dest {
        return Err(mismatch(
            "source address",
            request.dest.to_string(),
            reply.source.to_string(),
        ));
    }
    if reply.dest != request.source {
        return Err(mismatch(
            "destination address",
            request.source.to_string(),
            reply.dest.to_string(),
        ));
    }
    if let (Body::CyclicRequest(q), Body::CyclicReply(r)) = (&request.body, &reply.body) {
        match (&q.service, &r.service) {
            (Some(qs), Some(rs)) if qs.index != rs.index => {
                return Err(mismatch(
                    "service index echo",
                    qs.index.to_string(),
                    rs.index.to_string(),
                ));
            }
            (Some(_), None) => {
                return Err(mismatch("service channel", "present".into(), "absent".into()));
            }
            _ => {}
        }
    }
    Ok(())
}

fn mismatch(field: &'static str, expected: String, actual: String) -> DecodeError {
    DecodeError::ReplyMismatch {
        field,
        expected,
        actual,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::sd2::codec::{Cyclic, Data, ErrorCode, ServiceChannel, ServiceFunction};

    fn read() -> Telegram {
        Telegram::read_request(2, 1, 398, 0)
    }

    fn reply(dest: u8, source: u8) -> Telegram {
        Telegram {
            dest,
            source,
            body: Body::ReadReply {
                error: ErrorCode::OK,
                data: Data::new(&[1, 2, 3, 4]).unwrap_or_default(),
            },
        }
    }

    #[test]
    fn matching_reply_passes() {
        assert_eq!(check_reply(&read(), &reply(1, 2)), Ok(()));
    }

    #[test]
    fn wrong_source_destination_and_command() {
        let e = check_reply(&read(), &reply(1, 4)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "reply does not answer the request: source address expected 2, got 4"
        );
        assert!(check_reply(&read(), &reply(3, 2)).is_err());
        let write_reply = Telegram {
            dest: 1,
            source: 2,
            body: Body::WriteReply { error: ErrorCode::OK },
        };
        let e = check_reply(&read(), &write_reply).unwrap_err();
        assert!(e.to_string().contains("command expected 0x8d, got 0x8e"));
    }

    #[test]
    fn service_index_must_echo() {
        let svc = |index| ServiceChannel::request(true, ServiceFunction::Read, 4, index, [0; 4]);
        let q = Telegram {
            dest: 2,
            source: 1,
            body: Body::CyclicRequest(Cyclic::request(6, 0, false).with_service(svc(39))),
        };
        let ok = Telegram {
            dest: 1,
            source: 2,
            body: Body::CyclicReply(Cyclic::reply([1, 0], 0x231, 0, 0, 0).with_service(svc(39))),
        };
        let bad = Telegram {
            dest: 1,
            source: 2,
            body: Body::CyclicReply(Cyclic::reply([1, 0], 0x231, 0, 0, 0).with_service(svc(40))),
        };
        let none = Telegram {
            dest: 1,
            source: 2,
            body: Body::CyclicReply(Cyclic::reply([1, 0], 0x231, 0, 0, 0)),
        };
        assert_eq!(check_reply(&q, &ok), Ok(()));
        assert!(check_reply(&q, &bad)
            .unwrap_err()
            .to_string()
            .contains("service index echo expected 39, got 40"));
        assert!(check_reply(&q, &none).is_err());
    }
}
