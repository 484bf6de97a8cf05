//! The bridge from an async handler to the synchronous library (a store query, a page
//! renderer): the work runs on tokio's blocking pool so the server keeps answering.

use super::WebError;

/// Runs `work` on the blocking pool and gives back what it returned; a panic in it
/// becomes an error the handler turns into a 500, never a dead server.
pub async fn blocking<T, F>(work: F) -> Result<T, WebError>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    tokio::task::spawn_blocking(work)
        .await
        .map_err(|e| WebError::Worker(e.to_string()))
}
