//! The DNC 8-byte cyclic telegram (cmd 0x10, reply 0x90) and its optional acyclic service
//! channel. Pure field access; framing lives in `telegram.rs`.

/// The cyclic payload: two header bytes and eight process-data bytes, optionally followed
/// by the service channel. In a request the PDO carries control word and speed reference;
/// in a reply status word, actual speed, drive error and actual current.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Cyclic {
    pub header: [u8; 2],
    pub pdo: [u8; 8],
    pub service: Option<ServiceChannel>,
}

/// Header bit 2: the heartbeat toggle (0x01 / 0x05 alternate when the heartbeat is used).
pub const HEADER_TOGGLE: u8 = 0x04;

/// Speed reference scaling: 0x3FFF is +100 % of the drive's velocity scaling.
pub const SPEED_FULL_SCALE: i16 = 0x3FFF;

impl Cyclic {
    /// A request with control word and speed reference; header 0x01 (or 0x05 with the toggle).
    pub fn request(control_word: u16, speed: i16, toggle: bool) -> Cyclic {
        let mut pdo = [0u8; 8];
        pdo[0..2].copy_from_slice(&control_word.to_le_bytes());
        pdo[2..4].copy_from_slice(&speed.to_le_bytes());
        Cyclic {
            header: [0x01 | if toggle { HEADER_TOGGLE } else { 0 }, 0],
            pdo,
            service: None,
        }
    }

    /// A reply's process data.
    pub fn reply(header: [u8; 2], status_word: u16, speed: i16, drive_error: u16, current: i16) -> Cyclic {
        let mut pdo = [0u8; 8];
        pdo[0..2].copy_from_slice(&status_word.to_le_bytes());
        pdo[2..4].copy_from_slice(&speed.to_le_bytes());
        pdo[4..6].copy_from_slice(&drive_error.to_le_bytes());
        pdo[6..8].copy_from_slice(&current.to_le_bytes());
        Cyclic {
            header,
            pdo,
            service: None,
        }
    }

    pub fn with_service(mut self, service: ServiceChannel) -> Cyclic {
        self.service = Some(service);
        self
    }

    fn u16_at(&self, i: usize) -> u16 {
        u16::from_le_bytes([self.pdo[i], self.pdo[i + 1]])
    }

    /// Request: control word (pdo0/1). Reply: status word (same bytes).
    pub fn word(&self) -> u16 {
        self.u16_at(0)
    }

    /// Speed reference (request) or actual speed (reply), as a fraction of full scale
    /// 0x3FFF = +100 %.
    pub fn speed(&self) -> i16 {
        self.u16_at(2) as i16
    }

    /// Reply only: the drive error (pdo4/5).
    pub fn drive_error(&self) -> u16 {
        self.u16_at(4)
    }

    /// Reply only: the actual current (pdo6/7), in the drive's own scaling.
    pub fn current(&self) -> i16 {
        self.u16_at(6) as i16
    }

    pub fn toggle(&self) -> bool {
        self.header[0] & HEADER_TOGGLE != 0
    }

    /// Speed as percent of the drive's velocity scaling.
    pub fn speed_percent(&self) -> f64 {
        f64::from(self.speed()) * 100.0 / f64::from(SPEED_FULL_SCALE)
    }
}

/// What a service-channel request asks for (ctrl bits 1–2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServiceFunction {
    Read,
    SetArrayIndex,
    Write,
    /// Function 3: the drive goes to fault.
    Invalid,
}

impl ServiceFunction {
    pub fn from_bits(bits: u8) -> ServiceFunction {
        match bits & 0x03 {
            0 => ServiceFunction::Read,
            1 => ServiceFunction::SetArrayIndex,
            2 => ServiceFunction::Write,
            _ => ServiceFunction::Invalid,
        }
    }

    pub fn bits(self) -> u8 {
        match self {
            ServiceFunction::Read => 0,
            ServiceFunction::SetArrayIndex => 1,
            ServiceFunction::Write => 2,
            ServiceFunction::Invalid => 3,
        }
    }

    pub fn id(self) -> &'static str {
        match self {
            ServiceFunction::Read => "read",
            ServiceFunction::SetArrayIndex => "set_array_index",
            ServiceFunction::Write => "write",
            ServiceFunction::Invalid => "invalid",
        }
    }
}

/// The acyclic service channel appended to a cyclic telegram:
/// `reserved ctrl index_lo index_hi sdata0..3`. In a reply `ctrl` holds the state byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ServiceChannel {
    /// The byte before ctrl; 0x00 in every printed example.
    pub reserved: u8,
    pub ctrl: u8,
    pub index: u16,
    pub data: [u8; 4],
}

impl ServiceChannel {
    /// A request. `valid_bytes` is 1..=4 (clamped), the number of meaningful bytes in `data`.
    pub fn request(
        toggle: bool,
        function: ServiceFunction,
        valid_bytes: u8,
        index: u16,
        data: [u8; 4],
    ) -> Self {
        let last = valid_bytes.clamp(1, 4) - 1;
        ServiceChannel {
            reserved: 0,
            ctrl: u8::from(toggle) | (function.bits() << 1) | (last << 3),
            index,
            data,
        }
    }

    /// ctrl bit 0: must change to start a new service.
    pub fn toggle(&self) -> bool {
        self.ctrl & 0x01 != 0
    }

    /// ctrl bits 1–2.
    pub fn function(&self) -> ServiceFunction {
        ServiceFunction::from_bits(self.ctrl >> 1)
    }

    /// ctrl bits 3–4 plus one: how many bytes of `data` are valid.
    pub fn valid_bytes(&self) -> usize {
        usize::from((self.ctrl >> 3) & 0x03) + 1
    }

    pub fn value(&self) -> u32 {
        u32::from_le_bytes(self.data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ctrl_bits_of_the_printed_examples() {
        let read = ServiceChannel::request(false, ServiceFunction::Read, 2, 0x27, [0; 4]);
        assert_eq!(read.ctrl, 0x08);
        let write = ServiceChannel::request(true, ServiceFunction::Write, 2, 0x160, [1, 0, 0, 0]);
        assert_eq!(write.ctrl, 0x0D);
        assert!(write.toggle());
        assert_eq!(write.function(), ServiceFunction::Write);
        assert_eq!(write.valid_bytes(), 2);
        assert_eq!(write.value(), 1);
    }

    #[test]
    fn speed_scaling() {
        assert_eq!(Cyclic::request(6, 0x3FFF, false).speed_percent(), 100.0);
        assert_eq!(Cyclic::request(6, -16384, false).pdo[2..4], [0x00, 0xC0]);
        assert!((Cyclic::request(6, 0x1FFF, false).speed_percent() - 50.0).abs() < 0.01);
        let r = Cyclic::reply([1, 0], 0x0237, 100, 7, -5);
        assert_eq!(
            (r.word(), r.speed(), r.drive_error(), r.current()),
            (0x0237, 100, 7, -5)
        );
        assert!(Cyclic::request(7, 0, true).toggle());
    }
}
