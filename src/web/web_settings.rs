//! Where a web front end listens and who may use it: loopback alone may go without a
//! token for reading; an address other machines can reach always needs one. A token
//! exists either way, for the requests that change something (POST, token in a header).

use super::{AccessToken, WebError};
use std::net::SocketAddr;

#[derive(Debug, Clone)]
pub struct WebSettings {
    listen: SocketAddr,
    token: AccessToken,
    reads_need_token: bool,
}

impl WebSettings {
    /// Listening on `listen`, guarded by `token`. Without a token, only a loopback address
    /// is allowed (a token is made for the state-changing requests only); any other
    /// address is refused with [`WebError::TokenRequired`].
    pub fn new(listen: SocketAddr, token: Option<AccessToken>) -> Result<WebSettings, WebError> {
        match token {
            Some(token) => Ok(WebSettings {
                listen,
                token,
                reads_need_token: true,
            }),
            None if listen.ip().is_loopback() => Ok(WebSettings {
                listen,
                token: AccessToken::generate(),
                reads_need_token: false,
            }),
            None => Err(WebError::TokenRequired { address: listen }),
        }
    }

    pub fn listen(&self) -> SocketAddr {
        self.listen
    }

    /// The token: a page that makes POST requests puts it in its script's
    /// [`super::TOKEN_HEADER`].
    pub fn token(&self) -> &AccessToken {
        &self.token
    }

    /// Whether reading a page needs the token too (any token given, any non-loopback
    /// address).
    pub fn reads_need_token(&self) -> bool {
        self.reads_need_token
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_loopback_goes_without_a_token() {
        let at = |a: &str| {
            a.parse::<SocketAddr>()
                .unwrap_or(SocketAddr::from(([1, 1, 1, 1], 1)))
        };
        for open in ["0.0.0.0:8080", "192.168.1.5:80", "[::]:8080"] {
            assert!(
                matches!(
                    WebSettings::new(at(open), None),
                    Err(WebError::TokenRequired { .. })
                ),
                "{open}"
            );
            let guarded = WebSettings::new(at(open), Some(AccessToken::generate()));
            assert!(guarded.is_ok_and(|s| s.reads_need_token()));
        }
        for local in ["127.0.0.1:8080", "[::1]:0"] {
            let s = WebSettings::new(at(local), None);
            assert!(s.is_ok_and(|s| !s.reads_need_token() && s.token().text().len() == 64));
        }
    }
}
