//! What every family's link shares: the observer that sees each telegram (traces, `-v`),
//! the explainer through which a family says what its telegrams mean, the counters of
//! what a link did, and the listening every byte-stream link does around its framing. Family-neutral: the links themselves live in `family/<id>/`.

mod link_core;
mod link_stats;
mod telegram_explainer;
mod telegram_observer;

pub use link_core::{LinkCore, ReplyWait};
pub use link_stats::LinkStats;
pub use telegram_explainer::TelegramExplainer;
pub use telegram_observer::{Direction, TelegramObserver};
