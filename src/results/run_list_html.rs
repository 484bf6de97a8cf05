//! The page of the store's runs (`results serve`'s first page): a form with the filters
//! of `results list` (station, operator, part, recipe, unit, verdict, since, until), then
//! a row per run with what a reader must not miss beside its verdict (simulated, VOID,
//! unsynced), each run and unit leading to its own page. Escapes every text.

use super::certificate_html::{page_start, shown_time, verdict_html};
use super::{PageLinks, StoredRun};
use crate::report::esc;
use std::fmt::Write as _;

/// The filters as the reader typed them, to show them again in the form.
#[derive(Debug, Clone, Default)]
pub struct ListForm {
    /// `(name, value)` of each text field, in the form's order.
    pub fields: Vec<(&'static str, String)>,
    pub simulated: bool,
}

/// The fields of the form: the query names `results serve` reads, and their labels.
pub const LIST_FIELDS: [(&str, &str); 9] = [
    ("station", "Station"),
    ("operator", "Operator"),
    ("part", "Part"),
    ("recipe", "Recipe"),
    ("unit", "Unit"),
    ("verdict", "Verdict"),
    ("since", "Since"),
    ("until", "Until"),
    ("limit", "At most"),
];

/// The page of `runs` (newest first), those in `unsynced` marked, in the store `store`.
pub fn run_list_page(
    runs: &[StoredRun],
    unsynced: &[String],
    store: &str,
    form: &ListForm,
    links: PageLinks,
) -> String {
    let mut h = page_start("Runs");
    h.push_str(&links.nav());
    let _ = writeln!(
        h,
        "<header>\n<h1>Runs</h1>\n<p class=\"why\">{} run(s) in {}, newest first.</p>\n</header>",
        runs.len(),
        esc(store)
    );
    if links != PageLinks::None {
        form_html(&mut h, form);
    }
    h.push_str("<section>\n<table id=\"runs\">\n<thead><tr><th>Run</th><th>Started (UTC)</th><th>Verdict</th><th>Recipe</th><th>Unit</th><th>Part</th><th>Station</th><th>Operator</th><th>Drive</th></tr></thead>\n<tbody>\n");
    for r in runs {
        let mut verdict = verdict_html(r);
        if unsynced.contains(&r.run.id) {
            verdict.push_str(" <span class=\"unsynced\">(unsynced: kept on its bench)</span>");
        }
        let cell = |v: &Option<String>| esc(v.as_deref().unwrap_or(""));
        let _ = writeln!(
            h,
            "<tr class=\"{}\"><td class=\"step\">{}</td><td>{}</td><td class=\"verdict-cell {}\">{verdict}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            if r.verdict() == "passed" { "" } else { "fail" },
            links.run(&r.run.id, &format!("<code>{}</code>", esc(&r.run.id))),
            esc(&shown_time(&r.run.started_at)),
            if r.verdict() == "passed" { "ok" } else { "fail" },
            esc(&r.run.recipe),
            r.run
                .unit
                .serial
                .as_deref()
                .map_or(String::new(), |s| links.unit(s, &esc(s))),
            cell(&r.run.unit.part),
            cell(&r.run.unit.station),
            cell(&r.run.unit.operator),
            if r.run.simulated {
                "simulated".to_string()
            } else {
                esc(&r.run.drive)
            },
        );
    }
    h.push_str("</tbody>\n</table>\n");
    if runs.is_empty() {
        let _ = writeln!(
            h,
            "<p class=\"why\" id=\"none\">No runs{}.</p>",
            if form.simulated {
                ""
            } else {
                " (runs on the simulated drive are hidden: tick “simulated”)"
            }
        );
    }
    page_end(h)
}

fn form_html(h: &mut String, form: &ListForm) {
    h.push_str("<form class=\"filters\" method=\"get\" action=\"/\">\n");
    for (name, label) in LIST_FIELDS {
        let value = form
            .fields
            .iter()
            .find(|(n, _)| *n == name)
            .map_or("", |(_, v)| v.as_str());
        let _ = writeln!(
            h,
            "<label>{label} <input name=\"{name}\" value=\"{}\" size=\"12\"></label>",
            esc(value)
        );
    }
    let _ = writeln!(
        h,
        "<label><input type=\"checkbox\" name=\"simulated\" value=\"1\"{}> simulated</label>\n<button type=\"submit\">Filter</button>\n</form>",
        if form.simulated { " checked" } else { "" }
    );
}

/// The footer every page of the store's ends with.
pub(super) fn page_end(mut h: String) -> String {
    let _ = write!(
        h,
        "<footer>Written by drivescript {} from its results store.</footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}
