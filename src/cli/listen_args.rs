//! `--listen` and `--token-file`, the same for every command that serves a browser
//! (`results serve`, `station`): where to listen and which access token guards it. Turns
//! them into the web layer's settings and says at start where to point the browser.

use crate::web::{AccessToken, WebError, WebServer, WebSettings};
use clap::Args;
use std::net::SocketAddr;
use std::path::PathBuf;

#[derive(Debug, Clone, Args)]
pub struct ListenArgs {
    /// Where to listen, IP:PORT. Only loopback (127.0.0.1, [::1]) goes without an access
    /// token; on any other address (0.0.0.0:8080 for the whole network) a token is
    /// generated and printed at start, or read from --token-file.
    #[arg(long, value_name = "IP:PORT", default_value = "127.0.0.1:8080", value_parser = parse_listen)]
    pub listen: SocketAddr,
    /// Read the access token from the first line of FILE (16 to 256 letters, digits, `-`,
    /// `_`, `.`); browsers then need it on loopback too.
    #[arg(long, value_name = "FILE")]
    pub token_file: Option<PathBuf>,
}

/// `localhost:8080` is taken as 127.0.0.1:8080: no name lookup decides where to listen.
fn parse_listen(text: &str) -> Result<SocketAddr, WebError> {
    let t = text.trim();
    let t = t
        .strip_prefix("localhost:")
        .map(|port| format!("127.0.0.1:{port}"))
        .unwrap_or_else(|| t.to_string());
    t.parse().map_err(|_| WebError::BadListen {
        text: text.to_string(),
    })
}

impl ListenArgs {
    /// The web layer's settings: the token from --token-file, else one generated when the
    /// address is not loopback.
    pub fn settings(&self) -> Result<WebSettings, WebError> {
        let token = match &self.token_file {
            Some(path) => Some(AccessToken::from_file(path)?),
            None if !self.listen.ip().is_loopback() => Some(AccessToken::generate()),
            None => None,
        };
        WebSettings::new(self.listen, token)
    }

    /// What to tell the user once `server` listens: the address to open, with the token
    /// when it was generated here (a token from a file stays out of the console and its
    /// logs).
    pub fn announcement(&self, server: &WebServer, what: &str) -> String {
        let at = server.address();
        match &self.token_file {
            Some(file) => format!(
                "{what} at http://{at}/ — open it once as http://{at}/?token=TOKEN with the token in {}",
                file.display()
            ),
            None if server.url().contains("?token=") => format!(
                "{what} at {} — anyone with this address (token included) can read these pages; keep it to those who may",
                server.url()
            ),
            None => format!("{what} at {} (this machine only)", server.url()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listen_addresses_are_ip_and_port() {
        assert_eq!(parse_listen("localhost:8080").ok(), "127.0.0.1:8080".parse().ok());
        assert_eq!(parse_listen("[::1]:0").ok(), "[::1]:0".parse().ok());
        for bad in ["8080", "bench:80", "0.0.0.0", ""] {
            let e = parse_listen(bad).err().map(|e| e.to_string());
            assert!(e.is_some_and(|e| e.contains("IP:PORT")), "{bad}");
        }
    }

    #[test]
    fn a_reachable_address_always_gets_a_token() {
        let args = |listen: &str| ListenArgs {
            listen: parse_listen(listen).unwrap_or(SocketAddr::from(([0, 0, 0, 0], 1))),
            token_file: None,
        };
        assert!(args("0.0.0.0:8080")
            .settings()
            .is_ok_and(|s| s.reads_need_token()));
        assert!(args("127.0.0.1:8080")
            .settings()
            .is_ok_and(|s| !s.reads_need_token()));
    }
}
