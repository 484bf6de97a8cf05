//! The yield page: first-pass and final yield per recipe, station and day, the same rows
//! `results yield` prints. Escapes every text.

use super::certificate_html::page_start;
use super::run_list_html::page_end;
use super::{PageLinks, YieldRow};
use crate::report::esc;
use std::fmt::Write as _;

pub fn yield_page(rows: &[YieldRow], include_void: bool, links: PageLinks) -> String {
    let mut h = page_start("Yield");
    h.push_str(&links.nav());
    let _ = writeln!(
        h,
        "<header>\n<h1>Yield</h1>\n<p class=\"why\">First-pass yield (FPY): units whose first run passed; final yield: units whose last run passed, of the units tested that day at that station. Refused and unfinished runs are left out{}.</p>\n</header>",
        if include_void { "" } else { ", and voided runs" }
    );
    h.push_str("<section>\n<table id=\"yield\">\n<thead><tr><th>Recipe</th><th>Station</th><th>Day (UTC)</th><th>Units</th><th>First pass</th><th>FPY</th><th>Final pass</th><th>Final yield</th><th>Runs</th></tr></thead>\n<tbody>\n");
    for r in rows {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{:.1} %</td><td class=\"num\">{}</td><td class=\"num\">{:.1} %</td><td class=\"num\">{}</td></tr>",
            esc(&r.recipe),
            esc(&r.station),
            esc(&r.day),
            r.units,
            r.first_pass,
            r.first_pass_percent(),
            r.final_pass,
            r.final_percent(),
            r.runs
        );
    }
    h.push_str("</tbody>\n</table>\n");
    if rows.is_empty() {
        h.push_str("<p class=\"why\" id=\"none\">No finished runs.</p>\n");
    }
    h.push_str("</section>\n");
    page_end(h)
}
