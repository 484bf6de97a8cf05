//! The `--report` page of a command that runs several files: one row per file with its
//! verdict and a link to that file's own report, self-contained like the reports (the
//! same stylesheet, inline; no scripts, fonts or images). Knows nothing of runs: the
//! caller says what each row holds.

use super::html_text::esc;
use std::fmt::Write as _;

/// One file of the command, as its row shows it.
pub struct IndexEntry {
    /// The recipe or script file, as given on the command line.
    pub file: String,
    /// The run's verdict word (`PASSED`, `FAILED`, `NOT RUN — INVALID`, `NOT FINISHED`, …).
    pub verdict: String,
    /// Whether the verdict is a pass (the row's colour).
    pub passed: bool,
    /// What the verdict means, in a few words (`exit code 1`, `the command ended before it`).
    pub detail: String,
    /// The file's own report, relative to the index page; `None` when it has none.
    pub report: Option<String>,
}

/// The index page: `verdict` is the whole command's (the worst).
pub fn html_index<'e>(
    entries: impl IntoIterator<Item = &'e IndexEntry>,
    verdict: &str,
    passed: bool,
    detail: &str,
) -> String {
    let entries: Vec<&IndexEntry> = entries.into_iter().collect();
    let mut h = String::with_capacity(4096);
    let class = if passed { "passed" } else { "failed" };
    let mark = if passed { "✔" } else { "✘" };
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"drivescript {version}\">\n\
         <title>{count} files — {verdict}</title>\n<style>{CSS}</style>\n</head>\n<body>\n\
         <header>\n<h1>{count} files in one run</h1>\n\
         <p class=\"verdict {class}\" id=\"verdict\">{mark} {verdict}</p>\n\
         <p class=\"why\">{detail}</p>\n</header>\n\
         <section id=\"files\">\n<h2>Files</h2>\n<table>\n\
         <thead><tr><th scope=\"col\">#</th><th scope=\"col\">File</th>\
         <th scope=\"col\">Verdict</th><th scope=\"col\">Report</th></tr></thead>\n<tbody>\n",
        version = env!("CARGO_PKG_VERSION"),
        count = entries.len(),
        verdict = esc(verdict),
        detail = esc(detail),
    );
    for (i, e) in entries.iter().enumerate() {
        let (row, cell) = if e.passed {
            ("", "ok")
        } else {
            (" class=\"fail\"", "fail")
        };
        let link = match &e.report {
            Some(href) => format!("<a href=\"{}\">{}</a>", esc(&href_of(href)), esc(href)),
            None => "none".to_string(),
        };
        let _ = writeln!(
            h,
            "<tr{row}><td class=\"num\">{}</td><td><code>{}</code></td>\
             <td><span class=\"{cell}\">{}</span> ({})</td><td>{link}</td></tr>",
            i + 1,
            esc(&e.file),
            esc(&e.verdict),
            esc(&e.detail),
        );
    }
    let _ = write!(
        h,
        "</tbody>\n</table>\n</section>\n<footer>Written by drivescript {} as the run went; \
         each file's own report holds its steps, checks, plots and safe stop.</footer>\n\
         </body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    h
}

/// The same stylesheet as the reports, so the pages look alike.
const CSS: &str = include_str!("html_report.css");

/// A relative file name as a URL path: every byte outside the unreserved characters
/// percent-encoded, so that `#`, `?`, `%` or spaces in a recipe's name keep the link.
fn href_of(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    for b in path.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_are_percent_encoded_and_texts_escaped() {
        for (file, href) in [
            ("report-1-a b#?.html", "report-1-a%20b%23%3F.html"),
            ("ü.html", "%C3%BC.html"),
        ] {
            assert_eq!(href_of(file), href, "{file}");
        }
        let page = html_index(
            &[IndexEntry {
                file: "<a>.yaml".into(),
                verdict: "FAILED".into(),
                passed: false,
                detail: "exit code 1".into(),
                report: Some("r-1-<a>.html".into()),
            }],
            "FAILED",
            false,
            "1 of 1 failed",
        );
        assert!(page.contains("<code>&lt;a&gt;.yaml</code>"), "{page}");
        assert!(page.contains("href=\"r-1-%3Ca%3E.html\""), "{page}");
    }
}
