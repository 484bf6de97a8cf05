//! `on_failure: stop | continue`, of the recipe and of a block (repeat, attempts,
//! include): what a failed check does to the rest of the run. It must not run anything.

use super::{did_you_mean, Loader};
use crate::diag::YamlNode;
use crate::recipe::recipe::OnFailure;

impl Loader<'_, '_> {
    /// The policy a value names; a misspelt word is refused with the closest one.
    pub(super) fn on_failure(&mut self, node: &YamlNode) -> Option<OnFailure> {
        let word = self.r.scalar_text(node, "`on_failure`")?;
        if let Some(policy) = OnFailure::from_word(&word) {
            return Some(policy);
        }
        let help = did_you_mean(&word, OnFailure::WORDS.into_iter())
            .map(|w| format!("did you mean `{w}`?"))
            .unwrap_or_else(|| "write `stop` (the first failed check ends the run) or `continue`".into());
        self.refuse(
            &node.span,
            format!("`on_failure: {word}` is no policy; it is `stop` or `continue`"),
            "unknown policy",
            Some(help),
        )
    }

    /// A block's own `on_failure:`, read from its settings (`None` when it names none or
    /// the block is written without settings); the block's own reader accepts the key.
    pub(super) fn block_on_failure(&mut self, body: &YamlNode) -> Option<OnFailure> {
        let (_, value) = body.entries()?.iter().find(|(k, _)| k.value == "on_failure")?;
        self.on_failure(value)
    }
}
