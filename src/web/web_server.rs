//! A running web front end: the socket bound before it returns (so a taken port is an
//! error at once and the real address is known for port 0), served on a thread of its
//! own by a tokio runtime of its own, the token guard in front of every route. The
//! program's own threads (a run, the stop) never wait on it.

use super::token_guard::{guard, TokenGuard};
use super::{Asset, WebError, WebSettings};
use axum::extract::Path;
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use std::net::SocketAddr;
use std::sync::Arc;
use std::thread::JoinHandle;

pub struct WebServer {
    address: SocketAddr,
    url: String,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl WebServer {
    /// Serves `pages` (a front end's routes, its state already given) and `assets` (under
    /// `/assets/NAME`) as `settings` say. Returns once the socket listens.
    pub fn start(
        settings: WebSettings,
        pages: Router,
        assets: &'static [Asset],
    ) -> Result<WebServer, WebError> {
        let listener = std::net::TcpListener::bind(settings.listen())
            .and_then(|l| l.set_nonblocking(true).map(|()| l))
            .map_err(|source| WebError::Bind {
                address: settings.listen(),
                source,
            })?;
        let address = listener.local_addr().map_err(|source| WebError::Bind {
            address: settings.listen(),
            source,
        })?;
        let url = if settings.reads_need_token() {
            format!("http://{address}/?token={}", settings.token().text())
        } else {
            format!("http://{address}/")
        };
        let guard_state = Arc::new(TokenGuard {
            token: settings.token().clone(),
            reads_need_token: settings.reads_need_token(),
            cookie: format!("drivescript_token_{}", address.port()),
        });
        let app = pages
            .route(
                "/assets/{name}",
                get(move |Path(name): Path<String>| async move { asset(assets, &name) }),
            )
            .layer(axum::middleware::from_fn_with_state(guard_state, guard));
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_io()
            .thread_name("web")
            .max_blocking_threads(4)
            .build()
            .map_err(WebError::Runtime)?;
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let thread = std::thread::Builder::new()
            .name("web".into())
            .spawn(move || {
                runtime.block_on(async move {
                    let listener = match tokio::net::TcpListener::from_std(listener) {
                        Ok(l) => l,
                        Err(e) => {
                            eprintln!("error: the web server cannot use its socket on {address}: {e}");
                            return;
                        }
                    };
                    let served = axum::serve(listener, app)
                        .with_graceful_shutdown(async {
                            let _ = stopped.await;
                        })
                        .await;
                    if let Err(e) = served {
                        eprintln!("error: the web server on {address} stopped: {e}");
                    }
                });
            })
            .map_err(WebError::Runtime)?;
        Ok(WebServer {
            address,
            url,
            stop: Some(stop),
            thread: Some(thread),
        })
    }

    /// The address it listens on (the real port where port 0 was asked).
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// The address a browser opens first: with `?token=…` when reading needs the token.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// Whether its thread still serves (a panic that ended it is a bug the front end
    /// must answer: the station stops the run it can no longer supervise).
    pub fn is_serving(&self) -> bool {
        self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }

    /// Stops taking connections, lets the requests under way finish, and returns when
    /// the server's thread has ended.
    pub fn shutdown(mut self) {
        self.stop_and_join();
    }

    fn stop_and_join(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl Drop for WebServer {
    fn drop(&mut self) {
        self.stop_and_join();
    }
}

fn asset(assets: &[Asset], name: &str) -> Response {
    match assets.iter().find(|a| a.name == name) {
        Some(a) => (
            [
                (header::CONTENT_TYPE, a.content_type()),
                (header::CACHE_CONTROL, "max-age=3600"),
            ],
            a.body,
        )
            .into_response(),
        None => (StatusCode::NOT_FOUND, "no such asset").into_response(),
    }
}
