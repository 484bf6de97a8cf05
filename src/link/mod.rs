//! What every family's link shares: the observer that sees each telegram (traces, `-v`),
//! the explainer through which a family says what its telegrams mean, the counters of
//! what a link did, the listening every link does around its framing, and the one retry
//! loop ([`RetryPlan`]) each family's link runs with its own attempt and timing. Family-neutral: the links themselves live in `family/<id>/`.

mod link_core;
mod link_stats;
mod retry_plan;
mod telegram_explainer;
mod telegram_observer;

pub use link_core::{LinkCore, ReplyWait};
pub use link_stats::LinkStats;
pub use retry_plan::{AttemptFailure, CoreLink, ExchangeText, Refusal, RetryPlan, Settle, Unanswered};
pub use telegram_explainer::{ExplainError, TelegramExplainer};
pub use telegram_observer::{Direction, TelegramObserver};
