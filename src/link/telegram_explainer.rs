//! A family's reading of its own telegrams, for the trace (one line each) and for
//! `drivescript decode` (in full, or as JSON). Each family implements it once, so a trace
//! and `decode` always say the same. It keeps the last request it saw, so that a reply can
//! be read as the object it answers.

use super::Direction;

/// Why bytes are no valid telegram of the family (`rejected: REASON`). There is one kind:
/// the reason is text for the person reading a capture.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct ExplainError {
    pub reason: String,
}

impl From<String> for ExplainError {
    fn from(reason: String) -> Self {
        ExplainError { reason }
    }
}

pub trait TelegramExplainer: Send {
    /// One line: `read object 67 status_word`, `reply status_word = 0x0237 operation
    /// enabled`, or `rejected: REASON` for bytes that are no valid telegram.
    fn summary(&mut self, direction: Direction, bytes: &[u8]) -> String;
    /// The full explanation (several lines), or the reason the bytes are no valid telegram.
    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError>;
    /// The telegram as one JSON object (the keys of the family's golden vectors), or
    /// `{"reject": REASON}`. The second value is false when it was rejected.
    fn json(&mut self, bytes: &[u8]) -> (serde_json::Value, bool);
}
