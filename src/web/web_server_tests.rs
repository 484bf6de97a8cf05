//! The layer served for real on a loopback socket, spoken to in plain HTTP/1.1.

use super::*;
use axum::Router;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};

static ASSETS: &[Asset] = &[Asset::new("page.css", b"body{color:black}")];

fn pages() -> Router {
    Site::new()
        .page("/", || async { axum::response::Html("<p>home</p>") })
        .page("/work", || async {
            blocking(|| 6 * 7)
                .await
                .map(|n| n.to_string())
                .unwrap_or_default()
        })
        .action("/act", || async { "done" })
        .missing(|| async { (axum::http::StatusCode::NOT_FOUND, "no such page") })
        .on(())
}

/// Status line, headers and body of one request.
fn ask(at: SocketAddr, request: &str) -> (u16, String, String) {
    let mut s = TcpStream::connect(at).expect("connects");
    s.write_all(request.as_bytes()).expect("sends");
    let mut answer = String::new();
    let _ = s.read_to_string(&mut answer);
    let (head, body) = answer.split_once("\r\n\r\n").unwrap_or((&answer, ""));
    let status = head.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, head.to_ascii_lowercase(), body.to_string())
}

fn get_req(path: &str, host: &str, extra: &str) -> String {
    format!("GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n{extra}\r\n")
}

#[test]
fn loopback_reads_freely_but_acts_only_with_the_token_in_a_header() {
    let local: SocketAddr = "127.0.0.1:0".parse().expect("an address");
    let settings = WebSettings::new(local, None).expect("loopback needs no token");
    let token = settings.token().text().to_string();
    let server = WebServer::start(settings, pages(), ASSETS).expect("starts");
    let at = server.address();
    assert_ne!(at.port(), 0);
    assert_eq!(server.url(), format!("http://{at}/"));
    let host = at.to_string();
    let (status, head, body) = ask(at, &get_req("/", &host, ""));
    assert_eq!((status, body.as_str()), (200, "<p>home</p>"), "{head}");
    assert!(head.contains("x-content-type-options: nosniff"), "{head}");
    assert_eq!(ask(at, &get_req("/work", &host, "")).2, "42");
    let (status, head, body) = ask(at, &get_req("/assets/page.css", &host, ""));
    assert_eq!(status, 200);
    assert!(head.contains("content-type: text/css"), "{head}");
    assert_eq!(body, "body{color:black}");
    assert_eq!(ask(at, &get_req("/assets/other.css", &host, "")).0, 404);
    assert_eq!(ask(at, &get_req("/nowhere", &host, "")).2, "no such page");
    // An action is a POST and nothing else.
    assert_eq!(ask(at, &get_req("/act", &host, "")).0, 405);
    // DNS rebinding: another name for this address is not served.
    assert_eq!(ask(at, &get_req("/", "evil.example", "")).0, 403);
    let post = |extra: &str| {
        format!("POST /act HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\nContent-Length: 0\r\n{extra}\r\n")
    };
    assert_eq!(ask(at, &post("")).0, 401);
    assert_eq!(
        ask(at, &post("x-drivescript-token: wrong-wrong-wrong-wrong\r\n")).0,
        403
    );
    // A cookie is what another site's form could make a browser send: not enough.
    let cookie = format!("Cookie: drivescript_token_{}={token}\r\n", at.port());
    assert_eq!(ask(at, &post(&cookie)).0, 401);
    let (status, _, body) = ask(at, &post(&format!("x-drivescript-token: {token}\r\n")));
    assert_eq!((status, body.as_str()), (200, "done"));
    let delete = format!("DELETE / HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n");
    assert_eq!(ask(at, &delete).0, 405);
    server.shutdown();
    assert!(TcpStream::connect(at).is_err(), "still listening after shutdown");
}

#[test]
fn a_guarded_server_wants_the_token_and_swaps_the_url_for_a_cookie() {
    let local: SocketAddr = "127.0.0.1:0".parse().expect("an address");
    let token = AccessToken::generate();
    let settings = WebSettings::new(local, Some(token.clone())).expect("settings");
    let server = WebServer::start(settings, pages(), ASSETS).expect("starts");
    let at = server.address();
    assert_eq!(server.url(), format!("http://{at}/?token={}", token.text()));
    let host = "bench-7.factory:8080";
    assert_eq!(ask(at, &get_req("/", host, "")).0, 401);
    assert_eq!(ask(at, &get_req("/assets/page.css", host, "")).0, 401);
    assert_eq!(ask(at, &get_req("/?token=not-the-token-at-all", host, "")).0, 403);
    let (status, head, _) = ask(
        at,
        &get_req(&format!("/work?a=1&token={}", token.text()), host, ""),
    );
    assert_eq!(status, 303);
    assert!(head.contains("location: /work?a=1\r\n"), "{head}");
    let cookie_line = head
        .lines()
        .find(|l| l.starts_with("set-cookie:"))
        .unwrap_or_default();
    assert!(cookie_line.contains("httponly"), "{cookie_line}");
    assert!(cookie_line.contains("samesite=strict"), "{cookie_line}");
    let name = format!("drivescript_token_{}", at.port());
    let good = format!("Cookie: other=1; {name}={}\r\n", token.text());
    assert_eq!(ask(at, &get_req("/work", host, &good)).2, "42");
    let bad = format!("Cookie: {name}=not-the-token-at-all\r\n");
    assert_eq!(ask(at, &get_req("/work", host, &bad)).0, 403);
    let header = format!("x-drivescript-token: {}\r\n", token.text());
    assert_eq!(ask(at, &get_req("/", host, &header)).0, 200);
    drop(server);
    assert!(TcpStream::connect(at).is_err(), "still listening after drop");
}

#[test]
fn a_taken_port_is_an_error_at_start() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("binds");
    let at = taken.local_addr().expect("an address");
    let settings = WebSettings::new(at, None).expect("settings");
    let e = WebServer::start(settings, pages(), ASSETS).err();
    assert!(matches!(e, Some(WebError::Bind { .. })), "{e:?}");
}
