//! Why a line is not a valid Lenze 931 request or reply, or why a reply does not answer
//! its request: what was expected, what arrived, and where (character offset).

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    #[error("empty line: a request or reply has at least one character before the CR")]
    Empty,

    #[error("character {offset} is {found:?}; a line holds printable ASCII only")]
    NotAscii { offset: usize, found: char },

    #[error("{what} at character {offset}: expected {expected}, got {actual:?}")]
    BadField {
        what: &'static str,
        offset: usize,
        expected: String,
        actual: String,
    },

    #[error("unknown command {line:?} (known: OW:NNNN:DDDDDDDD, OR/OI/ON/OX:NNNN, BAUDbbbb, BOOT?, BUS?, INIT!, RESET!, SAVE!, SEP!, TYPE?, VERSION?, =iiiiss:dd.., ?iiiiss)")]
    UnknownRequest { line: String },

    #[error("unknown reply {line:?} (known: OK!, NNNN:DDDDDDDD, XX:FFFFFFFF, DONE, TYPE:dddd, xxxx:VERSION:dddd, xxxx:BUS:..., SERVICE, APPLICATION, =iiiiss:dd.., ERROR!)")]
    UnknownReply { line: String },

    #[error("the reply {reply:?} does not answer {request:?}: expected {expected}")]
    Mismatch {
        request: String,
        reply: String,
        expected: String,
    },

    #[error("line of {len}+ characters without a CR; no line of this protocol is longer than {max}")]
    TooLong { len: usize, max: usize },
}
