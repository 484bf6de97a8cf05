//! The routes of `results serve` and what each page asks of the store. One store
//! connection, reopened after it failed (a PostgreSQL server restarted), used by one
//! request at a time on the web layer's blocking pool.

use super::SiteQuery;
use crate::report::esc;
use crate::results::run_list_html::run_list_page;
use crate::results::{
    capability_html, certificate_html, trend_html, yield_html, Locator, PageLinks, RunFilter, Spool, Store,
    StoreError,
};
use crate::web::{blocking, Asset, Site, WebError, WebServer, WebSettings};
use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use axum::response::{Html, IntoResponse, Response};
use axum::Router;
use std::sync::{Arc, Mutex, PoisonError};

/// The store behind the pages.
pub struct StoreSite {
    locator: Locator,
    store: Mutex<Option<Store>>,
}

/// Why a page could not be made, with the status it is answered with.
enum PageError {
    Store(StoreError),
    Asked(String),
    Worker(WebError),
}

impl StoreSite {
    /// The pages of the store at `locator`, opened now so that a wrong store is said
    /// before anything listens.
    pub fn open(locator: Locator) -> Result<StoreSite, StoreError> {
        let store = locator.open(false)?;
        Ok(StoreSite {
            locator,
            store: Mutex::new(Some(store)),
        })
    }

    /// Serves the pages as `settings` say.
    pub fn serve(self, settings: WebSettings) -> Result<WebServer, WebError> {
        WebServer::start(settings, self.routes(), NO_ASSETS)
    }

    fn routes(self) -> Router {
        Site::new()
            .page("/", list)
            .page("/run/{id}", run)
            .page("/unit/{serial}", unit)
            .page("/trend", trend)
            .page("/capability", capability)
            .page("/yield", yields)
            .missing(not_found)
            .on(Arc::new(self))
    }

    /// `read` on the store, reopening it first when the last use failed to reach it.
    fn with_store<T>(&self, read: impl FnOnce(&mut Store) -> Result<T, StoreError>) -> Result<T, StoreError> {
        let mut slot = self.store.lock().unwrap_or_else(PoisonError::into_inner);
        let store = match slot.as_mut() {
            Some(s) => s,
            None => slot.insert(self.locator.open(false)?),
        };
        let answer = read(store);
        if matches!(
            answer,
            Err(StoreError::Unreachable { .. } | StoreError::Query { .. })
        ) {
            *slot = None;
        }
        answer
    }
}

static NO_ASSETS: &[Asset] = &[];

type SiteState = State<Arc<StoreSite>>;

/// Makes a page on the blocking pool: store reads and renderers are synchronous.
async fn page(
    site: Arc<StoreSite>,
    make: impl FnOnce(&StoreSite) -> Result<String, PageError> + Send + 'static,
) -> Response {
    match blocking(move || make(&site)).await {
        Ok(Ok(html)) => Html(html).into_response(),
        Ok(Err(e)) => e.into_response(),
        Err(e) => PageError::Worker(e).into_response(),
    }
}

fn links(q: &SiteQuery) -> PageLinks {
    PageLinks::Served {
        simulated: q.simulated(),
    }
}

fn filter(q: &SiteQuery, default_limit: Option<u64>) -> Result<RunFilter, PageError> {
    q.filter(default_limit).map_err(|e| PageError::Asked(e.0))
}

async fn list(State(site): SiteState, Query(q): Query<SiteQuery>) -> Response {
    page(site, move |site| {
        let filter = RunFilter {
            include_void: true,
            ..filter(&q, Some(50))?
        };
        let unsynced = Spool::new(site.locator.spool_path()).runs();
        let runs = site.with_store(|s| s.list(&filter))?;
        Ok(run_list_page(
            &runs,
            &unsynced,
            &site.locator.name(),
            &q.form(),
            links(&q),
        ))
    })
    .await
}

