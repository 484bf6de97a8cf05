use super::*;
use crate::family::modbus::codec::rtu;
use proptest::prelude::*;

fn read(function: Function, start: u16, count: u16) -> Request {
    Request::Read {
        function,
        start,
        count,
    }
}

/// Each worked example of the Application Protocol Specification V1.1b3 as a request PDU,
/// its reply PDU, and both decoded (section and page of the specification).
/// What it shows, request PDU, request, reply PDU, reply.
type Example = (&'static str, Vec<u8>, Request, Vec<u8>, Response);

fn spec_examples() -> Vec<Example> {
    vec![
        (
            "6.3 (p. 15) read holding registers 108-110",
            vec![0x03, 0x00, 0x6B, 0x00, 0x03],
            read(Function::ReadHolding, 0x006B, 3),
            vec![0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64],
            Response::Registers {
                function: Function::ReadHolding,
                values: vec![555, 0, 100],
            },
        ),
        (
            "6.4 read input register 9",
            vec![0x04, 0x00, 0x08, 0x00, 0x01],
            read(Function::ReadInput, 0x0008, 1),
            vec![0x04, 0x02, 0x00, 0x0A],
            Response::Registers {
                function: Function::ReadInput,
                values: vec![10],
            },
        ),
        (
            "6.6 write register 2 to 00 03 hex",
            vec![0x06, 0x00, 0x01, 0x00, 0x03],
            Request::WriteSingle { address: 1, value: 3 },
            vec![0x06, 0x00, 0x01, 0x00, 0x03],
            Response::WriteSingle { address: 1, value: 3 },
        ),
        (
            "6.12 (pp. 30-31) write two registers starting at 2 to 00 0A and 01 02 hex",
            vec![0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02],
            Request::WriteMultiple {
                start: 1,
                values: vec![0x000A, 0x0102],
            },
            vec![0x10, 0x00, 0x01, 0x00, 0x02],
            Response::WriteMultiple { start: 1, count: 2 },
        ),
        (
            "6.17 read six registers starting at 4, write three starting at 15",
            vec![
                0x17, 0x00, 0x03, 0x00, 0x06, 0x00, 0x0E, 0x00, 0x03, 0x06, 0x00, 0xFF, 0x00, 0xFF, 0x00,
                0xFF,
            ],
            Request::ReadWrite {
                read_start: 3,
                read_count: 6,
                write_start: 14,
                values: vec![0xFF, 0xFF, 0xFF],
            },
            vec![
                0x17, 0x0C, 0x00, 0xFE, 0x0A, 0xCD, 0x00, 0x01, 0x00, 0x03, 0x00, 0x0D, 0x00, 0xFF,
            ],
            Response::Registers {
                function: Function::ReadWrite,
                values: vec![0x00FE, 0x0ACD, 0x0001, 0x0003, 0x000D, 0x00FF],
            },
        ),
    ]
}

#[test]
fn the_specifications_worked_examples_byte_for_byte() {
    for (what, request_pdu, request, reply_pdu, reply) in spec_examples() {
        assert_eq!(request.encode().as_ref(), Ok(&request_pdu), "{what}");
        assert_eq!(Request::decode(&request_pdu).as_ref(), Ok(&request), "{what}");
        assert_eq!(reply.encode(), reply_pdu, "{what}");
        assert_eq!(Response::decode(&reply_pdu).as_ref(), Ok(&reply), "{what}");
        assert_eq!(request.check(&reply), Ok(()), "{what}");
        assert_eq!(
            Request::length_from(&request_pdu).and_then(Result::ok),
            Some(request_pdu.len())
        );
        assert_eq!(
            Response::length_from(&reply_pdu).and_then(Result::ok),
            Some(reply_pdu.len())
        );
    }
}

/// Application Protocol V1.1b3, section 7 (p. 47): read coils at 04A1 hex refused with
/// exception 02.
#[test]
fn the_specifications_exception_example() {
    let reply = Response::decode(&[0x81, 0x02]).unwrap();
    assert_eq!(
        reply,
        Response::Exception {
            function: 0x01,
            code: ExceptionCode::ILLEGAL_DATA_ADDRESS
        }
    );
    assert_eq!(reply.encode(), vec![0x81, 0x02]);
}

/// RTU frames with their CRC as printed in a real inverter's manual: Sunfar E500 Series
/// User Manual, Appendix II "MODBUS Protocol", 1.2 Example, pp. 90-91.
#[test]
fn rtu_frames_of_the_sunfar_e500_manual_byte_for_byte() {
    let frames: Vec<(Vec<u8>, u8, Vec<u8>)> = vec![
        (
            vec![0x01, 0x06, 0x10, 0x01, 0x00, 0x01, 0x1D, 0x0A],
            1,
            Request::WriteSingle {
                address: 0x1001,
                value: 1,
            }
            .encode()
            .unwrap(),
        ),
        (
            vec![0x01, 0x06, 0x10, 0x02, 0x01, 0xF4, 0x2C, 0xDD],
            1,
            Request::WriteSingle {
                address: 0x1002,
                value: 500,
            }
            .encode()
            .unwrap(),
        ),
        (
            vec![0x01, 0x03, 0xD0, 0x00, 0x00, 0x02, 0xFC, 0xCB],
            1,
            read(Function::ReadHolding, 0xD000, 2).encode().unwrap(),
        ),
        (
            vec![0x01, 0x03, 0x04, 0x01, 0xF4, 0x00, 0x0B, 0xFB, 0xFA],
            1,
            Response::Registers {
                function: Function::ReadHolding,
                values: vec![500, 11],
            }
            .encode(),
        ),
        (
            vec![
                0x01, 0x10, 0x10, 0x01, 0x00, 0x02, 0x04, 0x00, 0x01, 0x01, 0x90, 0xAF, 0x9F,
            ],
            1,
            Request::WriteMultiple {
                start: 0x1001,
                values: vec![1, 400],
            }
            .encode()
            .unwrap(),
        ),
        (
            vec![0x01, 0x10, 0x10, 0x01, 0x00, 0x02, 0x14, 0xC8],
            1,
            Response::WriteMultiple {
                start: 0x1001,
                count: 2,
            }
            .encode(),
        ),
    ];
    for (frame, slave, pdu) in frames {
        assert_eq!(rtu::encode(slave, &pdu), frame);
        assert_eq!(rtu::decode(&frame), Ok((slave, &pdu[..])));
    }
    let mut bad = vec![0x01, 0x06, 0x10, 0x01, 0x00, 0x01, 0x1D, 0x0B];
    assert!(matches!(rtu::decode(&bad), Err(CodecError::Crc { .. })));
    bad[7] = 0x0A;
    bad[3] ^= 0x40;
    assert!(matches!(rtu::decode(&bad), Err(CodecError::Crc { .. })));
}

#[test]
fn requests_the_specification_forbids_are_never_encoded_nor_decoded() {
    assert!(read(Function::ReadHolding, 0, 0).encode().is_err());
    assert!(read(Function::ReadHolding, 0, 126).encode().is_err());
    assert!(read(Function::ReadInput, 0, 125).encode().is_ok());
    assert!(Request::WriteMultiple {
        start: 0,
        values: vec![0; 124]
    }
    .encode()
    .is_err());
    assert!(Request::decode(&[0x03, 0x00, 0x00, 0x00, 0x00]).is_err());
    assert!(Request::decode(&[0x10, 0x00, 0x01, 0x00, 0x02, 0x03, 0x00, 0x0A, 0x01]).is_err());
    assert!(Response::decode(&[0x03, 0x03, 0x00, 0x0A, 0x01]).is_err());
}

#[test]
fn a_reply_that_does_not_answer_is_told() {
    let request = read(Function::ReadHolding, 0x2000, 1);
    let other = Response::Registers {
        function: Function::ReadInput,
        values: vec![1],
    };
    assert!(request
        .check(&other)
        .unwrap_err()
        .to_string()
        .contains("1 register(s)"));
    let refused = Response::Exception {
        function: 0x03,
        code: ExceptionCode::ILLEGAL_DATA_ADDRESS,
    };
    assert_eq!(request.check(&refused), Ok(()));
    let wrong_function = Response::Exception {
        function: 0x06,
        code: ExceptionCode::ILLEGAL_DATA_ADDRESS,
    };
    assert!(request.check(&wrong_function).is_err());
}

fn any_request() -> impl Strategy<Value = Request> {
    let values = |max| proptest::collection::vec(any::<u16>(), 1..=max);
    prop_oneof![
        (any::<bool>(), any::<u16>(), 1..=125u16).prop_map(|(input, start, count)| read(
            if input {
                Function::ReadInput
            } else {
                Function::ReadHolding
            },
            start,
            count
        )),
        (any::<u16>(), any::<u16>()).prop_map(|(address, value)| Request::WriteSingle { address, value }),
        (any::<u16>(), values(123)).prop_map(|(start, values)| Request::WriteMultiple { start, values }),
        (any::<u16>(), 1..=125u16, any::<u16>(), values(121)).prop_map(
            |(read_start, read_count, write_start, values)| {
                Request::ReadWrite {
                    read_start,
                    read_count,
                    write_start,
                    values,
                }
            }
        ),
    ]
}

fn any_response() -> impl Strategy<Value = Response> {
    prop_oneof![
        (0..3usize, proptest::collection::vec(any::<u16>(), 1..=125)).prop_map(|(f, values)| {
            Response::Registers {
                function: [Function::ReadHolding, Function::ReadInput, Function::ReadWrite][f],
                values,
            }
        }),
        (any::<u16>(), any::<u16>()).prop_map(|(address, value)| Response::WriteSingle { address, value }),
        (any::<u16>(), any::<u16>()).prop_map(|(start, count)| Response::WriteMultiple { start, count }),
        (1..0x80u8, any::<u8>()).prop_map(|(function, code)| Response::Exception {
            function,
            code: ExceptionCode(code)
        }),
    ]
}

proptest! {
    #[test]
    fn requests_round_trip_through_pdu_and_rtu_frame(request in any_request(), slave in 1..=247u8) {
        let pdu = request.encode().unwrap();
        prop_assert_eq!(Request::decode(&pdu), Ok(request));
        let frame = rtu::encode(slave, &pdu);
        prop_assert_eq!(rtu::split(&frame, rtu::Sender::Master), rtu::Split::Frame(frame.len()));
        prop_assert_eq!(rtu::decode(&frame), Ok((slave, &pdu[..])));
    }

    #[test]
    fn replies_round_trip_through_pdu_and_mbap_frame(reply in any_response(), tid in any::<u16>(), unit in any::<u8>()) {
        let pdu = reply.encode();
        prop_assert_eq!(Response::decode(&pdu), Ok(reply));
        let frame = crate::family::modbus::codec::mbap::encode(tid, unit, &pdu);
        prop_assert_eq!(crate::family::modbus::codec::mbap::frame_len(&frame), Some(frame.len()));
        let decoded = crate::family::modbus::codec::mbap::decode(&frame).unwrap();
        prop_assert_eq!((decoded.transaction, decoded.unit, decoded.pdu), (tid, unit, &pdu[..]));
    }

    #[test]
    fn no_bytes_make_the_codec_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _ = Request::decode(&bytes);
        let _ = Response::decode(&bytes);
        let _ = Request::length_from(&bytes);
        let _ = Response::length_from(&bytes);
        let _ = rtu::decode(&bytes);
        let _ = rtu::split(&bytes, rtu::Sender::Master);
        let _ = rtu::split(&bytes, rtu::Sender::Slave);
        let _ = crate::family::modbus::codec::mbap::decode(&bytes);
        let _ = crate::family::modbus::codec::mbap::frame_len(&bytes);
    }
}

/// A write request cut anywhere before its values' byte count is refused by its length,
/// never read past its end (a PDU of function 16 or 23 and nothing else once panicked).
#[test]
fn a_write_request_cut_short_is_refused_by_its_length() {
    let write_multiple = [0x10, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x0A];
    let read_write = [
        0x17, 0x00, 0x01, 0x00, 0x01, 0x00, 0x02, 0x00, 0x01, 0x02, 0x00, 0x0A,
    ];
    for (whole, values_at) in [(&write_multiple[..], 6), (&read_write[..], 10)] {
        assert!(Request::decode(whole).is_ok(), "{whole:02X?}");
        for len in 1..values_at {
            match Request::decode(&whole[..len]) {
                Err(CodecError::Length { .. }) => {}
                other => panic!("{:02X?}: {other:?}", &whole[..len]),
            }
        }
    }
}
