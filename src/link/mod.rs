//! What every family's link shares: the observer that sees each telegram (traces, `-v`),
//! the explainer through which a family says what its telegrams mean, and the counters of
//! what a link did. Family-neutral: the links themselves live in `family/<id>/`.

mod link_stats;
mod telegram_explainer;
mod telegram_observer;

pub use link_stats::LinkStats;
pub use telegram_explainer::TelegramExplainer;
pub use telegram_observer::{Direction, TelegramObserver};
