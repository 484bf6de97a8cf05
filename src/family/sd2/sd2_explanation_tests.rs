//! The full explanation of SD2 telegrams, as `decode` prints it.

use super::*;

struct NoNames;
impl ObjectNames for NoNames {
    fn object_name(&self, _: u16, _: u32) -> Option<String> {
        None
    }
    fn object_value(&self, _: u16, _: u32, _: &[u8]) -> Option<String> {
        None
    }
    fn is_control_word(&self, index: u16) -> bool {
        index == 68
    }
    fn is_status_word(&self, index: u16) -> bool {
        index == 67
    }
    fn state_of(&self, status: u16) -> Option<String> {
        crate::drive::DeviceState::from_status_word(status).map(|s| s.to_string())
    }
}

fn explain_hex(hex: &str, request: Option<&Telegram>) -> String {
    let bytes = crate::hex::parse_hex(hex).unwrap();
    let t = Telegram::decode(&bytes).unwrap();
    explain(&t, &bytes, request, &NoNames)
}

#[test]
fn write_of_the_control_word() {
    let text = explain_hex("00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97", None);
    assert!(
        text.contains("request   write wide object (cmd 0x0e), PC (1) → drive 2 (switch 0, drive A)"),
        "{text}"
    );
    assert!(text.contains("68 (0x0044)"));
    assert!(text.contains("06 00 (2 bytes) = 6 (u16)"));
    assert!(text.contains("control   6: shutdown (bits set: 1 enable voltage, 2 quick stop off)"));
    assert!(text.contains("0x0b as captured from real drives (the manual's formula gives 0x0c)"));
    assert!(text.contains("check     0x97 ok"));
}

#[test]
fn read_reply_in_the_context_of_its_request() {
    let req = Telegram::read_request(2, 1, 67, 0);
    let bytes = Telegram {
        dest: 1,
        source: 2,
        body: Body::ReadReply {
            error: super::super::codec::ErrorCode::OK,
            data: Data::new(&[0x37, 0x02]).unwrap(),
        },
    }
    .encode(WriteLength::Captured);
    let text = explain_hex(&to_hex(&bytes), Some(&req));
    assert!(text.contains("status    0x0237: operation enabled"), "{text}");
    let text = explain_hex("00 09 01 02 8d 04 00 7f 50 0f 00 84", None);
    assert!(text.contains("= 1003647 (i32)"), "{text}");
    assert!(text.contains("error     0x00 no error"));
}

#[test]
fn cyclic_with_service_channel() {
    let text = explain_hex(
        "00 15 02 01 10 05 00 06 00 ff 0f 00 00 00 00 00 0d 60 01 01 00 00 00 4f",
        None,
    );
    assert!(text.contains("heartbeat toggle set"), "{text}");
    assert!(
        text.contains("ctrl 0x0d: write object, toggle 1, 2 valid bytes"),
        "{text}"
    );
    assert!(text.contains("352 (0x0160)"));
    assert!(text.contains("4095 = 25.0 %"));
}

#[test]
fn strings_are_recognised() {
    assert_eq!(as_string(b"\x20Test Motor\0\0"), Some("Test Motor".into()));
    assert_eq!(as_string(&[0x04, 0x40, 0x42, 0x0f]), None);
    assert_eq!(as_string(&[2]), None);
}
