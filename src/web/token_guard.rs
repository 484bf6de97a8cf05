//! The check every request passes before a page sees it. Reading (GET, HEAD): free on
//! loopback when no token was given (but only under a loopback host name, so a web page
//! cannot rebind its own name to this server); otherwise the token, first in the URL
//! (`?token=…`, then swapped for an HttpOnly SameSite=Strict cookie and a redirect that
//! drops it from the address bar), then the cookie or the header. Changing (POST): the
//! token in [`super::TOKEN_HEADER`] always, which another site's page cannot send. Every
//! other method is refused.

use super::{AccessToken, TOKEN_HEADER};
use axum::body::Body;
use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::sync::Arc;

#[derive(Debug)]
pub(super) struct TokenGuard {
    pub token: AccessToken,
    pub reads_need_token: bool,
    /// The cookie's name: one per port, so two servers on one host keep their own.
    pub cookie: String,
}

/// What a request offered.
enum Offered {
    Nothing,
    Right,
    Wrong,
}

impl TokenGuard {
    fn offered(&self, value: Option<&str>) -> Offered {
        match value {
            None => Offered::Nothing,
            Some(v) if self.token.matches(v) => Offered::Right,
            Some(_) => Offered::Wrong,
        }
    }

    fn cookie_value<'h>(&self, headers: &'h HeaderMap) -> Option<&'h str> {
        headers
            .get_all(header::COOKIE)
            .iter()
            .filter_map(|v| v.to_str().ok())
            .flat_map(|v| v.split(';'))
            .filter_map(|pair| pair.trim().split_once('='))
            .find(|(name, _)| *name == self.cookie)
            .map(|(_, value)| value)
    }
}

fn header_value(headers: &HeaderMap) -> Option<&str> {
    headers.get(TOKEN_HEADER).and_then(|v| v.to_str().ok())
}

/// `token` out of a query string, and the query without it.
fn split_query(query: &str) -> (Option<&str>, String) {
    let mut token = None;
    let mut rest = Vec::new();
    for pair in query.split('&').filter(|p| !p.is_empty()) {
        match pair.strip_prefix("token=") {
            Some(t) => token = Some(t),
            None => rest.push(pair),
        }
    }
    (token, rest.join("&"))
}

fn refused(status: StatusCode, why: &str) -> Response {
    let page = format!(
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{status}</title></head><body><h1>{status}</h1><p>{why}</p></body></html>"
    );
    (status, [(header::CONTENT_TYPE, "text/html; charset=utf-8")], page).into_response()
}

fn missing() -> Response {
    refused(
        StatusCode::UNAUTHORIZED,
        "This server needs its access token: open the address it printed when it started (the one ending in ?token=…), or ask whoever runs it.",
    )
}

fn wrong() -> Response {
    refused(
        StatusCode::FORBIDDEN,
        "The access token is not this server's: open the address it printed when it started.",
    )
}

/// Whether `host` (the Host header) names this machine's loopback.
fn loopback_host(host: Option<&str>) -> bool {
    let Some(host) = host else { return false };
    let name = match host.rsplit_once(':') {
        Some((name, port)) if port.bytes().all(|b| b.is_ascii_digit()) => name,
        _ => host,
    };
    matches!(name, "127.0.0.1" | "localhost" | "[::1]")
}

pub(super) async fn guard(State(g): State<Arc<TokenGuard>>, request: Request, next: Next) -> Response {
    let headers = request.headers();
    let mut response = match *request.method() {
        Method::GET | Method::HEAD => {
            if !g.reads_need_token {
                let host = headers.get(header::HOST).and_then(|h| h.to_str().ok());
                if !loopback_host(host) {
                    return refused(
                        StatusCode::FORBIDDEN,
                        "This server answers only under its loopback address (127.0.0.1 or localhost).",
                    );
                }
                next.run(request).await
            } else {
                let (in_url, rest) = split_query(request.uri().query().unwrap_or_default());
                match g.offered(in_url) {
                    Offered::Right => return with_cookie(&g, request.uri().path(), &rest),
                    Offered::Wrong => return wrong(),
                    Offered::Nothing => {}
                }
                match (
                    g.offered(g.cookie_value(headers)),
                    g.offered(header_value(headers)),
                ) {
                    (Offered::Right, _) | (_, Offered::Right) => next.run(request).await,
                    (Offered::Wrong, _) | (_, Offered::Wrong) => return wrong(),
                    _ => return missing(),
                }
            }
        }
        Method::POST => match g.offered(header_value(headers)) {
            Offered::Right => next.run(request).await,
            Offered::Wrong => return wrong(),
            Offered::Nothing => return missing(),
        },
        _ => {
            let mut r = refused(
                StatusCode::METHOD_NOT_ALLOWED,
                "Only GET (to read) and POST (to act, with the token in a header) are answered.",
            );
            r.headers_mut()
                .insert(header::ALLOW, HeaderValue::from_static("GET, HEAD, POST"));
            return r;
        }
    };
    let h = response.headers_mut();
    h.insert("x-content-type-options", HeaderValue::from_static("nosniff"));
    h.insert("referrer-policy", HeaderValue::from_static("no-referrer"));
    h.insert("x-frame-options", HeaderValue::from_static("DENY"));
    h.entry(header::CACHE_CONTROL)
        .or_insert(HeaderValue::from_static("no-store"));
    response
}

/// The right token in the URL: kept as a cookie, and the browser sent on to the same page
/// without it, so it stays out of the history and of links.
fn with_cookie(g: &TokenGuard, path: &str, rest: &str) -> Response {
    let to = if rest.is_empty() {
        path.to_string()
    } else {
        format!("{path}?{rest}")
    };
    let cookie = format!(
        "{}={}; HttpOnly; SameSite=Strict; Path=/",
        g.cookie,
        g.token.text()
    );
    let mut r = Response::new(Body::empty());
    *r.status_mut() = StatusCode::SEE_OTHER;
    if let (Ok(location), Ok(cookie)) = (HeaderValue::from_str(&to), HeaderValue::from_str(&cookie)) {
        r.headers_mut().insert(header::LOCATION, location);
        r.headers_mut().insert(header::SET_COOKIE, cookie);
    }
    r.headers_mut()
        .insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_token_is_taken_out_of_the_query() {
        assert_eq!(split_query("token=abc"), (Some("abc"), String::new()));
        assert_eq!(
            split_query("station=A&token=abc&part=7"),
            (Some("abc"), "station=A&part=7".to_string())
        );
        assert_eq!(split_query("station=A"), (None, "station=A".to_string()));
    }

    #[test]
    fn only_loopback_host_names_pass() {
        for ok in ["127.0.0.1:8080", "localhost:1", "[::1]:80", "localhost"] {
            assert!(loopback_host(Some(ok)), "{ok}");
        }
        for bad in ["evil.example:8080", "127.0.0.1.evil.example", "", "[::2]:80"] {
            assert!(!loopback_host(Some(bad)), "{bad}");
        }
        assert!(!loopback_host(None));
    }
}
