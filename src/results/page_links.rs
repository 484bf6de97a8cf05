//! Where the names on a store's page lead: nowhere on a page written to a file (it must
//! stand alone), to the other pages of the store under `results serve` (a run to its
//! report, a serial to its certificate, a check to its trend and capability). The one
//! place the served pages' addresses are spelt.

use crate::report::esc;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PageLinks {
    /// A page written to a file: plain text, no links.
    #[default]
    None,
    /// A page `results serve` answers; `simulated` carries the choice to show runs on the
    /// simulated drive from page to page.
    Served { simulated: bool },
}

impl PageLinks {
    fn href(&self, path: &str, query: &[(&str, &str)]) -> Option<String> {
        let PageLinks::Served { simulated } = *self else {
            return None;
        };
        let mut pairs: Vec<String> = query
            .iter()
            .map(|(k, v)| format!("{k}={}", url_escape(v)))
            .collect();
        if simulated {
            pairs.push("simulated=1".into());
        }
        Some(match pairs.is_empty() {
            true => path.to_string(),
            false => format!("{path}?{}", pairs.join("&")),
        })
    }

    /// `html` (already escaped) as a link to `href`, or as it is without one.
    fn anchor(href: Option<String>, html: &str) -> String {
        match href {
            Some(h) => format!("<a href=\"{}\">{html}</a>", esc(&h)),
            None => html.to_string(),
        }
    }

    /// A run's id, leading to its report.
    pub fn run(&self, id: &str, html: &str) -> String {
        Self::anchor(self.href(&format!("/run/{}", url_escape(id)), &[]), html)
    }

    /// A unit's serial, leading to its certificate.
    pub fn unit(&self, serial: &str, html: &str) -> String {
        Self::anchor(self.href(&format!("/unit/{}", url_escape(serial)), &[]), html)
    }

    /// ` (trend · capability)` after a check of `recipe` named `case` as the JUnit report
    /// names it (stage and key: one measurement); nothing on a file.
    pub fn check_pages(&self, case: &str, recipe: &str) -> String {
        let query = [("check", case), ("recipe", recipe)];
        match (self.href("/trend", &query), self.href("/capability", &query)) {
            (Some(t), Some(c)) => format!(
                " <small class=\"links\">(<a href=\"{}\">trend</a> · <a href=\"{}\">capability</a>)</small>",
                esc(&t),
                esc(&c)
            ),
            _ => String::new(),
        }
    }

    /// The bar at the top of a served page: the run list and the yield; nothing on a file.
    pub fn nav(&self) -> String {
        match (self.href("/", &[]), self.href("/yield", &[])) {
            (Some(runs), Some(yields)) => format!(
                "<nav class=\"site\"><a href=\"{}\">Runs</a> · <a href=\"{}\">Yield</a></nav>\n",
                esc(&runs),
                esc(&yields)
            ),
            _ => String::new(),
        }
    }
}

/// Percent-encoding of everything but RFC 3986's unreserved characters.
pub fn url_escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for b in text.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.' | b'~') {
            s.push(b as char);
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_get_no_links_and_served_pages_escaped_ones() {
        assert_eq!(PageLinks::None.run("r1", "r1"), "r1");
        assert_eq!(PageLinks::None.check_pages("k", "R"), "");
        assert_eq!(PageLinks::None.nav(), "");
        let served = PageLinks::Served { simulated: true };
        assert_eq!(
            served.unit("SP 1/../x", "SP"),
            "<a href=\"/unit/SP%201%2F..%2Fx?simulated=1\">SP</a>"
        );
        let pages = served.check_pages("speed mean near", "R");
        assert!(
            pages.contains("/trend?check=speed%20mean%20near&amp;recipe=R&amp;simulated=1"),
            "{pages}"
        );
    }
}
