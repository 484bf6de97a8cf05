//! `results serve`: the results store's pages over HTTP for a quality lead's browser —
//! the run list with its filters, a run's report, a unit's certificate, trend, capability
//! and yield — read-only, from SQLite or PostgreSQL. A front end like the command line:
//! the pages are the store's renderers (`results::*_html`), the HTTP is the shared `web`
//! layer. Must not write to the store, nor read any file a request names.

mod site_query;
mod store_site;

pub use site_query::SiteQuery;
pub use store_site::StoreSite;