async fn run(State(site): SiteState, Path(id): Path<String>, Query(q): Query<SiteQuery>) -> Response {
    page(site, move |site| {
        let run = site.with_store(|s| s.run(&id))?;
        Ok(certificate_html::run_certificate(&run, links(&q)))
    })
    .await
}

async fn unit(State(site): SiteState, Path(serial): Path<String>, Query(q): Query<SiteQuery>) -> Response {
    page(site, move |site| {
        let filter = RunFilter {
            unit: Some(serial.clone()),
            include_void: true,
            ..filter(&q, None)?
        };
        let runs = site.with_store(|s| s.unit_runs_in(&filter))?;
        if runs.is_empty() {
            return Err(PageError::Store(StoreError::NotFound(format!(
                "no run of unit {serial}{}",
                if q.simulated() {
                    ""
                } else {
                    " (runs on the simulated drive are hidden: add ?simulated=1)"
                }
            ))));
        }
        Ok(certificate_html::unit_certificate(&serial, &runs, links(&q)))
    })
    .await
}

fn asked_check(q: &SiteQuery) -> Result<String, PageError> {
    q.check().ok_or_else(|| {
        PageError::Asked("which check? add ?check=… (a check's name as its run report shows it)".into())
    })
}

async fn trend(State(site): SiteState, Query(q): Query<SiteQuery>) -> Response {
    page(site, move |site| {
        let check = asked_check(&q)?;
        let filter = filter(&q, None)?;
        let points = site.with_store(|s| s.trend(&check, &filter))?;
        if points.is_empty() {
            return Err(PageError::Store(StoreError::NotFound(format!(
                "no values of `{check}`"
            ))));
        }
        Ok(trend_html::trend_page(&check, &points, links(&q)))
    })
    .await
}

async fn capability(State(site): SiteState, Query(q): Query<SiteQuery>) -> Response {
    page(site, move |site| {
        let check = asked_check(&q)?;
        let filter = filter(&q, None)?;
        let c = site.with_store(|s| s.capability(&check, &filter))?;
        if c.n == 0 {
            return Err(PageError::Store(StoreError::NotFound(format!(
                "no values of `{check}`"
            ))));
        }
        Ok(capability_html::capability_page(&c, links(&q)))
    })
    .await
}

async fn yields(State(site): SiteState, Query(q): Query<SiteQuery>) -> Response {
    page(site, move |site| {
        let filter = filter(&q, None)?;
        let rows = site.with_store(|s| s.yields(&filter))?;
        Ok(yield_html::yield_page(&rows, filter.include_void, links(&q)))
    })
    .await
}

async fn not_found() -> Response {
    error_page(StatusCode::NOT_FOUND, "There is no such page.")
}

impl From<StoreError> for PageError {
    fn from(e: StoreError) -> Self {
        PageError::Store(e)
    }
}

/// A page that says what went wrong, with the way back to the list.
fn error_page(status: StatusCode, text: &str) -> Response {
    let page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{status}</title>\n</head>\n<body>\n{}<h1>{status}</h1>\n<p id=\"error\">{}</p>\n</body>\n</html>\n",
        PageLinks::Served { simulated: false }.nav(),
        esc(text)
    );
    (status, Html(page)).into_response()
}

impl IntoResponse for PageError {
    fn into_response(self) -> Response {
        let (status, text) = match &self {
            PageError::Store(e @ StoreError::NotFound(_)) => (StatusCode::NOT_FOUND, e.to_string()),
            PageError::Store(e @ StoreError::Refused(_)) => (StatusCode::BAD_REQUEST, e.to_string()),
            PageError::Store(e @ StoreError::Unreachable { .. }) => {
                (StatusCode::SERVICE_UNAVAILABLE, e.to_string())
            }
            PageError::Store(e) => (StatusCode::INTERNAL_SERVER_ERROR, e.to_string()),
            PageError::Asked(why) => (StatusCode::BAD_REQUEST, why.clone()),
            PageError::Worker(e) => (StatusCode::INTERNAL_SERVER_ERROR, e.to_string()),
        };
        error_page(status, &text)
    }
}
