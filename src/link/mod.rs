//! Request → reply over a transport, for one protocol family at a time: timeouts, bounded
//! retries, flushing stale input, and checking that a reply answers its request.
//! Builds telegrams only through `protocol`; knows nothing about object names or units.

mod link_config;
mod link_error;
mod link_stats;
mod telegram_observer;

pub use link_config::LinkConfig;
pub use link_error::LinkError;
pub use link_stats::LinkStats;
pub use telegram_observer::{Direction, TelegramObserver};
