//! What can keep a web front end from serving: typed so a caller tells a taken port from
//! a missing token from an unreadable token file. Says what happened and what to do.

use std::net::SocketAddr;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum WebError {
    #[error("cannot listen on {address}: {source} (choose another --listen address or port)")]
    Bind {
        address: SocketAddr,
        source: std::io::Error,
    },
    #[error(
        "{address} can be reached from other machines, and no access token guards it: give --token-file FILE (or listen on 127.0.0.1)"
    )]
    TokenRequired { address: SocketAddr },
    #[error("cannot read the access token from {}: {source}", path.display())]
    TokenFile { path: PathBuf, source: std::io::Error },
    #[error("{}: {why} (write one line of 16 to 256 letters, digits, `-`, `_` or `.`)", path.display())]
    BadToken { path: PathBuf, why: &'static str },
    #[error("`{text}` is no address to listen on: write IP:PORT (127.0.0.1:8080, 0.0.0.0:8080, [::1]:8080)")]
    BadListen { text: String },
    #[error("the web server could not start its runtime: {0}")]
    Runtime(std::io::Error),
    #[error("a page could not be made: its worker stopped ({0})")]
    Worker(String),
}
