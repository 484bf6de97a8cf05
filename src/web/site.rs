//! A front end's routes, set up one way for every front end: its pages (GET: they only
//! read), its actions (POST: what changes state, so the token guard asks each for the
//! token in its header), what answers a path it does not serve, and the state they all
//! share. Knows no page of its own; the front end hands the result to [`super::WebServer`].

use axum::handler::Handler;
use axum::routing::{get, post};
use axum::Router;

pub struct Site<S>(Router<S>);

impl<S: Clone + Send + Sync + 'static> Site<S> {
    pub fn new() -> Self {
        Site(Router::new())
    }

    /// A page at `path`: read with GET, changing nothing.
    pub fn page<H: Handler<T, S>, T: 'static>(self, path: &str, handler: H) -> Self {
        Site(self.0.route(path, get(handler)))
    }

    /// An action at `path`: a POST, the only way anything changes.
    pub fn action<H: Handler<T, S>, T: 'static>(self, path: &str, handler: H) -> Self {
        Site(self.0.route(path, post(handler)))
    }

    /// What answers a path no page or action is at (otherwise an empty 404).
    pub fn missing<H: Handler<T, S>, T: 'static>(self, handler: H) -> Self {
        Site(self.0.fallback(handler))
    }

    /// The routes, sharing `state`.
    pub fn on(self, state: S) -> Router {
        self.0.with_state(state)
    }
}

impl<S: Clone + Send + Sync + 'static> Default for Site<S> {
    fn default() -> Self {
        Self::new()
    }
}
