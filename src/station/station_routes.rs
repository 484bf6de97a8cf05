//! The station's pages and requests on the shared web layer: the page itself (with the
//! token its script sends back in a header), its assets, the event stream, and the three
//! things an operator does — start a recipe by its number, answer the open question,
//! press Stop — plus this bench's last runs, the last run's report and its unit's
//! certificate. Each request names only numbers and typed text; the files served are the
//! station's own. Translates HTTP to [`Station`] calls; decides nothing itself.

use super::bench_history;
use super::event_log::Catch;
use super::station::{Refused, Station};
use crate::report::esc;
use crate::web::{blocking, Asset, Site};
use axum::body::Body;
use axum::body::Bytes;
use axum::extract::State;
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Router;
use serde::de::DeserializeOwned;
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// The page's files, compiled in; uPlot is vendored from the npm registry (MIT, its
/// licence beside it).
pub const ASSETS: &[Asset] = &[
    Asset::new("station.js", include_bytes!("assets/station.js")),
    Asset::new("station.css", include_bytes!("assets/station.css")),
    Asset::new("uplot.min.js", include_bytes!("assets/uplot.min.js")),
    Asset::new("uplot.min.css", include_bytes!("assets/uplot.min.css")),
    Asset::new("uplot.LICENSE.txt", include_bytes!("assets/uplot.LICENSE")),
];

const PAGE: &str = include_str!("assets/station.html");

struct Shared {
    station: Arc<Station>,
    token: String,
}

type St = State<Arc<Shared>>;

/// The station's routes, for [`crate::web::WebServer::start`]; `token` is the one the
/// web layer checks (the page's script sends it with each POST).
pub fn routes(station: Arc<Station>, token: &str) -> Router {
    let shared = Arc::new(Shared {
        station,
        token: token.to_string(),
    });
    Site::new()
        .page("/", page)
        .page("/events", events)
        .page("/api/runs", runs)
        .page("/report", report)
        .page("/certificate", certificate)
        .action("/api/start", start)
        .action("/api/answer", answer)
        .action("/api/stop", stop)
        .on(shared)
}

async fn page(State(s): St) -> Response {
    let station = s.station.log().read(|v| v.station.clone());
    let html = PAGE
        .replace("{{TOKEN}}", &esc(&s.token))
        .replace("{{STATION}}", &esc(&station));
    ([(header::CONTENT_TYPE, "text/html; charset=utf-8")], html).into_response()
}

/// Server-sent events: the whole view first (or, for a page that reconnects with the
/// last event it has, only what it missed), then each event as it comes.
async fn events(State(s): St, headers: HeaderMap) -> Response {
    let after = headers
        .get("last-event-id")
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    let log = s.station.log().clone();
    let first = match log.catch_up(after) {
        Catch::Events(e) if e.is_empty() => None,
        caught => Some(caught),
    };
    let stream = futures_util::stream::unfold((log, after, first), |(log, after, first)| async move {
        let caught = match first {
            Some(c) => c,
            None => log.next(after).await?,
        };
        let (text, last) = sse_text(caught, after);
        Some((Ok::<_, std::convert::Infallible>(text), (log, last, None)))
    });
    (
        [
            (header::CONTENT_TYPE, "text/event-stream"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        Body::from_stream(stream),
    )
        .into_response()
}

/// The SSE text of what a page gets, and the number of the last event it then has.
fn sse_text(caught: Catch, after: Option<u64>) -> (String, Option<u64>) {
    match caught {
        Catch::View(n, json) => (format!("event: view\nid: {n}\ndata: {json}\n\n"), Some(n)),
        Catch::Events(events) => {
            let last = events.last().map(|(n, _)| *n).or(after);
            let text = events
                .iter()
                .map(|(n, json)| format!("id: {n}\ndata: {json}\n\n"))
                .collect();
            (text, last)
        }
    }
}

fn json_reply(status: StatusCode, value: serde_json::Value) -> Response {
    (
        status,
        [(header::CONTENT_TYPE, "application/json")],
        value.to_string(),
    )
        .into_response()
}

fn refused(status: StatusCode, why: &str) -> Response {
    json_reply(status, json!({"error": why}))
}

#[derive(Deserialize)]
struct StartBody {
    recipe: usize,
    serial: String,
    #[serde(default)]
    operator: String,
}

/// What an operator's request came to: the station's answer (200), or why it refused (409).
fn replied<T>(done: Result<T, Refused>, answer: impl FnOnce(T) -> serde_json::Value) -> Response {
    match done {
        Ok(t) => json_reply(StatusCode::OK, answer(t)),
        Err(e) => refused(StatusCode::CONFLICT, &e.0),
    }
}

/// A request's JSON body, or the refusal (400) saying what it must name.
fn body_of<T: DeserializeOwned>(body: &Bytes, names: &str) -> Result<T, Response> {
    serde_json::from_slice(body).map_err(|_| refused(StatusCode::BAD_REQUEST, names))
}

async fn start(State(s): St, body: Bytes) -> Response {
    match body_of::<StartBody>(
        &body,
        "a start names a recipe by its number, a serial and an operator",
    ) {
        Ok(b) => replied(
            s.station.start(b.recipe, &b.serial, &b.operator),
            |id| json!({"run": id}),
        ),
        Err(refusal) => refusal,
    }
}

#[derive(Deserialize)]
struct AnswerBody {
    dialog: u64,
    answer: String,
}

async fn answer(State(s): St, body: Bytes) -> Response {
    match body_of::<AnswerBody>(&body, "an answer names its question and the answer") {
        Ok(b) => replied(s.station.answer(b.dialog, &b.answer), |()| json!({"ok": true})),
        Err(refusal) => refusal,
    }
}

async fn stop(State(s): St) -> Response {
    replied(s.station.stop(), |presses| json!({"stops": presses}))
}

async fn runs(State(s): St) -> Response {
    let record = s.station.setup().options.record.clone();
    let station = s.station.setup().options.operator.identity().station;
    match blocking(move || bench_history::last_runs(&record, station)).await {
        Ok(list) => json_reply(StatusCode::OK, list),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

async fn report(State(s): St) -> Response {
    let Some(path) = s.station.last_run().0 else {
        return refused(StatusCode::NOT_FOUND, "no run has written its report yet");
    };
    match blocking(move || std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))).await {
        Ok(Ok(bytes)) => ([(header::CONTENT_TYPE, "text/html; charset=utf-8")], bytes).into_response(),
        Ok(Err(why)) => refused(StatusCode::NOT_FOUND, &why.to_string()),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

async fn certificate(State(s): St) -> Response {
    let Some(serial) = s.station.last_run().1 else {
        return refused(StatusCode::NOT_FOUND, "no unit has been tested yet");
    };
    let record = s.station.setup().options.record.clone();
    match blocking(move || bench_history::certificate(&record, &serial)).await {
        Ok(Ok(page)) => ([(header::CONTENT_TYPE, "text/html; charset=utf-8")], page).into_response(),
        Ok(Err(why)) => refused(StatusCode::NOT_FOUND, &why.to_string()),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_are_written_as_server_sent_events_with_their_numbers() {
        let (text, last) = sse_text(
            Catch::Events(vec![(3, "{}".into()), (4, "{\"a\":1}".into())]),
            Some(2),
        );
        assert_eq!(text, "id: 3\ndata: {}\n\nid: 4\ndata: {\"a\":1}\n\n");
        assert_eq!(last, Some(4));
        let (text, last) = sse_text(Catch::View(7, "{}".into()), None);
        assert_eq!(text, "event: view\nid: 7\ndata: {}\n\n");
        assert_eq!(last, Some(7));
    }
}
