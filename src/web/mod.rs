//! The HTTP layer the browser front ends share (`results serve`, the operator station):
//! a server on a thread of its own with its own tokio runtime, the access token that
//! guards it, embedded static assets, and the bridge from async handlers to the
//! synchronous library (`blocking`). Knows nothing of runs, stores or drives: a front end
//! hands it an `axum::Router` of its pages. Must never read a file a request names.

mod access_token;
mod asset;
mod blocking;
mod site;
mod token_guard;
mod web_error;
mod web_server;
mod web_settings;

pub use access_token::AccessToken;
pub use asset::Asset;
pub use blocking::blocking;
pub use site::Site;
pub use web_error::WebError;
pub use web_server::WebServer;
pub use web_settings::WebSettings;

/// The header a state-changing request (POST) carries its token in: a page of another
/// site can make a browser send a cookie, never a header, so a POST cannot be forged.
pub const TOKEN_HEADER: &str = "x-drivescript-token";

#[cfg(test)]
mod web_server_tests;
